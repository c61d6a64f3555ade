//! Nelder-Mead minimisation for the multi-constant refits (`fresnel-schlick-sg-tuned`,
//! `env-brdf-approx-tuned`): a few parameters, a minimax objective with kinks, no gradient.
//! Written by hand (40 lines; ARCHITECTURE.md): the crates that offer it (argmin) bring a
//! framework of traits for what is one loop here.

/// Minimises `f` from `start` by Nelder-Mead (reflection 1, expansion 2, contraction 1/2,
/// shrink 1/2) with an initial simplex of steps `step` along each axis, for `iters`
/// iterations; returns the best vertex and its value.
pub fn nelder_mead(
    f: &dyn Fn(&[f64]) -> f64,
    start: &[f64],
    step: f64,
    iters: usize,
) -> (Vec<f64>, f64) {
    let n = start.len();
    let mut s: Vec<Vec<f64>> = (0..=n)
        .map(|i| {
            let mut p = start.to_vec();
            if i > 0 {
                p[i - 1] += step * p[i - 1].abs().max(1e-3);
            }
            p
        })
        .collect();
    let mut v: Vec<f64> = s.iter().map(|p| f(p)).collect();
    for _ in 0..iters {
        let mut idx: Vec<usize> = (0..=n).collect();
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        let (b, w, sw) = (idx[0], idx[n], idx[n - 1]);
        let c: Vec<f64> = (0..n)
            .map(|k| idx[..n].iter().map(|&i| s[i][k]).sum::<f64>() / n as f64)
            .collect();
        let at = |t: f64| -> Vec<f64> { (0..n).map(|k| c[k] + t * (s[w][k] - c[k])).collect() };
        let r = at(-1.0);
        let fr = f(&r);
        if fr < v[b] {
            let e = at(-2.0);
            let fe = f(&e);
            (s[w], v[w]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < v[sw] {
            (s[w], v[w]) = (r, fr);
        } else {
            let k = at(0.5);
            let fk = f(&k);
            if fk < v[w] {
                (s[w], v[w]) = (k, fk);
            } else {
                for &i in &idx[1..] {
                    s[i] = (0..n).map(|k| (s[i][k] + s[b][k]) / 2.0).collect();
                    v[i] = f(&s[i]);
                }
            }
        }
    }
    let best = (0..=n).min_by(|&i, &j| v[i].total_cmp(&v[j])).unwrap();
    (s[best].clone(), v[best])
}

#[cfg(test)]
mod tests {
    #[test]
    fn finds_the_minimum_of_a_shifted_bowl_and_of_rosenbrock() {
        let bowl = |p: &[f64]| (p[0] - 3.0).powi(2) + 10.0 * (p[1] + 1.0).powi(2) + p[2].abs();
        let (p, v) = super::nelder_mead(&bowl, &[0.0, 0.0, 1.0], 1.0, 2000);
        assert!(
            v < 1e-8 && (p[0] - 3.0).abs() < 1e-4 && (p[1] + 1.0).abs() < 1e-4,
            "{p:?}"
        );
        let rosen = |p: &[f64]| 100.0 * (p[1] - p[0] * p[0]).powi(2) + (1.0 - p[0]).powi(2);
        let (p, _) = super::nelder_mead(&rosen, &[-1.2, 1.0], 0.5, 5000);
        assert!(
            (p[0] - 1.0).abs() < 1e-3 && (p[1] - 1.0).abs() < 1e-3,
            "{p:?}"
        );
    }
}
