//! One module per subcommand: `Args` (clap) and `run`.

pub mod check;
pub mod eval;
pub mod models;
