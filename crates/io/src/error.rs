//! The crate's error: who is at fault, the user's input (exit code 2) or an output the
//! tool could not write (exit code 3).

use std::fmt;
use std::path::Path;

/// An I/O failure, split by who is at fault: an input the user named (exit code 2) or an output
/// the tool could not write (exit code 3).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum IoError {
    /// An input could not be read, is too large or is not text. `message` names the problem.
    Input { path: String, message: String },
    /// An output could not be written.
    Output { path: String, message: String },
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::Input { path, message } => write!(f, "{path}: {message}"),
            IoError::Output { path, message } => write!(f, "cannot write {path}: {message}"),
        }
    }
}

impl std::error::Error for IoError {}

pub(crate) fn input_err(path: &Path, message: impl Into<String>) -> IoError {
    IoError::Input {
        path: path.display().to_string(),
        message: message.into(),
    }
}

pub(crate) fn output_err(path: &Path, e: impl fmt::Display) -> IoError {
    IoError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}
