//! One module per subcommand (`Args` and `run`; `errors` and `pareto` with their modes as
//! submodules), and `common`, the leaf modules they share. A command module imports
//! `common`, `crate::model_args` and the libraries, never another command module.

pub mod albedo;
pub mod bench;
pub mod check;
pub mod common;
pub mod compare;
pub mod conform;
pub mod demo;
pub mod errors;
pub mod eval;
pub mod fit;
pub mod fit_measured;
pub mod lut;
pub mod materials;
pub mod measured;
pub mod metals;
pub mod models;
pub mod normalize;
pub mod pareto;
pub mod plot;
pub mod render;
pub mod reproduce;
pub mod sample;
pub mod shader;
pub mod view;

use crate::CliError;
use std::io::Write;

/// Writes `bytes` to stdout and flushes. A closed stdout (EPIPE, e.g. `| head`) or any other
/// write failure is exit code 3 with a message, never a panic.
pub fn write_stdout(bytes: &[u8]) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)
        .and_then(|()| out.flush())
        .map_err(|e| CliError::io(format!("cannot write to stdout: {e}")))
}

/// `println!` that returns exit code 3 on a write failure instead of panicking (use with `?`
/// semantics: it returns from the enclosing function).
#[macro_export]
macro_rules! outln {
    () => {
        $crate::commands::write_stdout(b"\n")?
    };
    ($($t:tt)*) => {
        $crate::commands::write_stdout(format!("{}\n", format_args!($($t)*)).as_bytes())?
    };
}

/// `print!` counterpart of [`outln!`].
#[macro_export]
macro_rules! out {
    ($($t:tt)*) => {
        $crate::commands::write_stdout(format!($($t)*).as_bytes())?
    };
}
