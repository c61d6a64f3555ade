//! One module per subcommand: `Args` (clap) and `run`.

pub mod analysis;
pub mod bench;
pub mod check;
pub mod demo;
pub mod eval;
pub mod fit;
pub mod models;
pub mod plot;
pub mod render;
pub mod reproduce;
pub mod shader;
