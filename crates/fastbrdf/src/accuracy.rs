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
//! The zone is decided by the reference value divided by its peak over the sample set, and
//! `MaxAbs` errors are divided by that peak, for every kind ([`error`]; the peak is 1 for
//! lobes and shadowing terms: [`abs_is_absolute`]).
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
///
/// Split-sum terms (`Kind::Env`) take `alpha` as an input, not a parameter: their curve at
/// `alpha = value` reads `x` in (0, 1] as the scale at `cos_v = x` and `x` in (1, 2] as the
/// bias at `cos_v = x - 1`, so that one error bound covers both terms.
pub struct Curve {
    model: Model<f64>,
    /// `Kind::Env`: the bias term and the `alpha` input.
    env: Option<(Model<f64>, f64)>,
}

impl Curve {
    /// Builds `id` with the parameter `name = value` (other parameters at their defaults).
    pub fn new(id: &str, name: &str, value: f64) -> Result<Self> {
        if registry::find(id).is_ok_and(|e| e.info.kind == crate::Kind::Env) && name == "alpha" {
            return Ok(Self {
                model: registry::build::<f64>(id, &[("term", "scale")])?,
                env: Some((registry::build::<f64>(id, &[("term", "bias")])?, value)),
            });
        }
        let v = value.to_string();
        let given: Vec<(&str, &str)> = if name.is_empty() {
            vec![]
        } else {
            vec![(name, &v)]
        };
        Ok(Self {
            model: registry::build::<f64>(id, &given)?,
            env: None,
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
            Model::Env(scale) => match &self.env {
                Some((Model::Env(bias), alpha)) if x > 1.0 => bias.e(x - 1.0, *alpha),
                Some((_, alpha)) => scale.e(x, *alpha),
                None => scale.e(x, 0.3),
            },
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
        // Both terms (see `Curve`), denser at grazing where the terms bend.
        Model::Env(_) => (1..=200)
            .map(|i| (i as f64 / 200.0).powi(3))
            .flat_map(|x| [x, 1.0 + x])
            .collect(),
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

/// Whether a [`Metric::MaxAbs`] bound of a model of `kind` is an absolute error: the error is
/// divided by the reference's peak for every kind ([`error`]), and that peak is exactly 1 at
/// every parameter value for lobes (`c^n` at `c = 1`, a sample of [`lobe_samples`]) and
/// shadowing terms (`G1` at `cos = 1`, a sample too); below 1 for Fresnel (its value at the
/// smallest sampled cosine) and the split-sum terms, `1 / (pi alpha^2)`-sized for
/// distributions and BRDFs. `tests/bound_meaning.rs` measures this for every documented bound.
pub fn abs_is_absolute(kind: crate::Kind) -> bool {
    matches!(kind, crate::Kind::Lobe | crate::Kind::Shadowing)
}

/// The short name of a bound of a model of `kind` (`fastbrdf models`' table): `abs` (an
/// absolute error, [`abs_is_absolute`]), `abs/peak` (divided by the reference's peak) or
/// `rel` (divided by the reference's value).
pub fn bound_label(kind: crate::Kind, metric: Metric) -> &'static str {
    match metric {
        Metric::MaxAbs if abs_is_absolute(kind) => "abs",
        Metric::MaxAbs => "abs/peak",
        Metric::MaxRel => "rel",
    }
}

/// The error of `f` against the reference value `r` under `metric`: `MaxAbs` divided by
/// `peak` (the reference's largest sampled value at the same parameter, for every kind:
/// [`abs_is_absolute`] says where that is 1), `MaxRel` by `r`.
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

/// The parameter values a bound is checked on: for lobes n = lo..=hi in steps of 1 up to
/// [`N_STEP_MAX`], then [`PER_DECADE`] log-spaced values per decade to `hi`; for the rest
/// alpha log-spaced ([`PER_DECADE`] per decade) below [`ALPHA_STEP_MIN`], then in steps of
/// 0.01. Ranges inside the stepped part (the seeds' n = 1..1000, alpha = 0.05..0.6) get the
/// same grid as before the domain was widened (issue 14); the log-spaced tails keep a bound
/// over n up to 1e5 at about 1.2 times the cost of one over 1..1000.
pub fn param_values(bound: &ErrorBound) -> Vec<f64> {
    let (name, lo, hi) = bound.param;
    let mut out = vec![];
    let log_part = |out: &mut Vec<f64>, a: f64, b: f64| {
        // a, a r, a r^2, ... below b (b itself is left to the caller).
        let count = ((b / a).log10() * PER_DECADE).ceil().max(1.0) as usize;
        out.extend((0..count).map(|i| a * (b / a).powf(i as f64 / count as f64)));
    };
    if name == "n" {
        let top = hi.min(N_STEP_MAX);
        if lo <= top {
            let count = ((top - lo) / 1.0).round() as usize;
            out.extend((0..=count).map(|i| (lo + i as f64).min(top)));
        }
        if hi > N_STEP_MAX {
            let a = lo.max(N_STEP_MAX);
            log_part(&mut out, a, hi);
            out.retain(|&x| x >= lo);
            out.push(hi);
        }
    } else {
        // Small positive slopes logarithmically; a range from 0 (Fresnel's f0) linearly.
        let log = lo > 0.0 && lo < ALPHA_STEP_MIN;
        if log {
            log_part(&mut out, lo, hi.min(ALPHA_STEP_MIN));
        }
        let a = if log { lo.max(ALPHA_STEP_MIN) } else { lo };
        if a <= hi {
            let count = ((hi - a) / 0.01).round() as usize;
            out.extend((0..=count).map(|i| (a + i as f64 * 0.01).min(hi)));
        } else {
            out.push(hi);
        }
    }
    out.dedup();
    out
}

/// Above this exponent [`param_values`] steps n logarithmically.
pub const N_STEP_MAX: f64 = 1000.0;
/// Below this slope [`param_values`] steps alpha logarithmically.
pub const ALPHA_STEP_MIN: f64 = 0.05;
/// Log-spaced parameter values per decade in [`param_values`].
pub const PER_DECADE: f64 = 100.0;

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
                let (s32, s64) = shadow_inputs(wi, wo, true);
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
        (Model::Env(a), Model::Env(b)) => {
            for i in 0..=40 {
                let c32 = (i as f32 / 40.0).powi(2);
                for j in 0..=20 {
                    let a32 = 0.005f32 + (1.0 - 0.005) * (j as f32 / 20.0).powi(2);
                    note(
                        mixed_error(a.e(c32, a32), b.e(c32 as f64, a32 as f64)),
                        &|| format!("cos_v={c32} alpha={a32}"),
                    );
                }
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
/// appears). Optional parameters (`alpha_x`, `alpha_y` of Ward and Cook-Torrance) are given
/// on odd rows only, where their `requires` hold ([`crate::params::ParamSpec::allowed`]), both
/// at the same value (the anisotropic code paths at equal slopes; truly anisotropic slopes
/// have their own tests: `tests/reference.rs`, `tests/precision.rs`, `tests/batch.rs`, the
/// GPU crate's `tests/parity.rs`).
/// `light` keeps about four numeric rows (for the BRDFs, whose choice products are large).
pub fn domain_configs(info: &crate::ModelInfo, light: bool) -> Vec<Vec<(String, String)>> {
    use crate::params::ParamKind;
    fn values(name: &str, min: f64, max: f64) -> Vec<f64> {
        match name {
            "n" => vec![
                1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 16.0, 20.0, 33.0, 50.0, 100.0, 128.0,
                200.0, 333.0, 500.0, 777.0, 1000.0, 2000.0, 5000.0, 10000.0, 30000.0, 100000.0,
            ],
            // 0.7072 sits just above 1/sqrt(2), where seed 000's exponent 2/alpha^2 - 4 changes sign.
            "alpha" | "alpha_x" | "alpha_y" => {
                vec![
                    0.005, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7072, 0.85, 1.0,
                ]
            }
            "f0" => vec![0.0, 0.04, 0.5, 1.0],
            "eta" => vec![0.01, 0.5, 1.0, 1.33, 1.5, 3.0, 10.0],
            "k" => vec![0.0, 0.5, 3.0, 20.0],
            _ => vec![min, 0.5 * (min + max), max],
        }
    }
    let choice_sets = choice_sets(info);
    let mut numeric: Vec<(&crate::params::ParamSpec, Vec<f64>, bool)> = vec![];
    for p in info.params {
        if let ParamKind::Number {
            min, max, default, ..
        } = p.kind
        {
            numeric.push((p, values(p.name, min, max), default.is_none()))
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
            for (spec, vals, optional) in &numeric {
                let name = spec.name;
                let choice = |n: &str| set.iter().find(|(k, _)| k == n).map(|(_, v)| v.clone());
                if *optional && (r % 2 == 0 || !spec.allowed(choice)) {
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

// ---------- adversarial search over the whole documented domain ----------

/// The size of an adversarial search ([`f32_search`]): per combination of a model's choice
/// parameters, `restarts` random starts, each followed by `steps` hill-climbing steps over the
/// numeric parameters and the inputs together. Deterministic for a given `seed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SearchSize {
    pub restarts: usize,
    pub steps: usize,
    pub seed: u64,
}

impl SearchSize {
    /// The size `tests/precision.rs` and `fastbrdf check` use (about 7 million evaluations
    /// for the whole registry; seconds in release, about a minute in the test profile).
    pub const CI: Self = Self {
        restarts: 12,
        steps: 400,
        seed: 0x0011_5eed,
    };
    /// `fastbrdf check --full`: 8x the restarts and 4x the steps of [`SearchSize::CI`]
    /// (32x the evaluations), with another seed, so that it looks where CI did not.
    pub const FULL: Self = Self {
        restarts: 96,
        steps: 1600,
        seed: 0x00f1_11ed,
    };
}

/// What an adversarial search found: the largest mixed f32-vs-f64 error, where, and the
/// first non-finite or negative value (in either precision), if any.
#[derive(Clone, Debug, Default)]
pub struct Found {
    /// The largest `|v32 - v64| / max(1, |v64|)` found (infinite if a value was invalid).
    pub err: f64,
    /// The parameters (as given to the registry) where it occurs.
    pub params: Vec<(String, String)>,
    /// The input where it occurs.
    pub at: String,
    /// A non-finite or negative value found, with its parameters and input.
    pub invalid: Option<String>,
    /// Model evaluations (each in both precisions).
    pub evaluations: usize,
}

/// Values worth starting from for a numeric parameter: its edges, its default, the values
/// of [`domain_configs`] and, for `eta`, 1 (where the Fresnel terms vanish).
fn special_values(name: &str, min: f64, max: f64) -> Vec<f64> {
    let mut v = match name {
        "n" => vec![1.0, 2.0, 10.0, 100.0, 1000.0, 5000.0, 30000.0],
        "alpha" | "alpha_x" | "alpha_y" => vec![0.01, 0.05, 0.1, 0.5, 0.7072],
        "eta" => vec![1.0, 0.5, 1.5, 0.99, 1.01],
        "k" => vec![0.5, 3.0],
        _ => vec![0.5 * (min + max)],
    };
    v.extend([min, max]);
    v.retain(|x| *x >= min && *x <= max);
    v
}

/// The f32 value nearest to `v` inside `[min, max]`, written so that f64 parses it exactly:
/// both precisions then build the same model (a parameter's own rounding to f32 is a
/// different model, not an arithmetic error).
fn f32_param(v: f64, min: f64, max: f64) -> String {
    let mut x = v.clamp(min, max) as f32;
    while (x as f64) < min {
        x = f32_step(x, true);
    }
    while (x as f64) > max {
        x = f32_step(x, false);
    }
    (x as f64).to_string()
}

/// The next f32 above (`up`) or below `x` (`f32::next_up` needs Rust 1.86; MSRV 1.85).
fn f32_step(x: f32, up: bool) -> f32 {
    if x == 0.0 {
        let tiny = f32::from_bits(1);
        if up { tiny } else { -tiny }
    } else if (x > 0.0) == up {
        f32::from_bits(x.to_bits() + 1)
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

/// Maps `q` in [0, 1] onto a parameter range (logarithmically for ranges over positive
/// numbers spanning a factor 4 or more: exponents, roughnesses, indices).
fn param_at(q: f64, min: f64, max: f64) -> f64 {
    if log_mapped(min, max) {
        min * (max / min).powf(q)
    } else {
        min + q * (max - min)
    }
}

/// A shadowing term's inputs for the unit pair (`wi`, `wo`): in f32, and the same f32 values
/// in f64 (both precisions are fed the same inputs). `with_l` gives the two-sided form `cos_l`.
fn shadow_inputs(
    wi: [f64; 3],
    wo: [f64; 3],
    with_l: bool,
) -> (
    crate::model::ShadowInput<f32>,
    crate::model::ShadowInput<f64>,
) {
    let s = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
    let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let s32 = crate::model::ShadowInput {
        cos_v: wo[2] as f32,
        cos_l: if with_l { Some(wi[2] as f32) } else { None },
        cos_h: (s[2] / len) as f32,
        cos_vh: (0.5 * len) as f32,
    };
    let s64 = crate::model::ShadowInput {
        cos_v: s32.cos_v as f64,
        cos_l: s32.cos_l.map(f64::from),
        cos_h: s32.cos_h as f64,
        cos_vh: s32.cos_vh as f64,
    };
    (s32, s64)
}

/// The inverse of [`param_at`]: the `q` of parameter value `v`.
fn param_q(v: f64, min: f64, max: f64) -> f64 {
    if log_mapped(min, max) {
        (v / min).ln() / (max / min).ln()
    } else {
        (v - min) / (max - min)
    }
}

/// Whether [`param_at`] maps `[min, max]` logarithmically (positive, two or more octaves).
fn log_mapped(min: f64, max: f64) -> bool {
    min > 0.0 && max / min >= 4.0
}

/// A cosine from `u` in [0, 1] in one of three densities: uniform, dense near 1
/// (`1 - u^6`: narrow lobes) and dense near 0 (`u^6`: grazing, down to 1e-36).
fn cos_at(u: f64, mode: usize) -> f64 {
    match mode % 3 {
        0 => u,
        1 => 1.0 - u.powi(6),
        _ => u.powi(6),
    }
}

/// The direction pair for a BRDF or shadowing term from `u[0..4]`: `wi` from its cosine
/// (`cos_at`, or log-uniform in [COS_MIN, 1] for grazing) and azimuth, `wo` the reflection of `wi` about a microfacet normal `h` at
/// `theta_h = (pi/2) u^3` (dense near the mirror direction). Every pair of the upper
/// hemisphere has such a form.
fn pair_at(u: &[f64], mode: usize, target: Target) -> ([f32; 3], [f32; 3]) {
    use std::f64::consts::PI;
    if let (3, Target::Mirror(b)) = (mode, target) {
        // wo at the angle acos(b) (+- 1e-5) from the mirror direction of wi.
        let ci = u[0].max(1e-3);
        let si = ((1.0 - ci) * (1.0 + ci)).sqrt();
        let pi_ = 2.0 * PI * u[1];
        let wi = [si * pi_.cos(), si * pi_.sin(), ci];
        let r = [-wi[0], -wi[1], wi[2]];
        let g = b.clamp(-1.0, 1.0).acos() + 1e-5 * (2.0 * u[2] - 1.0);
        // An orthonormal pair (t1, t2) perpendicular to r.
        let t1 = [r[2] * pi_.cos(), r[2] * pi_.sin(), -si];
        let t2 = [
            r[1] * t1[2] - r[2] * t1[1],
            r[2] * t1[0] - r[0] * t1[2],
            r[0] * t1[1] - r[1] * t1[0],
        ];
        let ph = 2.0 * PI * u[3];
        let wo: [f64; 3] = std::array::from_fn(|k| {
            g.cos() * r[k] + g.sin() * (ph.cos() * t1[k] + ph.sin() * t2[k])
        });
        return (wi.map(|x| x as f32), wo.map(|x| x as f32));
    }
    // Grazing density: log-uniform from COS_MIN (below it every BRDF is 0 by rule) to 1.
    let ci = if mode % 3 == 2 {
        crate::vec3::COS_MIN.powf(1.0 - u[0])
    } else {
        cos_at(u[0], mode).clamp(0.0, 1.0)
    };
    let si = ((1.0 - ci) * (1.0 + ci)).sqrt();
    let pi_ = 2.0 * PI * u[1];
    let wi = [si * pi_.cos(), si * pi_.sin(), ci];
    let th = match (mode, target) {
        (3, Target::Half(b)) => b.clamp(-1.0, 1.0).acos() + 1e-5 * (2.0 * u[2] - 1.0),
        _ => 0.5 * PI * u[2].powi(3),
    };
    let ph = 2.0 * PI * u[3];
    let h = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
    let d = 2.0 * (wi[0] * h[0] + wi[1] * h[1] + wi[2] * h[2]);
    let wo = [d * h[0] - wi[0], d * h[1] - wi[1], d * h[2] - wi[2]];
    (wi.map(|x| x as f32), wo.map(|x| x as f32))
}

/// A break of the model (a cut or kink) that restarts of mode 3 start near: a cosine (lobes,
/// distributions), `reflect(wi).wo` (phong) or `cos theta_h` (blinn-phong).
#[derive(Clone, Copy, Debug)]
enum Target {
    None,
    Cos(f64),
    Mirror(f64),
    Half(f64),
}

/// The breaks of a model ([`Target`]s).
fn targets(m: &Model<f64>) -> Vec<Target> {
    match m {
        Model::Lobe(l) => {
            let mut t: Vec<Target> = l.kinks().into_iter().map(Target::Cos).collect();
            t.push(Target::Cos(l.zero_below()));
            t
        }
        Model::Brdf(b) => b
            .mirror_breaks()
            .into_iter()
            .map(Target::Mirror)
            .chain(b.half_breaks().into_iter().map(Target::Half))
            .collect(),
        _ => vec![],
    }
}

/// One evaluation in both precisions on the same f32 input: `(mixed error, where)`; the
/// error is infinite when either value is non-finite or negative.
fn eval_both(
    m32: &Model<f32>,
    m64: &Model<f64>,
    u: &[f64],
    mode: usize,
    target: Target,
) -> (f64, String) {
    let judge = |v32: f32, v64: f64| {
        if !(v32.is_finite() && v32 >= 0.0 && v64.is_finite() && v64 >= 0.0) {
            f64::INFINITY
        } else {
            mixed_error(v32, v64)
        }
    };
    match (m32, m64) {
        (Model::Lobe(a), Model::Lobe(b)) => {
            let c = match (mode, target) {
                (3, Target::Cos(t)) => (t + 1e-5 * (2.0 * u[0] - 1.0)).clamp(0.0, 1.0) as f32,
                _ => cos_at(u[0], mode) as f32,
            };
            let (v32, v64) = (a.eval(c), b.eval(c as f64));
            (judge(v32, v64), format!("c={c} f32={v32} f64={v64}"))
        }
        (Model::Distribution(a), Model::Distribution(b)) => {
            let c = cos_at(u[0], mode) as f32;
            let (v32, v64) = (a.eval(c), b.eval(c as f64));
            (judge(v32, v64), format!("cos_h={c} f32={v32} f64={v64}"))
        }
        (Model::Fresnel(a), Model::Fresnel(b)) => {
            let c = cos_at(u[0], mode) as f32;
            let (v32, v64) = (a.f(c), b.f(c as f64));
            (judge(v32, v64), format!("cos={c} f32={v32} f64={v64}"))
        }
        (Model::Shadowing(a), Model::Shadowing(b)) => {
            let (wi, wo) = pair_at(u, mode, target);
            let (wi, wo) = (wi.map(f64::from), wo.map(f64::from));
            let (s32, s64) = shadow_inputs(wi, wo, u[4] < 0.5);
            let (v32, v64) = (a.g(&s32), b.g(&s64));
            (judge(v32, v64), format!("{s32:?} f32={v32} f64={v64}"))
        }
        (Model::Env(a), Model::Env(b)) => {
            let c = cos_at(u[0], mode) as f32;
            let (lo, hi) = crate::params::ALPHA.range();
            let al = (lo * (hi / lo).powf(u[1])) as f32;
            let (v32, v64) = (a.e(c, al), b.e(c as f64, al as f64));
            (
                judge(v32, v64),
                format!("cos_v={c} alpha={al} f32={v32} f64={v64}"),
            )
        }
        (Model::Brdf(a), Model::Brdf(b)) => {
            let (wi, wo) = pair_at(u, mode, target);
            let v32 = a.eval(wi, wo);
            let v64 = b.eval(wi.map(f64::from), wo.map(f64::from));
            (
                judge(v32, v64),
                format!("wi={wi:?} wo={wo:?} f32={v32} f64={v64}"),
            )
        }
        _ => unreachable!("both precisions build the same kind"),
    }
}

/// Adversarial search for the largest f32-vs-f64 error of `info`'s model over its whole
/// documented domain: for every combination of its choice parameters, random restarts
/// (numeric parameters at their edges, at special values or uniform, logarithmically for
/// wide positive ranges; optional parameters given or not; inputs in three densities),
/// each refined by hill climbing over the numeric parameters and the inputs together with a
/// step shrinking geometrically from 0.3 to 1e-7. Numeric parameters are f32 values, fed
/// exactly to both precisions. Also records any non-finite or negative value.
pub fn f32_search(info: &crate::ModelInfo, size: SearchSize) -> Found {
    use crate::params::ParamKind;
    let choice_sets = choice_sets(info);
    let mut numeric: Vec<(&str, f64, f64, bool)> = vec![];
    for p in info.params {
        if let ParamKind::Number {
            min, max, default, ..
        } = p.kind
        {
            numeric.push((p.name, min, max, default.is_none()))
        }
    }
    let dims = match info.kind {
        crate::Kind::Brdf => 4,
        crate::Kind::Shadowing => 5,
        crate::Kind::Env => 2,
        _ => 1,
    };
    let mut state = size.seed ^ (info.id.len() as u64).wrapping_mul(0x9E37_79B9);
    for b in info.id.bytes() {
        state = state.rotate_left(5) ^ b as u64;
    }
    let mut rnd = move || splitmix(&mut state);
    let mut found = Found::default();
    // q: numeric coordinates in [0, 1]; given: whether each optional one is given.
    let given_of = |set: &[(String, String)], q: &[f64], on: &[bool]| {
        let mut g = set.to_vec();
        for (i, &(name, min, max, _)) in numeric.iter().enumerate() {
            if on[i] {
                g.push((
                    name.to_string(),
                    f32_param(param_at(q[i], min, max), min, max),
                ));
            }
        }
        g
    };
    let build = |g: &[(String, String)]| {
        let refs: Vec<(&str, &str)> = g.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        let m32 = registry::build::<f32>(info.id, &refs).ok()?;
        let m64 = registry::build::<f64>(info.id, &refs).ok()?;
        Some((m32, m64))
    };
    for set in &choice_sets {
        // Whether this choice combination has breaks (at default parameters).
        let breaks = build(set).map(|m| targets(&m.1)).unwrap_or_default();
        for r in 0..size.restarts {
            // Modes 0-2: input densities; mode 3 (every fourth restart of a model with cuts
            // or kinks): near one of them.
            let mode = if breaks.is_empty() { r % 3 } else { r % 4 };
            let mut target = Target::None;
            let mut q: Vec<f64> = numeric
                .iter()
                .map(|&(name, min, max, _)| {
                    let t = rnd();
                    if t < 0.2 {
                        0.0
                    } else if t < 0.4 {
                        1.0
                    } else if t < 0.6 {
                        let s = special_values(name, min, max);
                        let v = s[(rnd() * s.len() as f64) as usize % s.len()];
                        param_q(v, min, max)
                    } else {
                        rnd()
                    }
                })
                .collect();
            let on: Vec<bool> = numeric
                .iter()
                .map(|&(_, _, _, optional)| !optional || rnd() < 0.5)
                .collect();
            let mut u: Vec<f64> = (0..dims).map(|_| rnd()).collect();
            let mut g = given_of(set, &q, &on);
            let Some(mut models) = build(&g) else {
                continue; // e.g. a combination the model refuses: not part of its domain
            };
            if mode == 3 {
                let t = targets(&models.1);
                if t.is_empty() {
                    continue;
                }
                target = t[(rnd() * t.len() as f64) as usize % t.len()];
            }
            let (mut e, mut at) = eval_both(&models.0, &models.1, &u, mode, target);
            found.evaluations += 1;
            for t in 0..size.steps {
                let sigma = 0.3 * (1e-7f64 / 0.3).powf(t as f64 / size.steps as f64);
                let step = |x: f64, r: f64| (x + sigma * (2.0 * r - 1.0)).clamp(0.0, 1.0);
                if !numeric.is_empty() && mode != 3 && rnd() < 0.15 {
                    let q2: Vec<f64> = q
                        .iter()
                        .map(|&x| if rnd() < 0.5 { step(x, rnd()) } else { x })
                        .collect();
                    let g2 = given_of(set, &q2, &on);
                    if let Some(m2) = build(&g2) {
                        let (e2, at2) = eval_both(&m2.0, &m2.1, &u, mode, target);
                        found.evaluations += 1;
                        if e2 >= e {
                            (q, g, models, e, at) = (q2, g2, m2, e2, at2);
                        }
                    }
                } else {
                    let u2: Vec<f64> = u.iter().map(|&x| step(x, rnd())).collect();
                    let (e2, at2) = eval_both(&models.0, &models.1, &u2, mode, target);
                    found.evaluations += 1;
                    if e2 >= e {
                        (u, e, at) = (u2, e2, at2);
                    }
                }
            }
            if e.is_infinite() && found.invalid.is_none() {
                found.invalid = Some(format!("{g:?} {at}"));
            }
            if e > found.err || found.params.is_empty() {
                found.err = e;
                found.params = g;
                found.at = at;
            }
        }
    }
    found
}

/// Adversarial search for the worst error of `model_id` against a documented
/// [`ErrorBound`], over the bound's whole parameter range as a continuum (the grid of
/// [`worst`] steps `n` by 1 and `alpha` by 0.01): per restart, a parameter at an edge of the
/// range or log-uniform in it, an input drawn from the sample set, then hill climbing over
/// the parameter and the input together (golden-section refinement of [`worst_at`] does
/// the final polishing around the best point). Deterministic for a given size.
pub fn worst_search(model_id: &str, bound: &ErrorBound, size: SearchSize) -> Result<Worst> {
    let (name, lo, hi) = bound.param;
    let mut state = size.seed ^ 0xB0_0D5;
    for b in model_id.bytes().chain(bound.reference.bytes()) {
        state = state.rotate_left(7) ^ b as u64;
    }
    let mut rnd = move || splitmix(&mut state);
    let p_at = |q: f64| param_at(q, lo, hi).clamp(lo, hi);
    // The error function of x for one parameter value, with the sample set's peak (zones
    // and the MaxAbs scale are relative to it, as in `worst_at`).
    struct At {
        m: Curve,
        r: Curve,
        peak: f64,
        xs: Vec<f64>,
    }
    let at_p = |p: f64| -> Result<At> {
        let m = Curve::new(model_id, name, p)?;
        let r = Curve::new(bound.reference, name, p)?;
        let xs = samples(&m.model, p);
        let peak = xs
            .iter()
            .map(|&x| r.at(x))
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        Ok(At { m, r, peak, xs })
    };
    let err = |a: &At, x: f64| {
        let rv = a.r.at(x);
        if in_zone(bound.zone, rv / a.peak) {
            error(bound.metric, a.m.at(x), rv, a.peak)
        } else {
            0.0
        }
    };
    let mut best = Worst::default();
    let restarts = size.restarts * 4;
    let steps = size.steps / 2;
    for r in 0..restarts {
        let mut q = match r % 4 {
            0 => 0.0,
            1 => 1.0,
            _ => rnd(),
        };
        let mut a = at_p(p_at(q))?;
        let (xlo, xhi) =
            a.xs.iter()
                .fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        let mut x = a.xs[(rnd() * a.xs.len() as f64) as usize % a.xs.len()];
        let mut e = err(&a, x);
        best.samples += 1;
        for t in 0..steps {
            let sigma = 0.1 * (1e-9f64 / 0.1).powf(t as f64 / steps as f64);
            if rnd() < 0.1 && lo < hi {
                let q2 = (q + sigma * (2.0 * rnd() - 1.0)).clamp(0.0, 1.0);
                let a2 = at_p(p_at(q2))?;
                best.samples += a2.xs.len();
                let e2 = err(&a2, x);
                if e2 >= e {
                    (q, a, e) = (q2, a2, e2);
                }
            } else {
                let x2 = (x + sigma * (xhi - xlo) * (2.0 * rnd() - 1.0)).clamp(xlo, xhi);
                let e2 = err(&a, x2);
                best.samples += 1;
                if e2 >= e {
                    (x, e) = (x2, e2);
                }
            }
        }
        if e > best.err {
            best.err = e;
            best.param = p_at(q);
            best.x = x;
        }
    }
    Ok(best)
}

/// Every combination of a model's choice parameters (one empty set when it has none).
fn choice_sets(info: &crate::ModelInfo) -> Vec<Vec<(String, String)>> {
    let mut sets: Vec<Vec<(String, String)>> = vec![vec![]];
    for p in info.params {
        if let crate::params::ParamKind::Choice { options, default } = p.kind {
            sets = sets
                .iter()
                .flat_map(|set| {
                    options
                        .names()
                        .iter()
                        // Gated options only where their requirements hold (`Options::Gated`).
                        .filter(|o| {
                            options.allows(o, default, |n| {
                                set.iter().find(|(k, _)| k == n).map(|(_, v)| v.clone())
                            })
                        })
                        .map(move |o| {
                            let mut s = set.clone();
                            s.push((p.name.to_string(), o.to_string()));
                            s
                        })
                })
                .collect();
        }
    }
    sets
}
