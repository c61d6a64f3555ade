//! The kinds that are not shaded (shadowing, Fresnel and split-sum `env` terms) in the
//! explorer: their curves and their errors against a reference, the `terms` of `/api/plots`.
//!
//! A query's `models=` (and `ref=`) may name such terms beside the BRDFs, lobes and
//! distributions: [`split`] takes them out, so that the pictures, the albedo and the other
//! plots see the shaded models alone ([`shaded`]: an empty choice when there are none), and
//! [`terms`] draws each term against its reference: the chosen `ref` when it is of the same
//! kind, else the reference of the model's documented bound, else the kind's exact model
//! ([`exact`]). The errors are those of `fastbrdf errors` (`fastbrdf_analysis::errors::sweep`
//! at the swept parameter's value, other parameters at their defaults).

use super::query::{Chosen, MAX_MODELS, Query, chosen};
use crate::CliError;
use crate::commands::view::state::State;
use crate::model_args::{self, Use};
use fastbrdf::kind::Shading;
use fastbrdf::model::ShadowInput;
use fastbrdf::{Given, Kind, Model, ModelSpec};
use fastbrdf_analysis::errors;
use serde_json::{Value, json};

/// Points of each term's curve.
const POINTS: usize = 181;
/// The inputs of a split-sum term that are not parameters: the page's sliders for them.
pub const ENV_ALPHA: &str = "alpha";
pub const ENV_COS_V: &str = "cos_v";
/// Default `cos_v` (NoV) of the split-sum plot against alpha.
const COS_V_DEFAULT: f64 = 0.5;

/// The kind's exact model: the reference of a term that has no documented bound (and is
/// not the chosen reference's kind).
pub fn exact(kind: Kind) -> Option<&'static str> {
    match kind {
        Kind::Shadowing => Some("smith-ggx-correlated"),
        Kind::Fresnel => Some("fresnel-dielectric"),
        Kind::Env => Some("env-brdf"),
        _ => None,
    }
}

/// The registry id of `id` when it is a term the explorer does not shade (and no user's
/// model is called so).
fn term_id(state: &State, id: &str) -> Option<&'static str> {
    if state.user(id).is_some() {
        return None;
    }
    let e = fastbrdf::registry::find(id).ok()?;
    (e.info.kind.shading() == Shading::Not).then_some(e.info.id)
}

/// Whether term `id` takes the query value `name`: a parameter, or an input of a split-sum
/// term (`alpha`, `cos_v`).
fn term_takes(id: &str, name: &str) -> Result<bool, CliError> {
    let kind = fastbrdf::registry::find(id)?.info.kind;
    Ok(model_args::takes(id, name)?
        || (kind == Kind::Env && (name == ENV_ALPHA || name == ENV_COS_V)))
}

/// The extra slider entries of `/api/models`' `params` for a kind: a split-sum term's inputs
/// (`"input": true`: not parameters of `fastbrdf eval`, its input columns).
pub fn input_params(kind: Kind) -> Vec<Value> {
    if kind != Kind::Env {
        return vec![];
    }
    let (lo, hi) = fastbrdf::params::ALPHA.range();
    vec![
        json!({"name": ENV_ALPHA, "type": "number", "min": lo, "max": hi, "default": 0.3,
               "doc": "input: RMS microfacet slope (roughness) of the split-sum plot against NoV",
               "log": true, "input": true}),
        json!({"name": ENV_COS_V, "type": "number", "min": 0.0, "max": 1.0, "default": COS_V_DEFAULT,
               "doc": "input: NoV of the split-sum plot against alpha", "log": false, "input": true}),
    ]
}

/// A query split into its terms and the rest.
pub struct Split {
    /// The query of the shaded models (terms and their values taken out); None when only
    /// terms were chosen.
    pub rest: Option<Query>,
    /// The terms, the chosen reference first when it is one, each once, with their specs.
    pub terms: Vec<(&'static str, ModelSpec)>,
    /// The chosen reference when it is a term.
    pub term_ref: Option<&'static str>,
}

/// Splits `q`'s models (and reference) into terms and the others. A value goes to the rest
/// when a model there takes it or no term does (the rest's checks then refuse it, naming it);
/// with terms alone, a value none takes is refused here.
pub fn split(state: &State, q: &Query) -> Result<Split, CliError> {
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
    let term_ref = q
        .get("ref")
        .filter(|r| !r.is_empty())
        .and_then(|r| term_id(state, r));
    let mut term_ids: Vec<&'static str> = term_ref.into_iter().collect();
    let mut rest_ids: Vec<&str> = vec![];
    for id in ids {
        match term_id(state, id) {
            Some(t) => {
                if !term_ids.contains(&t) {
                    term_ids.push(t);
                }
            }
            None => rest_ids.push(id),
        }
    }
    if term_ids.is_empty() {
        return Ok(Split {
            rest: Some(Query(q.0.clone())),
            terms: vec![],
            term_ref: None,
        });
    }
    // The shaded reference stands in for the models when only terms were chosen.
    let ref_text = q.get("ref").filter(|r| !r.is_empty());
    if rest_ids.is_empty()
        && let Some(r) = ref_text.filter(|_| term_ref.is_none())
        && (state.user(r).is_some() || fastbrdf::registry::find(r).is_ok())
    {
        rest_ids.push(r);
    }
    let shaded_ref = ref_text.filter(|_| term_ref.is_none());
    let rest_takes = |k: &str| {
        rest_ids.iter().chain(shaded_ref.iter()).any(|id| {
            model_args::takes(id, k).unwrap_or(false)
                || state.user(id).is_some_and(|u| u.declares(k))
        })
    };
    let all = q.params();
    let mut rest_keep: Vec<&str> = vec![];
    for (k, _) in &all {
        let mut by_term = false;
        for t in &term_ids {
            by_term |= term_takes(t, k)?;
        }
        if rest_ids.is_empty() {
            if !by_term {
                return Err(fastbrdf::Error::UnknownParam {
                    model: term_ids.join(","),
                    param: fastbrdf_io::shorten(k, 64),
                }
                .into());
            }
        } else if rest_takes(k) || !by_term {
            rest_keep.push(k);
        }
    }
    let rest = (!rest_ids.is_empty()).then(|| {
        let params: Vec<String> = all.iter().map(|(k, _)| k.clone()).collect();
        Query(
            q.0.iter()
                .filter_map(|(k, v)| match k.as_str() {
                    "models" => Some((k.clone(), rest_ids.join(","))),
                    "ref" if term_ref.is_some() => None,
                    _ if params.contains(k) && !rest_keep.contains(&k.as_str()) => None,
                    _ => Some((k.clone(), v.clone())),
                })
                .collect(),
        )
    });
    let terms = term_ids
        .into_iter()
        .map(|id| {
            let spec =
                model_args::spec(id, &model_args::own_pairs(id, &all)?, None, None, Use::AsIs)?;
            spec.params()?;
            Ok((id, spec))
        })
        .collect::<Result<_, CliError>>()?;
    Ok(Split {
        rest,
        terms,
        term_ref,
    })
}

/// What a plots, albedo or render query chose among the shaded models ([`chosen`] of the
/// query without its terms): nothing when it chose terms alone.
pub fn shaded<'a>(state: &'a State, q: &Query) -> Result<Chosen<'a>, CliError> {
    match split(state, q)?.rest {
        Some(rest) => chosen(state, &rest),
        None => Ok(Chosen {
            models: vec![],
            users: vec![],
            reference: None,
            ref_user: None,
        }),
    }
}

/// A number of the query (`name`), in `[lo, hi]`, or `default`.
fn input(q: &Query, name: &str, lo: f64, hi: f64, default: f64) -> Result<f64, CliError> {
    let Some(t) = q.get(name) else {
        return Ok(default);
    };
    let v: f64 = t.parse().map_err(|_| {
        CliError::input(format!(
            "{name} '{}': not a number",
            fastbrdf_io::shorten(t, 64)
        ))
    })?;
    if !(lo..=hi).contains(&v) {
        return Err(CliError::input(format!(
            "{name} {v}: the split-sum input must be in [{lo}, {hi}]"
        )));
    }
    Ok(v)
}

/// The reference of term `id` and the rule that chose it (`chosen`, `bound`, `exact`).
fn reference_of(
    id: &str,
    kind: Kind,
    term_ref: Option<&str>,
) -> Option<(&'static str, &'static str)> {
    let e = fastbrdf::registry::find(id).ok()?;
    if let Some(r) = term_ref.and_then(|r| fastbrdf::registry::find(r).ok())
        && r.info.kind == kind
    {
        return (r.info.id != id).then_some((r.info.id, "chosen"));
    }
    if let Some(b) = e.info.bounds.first() {
        return Some((b.reference, "bound"));
    }
    exact(kind).filter(|x| *x != id).map(|x| (x, "exact"))
}

/// The parameter `fastbrdf errors` measures a term at: `alpha` (shadowing, split-sum) or
/// `f0` (Fresnel), if the model takes it.
fn swept_of(e: &fastbrdf::entry::Entry) -> Option<&'static str> {
    ["alpha", "f0", "n"]
        .into_iter()
        .find(|p| e.info.sweep_range(p).is_some())
}

/// Where an error's input `x` lies, in the plot's words.
fn place(kind: Kind, x: f64) -> Value {
    match kind {
        Kind::Shadowing => {
            json!({"cos_v": x, "theta_v_deg": x.clamp(-1.0, 1.0).acos().to_degrees()})
        }
        Kind::Fresnel => json!({"cos": x}),
        _ if x > 1.0 => json!({"term": "bias", "cos_v": x - 1.0}),
        _ => json!({"term": "scale", "cos_v": x}),
    }
}

/// The errors of term `id` against `reference` at `param = value`: `fastbrdf errors`' row
/// (`errors::sweep`, zone all), or why there is none.
fn errors_of(
    id: &str,
    reference: &str,
    param: &str,
    value: f64,
    kind: Kind,
) -> Result<Value, String> {
    let spec = errors::Spec {
        model: id.into(),
        reference: reference.into(),
        param: param.into(),
        zone: fastbrdf::Zone::All,
    };
    spec.validate().map_err(|e| e.to_string())?;
    if kind != Kind::Env {
        for m in [id, reference] {
            ModelSpec::new(m, &[(param, Given::Num(value))]).map_err(|e| e.to_string())?;
        }
    }
    let r = errors::sweep(&spec, &[value], &|| {}).map_err(|e| e.to_string())?[0];
    Ok(json!({
        "param": param, "value": value, "zone": "all",
        "max_abs": r.max_abs, "max_abs_at": r.max_abs_at, "max_abs_where": place(kind, r.max_abs_at),
        "max_rel": r.max_rel, "max_rel_at": r.max_rel_at, "max_rel_where": place(kind, r.max_rel_at),
        "rms": r.rms, "samples": r.samples,
    }))
}

/// [`POINTS`] points from `a` to `b`.
fn grid(a: f64, b: f64) -> Vec<f64> {
    (0..POINTS)
        .map(|k| a + (b - a) * k as f64 / (POINTS - 1) as f64)
        .collect()
}

/// A shadowing term's G1 (one-sided, as `fastbrdf errors` measures it: `h = n`) and its G2 in
/// the plane of incidence, `l` at `theta_l` opposite `v`, against theta_v in degrees.
fn shadowing_curves(m: &Model<f64>, theta_l: f64) -> (Vec<f64>, Vec<f64>) {
    let Model::Shadowing(s) = m else {
        return (vec![], vec![]);
    };
    let tl = theta_l.to_radians();
    let l = [-tl.sin(), 0.0, tl.cos()];
    let (mut g1, mut g2) = (vec![], vec![]);
    for t in grid(0.0, 90.0) {
        let tv = t.to_radians();
        let cos_v = tv.cos();
        g1.push(s.g(&ShadowInput {
            cos_v,
            cos_l: None,
            cos_h: 1.0,
            cos_vh: 1.0,
        }));
        let v = [tv.sin(), 0.0, cos_v];
        let h = [v[0] + l[0], 0.0, v[2] + l[2]];
        let n = (h[0] * h[0] + h[2] * h[2]).sqrt().max(f64::MIN_POSITIVE);
        g2.push(s.g(&ShadowInput {
            cos_v,
            cos_l: Some(l[2]),
            cos_h: h[2] / n,
            cos_vh: (v[0] * h[0] + v[2] * h[2]) / n,
        }));
    }
    (g1, g2)
}

/// One curve of a plot: the model's values and the reference's (null without one).
fn pair(label: &str, m: Vec<f64>, r: Option<Vec<f64>>) -> Value {
    json!({"label": label, "model": m, "reference": r})
}

/// The plots of term `id` (`spec`) against `reference` (its spec from the query's values it
/// takes), at incidence `theta_l` (shadowing's G2) and the split-sum inputs `alpha`, `cos_v`.
fn plots_of(
    kind: Kind,
    spec: &ModelSpec,
    reference: Option<&ModelSpec>,
    theta_l: f64,
    (alpha, cos_v): (f64, f64),
) -> Result<Vec<Value>, CliError> {
    let m = spec.model::<f64>()?;
    let r = reference.map(ModelSpec::model::<f64>).transpose()?;
    Ok(match kind {
        Kind::Shadowing => {
            let (g1, g2) = shadowing_curves(&m, theta_l);
            let (r1, r2) = r.as_ref().map(|r| shadowing_curves(r, theta_l)).unzip();
            vec![json!({
                "name": "shadowing", "x_label": "theta_v (deg)", "y_label": "G",
                "x": grid(0.0, 90.0),
                "curves": [pair("G1(v)", g1, r1),
                           pair(&format!("G2(v, l), theta_l = {theta_l} deg opposite"), g2, r2)],
            })]
        }
        Kind::Fresnel => {
            let xs = grid(0.0, 1.0);
            let f = |m: &Model<f64>| -> Vec<f64> {
                match m {
                    Model::Fresnel(f) => xs.iter().map(|&x| f.f(x)).collect(),
                    _ => vec![],
                }
            };
            vec![json!({
                "name": "fresnel", "x_label": "cos theta_vh", "y_label": "F", "x": xs,
                "curves": [pair("F", f(&m), r.as_ref().map(f))],
            })]
        }
        _ => {
            // Both terms, whatever `term` the spec chose: the scale and the bias of f0.
            let term = |s: &ModelSpec, t: &str| -> Result<Model<f64>, CliError> {
                let mut given: Vec<(&str, Given)> = s.given().to_vec();
                given.retain(|(k, _)| *k != "term");
                given.push(("term", Given::Choice(t.into())));
                Ok(ModelSpec::new(s.id(), &given)?.model::<f64>()?)
            };
            let env = |s: &ModelSpec| -> Result<[Model<f64>; 2], CliError> {
                Ok([term(s, "scale")?, term(s, "bias")?])
            };
            let ms = env(spec)?;
            let rs = reference.map(env).transpose()?;
            let e = |m: &Model<f64>, c: f64, a: f64| match m {
                Model::Env(t) => t.e(c, a),
                _ => f64::NAN,
            };
            let (nov, alphas) = (grid(0.0, 1.0), grid(fastbrdf::params::ALPHA_MIN, 1.0));
            let mut out = vec![];
            for (name, xs, x_label, at) in [
                ("env-nov", &nov, "NoV (cos_v)", true),
                ("env-alpha", &alphas, "alpha (roughness)", false),
            ] {
                let curve = |m: &Model<f64>| -> Vec<f64> {
                    xs.iter()
                        .map(|&x| if at { e(m, x, alpha) } else { e(m, cos_v, x) })
                        .collect()
                };
                let curves: Vec<Value> = ["scale", "bias"]
                    .iter()
                    .enumerate()
                    .map(|(k, t)| pair(t, curve(&ms[k]), rs.as_ref().map(|r| curve(&r[k]))))
                    .collect();
                out.push(json!({
                    "name": name, "x_label": x_label, "y_label": "scale, bias", "x": xs,
                    "at": if at { json!({"alpha": alpha}) } else { json!({"cos_v": cos_v}) },
                    "curves": curves,
                }));
            }
            out
        }
    })
}

/// The `terms` of `/api/plots`: each term's curves against its reference, and its errors
/// (docs/book/src/explorer-kinds.md gives the shape).
pub fn terms(split: &Split, q: &Query, theta_l: f64) -> Result<Vec<Value>, CliError> {
    let (lo, hi) = fastbrdf::params::ALPHA.range();
    let alpha = input(q, ENV_ALPHA, lo, hi, 0.3)?;
    let cos_v = input(q, ENV_COS_V, 0.0, 1.0, COS_V_DEFAULT)?;
    let all = q.params();
    let mut out = vec![];
    for (id, spec) in &split.terms {
        let e = fastbrdf::registry::find(id)?;
        let kind = e.info.kind;
        let reference = reference_of(id, kind, split.term_ref);
        // The reference with the query's values it takes (its curves follow the sliders).
        let ref_spec = reference
            .map(|(r, _)| {
                model_args::spec(r, &model_args::own_pairs(r, &all)?, None, None, Use::AsIs)
            })
            .transpose()?;
        let plots = plots_of(kind, spec, ref_spec.as_ref(), theta_l, (alpha, cos_v))?;
        let param = swept_of(e);
        let value = match (param, kind) {
            (Some(_), Kind::Env) => Some(alpha),
            (Some(p), _) => match spec.get(p) {
                Some(Given::Num(x)) => Some(*x),
                _ => e
                    .info
                    .params
                    .iter()
                    .find(|x| x.name == p)
                    .and_then(|x| match x.kind {
                        fastbrdf::params::ParamKind::Number { default, .. } => default,
                        _ => None,
                    }),
            },
            _ => None,
        };
        let (error, why) = match (reference, param, value) {
            (None, _, _) => (
                Value::Null,
                Some(format!(
                    "{id} is the reference ({} terms' exact model or the chosen reference)",
                    kind.name()
                )),
            ),
            (Some(_), None, _) | (Some(_), _, None) => (
                Value::Null,
                Some(format!(
                    "{id} takes no parameter that `fastbrdf errors` sweeps (alpha, f0)"
                )),
            ),
            (Some((r, _)), Some(p), Some(v)) => match errors_of(id, r, p, v, kind) {
                Ok(row) => (row, None),
                Err(w) => (Value::Null, Some(format!("no errors against {r}: {w}"))),
            },
        };
        // Values the errors do not follow: `fastbrdf errors` measures at the swept value, the
        // other parameters at their defaults.
        let ignored: Vec<&str> = spec
            .given()
            .iter()
            .map(|(k, _)| *k)
            .filter(|k| Some(*k) != param && *k != "term")
            .collect();
        out.push(json!({
            "id": id, "kind": kind.name(),
            "params": model_args::asked_pairs(id, spec).iter().map(|(k, v)| json!([k, v])).collect::<Vec<_>>(),
            "reference": reference.map(|r| r.0), "reference_rule": reference.map(|r| r.1),
            "plots": plots, "error": error, "why": why, "errors_ignore": ignored,
        }));
    }
    Ok(out)
}
