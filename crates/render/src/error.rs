//! Errors of the renderer: every one names what is wrong (and the file and line for inputs).

use std::fmt;

/// A render error.
#[derive(Debug)]
pub enum RenderError {
    /// A problem in an input file, with its line (1-based) when it has one.
    Input {
        file: String,
        line: Option<usize>,
        message: String,
    },
    /// An invalid option (size, samples, light, model parameters...).
    Invalid(String),
    /// A model error from the library.
    Model(fastbrdf::Error),
    /// Writing an output failed.
    Output { file: String, message: String },
    /// A buffer of the size the caller asked for could not be allocated (the film): an error,
    /// never an abort, so that an embedding process (Python) survives it.
    Memory(String),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Input {
                file,
                line: Some(l),
                message,
            } => write!(f, "{file}:{l}: {message}"),
            RenderError::Input {
                file,
                line: None,
                message,
            } => write!(f, "{file}: {message}"),
            RenderError::Invalid(m) | RenderError::Memory(m) => write!(f, "{m}"),
            RenderError::Model(e) => write!(f, "{e}"),
            RenderError::Output { file, message } => write!(f, "cannot write {file}: {message}"),
        }
    }
}

impl std::error::Error for RenderError {}

impl From<fastbrdf_io::IoError> for RenderError {
    fn from(e: fastbrdf_io::IoError) -> Self {
        match e {
            fastbrdf_io::IoError::Input { path, message } => RenderError::Input {
                file: path,
                line: None,
                message,
            },
            fastbrdf_io::IoError::Output { path, message } => RenderError::Output {
                file: path,
                message,
            },
        }
    }
}

impl From<fastbrdf::Error> for RenderError {
    fn from(e: fastbrdf::Error) -> Self {
        RenderError::Model(e)
    }
}

/// Result with a render error.
pub type Result<T, E = RenderError> = std::result::Result<T, E>;
