//! Chi-square goodness of fit of a sampler against its density (issue 15), as Mitsuba's
//! `ChiSquareTest`: draw `samples` directions, histogram them on `res_theta x res_phi` bins of
//! the upper hemisphere (theta in [0, pi/2], phi in [-pi, pi]), integrate the density over each
//! bin for the expected counts, pool the bins expecting fewer than 5 (Mitsuba's rule), and
//! read the p-value off the chi-square distribution. One more cell holds the draws that gave
//! no sample against `samples (1 - integral of the pdf)`, so the missing mass is tested too.
//!
//! Expected counts: `sub x sub` cells per bin, 5-point Gauss-Legendre in each (degree 9), on
//! `pdf(w) sin theta`, the cells doubled per bin until the value settles ([`expected`]). The p-value uses the regularised upper
//! incomplete gamma function written here ([`gamma_q`], Numerical Recipes' series and
//! continued fraction; tested against closed forms): 40 lines, where `statrs` would be a new
//! dependency (and its build) for one function.

use crate::sample::Rng;
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Sizes of one test.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    pub res_theta: usize,
    pub res_phi: usize,
    pub samples: usize,
    pub seed: u64,
    /// Integration cells per bin and axis.
    pub sub: usize,
    /// Significance before the Bonferroni correction.
    pub significance: f64,
}

impl Config {
    /// The CI sizes: 10 x 20 bins, 1e5 samples.
    pub fn ci() -> Self {
        Self {
            res_theta: 10,
            res_phi: 20,
            samples: 100_000,
            seed: 7,
            sub: 4,
            significance: 0.01,
        }
    }
    /// Mitsuba's sizes: 101 x 202 bins, 1e6 samples, 0.01.
    pub fn full() -> Self {
        Self {
            res_theta: 101,
            res_phi: 202,
            samples: 1_000_000,
            seed: 7,
            sub: 2,
            significance: 0.01,
        }
    }
}

/// What a test found.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Outcome {
    pub chi2: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The significance the p-value is held to (Bonferroni-corrected).
    pub threshold: f64,
    pub passed: bool,
    pub samples: usize,
    pub res_theta: usize,
    pub res_phi: usize,
    /// Counts per bin, row-major in theta.
    #[serde(skip)]
    pub observed: Vec<f64>,
    /// Expected counts per bin.
    #[serde(skip)]
    pub expected: Vec<f64>,
    /// Draws that gave no sample.
    pub missing_observed: f64,
    /// `samples (1 - pdf_integral)`.
    pub missing_expected: f64,
    /// The integral of the pdf over the upper hemisphere.
    pub pdf_integral: f64,
    /// Bins pooled for expecting fewer than 5.
    pub pooled: usize,
    /// A cell expecting 0 with draws in it (the p-value is then 0).
    pub impossible: bool,
}

/// The bin of direction `w` (any length), or `None` below the horizon.
pub fn bin(w: [f64; 3], res_theta: usize, res_phi: usize) -> Option<usize> {
    let l = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if !(l > 0.0) || w[2] < 0.0 {
        return None;
    }
    let theta = (w[2] / l).clamp(-1.0, 1.0).acos();
    let phi = w[1].atan2(w[0]);
    let i = ((theta / FRAC_PI_2 * res_theta as f64) as usize).min(res_theta - 1);
    let j = (((phi + PI) / TAU * res_phi as f64) as usize).min(res_phi - 1);
    Some(i * res_phi + j)
}

const GL5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_08),
    (0.906_179_845_938_664, 0.236_926_885_056_189_08),
];

/// The integral of `pdf` over bin `(i, j)` on `sub x sub` cells ([`bin_nodes`]).
fn bin_integral(
    pdf: &impl Fn([f64; 3]) -> f64,
    (i, j): (usize, usize),
    (res_theta, res_phi): (usize, usize),
    sub: usize,
) -> f64 {
    let mut acc = 0.0;
    let (dt, dp) = bin_nodes((i, j), (res_theta, res_phi), sub, |w, wtp, st| {
        acc += wtp * pdf(w) * st;
    });
    acc * 0.25 * dt * dp
}

/// The integration points of bin `(i, j)` on `sub x sub` cells, 5-point Gauss-Legendre in
/// each variable of each cell: `node(w, wt wp, sin theta)` per point (the integral of `f` is
/// `sum(wt wp f(w) sin theta) 0.25 dt dp`); returns the cell's sides `(dt, dp)`. Shared with
/// `fastbrdf conform`'s batched test, which evaluates all points of a round in one call.
pub fn bin_nodes(
    (i, j): (usize, usize),
    (res_theta, res_phi): (usize, usize),
    sub: usize,
    mut node: impl FnMut([f64; 3], f64, f64),
) -> (f64, f64) {
    let dt = FRAC_PI_2 / (res_theta * sub) as f64;
    let dp = TAU / (res_phi * sub) as f64;
    for a in 0..sub {
        let t0 = (i * sub + a) as f64 * dt;
        for b in 0..sub {
            let p0 = -PI + (j * sub + b) as f64 * dp;
            for (xt, wt) in GL5 {
                let t = t0 + 0.5 * dt * (1.0 + xt);
                let (st, ct) = t.sin_cos();
                for (xp, wp) in GL5 {
                    let p = p0 + 0.5 * dp * (1.0 + xp);
                    let (sp, cp) = p.sin_cos();
                    node([st * cp, st * sp, ct], wt * wp, st);
                }
            }
        }
    }
    (dt, dp)
}

/// The integral of `pdf` over every bin (row-major in theta): `sub x sub` cells per bin,
/// doubled until two successive values agree to 1e-4 relative (plus 1e-9), up to 128: a
/// narrow lobe squashed against the horizon (a grazing half-vector lobe) is thinner in theta
/// than its width suggests.
pub fn expected(
    pdf: &(impl Fn([f64; 3]) -> f64 + Sync),
    res_theta: usize,
    res_phi: usize,
    sub: usize,
) -> Vec<f64> {
    let res = (res_theta, res_phi);
    (0..res_theta)
        .into_par_iter()
        .flat_map_iter(|i| {
            (0..res_phi).map(move |j| {
                let mut s = sub.max(1);
                let mut v = bin_integral(pdf, (i, j), res, s);
                while s < 128 {
                    s *= 2;
                    let v2 = bin_integral(pdf, (i, j), res, s);
                    let done = (v2 - v).abs() <= 1e-4 * v2.abs() + 1e-9;
                    v = v2;
                    if done {
                        break;
                    }
                }
                v
            })
        })
        .collect()
}

/// [`run`] on a BRDF's sampler at `wo` by strategy `s`, against its f64 density. With `f32`,
/// the f32 model draws (at `wo` rounded to f32) and the f64 density is read at that rounded
/// `wo`: the f32 sampler is held to the exact density (`fastbrdf sample`, `tests/sampling.rs`).
pub fn run_brdf(
    b64: &dyn crate::model::Brdf<f64>,
    f32: Option<&dyn crate::model::Brdf<f32>>,
    wo: [f64; 3],
    s: crate::sample::Strategy,
    cfg: &Config,
    tests: usize,
) -> Outcome {
    run_brdf_with(b64, f32, wo, s, cfg, tests, &|| ())
}

/// [`run_brdf`] with a cancellation hook: `check` is called every [`CHECK_EVERY`] samples and
/// at every density evaluation (from rayon's threads too), so a caller can stop the test by
/// unwinding from it (the Python package's Ctrl-C). It must not change the outcome.
pub fn run_brdf_with(
    b64: &dyn crate::model::Brdf<f64>,
    f32: Option<&dyn crate::model::Brdf<f32>>,
    wo: [f64; 3],
    s: crate::sample::Strategy,
    cfg: &Config,
    tests: usize,
    check: &(dyn Fn() + Sync),
) -> Outcome {
    let drawn = std::sync::atomic::AtomicUsize::new(0);
    let tick = || {
        if drawn
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed)
            .is_multiple_of(CHECK_EVERY)
        {
            check();
        }
    };
    match f32 {
        Some(b32) => {
            let wo32 = wo.map(|x| x as f32);
            run(
                |u| {
                    tick();
                    b32.sample(wo32, [u[0] as f32, u[1] as f32], s)
                        .map(|x| x.wi.map(f64::from))
                },
                |wi| {
                    check();
                    b64.pdf(wo32.map(f64::from), wi, s)
                },
                cfg,
                tests,
            )
        }
        None => run(
            |u| {
                tick();
                b64.sample(wo, u, s).map(|x| x.wi)
            },
            |wi| {
                check();
                b64.pdf(wo, wi, s)
            },
            cfg,
            tests,
        ),
    }
}

/// How many samples [`run_brdf_with`] draws between two calls of its hook.
pub const CHECK_EVERY: usize = 4096;

/// Runs one test: `sample` maps `u` in [0, 1)^2 to a direction or no sample, `pdf` is the
/// density claimed for it; `tests` is the number of tests the significance is shared by
/// (Bonferroni).
pub fn run(
    sample: impl Fn([f64; 2]) -> Option<[f64; 3]>,
    pdf: impl Fn([f64; 3]) -> f64 + Sync,
    cfg: &Config,
    tests: usize,
) -> Outcome {
    let (rt, rp) = (cfg.res_theta, cfg.res_phi);
    let mut observed = vec![0.0; rt * rp];
    let mut missing = 0.0;
    let mut rng = Rng::new(cfg.seed);
    for _ in 0..cfg.samples {
        match sample(rng.pair()).and_then(|w| bin(w, rt, rp)) {
            Some(k) => observed[k] += 1.0,
            None => missing += 1.0,
        }
    }
    let n = cfg.samples as f64;
    let mut expected = expected(&pdf, rt, rp, cfg.sub);
    let integral: f64 = expected.iter().sum();
    for e in &mut expected {
        *e *= n;
    }
    let missing_expected = (n * (1.0 - integral)).max(0.0);
    let mut cells: Vec<(f64, f64)> = observed
        .iter()
        .copied()
        .zip(expected.iter().copied())
        .collect();
    cells.push((missing, missing_expected));
    let (chi2, dof, pooled, impossible) = statistic(&mut cells);
    let p_value = if impossible || dof == 0 {
        if impossible { 0.0 } else { 1.0 }
    } else {
        gamma_q(dof as f64 / 2.0, chi2 / 2.0)
    };
    let threshold = cfg.significance / tests.max(1) as f64;
    Outcome {
        chi2,
        dof,
        p_value,
        threshold,
        passed: p_value > threshold,
        samples: cfg.samples,
        res_theta: rt,
        res_phi: rp,
        observed,
        expected,
        missing_observed: missing,
        missing_expected,
        pdf_integral: integral,
        pooled,
        impossible,
    }
}

/// Pearson's statistic over `(observed, expected)` cells with Mitsuba's pooling: cells in
/// increasing order of expected count, those expecting fewer than 5 pooled (and cells after
/// them while the pool expects fewer than 5). Returns `(chi2, dof, pooled, impossible)`: a
/// cell observed but expecting nothing (or NaN) makes the histogram impossible under the pdf.
/// Shared with `fastbrdf conform`'s batched test.
pub fn statistic(cells: &mut [(f64, f64)]) -> (f64, usize, usize, bool) {
    const MIN: f64 = 5.0;
    cells.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (mut chi2, mut dof, mut pooled) = (0.0, 0usize, 0usize);
    let (mut pin, mut pexp) = (0.0, 0.0);
    let mut impossible = false;
    for &(o, e) in cells.iter() {
        if !(e > 0.0) && o > 0.0 {
            impossible = true;
        }
        if e < MIN || (pin > 0.0 && pexp < MIN) {
            pin += o;
            pexp += e;
            pooled += 1;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pin + pexp > 0.0 {
        if pexp > 0.0 {
            chi2 += (pin - pexp) * (pin - pexp) / pexp;
        } else if pin > 0.0 {
            impossible = true;
        }
        dof += 1;
    }
    (chi2, dof.saturating_sub(1), pooled, impossible)
}

/// The regularised upper incomplete gamma function `Q(a, x) = Gamma(a, x) / Gamma(a)`: the
/// chi-square survival function at `2x` with `2a` degrees of freedom.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let front = (-x + a * x.ln() - libm::lgamma(a)).exp();
    if x < a + 1.0 {
        // Series for P.
        let (mut ap, mut del) = (a, 1.0 / a);
        let mut sum = del;
        for _ in 0..100_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * front).clamp(0.0, 1.0)
    } else {
        // Lentz's continued fraction for Q.
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (front * h).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_q_matches_closed_forms() {
        // a = 1: Q = exp(-x); a = 1/2: Q = erfc(sqrt(x)); chi-square with 2 dof.
        for x in [0.01, 0.5, 1.0, 3.0, 10.0, 40.0] {
            let q1 = gamma_q(1.0, x);
            let e1 = (-x).exp();
            assert!((q1 - e1).abs() <= 1e-12 * e1, "{x}: {q1} vs {e1}");
            let qh = gamma_q(0.5, x);
            let e = libm::erfc(x.sqrt());
            assert!((qh - e).abs() <= 1e-12 * e.max(1e-15), "{x}: {qh} vs {e}");
        }
        // a = 3: Q = exp(-x)(1 + x + x^2/2).
        for x in [0.2, 2.0, 5.0, 30.0] {
            let q = gamma_q(3.0, x);
            let e = (-x).exp() * (1.0 + x + x * x / 2.0);
            assert!((q - e).abs() <= 1e-12 * e, "{x}: {q} vs {e}");
        }
        // The chi-square 1% point at 100 dof is 135.807.
        assert!((gamma_q(50.0, 135.807 / 2.0) - 0.01).abs() < 1e-5);
    }

    #[test]
    fn uniform_sampler_passes_and_a_biased_one_fails() {
        let cfg = Config::ci();
        let pdf = |w: [f64; 3]| if w[2] >= 0.0 { 1.0 / TAU } else { 0.0 };
        let uniform = |u: [f64; 2]| {
            let z = u[0];
            let s = (1.0 - z * z).sqrt();
            let (sp, cp) = (TAU * u[1]).sin_cos();
            Some([s * cp, s * sp, z])
        };
        let ok = run(uniform, pdf, &cfg, 1);
        assert!(ok.passed, "{ok:?}");
        assert!((ok.pdf_integral - 1.0).abs() < 1e-9);
        // z^1.05 instead of z: 5% off.
        let biased = |u: [f64; 2]| uniform([u[0].powf(0.95), u[1]]);
        let bad = run(biased, pdf, &cfg, 1);
        assert!(!bad.passed, "{bad:?}");
    }
}
