//! Typed errors: the library never prints; the CLI maps these to messages and exit codes.

use std::fmt;

/// Everything that can go wrong when building or evaluating a model.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// No model has this id.
    UnknownModel(String),
    /// The model has no parameter of this name.
    UnknownParam { model: String, param: String },
    /// A parameter value is outside its documented range, not a number, or not one of its
    /// choices.
    InvalidParam {
        model: String,
        param: String,
        value: String,
        expected: String,
    },
    /// A parameter that the chosen configuration needs is missing.
    MissingParam { model: String, param: String },
    /// An input (cosine or direction) outside the model's documented domain.
    Domain { input: String, reason: String },
    /// No named metal (`colour::METALS`) has this name; `known` lists the names
    /// (comma-separated), given by the caller so that this module imports nothing of the
    /// crate.
    UnknownMetal { name: String, known: String },
    /// A model of one kind was used where another kind is needed.
    WrongKind {
        model: String,
        expected: String,
        found: String,
    },
}

/// Longest user-given text (an id, a parameter name or value) echoed whole in a message.
const ECHO_MAX: usize = 40;

/// `s` as echoed in a message: at most [`ECHO_MAX`] characters, control characters escaped
/// (`fastbrdf_io::shorten`), so a 10 MB argument gives a one-line error.
fn echo(s: &str) -> String {
    fastbrdf_io::shorten(s, ECHO_MAX)
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::UnknownModel(id) => {
                let id = echo(id);
                write!(
                    f,
                    "unknown model id '{id}' (run `fastbrdf models` for the list)"
                )
            }
            Error::UnknownParam { model, param } => {
                let param = echo(param);
                write!(f, "model '{model}' has no parameter '{param}'")
            }
            Error::InvalidParam {
                model,
                param,
                value,
                expected,
            } => {
                let value = echo(value);
                write!(
                    f,
                    "model '{model}': parameter {param} = {value} is invalid: expected {expected}"
                )
            }
            Error::MissingParam { model, param } => {
                write!(f, "model '{model}': parameter {param} is required here")
            }
            Error::Domain { input, reason } => write!(f, "input {input}: {reason}"),
            Error::UnknownMetal { name, known } => {
                let name = echo(name);
                write!(
                    f,
                    "unknown metal '{name}': expected one of {known} (run `fastbrdf metals` for their constants)"
                )
            }
            Error::WrongKind {
                model,
                expected,
                found,
            } => {
                write!(
                    f,
                    "model '{model}' is a {found}, but a {expected} is needed"
                )
            }
        }
    }
}

impl std::error::Error for Error {}

/// Result with this crate's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 11: user-given text is shortened in messages.
    #[test]
    fn long_user_text_is_shortened_in_messages() {
        let long = "9".repeat(10_000_000);
        let e = Error::InvalidParam {
            model: "pow".into(),
            param: "n".into(),
            value: long.clone(),
            expected: "a number in [1, 10000]".into(),
        }
        .to_string();
        assert!(e.len() < 200 && e.contains("(9999960 more bytes)"), "{e}");
        let e = Error::UnknownModel(long.clone()).to_string();
        assert!(e.len() < 200, "{e}");
        let e = Error::UnknownParam {
            model: "pow".into(),
            param: "x\ny".into(),
        }
        .to_string();
        assert_eq!(e, "model 'pow' has no parameter 'x\\ny'");
        assert_eq!(echo("n"), "n");
    }
}
