//! Energy normalisation of a lobe used as a Phong BRDF, and closed-form fits of `coef(n)`.
//!
//! `Int(n) = integral_0^{pi/2} lobe(cos t) cos t sin t dt = integral_0^1 lobe(c) c dc`, by
//! adaptive Gauss-Kronrod in f64 to relative tolerance 1e-12, split at the lobe's zero
//! (`Lobe::zero_below`: flog's `2^(-3/n)`, the power forms' `1 - g/n`, the cubics' cut) and
//! kinks (`cubic-rational`'s junction); the integrand is bounded at both ends for every lobe.
//! `coef(n) = 1 / (2 pi Int(n))` makes the albedo of `coef(n) lobe(r . wo)` exactly 1 at
//! normal incidence.
//!
//! Fits (`--fit FORM`), weighted least squares on the relative error:
//! - `seed`: `a (n + b) + c / (d + n)`, seed 001's form. Linear in `(a, a b, c)` for fixed `d`,
//!   so `d` is found by a scan and golden-section search, the rest by linear least squares.
//! - `linear`: `a (n + b)`.
//! - `seed-published`: no fit; seed 001's printed constants `0.197, 1.24, 0.068, 0.64`.
//!
//! The energy residual of a fit is `max |coef_fit(n) 2 pi Int(n) - 1| = max |coef_fit / coef - 1|`.

use fastbrdf::Result;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

/// `Int(n)`, `coef(n)` and the quadrature's error estimate.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct NormRow {
    pub n: f64,
    pub int: f64,
    pub coef: f64,
    /// Estimated absolute error of `int`.
    pub int_err: f64,
}

/// `Int(n)` of lobe `id` with its error estimate (closed form `1 / (n + 2)` is not used here,
/// so that `pow` checks the quadrature).
pub fn integral(id: &str, n: f64) -> Result<(f64, f64)> {
    let lobe = fastbrdf::registry::lobe::<f64>(id, n)?;
    let lo = lobe.zero_below();
    let mut breaks = lobe.kinks();
    breaks.push(lo);
    // The lobe's width in c is about 1/n: start the adaptive split there.
    for k in [1.0, 4.0, 16.0, 64.0] {
        breaks.push(1.0 - k / n);
    }
    Ok(fastbrdf::quad::integrate(
        |c| lobe.eval(c) * c,
        lo,
        1.0,
        &breaks,
        1e-12,
    ))
}

/// `Int(n)` and `coef(n)` for every `n`, in parallel.
pub fn table(id: &str, ns: &[f64]) -> Result<Vec<NormRow>> {
    ns.par_iter()
        .map(|&n| {
            let (int, int_err) = integral(id, n)?;
            Ok(NormRow {
                n,
                int,
                coef: 1.0 / (2.0 * PI * int),
                int_err,
            })
        })
        .collect()
}

/// A closed form for `coef(n)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `a (n + b) + c / (d + n)`, fitted.
    Seed,
    /// `a (n + b)`, fitted.
    Linear,
    /// Seed 001's printed constants, not fitted.
    SeedPublished,
}

impl Form {
    /// How many values of n a fit of this form needs: its fitted constants (a fit through
    /// fewer points is underdetermined and would report a perfect, meaningless fit).
    pub fn min_points(self) -> usize {
        match self {
            Form::Seed => 4,
            Form::Linear => 2,
            Form::SeedPublished => 1,
        }
    }

    /// Refuses `points` values of n when the form needs more (see [`Form::min_points`]).
    pub fn check_points(self, points: usize) -> Result<(), String> {
        if points < self.min_points() {
            return Err(format!(
                "--fit needs at least {} values of n for its {} constants; --n gives {points}",
                self.min_points(),
                self.min_points()
            ));
        }
        Ok(())
    }

    /// Parses `seed`, `linear` or `seed-published`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "seed" => Some(Self::Seed),
            "linear" => Some(Self::Linear),
            "seed-published" => Some(Self::SeedPublished),
            _ => None,
        }
    }
    /// The formula, for printing.
    pub fn formula(self) -> &'static str {
        match self {
            Self::Seed | Self::SeedPublished => "a (n + b) + c / (d + n)",
            Self::Linear => "a (n + b)",
        }
    }
}

/// A fitted (or published) closed form and how well it matches.
#[derive(Clone, Debug, Serialize)]
pub struct Fit {
    pub form: &'static str,
    /// The constants, by name (`a`, `b`, `c`, `d`).
    pub constants: Vec<(&'static str, f64)>,
    /// RMS of `coef_fit - coef` (absolute) over the samples.
    pub rms: f64,
    /// Max of `|coef_fit / coef - 1|`, and the n where it occurs.
    pub max_rel: f64,
    pub max_rel_at: f64,
    /// `max |coef_fit(n) 2 pi Int(n) - 1|`: equal to `max_rel` by construction, reported under
    /// its physical name.
    pub energy_residual_max: f64,
}

fn eval_form(form: Form, k: &[f64], n: f64) -> f64 {
    match form {
        Form::Linear => k[0] * (n + k[1]),
        _ => k[0] * (n + k[1]) + k[2] / (k[3] + n),
    }
}

/// Weighted linear least squares (weights `w`) of `y ~ sum_j beta_j x_j`, by normal equations
/// with partial pivoting (a handful of unknowns).
pub fn lstsq(xs: &[Vec<f64>], y: &[f64], w: &[f64]) -> Vec<f64> {
    let m = xs[0].len();
    let mut a = vec![vec![0.0; m + 1]; m];
    for (i, row) in xs.iter().enumerate() {
        for j in 0..m {
            for k in 0..m {
                a[j][k] += w[i] * row[j] * row[k];
            }
            a[j][m] += w[i] * row[j] * y[i];
        }
    }
    for col in 0..m {
        let piv = (col..m)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        a.swap(col, piv);
        for row in 0..m {
            if row != col && a[col][col] != 0.0 {
                let f = a[row][col] / a[col][col];
                let pivot = a[col].clone();
                for (x, p) in a[row].iter_mut().zip(pivot) {
                    *x -= f * p;
                }
            }
        }
    }
    (0..m)
        .map(|j| {
            if a[j][j] != 0.0 {
                a[j][m] / a[j][j]
            } else {
                0.0
            }
        })
        .collect()
}

/// Fits `form` to `(n, coef)` rows (relative weighting), or evaluates the published constants.
pub fn fit(form: Form, rows: &[NormRow]) -> Fit {
    let ns: Vec<f64> = rows.iter().map(|r| r.n).collect();
    let ys: Vec<f64> = rows.iter().map(|r| r.coef).collect();
    let w: Vec<f64> = ys.iter().map(|y| 1.0 / (y * y)).collect();
    let rel_rms = |k: &[f64]| {
        (ns.iter()
            .zip(&ys)
            .map(|(&n, &y)| (eval_form(form, k, n) / y - 1.0).powi(2))
            .sum::<f64>()
            / ns.len() as f64)
            .sqrt()
    };
    let k: Vec<f64> = match form {
        Form::SeedPublished => vec![0.197, 1.24, 0.068, 0.64],
        Form::Linear => {
            let xs: Vec<Vec<f64>> = ns.iter().map(|&n| vec![n, 1.0]).collect();
            let beta = lstsq(&xs, &ys, &w);
            vec![beta[0], beta[1] / beta[0]]
        }
        Form::Seed => {
            let solve = |d: f64| {
                let xs: Vec<Vec<f64>> = ns.iter().map(|&n| vec![n, 1.0, 1.0 / (d + n)]).collect();
                let beta = lstsq(&xs, &ys, &w);
                vec![beta[0], beta[1] / beta[0], beta[2], d]
            };
            // d must keep d + n > 0 on the samples: scan, then golden-section refine.
            let n_min = ns.iter().copied().fold(f64::INFINITY, f64::min);
            let lo = -n_min + 1e-3;
            let grid: Vec<f64> = (0..=400)
                .map(|i| lo + (i as f64 / 400.0).powi(3) * (50.0 - lo))
                .collect();
            let best = grid
                .iter()
                .copied()
                .min_by(|&a, &b| rel_rms(&solve(a)).total_cmp(&rel_rms(&solve(b))))
                .unwrap_or(0.64);
            let step = (50.0 - lo) / 400.0 * 3.0;
            let (d, _) = fastbrdf::accuracy::golden_max(
                &|d| -rel_rms(&solve(d)),
                (best - step).max(lo),
                best + step,
                80,
            );
            solve(d)
        }
    };
    let mut max_rel = (0.0, ns.first().copied().unwrap_or(0.0));
    let mut sq = 0.0;
    for (&n, &y) in ns.iter().zip(&ys) {
        let f = eval_form(form, &k, n);
        sq += (f - y).powi(2);
        let rel = (f / y - 1.0).abs();
        if rel > max_rel.0 {
            max_rel = (rel, n);
        }
    }
    let names = ["a", "b", "c", "d"];
    Fit {
        form: form.formula(),
        constants: names.iter().copied().zip(k.iter().copied()).collect(),
        rms: (sq / ns.len().max(1) as f64).sqrt(),
        max_rel: max_rel.0,
        max_rel_at: max_rel.1,
        energy_residual_max: max_rel.0,
    }
}

/// `fastbrdf normalize --json`'s object: `{"model", "rows": [{n, int, coef, int_err}], "fit"}`
/// (the CLI and the Python package print this one value).
pub fn json(model: &str, rows: &[NormRow], fit: Option<&Fit>) -> serde_json::Value {
    serde_json::json!({"model": model, "rows": rows, "fit": fit})
}
