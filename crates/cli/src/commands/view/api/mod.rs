//! The JSON API of `fastbrdf view`: pure functions from a request (path and query) to a
//! response, so that the server loop, the tests and the benchmark see the same thing. Every
//! number is computed by the library functions the CLI commands call (`errors::at` as
//! `fastbrdf errors`, `albedo::curve`/`furnace` as `fastbrdf albedo`, the CPU renderer and
//! `compare::metrics` as `fastbrdf compare`, `export_form` as `fastbrdf shader`), and every
//! refusal carries the message the CLI would print for the same input.
//!
//! The query string is the explorer's text boundary: [`query`] parses it once per request into
//! the models' specs; the endpoints ([`models`](mod@models), [`plots`](mod@plots), [`errors`],
//! [`render`]) take them; [`user`] computes what the users' models (`--model file:PATH`) show.

mod conform;
mod errors;
mod gpu;
mod grids;
mod kinds;
mod models;
mod panes;
mod plots;
mod query;
mod render;
mod user;

pub use conform::conform_endpoint;
pub use errors::errors_endpoint;
pub use gpu::{scene_endpoint as gpu_scene, shader_endpoint as gpu_shader};
pub use models::{material, models, shader};
pub use panes::panes;
pub use plots::{albedo_endpoint, plots};
pub use query::{Query, Response};
pub use render::{flip_endpoint, render_endpoint};
pub use user::{MAX_UPLOAD, upload};
