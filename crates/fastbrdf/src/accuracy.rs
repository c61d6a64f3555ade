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

fn in_zone(zone: Zone, rel: f64) -> bool {
    match zone {
        Zone::All => true,
        Zone::Epicentre => rel >= 0.5,
        Zone::Band { lo, hi } => rel > lo && rel < hi,
    }
}

fn error(metric: Metric, f: f64, r: f64, peak: f64) -> f64 {
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

/// The worst error of `model` against `bound.reference` for one parameter value `p`.
pub fn worst_at(model_id: &str, bound: &ErrorBound, p: f64) -> Result<Worst> {
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
    for &i in order.iter().take(8) {
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
