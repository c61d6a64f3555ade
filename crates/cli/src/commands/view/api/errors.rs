//! `/api/errors`: one row of `fastbrdf errors` (a model against a model at one value of its
//! swept parameter), or the residuals of `fastbrdf errors --measured`.

use super::query::{Query, Reference, Response, check_unused, checked_id, one_model, spec_of};
use crate::CliError;
use crate::commands::view::state::{Measured, State};
use fastbrdf::{Given, ModelSpec};
use fastbrdf_analysis::errors;
use serde_json::{Value, json};

/// The errors row of `id` against `reference` at the swept parameter value `p`: exactly
/// `fastbrdf errors --model ID --reference REF --n|--m P --zone all` (the same checks first).
pub fn errors_row(
    id: &str,
    reference: &str,
    param: &str,
    p: f64,
) -> Result<errors::ErrorRow, CliError> {
    let spec = errors::Spec {
        model: id.into(),
        reference: reference.into(),
        param: param.into(),
        zone: fastbrdf::Zone::All,
    };
    spec.validate()?;
    for e in [id, reference] {
        ModelSpec::new(e, &[(param, Given::Num(p))])?;
    }
    let rows = errors::sweep(&spec, &[p], &|| {})?;
    Ok(rows[0])
}

/// The residuals of model `id` (`spec`: as it shades, from [`spec_of`]) against measured
/// data: what `fastbrdf errors --measured FILE --model ID` prints for the same parameters (the
/// same shading BRDF, `Problem` without a search, `measured_fit::fit` with its defaults).
pub fn measured_row(id: &str, spec: &ModelSpec, m: &Measured) -> Result<Value, CliError> {
    use fastbrdf_analysis::measured_fit::{self, Options, Problem};
    let brdf = spec.id();
    let problem =
        Problem::new(spec, false).map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
    let f = measured_fit::fit(&problem, &m.data, &Options::default(), &|_, _| {})
        .map_err(|e| CliError::input(format!("{}: {e}", m.path.display())))?;
    Ok(json!({
        "reference": m.name, "brdf": brdf, "ngan_l2": f.residuals.ngan_l2,
        "low_log": f.residuals.low_log, "max": f.residuals.max, "rho_d": f.rho_d,
        "rho_s": f.rho_s, "samples": m.data.len(),
    }))
}

/// `GET /api/errors?model=ID&ref=ID&n=N` (or `alpha=A`): one row of `fastbrdf errors --json`;
/// with `ref=` the measured file's name, the row of `fastbrdf errors --measured FILE --json`
/// (`NAME=VALUE` parameters as its `--param`).
pub fn errors_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    if let Some(r) = super::user::errors_user(state, q) {
        return r;
    }
    let id = checked_id(q.need("model")?)?;
    q.need("ref")?;
    if let Some(Reference::Measured(m)) = Reference::from_query(q, state)? {
        let all = q.params();
        check_unused(&[id], &all)?;
        let spec = spec_of(id, &all)?;
        one_model(id, &spec)?;
        let mut row = measured_row(id, &spec, m)?;
        row["model"] = json!(id);
        return Ok(Response::json(&row));
    }
    let reference = checked_id(q.need("ref")?)?;
    let (param, text) = match (q.get("n"), q.get("alpha")) {
        (Some(n), None) => ("n", n),
        (None, Some(a)) => ("alpha", a),
        _ => {
            return Err(CliError::input(
                "give n=N (lobes) or alpha=A (microfacet terms, Ward)",
            ));
        }
    };
    let p: f64 = text.parse().map_err(|_| {
        CliError::input(format!(
            "--{}: '{}' is not a number",
            if param == "n" { "n" } else { "m" },
            fastbrdf_io::shorten(text, 64)
        ))
    })?;
    let r = errors_row(id, reference, param, p)?;
    Ok(Response::json(&json!({
        "model": id, "reference": reference, "param": param, param: p, "zone": "all",
        "max_abs": r.max_abs, "max_abs_at": r.max_abs_at, "max_rel": r.max_rel,
        "max_rel_at": r.max_rel_at, "rms": r.rms, "samples": r.samples,
    })))
}
