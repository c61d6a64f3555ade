//! The JSON API of `fastbrdf view`: pure functions from a request (path and query) to a
//! response, so that the server loop, the tests and the benchmark see the same thing. Every
//! number is computed by the library functions the CLI commands call (`errors::at` as
//! `fastbrdf errors`, `albedo::curve`/`furnace` as `fastbrdf albedo`, the CPU renderer and
//! `compare::metrics` as `fastbrdf compare`, `export_form` as `fastbrdf shader`), and every
//! refusal carries the message the CLI would print for the same input.

use super::{Measured, State};
use crate::CliError;
use crate::commands::render::params_for;
use fastbrdf::Kind;
use fastbrdf::params::ParamKind;
use fastbrdf_analysis::{albedo, errors};
use fastbrdf_render::compare;
use fastbrdf_render::film::png_bytes;
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Light, Specular};
use fastbrdf_render::setup;
use serde_json::{Value, json};
use std::sync::Arc;
use std::time::Instant;

/// An HTTP answer: status, content type and body.
pub struct Response {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
}

impl Response {
    pub fn json(v: &Value) -> Self {
        Self {
            status: 200,
            content_type: "application/json",
            body: serde_json::to_vec(v).expect("serialisable"),
        }
    }
    /// `{"error": message}` with `status`.
    pub fn error(status: u16, message: &str) -> Self {
        Self {
            status,
            content_type: "application/json",
            body: serde_json::to_vec(&json!({ "error": message })).expect("serialisable"),
        }
    }
}

impl From<CliError> for Response {
    fn from(e: CliError) -> Self {
        // Exit code 2 (bad input) is the client's fault; anything else is the server's.
        Response::error(
            if e.code == crate::EXIT_INPUT {
                400
            } else {
                500
            },
            &e.message,
        )
    }
}

/// Largest picture side the server renders, samples per pixel axis, and models per request:
/// a request cannot ask for more memory or time than these allow.
pub const MAX_SIZE: u32 = 1024;
pub const MAX_SPP: u32 = 4;
pub const MAX_MODELS: usize = 6;
/// Points of the in-plane polar plot, of the lobe and error curves, albedo angles, and the
/// side of the theta_h x theta_d slice: fixed on the server, not requested.
const POLAR_POINTS: usize = 181;
const CURVE_POINTS: usize = 256;
const ALBEDO_ANGLES: [f64; 10] = [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0];
const SLICE: usize = 48;
/// Relative tolerance of the albedo quadrature in the explorer (the CLI uses 1e-7; 1e-3 keeps
/// a slider move within its time budget and is below the plot's resolution; the furnace
/// verdict allows each angle's own error estimate, as the CLI's does).
const ALBEDO_TOL: f64 = 1e-3;

/// Keys of the query that are not model parameters.
const RESERVED: [&str; 12] = [
    "models", "ref", "theta", "lang", "size", "spp", "mesh", "light", "client", "gen", "model",
    "quick",
];

/// The decoded query string, in order.
pub struct Query(pub Vec<(String, String)>);

impl Query {
    /// Parses `a=1&b=x%20y` (percent-decoding, `+` as space); malformed escapes are kept as
    /// they are (the value is then refused by whoever reads it).
    pub fn parse(q: &str) -> Self {
        Self(
            q.split('&')
                .filter(|s| !s.is_empty())
                .map(|kv| {
                    let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
                    (decode(k), decode(v))
                })
                .collect(),
        )
    }
    pub fn get(&self, key: &str) -> Option<&str> {
        self.0
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    fn need(&self, key: &str) -> Result<&str, CliError> {
        self.get(key)
            .ok_or_else(|| CliError::input(format!("missing query parameter '{key}'")))
    }
    /// The model parameters: every key that is not reserved, as `--param NAME=VALUE`.
    pub fn params(&self) -> Vec<(String, String)> {
        self.0
            .iter()
            .filter(|(k, _)| !RESERVED.contains(&k.as_str()))
            .cloned()
            .collect()
    }
}

/// Percent-decoding of one query component.
pub fn decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < b.len() => {
                match u8::from_str_radix(std::str::from_utf8(&b[i + 1..i + 3]).unwrap_or("zz"), 16)
                {
                    Ok(x) => {
                        out.push(x);
                        i += 2;
                    }
                    Err(_) => out.push(b'%'),
                }
            }
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// What the approximations are measured against: the one place that knows the kinds of
/// reference (`ref=` in every query).
pub enum Reference<'a> {
    /// A registry model, with the same parameters as the others.
    Model(&'static str),
    /// The server's `--measured` file (`ref=` its name).
    Measured(&'a Measured),
}

impl<'a> Reference<'a> {
    fn from_query(q: &Query, state: &'a State) -> Result<Option<Self>, CliError> {
        match q.get("ref") {
            None | Some("") => Ok(None),
            Some(r) => match &state.measured {
                Some(m) if m.name == r => Ok(Some(Reference::Measured(m))),
                _ => Ok(Some(Reference::Model(checked_id(r)?))),
            },
        }
    }
    /// What the page and the JSON call it: the model id, or the measured file's name.
    pub fn name(&self) -> &str {
        match self {
            Reference::Model(id) => id,
            Reference::Measured(m) => &m.name,
        }
    }
    /// The registry model, if the reference is one.
    fn model(&self) -> Option<&'static str> {
        match self {
            Reference::Model(id) => Some(id),
            Reference::Measured(_) => None,
        }
    }
}

/// A registry id the explorer can show (something to shade with), with the registry's message
/// for an unknown one.
fn checked_id(id: &str) -> Result<&'static str, CliError> {
    let e = fastbrdf::registry::find(id)?;
    fastbrdf::registry::shading_brdf(e.info.id, &[])?;
    Ok(e.info.id)
}

/// The chosen model ids (`models=a,b`), checked, at most [`MAX_MODELS`].
fn model_ids(q: &Query) -> Result<Vec<&'static str>, CliError> {
    let ids: Vec<&str> = q
        .need("models")?
        .split(',')
        .filter(|s| !s.is_empty())
        .collect();
    if ids.is_empty() || ids.len() > MAX_MODELS {
        return Err(CliError::input(format!(
            "models: give 1 to {MAX_MODELS} comma-separated model ids"
        )));
    }
    ids.into_iter().map(checked_id).collect()
}

/// Parameters for model `id`: those of `all` it takes (as `fastbrdf compare` gives them),
/// validated by the registry (its messages: out of range, not a number, unknown choice).
fn params_of(id: &str, all: &[(String, String)]) -> Result<Vec<(String, String)>, CliError> {
    let p = params_for(id, all)?;
    // The model's own parameters first, so that a message names the model chosen (not the
    // BRDF a lobe or a distribution is shaded as).
    let e = fastbrdf::registry::find(id)?;
    let own: Vec<(&str, &str)> = p
        .iter()
        .filter(|(k, _)| e.info.params.iter().any(|s| s.name == k))
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect();
    fastbrdf::registry::plan(id, &own)?;
    let (brdf, bp) = fastbrdf::registry::shading_brdf(id, &p)?;
    let given: Vec<(&str, &str)> = bp.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    fastbrdf::registry::plan(brdf, &given)?;
    Ok(p)
}

/// Every parameter of the query must be taken by at least one chosen model.
fn check_unused(ids: &[&str], all: &[(String, String)]) -> Result<(), CliError> {
    for (k, _) in all {
        let mut used = false;
        for id in ids {
            if params_for(id, &[(k.clone(), String::new())])?.len() == 1 {
                used = true;
            }
        }
        if !used {
            return Err(fastbrdf::Error::UnknownParam {
                model: ids.join(","),
                param: fastbrdf_io::shorten(k, 64),
            }
            .into());
        }
    }
    Ok(())
}

fn theta_i(q: &Query) -> Result<f64, CliError> {
    let t = q.get("theta").unwrap_or("30");
    let v: f64 = t.parse().map_err(|_| {
        CliError::input(format!(
            "theta '{}': not a number",
            fastbrdf_io::shorten(t, 64)
        ))
    })?;
    if !(0.0..90.0).contains(&v) {
        return Err(CliError::input(format!(
            "theta {v}: the incidence angle must be in [0, 90) degrees"
        )));
    }
    Ok(v)
}

/// `GET /api/models`: every model the explorer can show, with its parameters.
pub fn models(state: &State) -> Response {
    let list: Vec<Value> = fastbrdf::registry::all()
        .iter()
        .filter(|e| fastbrdf::registry::shading_brdf(e.info.id, &[]).is_ok())
        .map(|e| {
            let params: Vec<Value> = e
                .info
                .params
                .iter()
                .map(|p| match p.kind {
                    ParamKind::Number {
                        min, max, default, ..
                    } => json!({
                        "name": p.name, "type": "number", "min": min, "max": max,
                        "default": default, "doc": p.doc,
                        // Exponents and roughness span decades: their sliders are logarithmic.
                        "log": min > 0.0 && max / min >= 50.0,
                    }),
                    ParamKind::Choice { options, default } => {
                        let mut v = json!({
                            "name": p.name, "type": "choice", "options": options.names(),
                            "default": default, "doc": p.doc,
                        });
                        // As `fastbrdf models --json`: a default that follows another choice
                        // (cook-torrance's g follows d), so the page's menu shows what is used.
                        if let Some(f) = options.follow() {
                            let defaults: serde_json::Map<String, Value> = f
                                .defaults
                                .iter()
                                .map(|(k, d)| ((*k).to_string(), json!(d)))
                                .collect();
                            v["default_follows"] = json!({"param": f.param, "defaults": defaults});
                        }
                        v
                    }
                })
                .collect();
            json!({
                "id": e.info.id, "kind": e.info.kind.name(), "params": params,
                "formula": e.info.formula, "source": e.info.source,
                "bounds": e.info.bounds, "ops": e.info.ops,
                "swept": swept_param(e.info.id),
                "cost": state.cost(e.info.id),
            })
        })
        .collect();
    let materials: Vec<&str> = fastbrdf_analysis::materials::all()
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    Response::json(&json!({
        "models": list,
        "materials": materials,
        "mesh": state.mesh_name,
        "bench": state.bench_source,
        "measured": state.measured.as_ref().map(|m| json!({
            "name": m.name, "file": m.path.display().to_string(), "samples": m.data.len(),
        })),
        "limits": {"size": MAX_SIZE, "spp": MAX_SPP, "models": MAX_MODELS},
        "langs": ["wgsl", "glsl", "hlsl", "msl", "brdf-explorer"],
    }))
}

/// The parameter `fastbrdf errors` sweeps for model `id` (`n` for lobes, `alpha` otherwise),
/// if it takes one.
fn swept_param(id: &str) -> Option<&'static str> {
    let e = fastbrdf::registry::find(id).ok()?;
    ["n", "alpha"]
        .into_iter()
        .find(|p| e.info.sweep_range(p).is_some())
}

/// `GET /api/material?name=NAME&model=ID`: the parameters a MERL material's fit supplies.
pub fn material(q: &Query) -> Result<Response, CliError> {
    let id = checked_id(q.need("model")?)?;
    let p = crate::commands::materials::with_material(Some(q.need("name")?), id, &[])?;
    let obj: serde_json::Map<String, Value> = p
        .into_iter()
        .map(|(k, v)| {
            let val = v.parse::<f64>().map_or_else(|_| json!(v), |x| json!(x));
            (k, val)
        })
        .collect();
    Ok(Response::json(&json!({ "model": id, "params": obj })))
}

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
        fastbrdf::registry::build::<f64>(e, &[(param, &crate::commands::analysis::num(p))])?;
    }
    let rows = errors::sweep(&spec, &[p], &|| {})?;
    Ok(rows[0])
}

/// The residuals of model `id` (parameters `p`, as `params_of` gives them) against measured
/// data: what `fastbrdf errors --measured FILE --model ID` prints for the same parameters (the
/// same shading BRDF, `Problem` without a search, `measured_fit::fit` with its defaults).
pub fn measured_row(id: &str, p: &[(String, String)], m: &Measured) -> Result<Value, CliError> {
    use fastbrdf_analysis::measured_fit::{self, Options, Problem};
    let (brdf, bp) = fastbrdf::registry::shading_brdf(id, p)?;
    let problem = Problem::new(brdf, &bp, false)
        .map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
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
    let id = checked_id(q.need("model")?)?;
    q.need("ref")?;
    if let Some(Reference::Measured(m)) = Reference::from_query(q, state)? {
        let all = q.params();
        check_unused(&[id], &all)?;
        let p = params_of(id, &all)?;
        let mut row = measured_row(id, &p, m)?;
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

/// Evaluates the shading BRDF of `id` (lobes as `blinn-phong`, distributions as
/// `cook-torrance`: what the renderer shades with).
fn shading_model(id: &str, p: &[(String, String)]) -> Result<fastbrdf::Model<f64>, CliError> {
    let (brdf, bp) = fastbrdf::registry::shading_brdf(id, p)?;
    let given: Vec<(&str, &str)> = bp.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    Ok(fastbrdf::registry::build::<f64>(brdf, &given)?)
}

fn eval_brdf(m: &fastbrdf::Model<f64>, wi: [f64; 3], wo: [f64; 3]) -> f64 {
    match m {
        fastbrdf::Model::Brdf(b) => b.eval(wi, wo),
        _ => 0.0,
    }
}

/// The in-plane polar plot of `f` at incidence `ti_deg`: theta_o from -90 (the incident side:
/// wi is at -theta_i) to 90 degrees (the mirror direction is at +theta_i).
fn polar_of(f: impl Fn([f64; 3], [f64; 3]) -> f64, ti_deg: f64) -> Vec<f64> {
    let ti = ti_deg.to_radians();
    let wi = [ti.sin(), 0.0, ti.cos()];
    (0..POLAR_POINTS)
        .map(|k| {
            let t = -90.0 + 180.0 * k as f64 / (POLAR_POINTS - 1) as f64;
            let r = t.to_radians();
            f(wi, [-r.sin(), 0.0, r.cos()])
        })
        .collect()
}

/// The theta_h x theta_d slice of `f` at phi_d = 90 degrees (rows theta_d, columns theta_h).
fn slice_of(f: impl Fn([f64; 3], [f64; 3]) -> f64) -> Vec<f64> {
    let mut slice = Vec::with_capacity(SLICE * SLICE);
    for jd in 0..SLICE {
        let td = (jd as f64 + 0.5) / SLICE as f64 * std::f64::consts::FRAC_PI_2;
        for jh in 0..SLICE {
            let th = (jh as f64 + 0.5) / SLICE as f64 * std::f64::consts::FRAC_PI_2;
            // d in h's frame (phi_d = 90 degrees), rotated by theta_h about y.
            let d = [0.0, td.sin(), td.cos()];
            let (s, c) = th.sin_cos();
            let wi = [c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]];
            let h = [s, 0.0, c];
            let k = 2.0 * (h[0] * wi[0] + h[1] * wi[1] + h[2] * wi[2]);
            let wo = [k * h[0] - wi[0], k * h[1] - wi[1], k * h[2] - wi[2]];
            slice.push(f(wi, wo));
        }
    }
    slice
}

/// Rec. 709 luminance of an RGB BRDF value: what the plots show of measured data.
fn luminance(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
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

/// The lobe and error curves' abscissae, degrees.
fn curve_theta() -> Vec<f64> {
    (0..CURVE_POINTS)
        .map(|k| 89.9 * k as f64 / (CURVE_POINTS - 1) as f64)
        .collect()
}

/// The plots of one model (see README's API section for the shape).
fn plots_of(
    id: &'static str,
    all: &[(String, String)],
    reference: Option<&Reference>,
    ti_deg: f64,
) -> Result<Value, CliError> {
    let p = params_of(id, all)?;
    let m = shading_model(id, &p)?;
    let polar = polar_of(|wi, wo| eval_brdf(&m, wi, wo), ti_deg);
    let slice = slice_of(|wi, wo| eval_brdf(&m, wi, wo));
    // The model's own scalar curve at the swept parameter (what `errors` compares).
    let kind = fastbrdf::registry::find(id)?.info.kind;
    let swept = swept_param(id);
    let pval = swept.and_then(|s| p.iter().find(|(k, _)| k == s).map(|(_, v)| v.clone()));
    let pnum: Option<f64> = match (swept, &pval) {
        (Some(_), Some(v)) => v.parse().ok(),
        (Some(s), None) => match fastbrdf::registry::find(id)?
            .info
            .params
            .iter()
            .find(|x| x.name == s)
            .map(|x| x.kind)
        {
            Some(ParamKind::Number { default, .. }) => default,
            _ => None,
        },
        _ => None,
    };
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
    let (lobe, error) = match (swept, pnum) {
        (Some(s), Some(pv)) => {
            let c = fastbrdf::accuracy::Curve::new(id, s, pv)?;
            let lobe: Vec<f64> = theta_h.iter().map(|&t| c.at(to_x(t))).collect();
            let error = match reference.and_then(Reference::model) {
                Some(r)
                    if r != id
                        && swept_param(r) == Some(s)
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
        Some(Reference::Measured(mm)) => measured_row(id, &p, mm)?,
        _ => Value::Null,
    };
    Ok(json!({
        "id": id, "kind": kind.name(),
        "params": p.iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
        "polar": polar, "lobe": lobe, "error": error, "measured": measured,
        "slice": slice,
    }))
}

/// The directional albedo of one model and its white-furnace verdict, as `fastbrdf albedo`
/// computes them (lobes as energy-normalised `phong`, its defaults); null for a distribution
/// (not a BRDF on its own). `quick`: `albedo::curve_quick`'s estimate, without a verdict or
/// error estimates (`conserves`, `worst_*`, `error` null; `estimate` true).
fn albedo_of(id: &'static str, all: &[(String, String)], quick: bool) -> Result<Value, CliError> {
    let p = params_of(id, all)?;
    let albedo_v = match albedo::target(id, &p, "phong", "energy") {
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
                "brdf": t.id, "theta_deg": ALBEDO_ANGLES, "albedo": rows.iter().map(|r| r.albedo).collect::<Vec<_>>(),
                "error": rows.iter().map(|r| r.error).collect::<Vec<_>>(),
                "estimate": quick,
                "claims_energy": t.claims_energy, "conserves": holds, "tolerance": t.furnace_tolerance(),
                "worst_theta_deg": worst.map(|w| w.theta_deg), "worst_albedo": worst.map(|w| w.albedo),
            })
        }
        Err(_) => Value::Null,
    };
    Ok(json!({"id": id, "albedo": albedo_v}))
}

/// What a plots, albedo or render query chose: the registry model ids (a model reference
/// first, each once; a measured reference is not among them), the reference, and the
/// parameters.
type Chosen<'a> = (
    Vec<&'static str>,
    Option<Reference<'a>>,
    Vec<(String, String)>,
);

/// The model list of a plots, albedo or render query, a model reference first, each once.
fn chosen<'a>(state: &'a State, q: &Query) -> Result<Chosen<'a>, CliError> {
    let ids = model_ids(q)?;
    let reference = Reference::from_query(q, state)?;
    let all = q.params();
    let mut order: Vec<&'static str> = reference.iter().filter_map(Reference::model).collect();
    for id in ids {
        if !order.contains(&id) {
            order.push(id);
        }
    }
    check_unused(&order, &all)?;
    Ok((order, reference, all))
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
    let (order, reference, all) = chosen(state, q)?;
    use rayon::prelude::*;
    let mut out: Vec<Value> = order
        .par_iter()
        .map(|id| albedo_of(id, &all, quick))
        .collect::<Result<_, _>>()?;
    if let Some(Reference::Measured(m)) = &reference {
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
    let (seen, reference, all) = chosen(state, q)?;
    let ti = theta_i(q)?;
    // One model per task: the two cores of a slider move's budget.
    use rayon::prelude::*;
    let mut out: Vec<Value> = seen
        .par_iter()
        .map(|id| plots_of(id, &all, reference.as_ref(), ti))
        .collect::<Result<_, _>>()?;
    if let Some(Reference::Measured(m)) = &reference {
        out.insert(0, measured_plots(m, ti));
    }
    let polar_t: Vec<f64> = (0..POLAR_POINTS)
        .map(|k| -90.0 + 180.0 * k as f64 / (POLAR_POINTS - 1) as f64)
        .collect();
    let theta_h = curve_theta();
    Ok(Response::json(&json!({
        "theta_i_deg": ti,
        "reference": reference.as_ref().map(Reference::name),
        "reference_kind": reference.as_ref().map(|r| if r.model().is_some() { "model" } else { "measured" }),
        "polar_theta_deg": polar_t,
        "curve_theta_deg": theta_h,
        "slice_size": SLICE,
        "models": out,
        "ms": t.elapsed().as_secs_f64() * 1e3,
    })))
}

/// `GET /api/shader?model=ID&lang=LANG&NAME=VALUE...`: `fastbrdf shader` as text.
pub fn shader(q: &Query) -> Result<Response, CliError> {
    use fastbrdf_gpu::export::{Form, Lang, export_form};
    let id = checked_id(q.need("model")?)?;
    let lang_text = q.get("lang").unwrap_or("wgsl");
    let lang = Lang::parse(lang_text).ok_or_else(|| {
        CliError::input(format!(
            "lang '{}': expected wgsl, glsl, hlsl, msl or brdf-explorer",
            fastbrdf_io::shorten(lang_text, 64)
        ))
    })?;
    let p = params_of(id, &q.params())?;
    let given: Vec<(&str, &str)> = p.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    let text = export_form(id, &given, lang, Form::Literals)?;
    Ok(Response {
        status: 200,
        content_type: "text/plain; charset=utf-8",
        body: text.into_bytes(),
    })
}

/// Standard base64 (pictures inside JSON).
pub fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for (k, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if k <= c.len() {
                s.push(T[((n >> shift) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn parse_u32(q: &Query, key: &str, default: u32, lo: u32, hi: u32) -> Result<u32, CliError> {
    let Some(t) = q.get(key) else {
        return Ok(default);
    };
    match t.parse::<u32>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(CliError::input(format!(
            "{key} '{}': must be a whole number from {lo} to {hi}",
            fastbrdf_io::shorten(t, 64)
        ))),
    }
}

/// `GET /api/render?models=A,B&ref=R&size=N&spp=S&mesh=sphere|mesh&light=X,Y,Z&client=C&gen=G`:
/// the pictures (PNG, base64), difference maps against the reference, and RMSE/PSNR/FLIP as
/// `fastbrdf compare`. Renders wait for one of the server's render slots; a request whose
/// client has since sent a newer generation is dropped (409) before each model's render.
pub fn render_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let t0 = Instant::now();
    let (order, reference, all) = chosen(state, q)?;
    let size = parse_u32(q, "size", 256, 16, MAX_SIZE)?;
    let spp = parse_u32(q, "spp", 1, 1, MAX_SPP)?;
    let mut spec = setup::SceneSpec::new();
    match q.get("mesh").unwrap_or("sphere") {
        "sphere" => {}
        "mesh" => {
            if state.loaded_mesh.is_none() {
                return Err(CliError::input(
                    "mesh=mesh: the server was started without --mesh",
                ));
            }
        }
        m => {
            return Err(CliError::input(format!(
                "mesh '{}': expected sphere or mesh",
                fastbrdf_io::shorten(m, 64)
            )));
        }
    }
    let use_mesh = q.get("mesh") == Some("mesh");
    if let Some(l) = q.get("light") {
        spec.lights = vec![Light::parse(&format!("dir:{l}"))?];
    }
    let params: Vec<Vec<(String, String)>> = order
        .iter()
        .map(|id| params_of(id, &all))
        .collect::<Result<_, _>>()?;
    let client = q.get("client").unwrap_or("").to_string();
    let generation = match q.get("gen") {
        Some(g) => g.parse::<u64>().map_err(|_| {
            CliError::input(format!(
                "gen '{}': not a whole number",
                fastbrdf_io::shorten(g, 64)
            ))
        })?,
        None => 0,
    };
    state.note_generation(&client, generation);
    let loaded = if use_mesh {
        state.loaded_mesh.as_ref().expect("checked above")
    } else {
        &state.loaded_sphere
    };
    let scene_spec = if use_mesh {
        let mut s = spec.clone();
        s.mesh = state.mesh_path.clone();
        s
    } else {
        spec
    };
    let opts = Options {
        width: size,
        height: size,
        spp,
        shading: Shading::Batch,
    };
    let Some(_slot) = state.render_slot() else {
        return Ok(Response::error(503, "too many renders waiting; try again"));
    };
    // What is rendered, the reference first: a measured one as `fastbrdf compare --measured`
    // renders it (the whole BRDF in colour, weights 0, 1), the models as `fastbrdf compare`.
    let mut jobs: Vec<(String, setup::SceneSpec, Arc<Specular>)> = vec![];
    if let Some(Reference::Measured(m)) = &reference {
        let mut s = scene_spec.clone();
        (s.kd, s.ks) = (0.0, 1.0);
        let label = format!("measured {}", m.path.display());
        jobs.push((
            m.name.clone(),
            s,
            Arc::new(Specular::rgb(&label, m.brdf.clone())),
        ));
    }
    for (id, p) in order.iter().zip(&params) {
        jobs.push((
            id.to_string(),
            scene_spec.clone(),
            Arc::new(Specular::new(id, p)?),
        ));
    }
    let names: Vec<String> = jobs.iter().map(|j| j.0.clone()).collect();
    let mut pictures: Vec<Vec<u8>> = vec![];
    for (id, spec, specular) in jobs {
        // Nobody reads the answer of a client that has hung up: the slot goes to another.
        if super::client_gone() {
            return Ok(Response::error(499, "the client has gone"));
        }
        if state.superseded(&client, generation) {
            return Ok(Response::error(
                409,
                "superseded by a newer request from this client",
            ));
        }
        let scene = setup::scene(&spec, loaded, specular);
        let film = render(&scene, &opts, &|_, _| {})?;
        film.check_finite()
            .map_err(|e| CliError::input(format!("--model {id}: {e}")))?;
        pictures.push(film.to_srgb8(1.0));
    }
    let mut images = vec![];
    for (id, px) in names.iter().zip(&pictures) {
        images.push(json!({"id": id, "png": base64(&png_bytes(px, size, size)?)}));
    }
    let mut diffs = vec![];
    let mut metrics = vec![];
    if reference.is_some() {
        let r = &pictures[0];
        let d: Vec<Vec<f32>> = pictures[1..]
            .iter()
            .map(|t| compare::difference(r, t))
            .collect();
        let scale = d
            .iter()
            .flatten()
            .copied()
            .fold(0.0f32, f32::max)
            .max(1.0 / 255.0);
        for (k, (id, px)) in names[1..].iter().zip(&pictures[1..]).enumerate() {
            let m = compare::metrics(id, r, px, size, size);
            metrics.push(json!({"model": id, "rmse": m.rmse, "psnr": m.psnr, "flip": m.flip}));
            diffs.push(json!({"id": id, "png": base64(&png_bytes(&compare::heat_map(&d[k], scale), size, size)?)}));
        }
        return Ok(Response::json(&json!({
            "width": size, "height": size, "spp": spp, "reference": names[0],
            "images": images, "diffs": diffs, "diff_scale": scale, "metrics": metrics,
            "ms": t0.elapsed().as_secs_f64() * 1e3,
        })));
    }
    Ok(Response::json(&json!({
        "width": size, "height": size, "spp": spp, "reference": Value::Null,
        "images": images, "diffs": diffs, "diff_scale": Value::Null, "metrics": metrics,
        "ms": t0.elapsed().as_secs_f64() * 1e3,
    })))
}
