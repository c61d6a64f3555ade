//! The users' models in the API (`fastbrdf view --model file:PATH`): their plots (every point
//! of a request in one batch, one GPU dispatch), their errors against a reference (a registry
//! model, another user's model) on a fixed grid of direction pairs, evaluated in batches, and
//! `/api/errors` when either side is a user's model.

use super::grids::{curve_theta, luminance, polar_pairs, slice_pairs};
use super::query::{
    Chosen, Query, Reference, Response, UserPick, check_unused, checked_id, one_model, spec_of,
};
use crate::CliError;
use crate::commands::view::state::State;
use crate::commands::view::users::UserModel;
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, UserBrdf};
use fastbrdf_gpu::user::{Language, UserShader};
use serde_json::{Value, json};
use std::sync::Arc;

/// The errors grid: incidence and exitance angles (this many, evenly in (0, 85] degrees) by
/// exitant azimuths (this many, evenly in [0, 360) degrees; the incident azimuth is 0).
pub const GRID_THETA: usize = 12;
pub const GRID_PHI: usize = 16;
/// Largest polar angle of the errors grid, degrees (grazing values of a shader are not
/// compared: a model's guard there is its own choice).
pub const GRID_MAX_DEG: f64 = 85.0;

type Pair = ([f64; 3], [f64; 3]);

/// The direction pairs the errors are computed at ([`GRID_THETA`], [`GRID_PHI`]).
pub fn grid_pairs() -> Vec<Pair> {
    let theta = |k: usize| ((k + 1) as f64 / GRID_THETA as f64 * GRID_MAX_DEG).to_radians();
    let mut out = Vec::with_capacity(GRID_THETA * GRID_THETA * GRID_PHI);
    for i in 0..GRID_THETA {
        let ti = theta(i);
        let wi = [ti.sin(), 0.0, ti.cos()];
        for o in 0..GRID_THETA {
            let to = theta(o);
            for p in 0..GRID_PHI {
                let phi = std::f64::consts::TAU * p as f64 / GRID_PHI as f64;
                out.push((wi, [to.sin() * phi.cos(), to.sin() * phi.sin(), to.cos()]));
            }
        }
    }
    out
}

/// `b` at every pair in one call: [`UserBrdf::channels`] numbers per pair. An evaluator's
/// error is the server's (the GPU failed: HTTP 500), naming the model.
pub fn eval_batch(b: &dyn UserBrdf, pairs: &[Pair]) -> Result<Vec<f64>, CliError> {
    let wi: Vec<[f64; 3]> = pairs.iter().map(|p| p.0).collect();
    let wo: Vec<[f64; 3]> = pairs.iter().map(|p| p.1).collect();
    let mut out = vec![0.0; pairs.len() * b.channels()];
    b.eval(&wi, &wo, &mut out).map_err(|e| CliError {
        code: crate::EXIT_CHECK_FAILED,
        message: format!("{}: {e}", b.name()),
    })?;
    Ok(out)
}

/// One number per pair of `channels`-wide values: the value, or the Rec. 709 luminance of an
/// RGB one (what the plots show, as of measured data).
fn grey(v: &[f64], channels: usize) -> Vec<f64> {
    if channels == 3 {
        v.chunks(3).map(|c| luminance([c[0], c[1], c[2]])).collect()
    } else {
        v.chunks(channels.max(1)).map(|c| c[0]).collect()
    }
}

/// The plots of a user's model at incidence `ti_deg` (polar, lobe at wi = wo, slice: one batch
/// evaluation), with `against`, its errors against the reference (null: none).
pub fn user_plots(p: &UserPick, ti_deg: f64, against: Value) -> Result<Value, CliError> {
    let polar = polar_pairs(ti_deg);
    let lobe: Vec<Pair> = curve_theta()
        .iter()
        .map(|t| {
            let r = t.to_radians();
            let w = [r.sin(), 0.0, r.cos()];
            (w, w)
        })
        .collect();
    let slice = slice_pairs();
    let all: Vec<Pair> = polar.iter().chain(&lobe).chain(&slice).copied().collect();
    let c = p.brdf.channels();
    let g = grey(&eval_batch(p.brdf.as_ref(), &all)?, c);
    let (a, b) = (polar.len(), polar.len() + lobe.len());
    Ok(json!({
        "id": p.model.name, "kind": "user",
        "channel": if c == 3 { "luminance" } else { "value" },
        "file": p.model.path.display().to_string(),
        "params": p.values.iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
        "polar": &g[..a], "lobe": &g[a..b], "slice": &g[b..],
        "error": Value::Null, "measured": Value::Null, "against": against,
    }))
}

/// The errors of `model` against `reference` (named `ref_name`) over [`grid_pairs`], each
/// evaluated in one batch: per pair and colour channel (a grey side's value in every
/// channel) the absolute difference, the relative one where the reference is above 0, and
/// the RMS of the differences. Pairs where either side is not finite are counted
/// (`non_finite`), not compared.
pub fn against(
    model: &dyn UserBrdf,
    reference: &dyn UserBrdf,
    ref_name: &str,
) -> Result<Value, CliError> {
    let pairs = grid_pairs();
    let m = eval_batch(model, &pairs)?;
    let r = eval_batch(reference, &pairs)?;
    let (cm, cr) = (model.channels(), reference.channels());
    let c = cm.max(cr);
    let (mut max_abs, mut abs_at) = (0.0f64, 0usize);
    let (mut max_rel, mut rel_at) = (None::<f64>, 0usize);
    let (mut sum2, mut n, mut non_finite, mut peak) = (0.0, 0usize, 0usize, 0.0f64);
    for k in 0..pairs.len() {
        for j in 0..c {
            let (a, b) = (m[k * cm + j.min(cm - 1)], r[k * cr + j.min(cr - 1)]);
            if !a.is_finite() || !b.is_finite() {
                non_finite += 1;
                continue;
            }
            let d = (a - b).abs();
            peak = peak.max(b.abs());
            sum2 += d * d;
            n += 1;
            if d > max_abs {
                (max_abs, abs_at) = (d, k);
            }
            if b > 0.0 && max_rel.is_none_or(|x| d / b > x) {
                (max_rel, rel_at) = (Some(d / b), k);
            }
        }
    }
    let at = |k: usize| json!({"wi": pairs[k].0, "wo": pairs[k].1});
    Ok(json!({
        "reference": ref_name, "samples": pairs.len(), "channels": c,
        "max_abs": max_abs, "max_abs_at": at(abs_at),
        "max_rel": max_rel, "max_rel_at": max_rel.map(|_| at(rel_at)),
        "rms": if n > 0 { (sum2 / n as f64).sqrt() } else { 0.0 },
        "reference_peak": peak, "non_finite": non_finite,
    }))
}

/// A registry spec as a batch BRDF (None: not a full BRDF).
fn builtin(spec: &fastbrdf::ModelSpec) -> Option<Arc<dyn UserBrdf>> {
    Builtin::new(spec, Strategy::Auto)
        .ok()
        .map(|b| Arc::new(b) as Arc<dyn UserBrdf>)
}

/// The reference of a query as a batch BRDF: a registry model (as it shades) or a user's
/// model; None for measured data or none.
pub fn reference_brdf(c: &Chosen) -> Option<Arc<dyn UserBrdf>> {
    match &c.reference {
        Some(Reference::Model(id)) => c
            .models
            .iter()
            .find(|(m, _)| m == id)
            .and_then(|(_, s)| builtin(s)),
        Some(Reference::User(_)) => c
            .ref_user
            .as_ref()
            .map(|p| p.brdf.clone() as Arc<dyn UserBrdf>),
        _ => None,
    }
}

/// The albedo entry of a user's model at `angles` (degrees): `fastbrdf albedo --model
/// file:PATH`'s curve, by conform's batched quadrature (the largest channel at each angle),
/// with the white-furnace verdict at conform's tolerance; `error` null (the quadrature
/// refines until two rounds agree, it has no per-angle estimate).
pub fn albedo(
    name: &str,
    brdf: &fastbrdf_gpu::user::GpuBrdf,
    angles: &[f64],
) -> Result<Value, CliError> {
    use fastbrdf_analysis::conform;
    let cfg = conform::Config::ci();
    let mut values = Vec::with_capacity(angles.len());
    for &t in angles {
        let (a, _) = conform::albedo(brdf, t, &cfg).map_err(|e| CliError {
            code: crate::EXIT_CHECK_FAILED,
            message: format!("{name}: {e}"),
        })?;
        values.push(a.iter().copied().fold(f64::NAN, f64::max));
    }
    let tol = cfg.energy_tol;
    let worst = (0..angles.len())
        .max_by(|&a, &b| values[a].total_cmp(&values[b]))
        .expect("angles");
    Ok(json!({"id": name, "albedo": {
        "brdf": "user", "theta_deg": angles, "albedo": values,
        "error": vec![Value::Null; angles.len()], "estimate": false,
        "claims_energy": true, "conserves": values.iter().all(|v| *v <= 1.0 + tol),
        "tolerance": tol, "worst_theta_deg": angles[worst], "worst_albedo": values[worst],
    }}))
}

/// `GET /api/errors?model=A&ref=B&NAME=VALUE...` when A or B is a user's model: [`against`]
/// as `{model, reference, max_abs, max_abs_at, max_rel, max_rel_at, rms, samples, ...}`.
/// None when neither is one.
pub fn errors_user(state: &State, q: &Query) -> Option<Result<Response, CliError>> {
    let (Ok(model), Ok(r)) = (q.need("model"), q.need("ref")) else {
        return None;
    };
    let (mu, ru) = (state.user(model), state.user(r));
    if mu.is_none() && ru.is_none() {
        return None;
    }
    Some((|| {
        if state.measured.as_ref().is_some_and(|m| m.name == r) {
            return Err(CliError::input(format!(
                "ref {r}: a user's model is not compared with measured data in the explorer"
            )));
        }
        let all = q.params();
        let users: Vec<_> = [&mu, &ru].into_iter().flatten().collect();
        let registry: Vec<&'static str> = [(model, &mu), (r, &ru)]
            .into_iter()
            .filter(|(_, u)| u.is_none())
            .map(|(id, _)| checked_id(id))
            .collect::<Result<_, _>>()?;
        let to_registry: Vec<(String, String)> = all
            .iter()
            .filter(|(k, _)| !users.iter().any(|u| u.declares(k)))
            .cloned()
            .collect();
        if registry.is_empty() {
            if let Some((k, _)) = to_registry.first() {
                return Err(fastbrdf::Error::UnknownParam {
                    model: format!("{model},{r}"),
                    param: fastbrdf_io::shorten(k, 64),
                }
                .into());
            }
        } else {
            check_unused(&registry, &to_registry)?;
        }
        let side = |id: &str, u: Option<&UserModel>| match u {
            Some(u) => {
                let own: Vec<(String, String)> =
                    all.iter().filter(|(k, _)| u.declares(k)).cloned().collect();
                Ok(u.instance(&own)? as Arc<dyn UserBrdf>)
            }
            None => {
                let id = checked_id(id)?;
                let spec = spec_of(id, &to_registry)?;
                one_model(id, &spec)?;
                builtin(&spec).ok_or_else(|| {
                    CliError::input(format!("{id}: not a BRDF on its own (shade it first)"))
                })
            }
        };
        let (a, b) = (side(model, mu.as_deref())?, side(r, ru.as_deref())?);
        let mut v = against(a.as_ref(), b.as_ref(), r)?;
        v["model"] = json!(model);
        Ok(Response::json(&v))
    })())
}

/// `GET /api/shader?model=NAME` of a user's model: `lang=wgsl` the WGSL it runs as
/// (`UserShader::wgsl`), any other language the file as written.
pub fn user_shader(state: &State, q: &Query) -> Option<Result<Response, CliError>> {
    let u = state.user(q.get("model")?)?;
    let text = match q.get("lang").unwrap_or("wgsl") {
        "wgsl" => u.shader.wgsl().map_err(|e| CliError::input(e.message)),
        _ => Ok(u.shader.source().to_string()),
    };
    Some(text.map(|t| Response {
        status: 200,
        content_type: "text/plain; charset=utf-8",
        body: t.into_bytes(),
    }))
}

/// Largest file `POST /api/user` takes, bytes (the server reads no more: 413).
pub const MAX_UPLOAD: usize = 256 * 1024;
/// Longest name an upload may have.
const MAX_NAME: usize = 64;

/// The name of an upload (`?name=FILE.brdf|.wgsl|.glsl`), checked: 1 to [`MAX_NAME`]
/// letters, digits, `.`, `_`, `-` or `+`, not starting with `.`, ending in an extension that
/// says the language.
fn upload_name(q: &Query) -> Result<(&str, Language), CliError> {
    let name = q.get("name").ok_or_else(|| {
        CliError::input("missing query parameter 'name': the file's name, e.g. ?name=my.wgsl")
    })?;
    let ok = !name.is_empty()
        && name.len() <= MAX_NAME
        && !name.starts_with('.')
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"._-+".contains(&b));
    if !ok {
        return Err(CliError::input(format!(
            "name '{}': 1 to {MAX_NAME} letters, digits, '.', '_', '-' or '+', not starting \
             with '.' (e.g. my_ggx.wgsl)",
            fastbrdf_io::shorten(name, MAX_NAME)
        )));
    }
    let lang = Language::from_path(std::path::Path::new(name)).ok_or_else(|| {
        CliError::input(format!(
            "name {name}: unknown shader language: the name must end in .brdf (BRDF \
             Explorer), .wgsl or .glsl"
        ))
    })?;
    Ok((name, lang))
}

/// The line and column a compile error of file `origin` names (`ORIGIN:LINE:COL: ...`).
fn located(message: &str, origin: &str) -> (Option<u64>, Option<u64>) {
    let Some(rest) = message
        .strip_prefix(origin)
        .and_then(|r| r.strip_prefix(':'))
    else {
        return (None, None);
    };
    let mut parts = rest.splitn(3, ':');
    let line = parts.next().and_then(|l| l.parse().ok());
    let column = line.and(parts.next().and_then(|c| c.parse().ok()));
    (line, column)
}

/// A user's error of upload `name` as 400 `{"error", "line", "column"}` (line and column:
/// null when the message names none); the GPU's as 500.
fn upload_error(e: CliError, name: &str) -> Response {
    if e.code != crate::EXIT_INPUT {
        return Response::from(e);
    }
    let (line, column) = located(&e.message, name);
    Response {
        status: 400,
        content_type: "application/json",
        body: serde_json::to_vec(&json!({"error": e.message, "line": line, "column": column}))
            .expect("serialisable"),
    }
}

/// `POST /api/user?name=FILE.brdf|.wgsl|.glsl` with the file's text as the body (at most
/// [`MAX_UPLOAD`] bytes, UTF-8): compiled as `--model file:FILE` is at start-up (naga, then a
/// GPU pipeline), added as user's model `file:FILE` (replacing an earlier upload of that
/// name; at most [`MAX_UPLOADS`](crate::commands::view::state::MAX_UPLOADS), the oldest
/// dropped) and answered with its `/api/models` entry. A compile error is 400 with the message
/// `FILE:LINE:COL: ...` and its `line` and `column`.
pub fn upload(state: &State, q: &Query, body: &[u8]) -> Result<Response, CliError> {
    let (name, lang) = upload_name(q)?;
    if body.len() > MAX_UPLOAD {
        return Ok(Response::error(
            413,
            &format!(
                "{name}: {} bytes; an upload is at most {MAX_UPLOAD} bytes",
                body.len()
            ),
        ));
    }
    let text = std::str::from_utf8(body).map_err(|e| {
        CliError::input(format!("{name}: not UTF-8 text (byte {})", e.valid_up_to()))
    })?;
    if text.trim().is_empty() {
        return Err(CliError::input(format!("{name}: the file is empty")));
    }
    let shader = match UserShader::parse(text, name, lang) {
        Ok(s) => s,
        Err(e) => return Ok(upload_error(user_cli_error(e), name)),
    };
    let id = format!("{}{name}", crate::model_args::USER_PREFIX);
    let gpu = state.gpu(&id)?;
    let model = UserModel::new(id, name.into(), shader, Vec::new(), gpu, true);
    match model {
        Ok(m) => Ok(Response::json(&state.add_upload(m)?.entry_json())),
        Err(e) => Ok(upload_error(e, name)),
    }
}

/// A [`fastbrdf_gpu::user::UserError`] as the CLI reports it (input: exit 2, GPU: exit 1).
fn user_cli_error(e: fastbrdf_gpu::user::UserError) -> CliError {
    CliError {
        code: match e.kind {
            fastbrdf_gpu::user::UserErrorKind::Input => crate::EXIT_INPUT,
            fastbrdf_gpu::user::UserErrorKind::Gpu => crate::EXIT_CHECK_FAILED,
        },
        message: e.message,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn located_reads_line_and_column_after_the_name() {
        assert_eq!(
            super::located("a.wgsl:3:14: error: x", "a.wgsl"),
            (Some(3), Some(14))
        );
        assert_eq!(super::located("a.wgsl:7: error", "a.wgsl"), (Some(7), None));
        assert_eq!(super::located("a.wgsl: no brdf", "a.wgsl"), (None, None));
        assert_eq!(super::located("b.wgsl:3:1: x", "a.wgsl"), (None, None));
    }
}
