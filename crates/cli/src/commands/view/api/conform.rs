//! `GET /api/conform?model=NAME&NAME=VALUE...`: `fastbrdf conform MODEL --json` in the page,
//! for a user's model (start-up or uploaded, with the query's values of the parameters its
//! file declares) or a registry BRDF (sampled by its default strategy): the same checks, in
//! CI mode (`Config::ci`), the same JSON record (non-finite numbers null).

use super::query::{Query, Response, check_unused, checked_id};
use crate::CliError;
use crate::commands::view::state::State;
use crate::model_args::{self, Use};
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, UserBrdf};
use fastbrdf_analysis::conform::{self, Config};
use std::sync::Arc;

/// The conform report of the query's model, as `fastbrdf conform MODEL --json` prints it
/// (a failed check is still 200: the report says so; a bad model or value is 400, the GPU or
/// evaluator failing 500).
pub fn conform_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let id = q.need("model")?;
    let all = q.params();
    let brdf: Arc<dyn UserBrdf> = match state.user(id) {
        // Its file's values: an unknown name or a value out of range is refused by name.
        Some(u) => u.instance(&all)?,
        None => {
            let id = checked_id(id)?;
            check_unused(&[id], &all)?;
            let spec =
                model_args::spec(id, &model_args::own_pairs(id, &all)?, None, None, Use::AsIs)?;
            Arc::new(Builtin::new(&spec, Strategy::Auto)?)
        }
    };
    let report =
        conform::run(brdf.as_ref(), None, &Config::ci(), &|_: &str| {}).map_err(|e| CliError {
            code: crate::EXIT_CHECK_FAILED,
            message: format!("conform: {e}"),
        })?;
    let v = serde_json::to_value(&report).map_err(|e| CliError {
        code: crate::EXIT_CHECK_FAILED,
        message: format!("conform: {e}"),
    })?;
    Ok(Response::json(&v))
}
