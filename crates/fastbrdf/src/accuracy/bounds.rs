//! A documented [`ErrorBound`] re-measured: the worst error over the bound's parameter range,
//! on a grid with golden-section refinement of the maxima ([`worst`], [`worst_at`]) and by an
//! adversarial search over the range as a continuum ([`worst_search`]).

use super::{Curve, SearchSize, Worst, error, in_zone, param_at, samples, splitmix};
use crate::error::Result;
use crate::model::ErrorBound;

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
