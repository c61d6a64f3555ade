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
    /// A model of one kind was used where another kind is needed.
    WrongKind {
        model: String,
        expected: String,
        found: String,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::UnknownModel(id) => {
                write!(
                    f,
                    "unknown model id '{id}' (run `fastbrdf models` for the list)"
                )
            }
            Error::UnknownParam { model, param } => {
                write!(f, "model '{model}' has no parameter '{param}'")
            }
            Error::InvalidParam {
                model,
                param,
                value,
                expected,
            } => {
                write!(
                    f,
                    "model '{model}': parameter {param} = {value} is invalid: expected {expected}"
                )
            }
            Error::MissingParam { model, param } => {
                write!(f, "model '{model}': parameter {param} is required here")
            }
            Error::Domain { input, reason } => write!(f, "input {input}: {reason}"),
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
