//! Measuring a model against its reference: the sample sets, zones and metrics behind every
//! documented [`ErrorBound`](crate::model::ErrorBound), with grid-then-golden-section
//! refinement of the maxima.
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
//!
//! The module's parts:
//! - this file: the curves, sample sets, zones and metrics, and the deterministic inputs
//!   (`splitmix`, `direction_pairs`) shared with the tests and benchmarks;
//! - [`bounds`]: a documented bound re-measured, on a grid ([`worst`]) and by adversarial
//!   search ([`worst_search`]);
//! - [`configs`]: the model specs covering a model's documented domain ([`domain_configs`]);
//! - [`precision`]: f32 against f64, over those specs ([`f32_worst`]) and by adversarial
//!   search over the whole domain ([`f32_search`]).

pub mod bounds;
pub mod configs;
pub mod kernels;
pub mod precision;

pub use bounds::{
    ALPHA_STEP_MIN, N_STEP_MAX, PER_DECADE, golden_max, param_values, worst, worst_at,
    worst_at_grid, worst_search,
};
pub use configs::domain_configs;
pub use kernels::{KernelWorst, kernel_worst};
pub use precision::{Found, f32_search, f32_worst};

use crate::error::Result;
use crate::model::{Metric, Model, Zone};
use crate::registry;
use crate::spec::{Given, ModelSpec};

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
        if let Some(e) = registry::find(id)
            .ok()
            .filter(|e| e.info.kind == crate::Kind::Env && name == "alpha")
        {
            // A term-less env model (the sheen albedo rows) is its own "bias" half.
            let has_term = e.info.params.iter().any(|p| p.name == "term");
            let term = |t: &str| match has_term {
                true => ModelSpec::new(id, &[("term", Given::Choice(t.into()))]),
                false => ModelSpec::new(id, &[]),
            };
            return Ok(Self {
                model: term("scale")?.model()?,
                env: Some((term("bias")?.model()?, value)),
            });
        }
        let given: Vec<(&str, Given)> = if name.is_empty() {
            vec![]
        } else {
            vec![(name, Given::Num(value))]
        };
        Ok(Self {
            model: ModelSpec::new(id, &given)?.model()?,
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

/// Maps `q` in [0, 1] onto a parameter range (logarithmically for ranges over positive
/// numbers spanning a factor 4 or more: exponents, roughnesses, indices).
fn param_at(q: f64, min: f64, max: f64) -> f64 {
    if log_mapped(min, max) {
        min * (max / min).powf(q)
    } else {
        min + q * (max - min)
    }
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
