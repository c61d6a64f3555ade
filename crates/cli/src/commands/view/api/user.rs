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
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, UserBrdf};
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
        let side = |id: &str, u: Option<&crate::commands::view::users::UserModel>| match u {
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
