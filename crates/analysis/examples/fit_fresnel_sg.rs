//! Refits Karis's spherical-Gaussian Schlick form `2^((a c + b) c)` to `(1 - c)^5`: the
//! `(a, b)` that minimise the maximum absolute error over `c` in [0, 1] (the constants of
//! `fresnel-schlick-sg-tuned`, `crates/fastbrdf/src/microfacet/fresnel.rs`).
//! Run: `cargo run --release -p fastbrdf-analysis --example fit_fresnel_sg`.
//!
//! The maximum over a 20001-point grid, refined by golden section around the grid's largest
//! errors (`fastbrdf::accuracy::golden_max`), minimised by Nelder-Mead from Karis's constants
//! (two parameters, a smooth objective away from its kinks: no crate needed).

use fastbrdf::accuracy::golden_max;
use fastbrdf::microfacet::fresnel::SG_KARIS;

fn err_at(a: f64, b: f64, c: f64) -> f64 {
    (((a * c + b) * c).exp2() - (1.0 - c).powi(5)).abs()
}

/// The maximum error over `c` in [0, 1] and where it is.
fn max_err(a: f64, b: f64) -> (f64, f64) {
    const N: usize = 20_000;
    let h = 1.0 / N as f64;
    let mut errs: Vec<(f64, usize)> = (0..=N).map(|i| (err_at(a, b, i as f64 * h), i)).collect();
    errs.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut best = (errs[0].0, errs[0].1 as f64 * h);
    for &(_, i) in errs.iter().take(6) {
        let lo = (i as f64 - 1.0).max(0.0) * h;
        let hi = (i as f64 + 1.0).min(N as f64) * h;
        let (x, e) = golden_max(&|c| err_at(a, b, c), lo, hi, 60);
        if e > best.0 {
            best = (e, x);
        }
    }
    best
}

fn nelder_mead(f: impl Fn([f64; 2]) -> f64, start: [f64; 2], step: f64, iters: usize) -> [f64; 2] {
    let mut s = [
        start,
        [start[0] + step, start[1]],
        [start[0], start[1] + step],
    ];
    let mut v = s.map(&f);
    for _ in 0..iters {
        let mut idx = [0, 1, 2];
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        let (b, m, w) = (idx[0], idx[1], idx[2]);
        let c = [(s[b][0] + s[m][0]) / 2.0, (s[b][1] + s[m][1]) / 2.0];
        let at = |t: f64| [c[0] + t * (s[w][0] - c[0]), c[1] + t * (s[w][1] - c[1])];
        let r = at(-1.0);
        let fr = f(r);
        if fr < v[b] {
            let e = at(-2.0);
            let fe = f(e);
            (s[w], v[w]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < v[m] {
            (s[w], v[w]) = (r, fr);
        } else {
            let k = at(0.5);
            let fk = f(k);
            if fk < v[w] {
                (s[w], v[w]) = (k, fk);
            } else {
                for i in [m, w] {
                    s[i] = [(s[i][0] + s[b][0]) / 2.0, (s[i][1] + s[b][1]) / 2.0];
                    v[i] = f(s[i]);
                }
            }
        }
    }
    let best = (0..3).min_by(|&i, &j| v[i].total_cmp(&v[j])).unwrap();
    s[best]
}

fn main() {
    let (ka, kb) = SG_KARIS;
    let (e0, x0) = max_err(ka, kb);
    println!(
        "Karis   a = {ka:.6}, b = {kb:.6}: max |2^((a c + b) c) - (1 - c)^5| = {e0:.4e} at c = {x0:.4}"
    );
    // From Karis's constants and from a point away from them: both must agree (a minimax
    // with kinks can stall a simplex; a disagreement would show it).
    let fit = |mut p: [f64; 2]| {
        for step in [0.5, 0.05, 0.005, 0.0005] {
            p = nelder_mead(|q| max_err(q[0], q[1]).0, p, step, 200);
        }
        p
    };
    let (p, q) = (fit([ka, kb]), fit([-4.0, -8.0]));
    let (eq, _) = max_err(q[0], q[1]);
    println!(
        "(from a = -4, b = -8: a = {:.6}, b = {:.6}, max error {eq:.4e})",
        q[0], q[1]
    );
    let p = if eq < max_err(p[0], p[1]).0 { q } else { p };
    let (e1, x1) = max_err(p[0], p[1]);
    println!(
        "refit   a = {:.6}, b = {:.6}: max error {e1:.4e} at c = {x1:.4}",
        p[0], p[1]
    );
    println!(
        "(f32 constants: a = {:?}, b = {:?}; error removed: {:.1}%)",
        p[0] as f32,
        p[1] as f32,
        100.0 * (1.0 - e1 / e0)
    );
}
