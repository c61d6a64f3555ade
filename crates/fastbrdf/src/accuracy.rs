//! Measuring a model against its reference: the sample sets, zones and metrics behind every
//! documented [`ErrorBound`], with grid-then-golden-section refinement of the maxima.
//!
//! Each kind is reduced to a function of one scalar `x` for a fixed parameter value `p`:
//! - lobes: `x = c`, reference at the same `n`;
//! - distributions: `x = cos theta_h`;
//! - shadowing: `x = cos theta_v` (one-sided `G1`);
//! - full BRDFs: `x = theta`, with `wi = wo = (sin theta, 0, cos theta)` (so `theta_h = theta`
//!   and the approximations' relative error is that of their exponential factor).
//!
//! The zone is decided by the reference value divided by its peak over the sample set.
//! Samples are dense where the function changes: for a lobe of exponent `n`, uniform in
//! `u = n (1 - c)` on [0, 60] plus a geometric tail to `c = 0`.

use crate::error::Result;
use crate::model::{ErrorBound, Metric, Model, Zone};
use crate::registry;

/// The largest error found, and where.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Worst {
    /// The error value.
    pub err: f64,
    /// The parameter value (n or alpha) where it occurs.
    pub param: f64,
    /// The input `x` where it occurs.
    pub x: f64,
    /// Number of (parameter, x) samples evaluated (before refinement).
    pub samples: usize,
}

/// A scalar function of `x` for one parameter value.
pub struct Curve {
    model: Model<f64>,
}

impl Curve {
    /// Builds `id` with the parameter `name = value` (other parameters at their defaults).
    pub fn new(id: &str, name: &str, value: f64) -> Result<Self> {
        let v = value.to_string();
        let given: Vec<(&str, &str)> = if name.is_empty() {
            vec![]
        } else {
            vec![(name, &v)]
        };
        Ok(Self {
            model: registry::build::<f64>(id, &given)?,
        })
    }

    /// The built model.
    pub fn model(&self) -> &Model<f64> {
        &self.model
    }

    /// The value at `x` (see the module header for what `x` is per kind).
    pub fn at(&self, x: f64) -> f64 {
        match &self.model {
            Model::Lobe(l) => l.eval(x),
            Model::Distribution(d) => d.eval(x),
            Model::Shadowing(s) => s.g(&crate::model::ShadowInput {
                cos_v: x,
                cos_l: None,
                cos_h: 1.0,
                cos_vh: 1.0,
            }),
            Model::Fresnel(f) => f.f(x),
            Model::Brdf(b) => {
                let w = [x.sin(), 0.0, x.cos()];
                b.eval(w, w)
            }
        }
    }
}

/// The sample positions for a model of `kind` with parameter value `p`.
pub fn samples(model: &Model<f64>, p: f64) -> Vec<f64> {
    match model {
        Model::Lobe(_) => lobe_samples(p),
        Model::Distribution(_) => {
            // Uniform in t = tan^2 / alpha^2 on [0, 40], then to grazing.
            let mut xs: Vec<f64> = (0..=4000)
                .map(|i| 1.0 / (1.0 + p * p * (i as f64 * 0.01)).sqrt())
                .collect();
            xs.extend(
                (1..=400).map(|i| 1.0 / (1.0 + p * p * 40.0 * (1.0 + i as f64 * 0.25)).sqrt()),
            );
            xs.extend((0..=200).map(|i| 1e-6 + i as f64 * 0.005));
            xs
        }
        Model::Shadowing(_) | Model::Fresnel(_) => (1..=4000).map(|i| i as f64 / 4000.0).collect(),
        Model::Brdf(_) => {
            let top = 89.9f64.to_radians();
            let mut xs: Vec<f64> = (0..=4000)
                .map(|i| (i as f64 / 4000.0).powi(2) * top)
                .collect();
            xs.extend((0..=400).map(|i| (i as f64 * 0.0025 * p).min(top)));
            xs
        }
    }
}

/// Cosines for a lobe of exponent `n`: uniform in `u = n (1 - c)` on [0, 60] (step 0.02)
/// and geometric below, down to `c = 0`.
pub fn lobe_samples(n: f64) -> Vec<f64> {
    let mut xs: Vec<f64> = (0..=3000)
        .map(|i| 1.0 - (i as f64 * 0.02) / n)
        .filter(|c| *c >= 0.0)
        .collect();
    let c_lo = (1.0 - 60.0 / n).max(0.0);
    xs.extend((1..=400).map(|i| c_lo * (1.0 - i as f64 / 400.0)));
    xs.extend((0..=200).map(|i| i as f64 / 200.0));
    xs
}

/// Whether a reference value, divided by its peak, lies in `zone`.
pub fn in_zone(zone: Zone, rel: f64) -> bool {
    match zone {
        Zone::All => true,
        Zone::Epicentre => rel >= 0.5,
        Zone::Band { lo, hi } => rel > lo && rel < hi,
    }
}

/// The error of `f` against the reference value `r` under `metric` (`peak` scales `MaxAbs`).
pub fn error(metric: Metric, f: f64, r: f64, peak: f64) -> f64 {
    match metric {
        Metric::MaxAbs => (f - r).abs() / peak,
        Metric::MaxRel => {
            if r > 0.0 {
                (f - r).abs() / r
            } else if f == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        }
    }
}

/// The worst error of `model` against `bound.reference` for one parameter value `p`, with
/// golden-section refinement around the largest grid errors.
pub fn worst_at(model_id: &str, bound: &ErrorBound, p: f64) -> Result<Worst> {
    worst_at_impl(model_id, bound, p, true)
}

/// The same on the grid alone, without refinement (to show what refinement adds).
pub fn worst_at_grid(model_id: &str, bound: &ErrorBound, p: f64) -> Result<Worst> {
    worst_at_impl(model_id, bound, p, false)
}

fn worst_at_impl(model_id: &str, bound: &ErrorBound, p: f64, refine: bool) -> Result<Worst> {
    let name = bound.param.0;
    let m = Curve::new(model_id, name, p)?;
    let r = Curve::new(bound.reference, name, p)?;
    let xs = samples(&m.model, p);
    let refs: Vec<f64> = xs.iter().map(|&x| r.at(x)).collect();
    let peak = refs
        .iter()
        .copied()
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let err_at = |x: f64| {
        let rv = r.at(x);
        if in_zone(bound.zone, rv / peak) {
            error(bound.metric, m.at(x), rv, peak)
        } else {
            0.0
        }
    };
    // Grid.
    let mut order: Vec<usize> = (0..xs.len()).collect();
    let errs: Vec<f64> = xs
        .iter()
        .zip(&refs)
        .map(|(&x, &rv)| {
            if in_zone(bound.zone, rv / peak) {
                error(bound.metric, m.at(x), rv, peak)
            } else {
                0.0
            }
        })
        .collect();
    order.sort_by(|&a, &b| errs[b].total_cmp(&errs[a]));
    let mut sorted_x = xs.clone();
    sorted_x.sort_by(f64::total_cmp);
    let mut best = Worst {
        err: errs[order[0]],
        param: p,
        x: xs[order[0]],
        samples: xs.len(),
    };
    // Refine around the eight largest grid errors, between their sorted neighbours.
    for &i in order.iter().take(if refine { 8 } else { 0 }) {
        let x = xs[i];
        let k = sorted_x.partition_point(|v| *v < x);
        let lo = sorted_x[k.saturating_sub(1)];
        let hi = sorted_x[(k + 1).min(sorted_x.len() - 1)];
        let (xm, em) = golden_max(&err_at, lo, hi, 60);
        if em > best.err {
            best.err = em;
            best.x = xm;
        }
    }
    Ok(best)
}

/// Golden-section search for the maximum of `f` on `[a, b]`: `(argmax, max)`.
pub fn golden_max(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64, iters: usize) -> (f64, f64) {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..iters {
        if f1 < f2 {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = f(x2);
        } else {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = f(x1);
        }
    }
    if f1 > f2 { (x1, f1) } else { (x2, f2) }
}

/// The parameter values a bound is checked on: n = lo..=hi in steps of 1 for lobes, alpha
/// in steps of 0.01 for the rest.
pub fn param_values(bound: &ErrorBound) -> Vec<f64> {
    let (name, lo, hi) = bound.param;
    let step = if name == "n" { 1.0 } else { 0.01 };
    let count = ((hi - lo) / step).round() as usize;
    (0..=count)
        .map(|i| (lo + i as f64 * step).min(hi))
        .collect()
}

/// The worst error over the bound's whole parameter range.
pub fn worst(model_id: &str, bound: &ErrorBound) -> Result<Worst> {
    let mut best = Worst::default();
    let mut samples = 0;
    for p in param_values(bound) {
        let w = worst_at(model_id, bound, p)?;
        samples += w.samples;
        if w.err > best.err || best.samples == 0 {
            best = w;
        }
    }
    best.samples = samples;
    Ok(best)
}

/// The mixed f32-vs-f64 error `|v32 - v64| / max(1, |v64|)` used by every `f32_bound`.
pub fn mixed_error(v32: f32, v64: f64) -> f64 {
    (v32 as f64 - v64).abs() / v64.abs().max(1.0)
}

/// A uniform number in [0, 1) from SplitMix64, advancing `state` (deterministic test and
/// benchmark inputs; no statistical claims).
pub fn splitmix(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// Direction pairs covering the hemisphere for BRDF checks: normal incidence, random pairs,
/// near-specular pairs (where narrow lobes live) and a near-grazing back-to-back pair; all
/// with `cos theta >= 1e-3`. Deterministic for a given `seed`.
pub fn direction_pairs(count: usize, seed: u64) -> Vec<([f64; 3], [f64; 3])> {
    let mut state = seed;
    let mut next = move || splitmix(&mut state);
    let hemisphere = |next: &mut dyn FnMut() -> f64| {
        let z = 1e-3 + (1.0 - 1e-3) * next();
        let r = (1.0 - z * z).sqrt();
        let phi = 2.0 * std::f64::consts::PI * next();
        [r * phi.cos(), r * phi.sin(), z]
    };
    let mut out = vec![
        ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
        ([0.6, 0.0, 0.8], [-0.6, 0.0, 0.8]),
    ];
    for i in 0..count {
        let wi = hemisphere(&mut next);
        let wo = match i % 3 {
            0 => hemisphere(&mut next),
            _ => {
                let s = if i % 3 == 1 { 0.02 } else { 0.2 };
                let m = [
                    -wi[0] + s * (next() - 0.5),
                    -wi[1] + s * (next() - 0.5),
                    wi[2],
                ];
                let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                [m[0] / l, m[1] / l, (m[2] / l).max(1e-3)]
            }
        };
        out.push((wi, wo));
    }
    out.push(([0.9999, 0.0, 0.0141], [-0.9999, 0.0, 0.0141]));
    out
}

/// The worst mixed f32-vs-f64 error of one model configuration over inputs covering its
/// domain (the same f32 inputs fed to both precisions), and a description of where.
pub fn f32_worst(id: &str, given: &[(&str, &str)]) -> Result<(f64, String)> {
    use crate::model::ShadowInput;
    let m32 = registry::build::<f32>(id, given)?;
    let m64 = registry::build::<f64>(id, given)?;
    let param = |name: &str, default: f64| {
        given
            .iter()
            .find(|(k, _)| *k == name)
            .and_then(|(_, v)| v.parse().ok())
            .unwrap_or(default)
    };
    let mut worst = (0.0, String::new());
    let mut note = |e: f64, what: &dyn Fn() -> String| {
        if !(e <= worst.0) {
            worst = (e, what());
        }
    };
    match (&m32, &m64) {
        (Model::Lobe(a), Model::Lobe(b)) => {
            let n = param("n", 20.0);
            for c in lobe_samples(n)
                .into_iter()
                .chain((0..=1000).map(|i| i as f64 / 1000.0))
            {
                let c32 = c as f32;
                note(mixed_error(a.eval(c32), b.eval(c32 as f64)), &|| {
                    format!("c={c32}")
                });
            }
        }
        (Model::Distribution(a), Model::Distribution(b)) => {
            for c in samples(&m64, param("alpha", 0.3)) {
                let c32 = c as f32;
                note(mixed_error(a.eval(c32), b.eval(c32 as f64)), &|| {
                    format!("cos_h={c32}")
                });
            }
        }
        (Model::Shadowing(a), Model::Shadowing(b)) => {
            for (wi, wo) in direction_pairs(400, 5) {
                let s = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
                let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
                let s32 = ShadowInput {
                    cos_v: wo[2] as f32,
                    cos_l: Some(wi[2] as f32),
                    cos_h: (s[2] / len) as f32,
                    cos_vh: (0.5 * len) as f32,
                };
                let s64 = ShadowInput {
                    cos_v: s32.cos_v as f64,
                    cos_l: s32.cos_l.map(f64::from),
                    cos_h: s32.cos_h as f64,
                    cos_vh: s32.cos_vh as f64,
                };
                note(mixed_error(a.g(&s32), b.g(&s64)), &|| format!("{s32:?}"));
                let (o32, o64) = (
                    ShadowInput { cos_l: None, ..s32 },
                    ShadowInput { cos_l: None, ..s64 },
                );
                note(mixed_error(a.g(&o32), b.g(&o64)), &|| format!("{o32:?}"));
            }
        }
        (Model::Fresnel(a), Model::Fresnel(b)) => {
            for i in 0..=2000 {
                let c32 = i as f32 / 2000.0;
                note(mixed_error(a.f(c32), b.f(c32 as f64)), &|| {
                    format!("cos={c32}")
                });
            }
        }
        (Model::Brdf(a), Model::Brdf(b)) => {
            for (wi, wo) in direction_pairs(600, 3) {
                let (i32, o32) = (wi.map(|x| x as f32), wo.map(|x| x as f32));
                let e = mixed_error(
                    a.eval(i32, o32),
                    b.eval(i32.map(f64::from), o32.map(f64::from)),
                );
                note(e, &|| format!("wi={i32:?} wo={o32:?}"));
            }
        }
        _ => unreachable!("both precisions build the same kind"),
    }
    Ok(worst)
}

/// Parameter sets covering a model's documented domain: every combination of its choice
/// parameters, crossed with "rows" that walk each numeric parameter through representative
/// values including the range's edges (cycling, so that every value of every parameter
/// appears). Optional parameters (Ward's `alpha_x`, `alpha_y`) are given on odd rows only.
/// `light` keeps about four numeric rows (for the BRDFs, whose choice products are large).
pub fn domain_configs(info: &crate::ModelInfo, light: bool) -> Vec<Vec<(String, String)>> {
    use crate::params::ParamKind;
    fn values(name: &str, min: f64, max: f64) -> Vec<f64> {
        match name {
            "n" => vec![
                1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 16.0, 20.0, 33.0, 50.0, 100.0, 128.0,
                200.0, 333.0, 500.0, 777.0, 1000.0, 2000.0, 5000.0, 10000.0,
            ],
            // 0.7072 sits just above 1/sqrt(2), where seed 000's exponent 2/alpha^2 - 4 changes sign.
            "alpha" | "alpha_x" | "alpha_y" => {
                vec![0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7072, 0.85, 1.0]
            }
            "f0" => vec![0.0, 0.04, 0.5, 1.0],
            "eta" => vec![0.01, 0.5, 1.0, 1.33, 1.5, 3.0, 10.0],
            "k" => vec![0.0, 0.5, 3.0, 20.0],
            _ => vec![min, 0.5 * (min + max), max],
        }
    }
    let mut choice_sets: Vec<Vec<(String, String)>> = vec![vec![]];
    let mut numeric: Vec<(&str, Vec<f64>, bool)> = vec![];
    for p in info.params {
        match p.kind {
            ParamKind::Choice { options, .. } => {
                choice_sets = choice_sets
                    .iter()
                    .flat_map(|set| {
                        options.iter().map(move |o| {
                            let mut s = set.clone();
                            s.push((p.name.to_string(), o.to_string()));
                            s
                        })
                    })
                    .collect();
            }
            ParamKind::Number { min, max, default } => {
                numeric.push((p.name, values(p.name, min, max), default.is_none()))
            }
        }
    }
    let rows = numeric.iter().map(|(_, v, _)| v.len()).max().unwrap_or(1);
    let rows: Vec<usize> = if light {
        (0..rows).step_by(rows.div_ceil(4).max(1)).collect()
    } else {
        (0..rows).collect()
    };
    let mut out = vec![];
    for set in &choice_sets {
        for &r in &rows {
            let mut s = set.clone();
            for (name, vals, optional) in &numeric {
                if *optional && r % 2 == 0 {
                    continue;
                }
                s.push((
                    name.to_string(),
                    vals[(r * 7 + name.len()) % vals.len()].to_string(),
                ));
            }
            out.push(s);
        }
    }
    out
}
