//! Refits the constants of MaterialX's rational fit of the split-sum terms
//! (`env-brdf-materialx`) to the quadrature reference `env-brdf` (GGX, height-correlated
//! Smith): the constants of `env-brdf-materialx-tuned`
//! (`crates/fastbrdf/src/microfacet/env_rational.rs`, `TUNED`).
//! Run: `cargo run --release -p fastbrdf-analysis --example fit_env_rational`.
//!
//! Each term (scale, bias) separately: its numerator's 9 and its denominator's 8 free
//! coefficients (the constant stays 1) minimise the larger of the maximum and the mean
//! absolute error, each divided by MaterialX's (so that the max falls without the mean
//! rising); the max over a grid of
//! `cos_v` (denser at grazing) and `alpha` in [0.005, 1] (uniform and logarithmic), by
//! Nelder-Mead (`fastbrdf_analysis::simplex`) with restarts from MaterialX's constants; a
//! denominator that reaches 0 on the grid is refused (infinite objective). Then both constant
//! sets are measured on a finer grid.

use fastbrdf::microfacet::env_brdf::Dfg;
use fastbrdf::microfacet::env_rational::{Coeffs, MATERIALX, Rational, poly};
use fastbrdf::plan::EnvForm;
use fastbrdf_analysis::simplex::nelder_mead;
use rayon::prelude::*;

type Grid = Vec<(f64, f64, [f64; 2])>;
type X = fastbrdf::math::Exact;

fn reference(nv: usize, na: usize) -> Grid {
    let alphas: Vec<f64> = (0..na)
        .map(|j| 0.005 + 0.995 * j as f64 / (na - 1) as f64)
        .chain((0..na).map(|j| 0.005 * 200f64.powf(j as f64 / (na - 1) as f64)))
        .collect();
    let pts: Vec<(f64, f64)> = (1..=nv)
        .flat_map(|i| {
            let v = (i as f64 / nv as f64).powi(3);
            alphas.iter().map(move |&a| (v, a))
        })
        .collect();
    pts.into_par_iter()
        .map(|(v, a)| {
            let e = |bias| Dfg { bias }.e::<f64, X>(v, a);
            (v, a, [e(false), e(true)])
        })
        .collect()
}

/// The coefficients of one term from the 17 free numbers.
fn term(p: &[f64]) -> ([f64; 9], [f64; 9]) {
    let num: [f64; 9] = p[..9].try_into().unwrap();
    let mut den = [1.0; 9];
    den[1..].copy_from_slice(&p[9..17]);
    (num, den)
}

fn coeffs(bias: bool, p: &[f64], base: &Coeffs) -> Coeffs {
    let mut c = *base;
    let (n, d) = term(p);
    let (i, j) = if bias { (1, 3) } else { (0, 2) };
    c[i] = n;
    c[j] = d;
    c
}

/// The mean's grid: midpoints uniform in `cos_v` and `alpha` (as `fastbrdf errors` measures
/// the mean, fastbrdf_analysis::env_errors).
fn uniform(n: usize) -> Grid {
    let pts: Vec<(f64, f64)> = (0..n)
        .flat_map(|i| {
            (0..n).map(move |j| {
                let v = (i as f64 + 0.5) / n as f64;
                (v, 0.005 + 0.995 * (j as f64 + 0.5) / n as f64)
            })
        })
        .collect();
    pts.into_par_iter()
        .map(|(v, a)| {
            let e = |bias| Dfg { bias }.e::<f64, X>(v, a);
            (v, a, [e(false), e(true)])
        })
        .collect()
}

/// (max abs error, cos_v, alpha, mean abs error) of one term.
fn err(c: &Coeffs, bias: bool, grid: &Grid) -> (f64, f64, f64, f64) {
    let m = Rational::new(bias, c);
    let den = c[if bias { 3 } else { 2 }].map(fastbrdf::real::K::new);
    let mut worst = (0.0, 0.0, 0.0, 0.0);
    let mut sum = 0.0;
    for &(v, a, r) in grid {
        // A denominator that reaches 0 (or changes sign) is refused.
        let d = poly::<f64, X>(&den, v, a);
        if d <= 1e-6 {
            return (f64::INFINITY, v, a, f64::INFINITY);
        }
        let e = (m.e::<f64, X>(v, a) - r[bias as usize]).abs();
        sum += e;
        if e > worst.0 || e.is_nan() {
            worst = (e, v, a, 0.0);
        }
    }
    worst.3 = sum / grid.len() as f64;
    worst
}

fn main() {
    let coarse = reference(40, 24);
    let fine = reference(200, 80);
    let (mean_coarse, mean_fine) = (uniform(32), uniform(64));
    let mut tuned = MATERIALX;
    for bias in [false, true] {
        let name = if bias { "bias" } else { "scale" };
        let (e0, v0, a0, _) = err(&MATERIALX, bias, &fine);
        let m0 = err(&MATERIALX, bias, &mean_fine).3;
        println!(
            "{name}: MaterialX max {e0:.4e} (cos_v = {v0:.4}, alpha = {a0:.4}), mean {m0:.4e}"
        );
        let (i, j) = if bias { (1, 3) } else { (0, 2) };
        let start: Vec<f64> = MATERIALX[i]
            .iter()
            .chain(MATERIALX[j][1..].iter())
            .copied()
            .collect();
        // Both the max and the mean, relative to MaterialX's on this grid: the refit must
        // improve the max without giving up the mean.
        let (c0, m0c) = (
            err(&MATERIALX, bias, &coarse).0,
            err(&MATERIALX, bias, &mean_coarse).3,
        );
        let f = |p: &[f64]| {
            let c = coeffs(bias, p, &MATERIALX);
            (err(&c, bias, &coarse).0 / c0).max(err(&c, bias, &mean_coarse).3 / m0c)
        };
        let mut best = (start.clone(), f(&start));
        for round in 0..8 {
            let step = [0.3, 0.1, 0.03, 0.01, 0.1, 0.03, 0.01, 0.003][round];
            let (p, v) = nelder_mead(&f, &best.0, step, 20000);
            if v < best.1 {
                best = (p, v);
            }
            eprintln!("{name} round {round}: {:.4e}", best.1);
        }
        tuned = coeffs(bias, &best.0, &tuned);
        let (e1, v1, a1, _) = err(&tuned, bias, &fine);
        let m1 = err(&tuned, bias, &mean_fine).3;
        println!("{name}: refit max {e1:.4e} (cos_v = {v1:.4}, alpha = {a1:.4}), mean {m1:.4e}");
    }
    println!("pub const TUNED: Coeffs = [");
    for row in tuned {
        let l: Vec<String> = row.iter().map(|x| format!("{x:.6}")).collect();
        println!("    [{}],", l.join(", "));
    }
    println!("];");
}
