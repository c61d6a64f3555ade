//! Fits the constants of `sheen-albedo-tuned` (`crates/fastbrdf/src/microfacet/sheen_albedo.rs`,
//! `TUNED`): this project's form at the cost of the Khronos / Enterprise PBR fit,
//! `exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha`, against the quadrature
//! `sheen-albedo`, once per visibility (Charlie's, Neubelt's); and, for comparison, refits the
//! Khronos form's own 4 constants (`a (1 - mu)^3 + 1 / (b + exp(c sqrt(alpha) + d))`,
//! `sheen-albedo-khronos`), which gains little: the form, not its constants, is the limit.
//! Run: `cargo run --release -p fastbrdf-analysis --example fit_sheen_albedo`.
//!
//! Objective (as `fit_env_rational`): the larger of the max and the mean absolute error, each
//! divided by the Khronos constants' on the same grid (so that the max falls without the mean
//! rising); the max over `mu = 0.001 + 0.999 (i / 40)^2` and 24 uniform plus 24 logarithmic
//! `alpha` in [0.07, 1], the mean over 32 x 32 midpoints; Nelder-Mead
//! (`fastbrdf_analysis::simplex`) with restarts, from the Khronos constants and, for the new
//! form, from [`START`] (found by hand on this form). Then every constant set is measured on
//! finer grids (161 x 128 and 64 x 64; the ledger's own measurement: `fastbrdf errors --model
//! sheen-albedo-tuned`).

use fastbrdf::microfacet::sheen::{ALPHA_MIN, Vis, albedo_quadrature};
use fastbrdf::microfacet::sheen_albedo::{KHRONOS, fit, own};
use fastbrdf::real::K;
use fastbrdf_analysis::simplex::nelder_mead;
use rayon::prelude::*;

type Grid = Vec<(f64, f64, f64)>;

fn grid(pts: Vec<(f64, f64)>, vis: Vis) -> Grid {
    pts.into_par_iter()
        .map(|(m, a)| (m, a, albedo_quadrature(m, a, vis)))
        .collect()
}

fn max_grid(nm: usize, na: usize, vis: Vis) -> Grid {
    let alphas: Vec<f64> = (0..na)
        .map(|j| ALPHA_MIN + (1.0 - ALPHA_MIN) * j as f64 / (na - 1) as f64)
        .chain((0..na).map(|j| ALPHA_MIN * (1.0 / ALPHA_MIN).powf(j as f64 / (na - 1) as f64)))
        .collect();
    let pts = (0..=nm)
        .flat_map(|i| {
            let m = 0.001 + 0.999 * (i as f64 / nm as f64).powi(2);
            alphas.iter().map(move |&a| (m, a))
        })
        .collect();
    grid(pts, vis)
}

fn mean_grid(n: usize, vis: Vis) -> Grid {
    let mid = move |i: usize| (i as f64 + 0.5) / n as f64;
    let pts = (0..n)
        .flat_map(|i| {
            (0..n).map(move |j| {
                (
                    0.001 + 0.999 * mid(i),
                    ALPHA_MIN + (1.0 - ALPHA_MIN) * mid(j),
                )
            })
        })
        .collect();
    grid(pts, vis)
}

/// Where this project's form starts, per visibility (a hand search on the form).
const START: [[f64; 5]; 2] = [
    [-0.42, -1.63, 0.088, -1.0, 0.2],
    [-0.6, 0.63, 0.28, -1.7, -0.14],
];

type X = fastbrdf::math::Exact;

/// The Khronos form (4 constants) or this project's (5) at `(mu, alpha)`.
fn at(p: &[f64], m: f64, a: f64) -> f64 {
    match p.len() {
        4 => fit::<f64, X>(&[0, 1, 2, 3].map(|i| K::new(p[i])), m, a),
        _ => own::<f64, X>(&[0, 1, 2, 3, 4].map(|i| K::new(p[i])), m, a),
    }
}

/// (max abs error, mu, alpha, mean abs error) of constants `p` on `g`.
fn err(p: &[f64], g: &Grid) -> (f64, f64, f64, f64) {
    let mut worst = (0.0, 0.0, 0.0, 0.0);
    let mut sum = 0.0;
    for &(m, a, r) in g {
        let e = (at(p, m, a) - r).abs();
        sum += e;
        if e > worst.0 || e.is_nan() {
            worst = (e, m, a, 0.0);
        }
    }
    worst.3 = sum / g.len() as f64;
    worst
}

fn main() {
    let mut tuned = vec![];
    for (k, vis) in [Vis::Charlie, Vis::Neubelt].into_iter().enumerate() {
        let (coarse, fine) = (max_grid(40, 24, vis), max_grid(160, 64, vis));
        let (mean_coarse, mean_fine) = (mean_grid(32, vis), mean_grid(64, vis));
        let (c0, n0c) = (err(&KHRONOS, &coarse).0, err(&KHRONOS, &mean_coarse).3);
        let report = |what: &str, p: &[f64]| {
            let (e, m, a, _) = err(p, &fine);
            let n = err(p, &mean_fine).3;
            println!("{vis:?}: {what} max {e:.4e} (mu = {m:.4}, alpha = {a:.4}), mean {n:.4e}");
        };
        report("Khronos", &KHRONOS);
        let f = |p: &[f64]| (err(p, &coarse).0 / c0).max(err(p, &mean_coarse).3 / n0c);
        let search = |start: &[f64]| {
            let mut best = (start.to_vec(), f(start));
            for round in 0..8 {
                let step = [0.3, 0.1, 0.03, 0.01, 0.1, 0.03, 0.01, 0.003][round];
                let (p, v) = nelder_mead(&f, &best.0, step, 4000);
                if v < best.1 {
                    best = (p, v);
                }
                eprintln!("{vis:?} round {round}: {:.4e}", best.1);
            }
            best.0
        };
        report("Khronos form refitted", &search(&KHRONOS));
        let p = search(&START[k]);
        report("sheen-albedo-tuned", &p);
        tuned.push(p);
    }
    println!("pub const TUNED: [OwnCoeffs; 2] = [");
    for c in tuned {
        let l: Vec<String> = c.iter().map(|x| format!("{x:.8}")).collect();
        println!("    [{}],", l.join(", "));
    }
    println!("];");
}
