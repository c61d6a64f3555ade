//! `/api/plots` and `/api/albedo`: the polar plot, the theta_h x theta_d slice, the lobe and
//! error curves (what `fastbrdf errors` compares) and the directional albedo of each model,
//! every number from the library functions the CLI commands call.

use super::errors::{errors_row, measured_row};
use super::grids::{POLAR_POINTS, SLICE, curve_theta, luminance, polar_pairs, slice_pairs};
use super::query::{Query, Reference, Response, one_model, theta_i};
use super::user;
use crate::CliError;
use crate::commands::common::numbers::swept;
use crate::commands::view::state::{Measured, State};
use crate::model_args::{self, asked_pairs};
use fastbrdf::params::ParamKind;
use fastbrdf::{Given, Kind, ModelSpec};
use fastbrdf_analysis::albedo;
use serde_json::{Value, json};
use std::time::Instant;

/// Albedo angles: fixed on the server, not requested.
const ALBEDO_ANGLES: [f64; 10] = [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0];
/// Relative tolerance of the albedo quadrature in the explorer (the CLI uses 1e-7; 1e-3 keeps
/// a slider move within its time budget and is below the plot's resolution; the furnace
/// verdict allows each angle's own error estimate, as the CLI's does).
const ALBEDO_TOL: f64 = 1e-3;

fn eval_brdf(m: &fastbrdf::Model<f64>, wi: [f64; 3], wo: [f64; 3]) -> f64 {
    match m {
        fastbrdf::Model::Brdf(b) => b.eval(wi, wo),
        _ => 0.0,
    }
}

/// The in-plane polar plot of `f` at incidence `ti_deg` ([`polar_pairs`]).
fn polar_of(f: impl Fn([f64; 3], [f64; 3]) -> f64, ti_deg: f64) -> Vec<f64> {
    polar_pairs(ti_deg)
        .into_iter()
        .map(|(a, b)| f(a, b))
        .collect()
}

/// The theta_h x theta_d slice of `f` ([`slice_pairs`]).
fn slice_of(f: impl Fn([f64; 3], [f64; 3]) -> f64) -> Vec<f64> {
    slice_pairs().into_iter().map(|(a, b)| f(a, b)).collect()
}

/// The plots of the measured reference: polar and slice of its luminance, its "lobe" as a
/// BRDF's (the value at wi = wo against theta), no error curves (it is the reference).
fn measured_plots(m: &Measured, ti_deg: f64) -> Value {
    let f = |wi: [f64; 3], wo: [f64; 3]| luminance(m.brdf.eval_rgb(wi, wo));
    let lobe: Vec<f64> = curve_theta()
        .iter()
        .map(|t| {
            let r = t.to_radians();
            let w = [r.sin(), 0.0, r.cos()];
            f(w, w)
        })
        .collect();
    json!({
        "id": m.name, "kind": "measured", "channel": "luminance", "params": [],
        "polar": polar_of(f, ti_deg), "lobe": lobe, "error": Value::Null,
        "measured": Value::Null, "slice": slice_of(f),
    })
}

/// The plots of one model `id` (`spec`: as it shades, from [`spec_of`](super::query::spec_of);
/// docs/book/src/explorer.md's JSON API gives the shape).
fn plots_of(
    id: &'static str,
    spec: &ModelSpec,
    reference: Option<&Reference>,
    ti_deg: f64,
) -> Result<Value, CliError> {
    let m = spec.model::<f64>()?;
    let polar = polar_of(|wi, wo| eval_brdf(&m, wi, wo), ti_deg);
    let slice = slice_of(|wi, wo| eval_brdf(&m, wi, wo));
    // The model's own scalar curve at the swept parameter (what `errors` compares).
    let e = fastbrdf::registry::find(id)?;
    let kind = e.info.kind;
    let swept_here = swept(e);
    let pnum: Option<f64> = swept_here.and_then(|s| match spec.get(s) {
        Some(Given::Num(x)) => Some(*x),
        Some(_) => None,
        None => match e.info.params.iter().find(|x| x.name == s).map(|x| x.kind) {
            Some(ParamKind::Number { default, .. }) => default,
            _ => None,
        },
    });
    let theta_h = curve_theta();
    let to_x = |deg: f64| {
        if kind == Kind::Brdf {
            deg.to_radians()
        } else {
            deg.to_radians().cos()
        }
    };
    let x_to_deg = |x: f64| {
        if kind == Kind::Brdf {
            x.to_degrees()
        } else {
            x.clamp(-1.0, 1.0).acos().to_degrees()
        }
    };
    let (lobe, error) = match (swept_here, pnum) {
        (Some(s), Some(pv)) => {
            let c = fastbrdf::accuracy::Curve::new(id, s, pv)?;
            let lobe: Vec<f64> = theta_h.iter().map(|&t| c.at(to_x(t))).collect();
            let error = match reference.and_then(Reference::model) {
                Some(r)
                    if r != id
                        && fastbrdf::registry::find(r).ok().and_then(swept) == Some(s)
                        && fastbrdf::registry::find(r)?.info.kind == kind =>
                {
                    let rc = fastbrdf::accuracy::Curve::new(r, s, pv)?;
                    let rv: Vec<f64> = theta_h.iter().map(|&t| rc.at(to_x(t))).collect();
                    let peak = rv
                        .iter()
                        .copied()
                        .fold(0.0, f64::max)
                        .max(f64::MIN_POSITIVE);
                    let scale = if kind == Kind::Lobe { 1.0 } else { peak };
                    let abs: Vec<f64> =
                        lobe.iter().zip(&rv).map(|(m, r)| (m - r) / scale).collect();
                    let rel: Vec<Option<f64>> = lobe
                        .iter()
                        .zip(&rv)
                        .map(|(m, r)| {
                            if *r > 0.0 {
                                Some((m - r).abs() / r)
                            } else {
                                None
                            }
                        })
                        .collect();
                    let row = errors_row(id, r, s, pv)?;
                    json!({
                        "reference": r, "param": s, "value": pv, "abs": abs, "rel": rel,
                        "max_abs": row.max_abs, "max_abs_at": row.max_abs_at,
                        "max_abs_at_deg": x_to_deg(row.max_abs_at),
                        "max_rel": row.max_rel, "max_rel_at": row.max_rel_at,
                        "max_rel_at_deg": x_to_deg(row.max_rel_at), "rms": row.rms,
                    })
                }
                _ => Value::Null,
            };
            (json!(lobe), error)
        }
        _ => (Value::Null, Value::Null),
    };
    // Against measured data: the residuals of `fastbrdf errors --measured`.
    let measured = match reference {
        Some(Reference::Measured(mm)) => measured_row(id, spec, mm)?,
        _ => Value::Null,
    };
    Ok(json!({
        "id": id, "kind": kind.name(),
        "params": asked_pairs(id, spec).iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
        "polar": polar, "lobe": lobe, "error": error, "measured": measured,
        "slice": slice,
    }))
}

/// The directional albedo of one model and its white-furnace verdict, as `fastbrdf albedo`
/// computes them (lobes as energy-normalised `phong`, its defaults); null for a distribution
/// (not a BRDF on its own). `quick`: `albedo::curve_quick`'s estimate, without a verdict or
/// error estimates (`conserves`, `worst_*`, `error` null; `estimate` true).
fn albedo_of(id: &'static str, spec: &ModelSpec, quick: bool) -> Result<Value, CliError> {
    let own = model_args::unshaded(id, spec)?;
    let albedo_v = match albedo::target(&own, "phong", "energy") {
        // A distribution is not a BRDF on its own: no albedo.
        Err(fastbrdf::Error::WrongKind { .. }) => Value::Null,
        Err(e) => return Err(e.into()),
        Ok(t) => {
            // The quick estimate: a fixed quadrature on the same angles (a looser tolerance
            // of the adaptive one is no faster: its initial panels are most of the cost).
            let rows = if quick {
                albedo::curve_quick(&t, &ALBEDO_ANGLES)?
            } else {
                albedo::curve(&t, &ALBEDO_ANGLES, ALBEDO_TOL)?
            };
            let (holds, worst) = albedo::furnace(&rows, t.furnace_tolerance());
            let (holds, worst) = if quick {
                (None, None)
            } else {
                (Some(holds), worst)
            };
            json!({
                "brdf": t.id(), "theta_deg": ALBEDO_ANGLES, "albedo": rows.iter().map(|r| r.albedo).collect::<Vec<_>>(),
                "error": rows.iter().map(|r| r.error).collect::<Vec<_>>(),
                "estimate": quick,
                "claims_energy": t.claims_energy, "conserves": holds, "tolerance": t.furnace_tolerance(),
                "worst_theta_deg": worst.map(|w| w.theta_deg), "worst_albedo": worst.map(|w| w.albedo),
            })
        }
    };
    Ok(json!({"id": id, "albedo": albedo_v}))
}

/// `GET /api/albedo?models=A,B&ref=R&NAME=VALUE...[&quick=1]`: directional albedo against
/// incidence and the white-furnace verdict of each model (apart from /api/plots: the
/// quadrature is the slow part, so the other plots need not wait for it). `quick=1`: the
/// estimate the page draws first (no verdict).
pub fn albedo_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let t = Instant::now();
    let quick = match q.get("quick") {
        None | Some("0") => false,
        Some("1") => true,
        Some(v) => {
            return Err(CliError::input(format!(
                "quick '{}': expected 0 or 1",
                fastbrdf_io::shorten(v, 64)
            )));
        }
    };
    // Shadowing, Fresnel and split-sum terms have no albedo: skipped.
    let c = super::kinds::shaded(state, q)?;
    let (models, reference) = (&c.models, &c.reference);
    for (id, spec) in models {
        one_model(id, spec)?;
    }
    use rayon::prelude::*;
    let mut out: Vec<Value> = models
        .par_iter()
        .map(|(id, spec)| albedo_of(id, spec, quick))
        .collect::<Result<_, _>>()?;
    for u in &c.users {
        out.push(user::albedo(&u.model.name, &u.brdf, &ALBEDO_ANGLES)?);
    }
    if let Some(u) = &c.ref_user {
        out.insert(0, user::albedo(&u.model.name, &u.brdf, &ALBEDO_ANGLES)?);
    }
    if let Some(Reference::Measured(m)) = reference {
        out.insert(
            0,
            json!({"id": m.name, "albedo": Value::Null,
                   "why": "not computed for measured data (the explorer integrates registry models only)"}),
        );
    }
    Ok(Response::json(&json!({
        "models": out,
        "estimate": quick,
        "ms": t.elapsed().as_secs_f64() * 1e3,
    })))
}

/// `GET /api/plots?models=A,B&ref=R&theta=DEG&NAME=VALUE...`: every plot's numbers.
pub fn plots(state: &State, q: &Query) -> Result<Response, CliError> {
    let t = Instant::now();
    // The terms (shadowing, Fresnel, split-sum) apart: their curves are `terms`.
    let split = super::kinds::split(state, q)?;
    let c = super::kinds::shaded(state, q)?;
    let (models, reference) = (&c.models, &c.reference);
    for (id, spec) in models {
        one_model(id, spec)?;
    }
    let ti = theta_i(q)?;
    let terms = super::kinds::terms(&split, q, ti)?;
    // A user's model or a user's reference: errors from batched evaluations on a grid.
    let ref_brdf = user::reference_brdf(&c);
    let user_ref = matches!(reference, Some(Reference::User(_)));
    let against = |b: Option<std::sync::Arc<dyn fastbrdf::user::UserBrdf>>, id: &str| match (
        &ref_brdf, b, reference,
    ) {
        (Some(r), Some(b), Some(rf)) if rf.name() != id => {
            user::against(b.as_ref(), r.as_ref(), rf.name())
        }
        _ => Ok(Value::Null),
    };
    // One model per task: the two cores of a slider move's budget.
    use rayon::prelude::*;
    let mut out: Vec<Value> = models
        .par_iter()
        .map(|(id, spec)| {
            let mut v = plots_of(id, spec, reference.as_ref(), ti)?;
            if user_ref {
                let b = fastbrdf::user::Builtin::new(spec, fastbrdf::sample::Strategy::Auto)
                    .ok()
                    .map(|b| {
                        std::sync::Arc::new(b) as std::sync::Arc<dyn fastbrdf::user::UserBrdf>
                    });
                v["against"] = against(b, id)?;
            }
            Ok::<_, CliError>(v)
        })
        .collect::<Result<_, _>>()?;
    // The users' models: each one batch of points (a GPU dispatch), one after another.
    for u in &c.users {
        let b = u.brdf.clone() as std::sync::Arc<dyn fastbrdf::user::UserBrdf>;
        let a = against(Some(b), &u.model.name)?;
        out.push(user::user_plots(u, ti, a)?);
    }
    if let Some(u) = &c.ref_user {
        out.insert(0, user::user_plots(u, ti, Value::Null)?);
    }
    if let Some(Reference::Measured(m)) = reference {
        out.insert(0, measured_plots(m, ti));
    }
    let polar_t: Vec<f64> = (0..POLAR_POINTS)
        .map(|k| -90.0 + 180.0 * k as f64 / (POLAR_POINTS - 1) as f64)
        .collect();
    let theta_h = curve_theta();
    Ok(Response::json(&json!({
        "theta_i_deg": ti,
        "reference": reference.as_ref().map(Reference::name),
        "reference_kind": reference.as_ref().map(Reference::kind),
        "polar_theta_deg": polar_t,
        "curve_theta_deg": theta_h,
        "slice_size": SLICE,
        "models": out,
        "terms": terms,
        "ms": t.elapsed().as_secs_f64() * 1e3,
    })))
}
