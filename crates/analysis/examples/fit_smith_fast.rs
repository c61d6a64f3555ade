//! Refits Hammon's fast height-correlated Smith term for GGX (`smith-ggx-correlated-fast`,
//! Filament's `V_SmithGGXCorrelated_Fast`): the same form with `alpha` replaced by
//! `k(alpha) = alpha (c0 + c1 alpha + c2 alpha^2)`, the constants of
//! `smith-ggx-correlated-fast-tuned` (`crates/fastbrdf/src/microfacet/smith_ggx.rs`,
//! `FAST_TUNED`). Run: `cargo run --release -p fastbrdf-analysis --example fit_smith_fast`.
//!
//! Per alpha, the `k` that minimises the maximum two-sided error against the exact
//! `smith-ggx-correlated` over a grid of both cosines (log-spaced from 1e-4 to 1) is found by
//! golden section; `k / alpha` is then fitted by least squares with a quadratic in alpha
//! (the optimum runs from 0.53 at small alpha to exactly 1 at alpha = 1, where Hammon's form
//! is exact).

use fastbrdf::Model;
use fastbrdf::model::ShadowInput;

fn cosines() -> Vec<f64> {
    (0..=60)
        .map(|i| 10f64.powf(-4.0 + 4.0 * i as f64 / 60.0))
        .collect()
}

fn fast(k: f64, v: f64, l: f64) -> f64 {
    let tv = 2.0 * v * l;
    tv / (tv * (1.0 - k) + k * (v + l))
}

fn exact(alpha: f64) -> impl Fn(f64, f64) -> f64 {
    let spec = fastbrdf::ModelSpec::new(
        "smith-ggx-correlated",
        &[("alpha", fastbrdf::Given::Num(alpha))],
    );
    let Ok(Model::Shadowing(g)) = spec.and_then(|s| s.model::<f64>()) else {
        panic!("smith-ggx-correlated is a shadowing term")
    };
    move |v, l| {
        g.g(&ShadowInput {
            cos_v: v,
            cos_l: Some(l),
            cos_h: 1.0,
            cos_vh: 1.0,
        })
    }
}

fn max_err(k: f64, ex: &dyn Fn(f64, f64) -> f64, cs: &[f64]) -> f64 {
    let mut m: f64 = 0.0;
    for &v in cs {
        for &l in cs {
            m = m.max((fast(k, v, l) - ex(v, l)).abs());
        }
    }
    m
}

fn main() {
    let cs = cosines();
    let alphas: Vec<f64> = (0..=40)
        .map(|i| 0.005 * (1.0f64 / 0.005).powf(i as f64 / 40.0))
        .collect();
    let mut rows = vec![];
    for &a in &alphas {
        let ex = exact(a);
        let (k, e) = fastbrdf::accuracy::golden_max(
            &|k| -max_err(k, &ex, &cs),
            0.2 * a,
            (2.0 * a).min(1.5),
            60,
        );
        rows.push((a, k / a, -e, max_err(a, &ex, &cs)));
    }
    // Least squares for k / alpha = c0 + c1 alpha + c2 alpha^2 (normal equations, 3x3).
    let mut m = [[0.0f64; 4]; 3];
    for &(a, r, _, _) in &rows {
        let p = [1.0, a, a * a];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += p[i] * p[j];
            }
            m[i][3] += p[i] * r;
        }
    }
    for col in 0..3 {
        let piv = m[col][col];
        m[col].iter_mut().for_each(|x| *x /= piv);
        let pivot_row = m[col];
        for (i, row) in m.iter_mut().enumerate() {
            if i != col {
                let f = row[col];
                row.iter_mut().zip(pivot_row).for_each(|(x, p)| *x -= f * p);
            }
        }
    }
    let c = [m[0][3], m[1][3], m[2][3]];
    println!("alpha      k/alpha (optimum)  fitted   max error: Hammon  optimum  fitted");
    let mut worst = (0.0f64, 0.0f64);
    for &(a, r, e_opt, e_hammon) in &rows {
        let fit = c[0] + c[1] * a + c[2] * a * a;
        let e_fit = max_err(a * fit, &exact(a), &cs);
        worst = (worst.0.max(e_hammon), worst.1.max(e_fit));
        println!("{a:<10.5} {r:<18.5} {fit:<8.5} {e_hammon:>17.4} {e_opt:>8.4} {e_fit:>7.4}");
    }
    println!("FAST_TUNED = [{:.6}, {:.6}, {:.6}]", c[0], c[1], c[2]);
    println!(
        "max two-sided error on the grid: Hammon {:.4}, refit {:.4} ({:.0}% removed)",
        worst.0,
        worst.1,
        100.0 * (1.0 - worst.1 / worst.0)
    );
}
