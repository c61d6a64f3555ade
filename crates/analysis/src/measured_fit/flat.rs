//! Identifiability: the fitted quantities the data do not determine (flat directions of the
//! column-normalised Jacobian at the optimum).

use super::{Data, FLAT_TOL, Problem};
use std::f64::consts::PI;

/// The fitted quantities along flat directions of the model at the optimum (see the module
/// documentation): the Jacobian `J` of `cos_k f_c(k)` (rows: samples x channels) with respect
/// to the free parameters (central differences) and the six albedos (exact), columns scaled to
/// unit length; the eigenvectors of `J^T J` with an eigenvalue below `FLAT_TOL^2` name them.
pub fn undetermined(
    problem: &Problem,
    data: &Data,
    values: &[f64],
    spec: &[f64],
    alb: &[[f64; 2]; 3],
) -> Vec<String> {
    let k = problem.free.len();
    let n = data.len();
    let mut names: Vec<String> = problem.free.iter().map(|f| f.name.to_string()).collect();
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(k + 6);
    for (i, f) in problem.free.iter().enumerate() {
        let v = values[i];
        let h = 1e-5 * if f.log { v } else { f.hi - f.lo };
        let (a, b) = ((v - h).max(f.lo), (v + h).min(f.hi));
        let at = |x: f64| {
            let mut p = values.to_vec();
            p[i] = x;
            problem.spec(data, &p)
        };
        let col = match (at(a), at(b)) {
            (Some(sa), Some(sb)) if b > a => (0..n)
                .flat_map(|j| {
                    let d = data.wi[j][2] * (sb[j] - sa[j]) / (b - a);
                    alb.map(|c| c[1] * d)
                })
                .collect(),
            // Not differentiable here (a model error at a neighbour): say nothing of it.
            _ => vec![f64::NAN; 3 * n],
        };
        cols.push(col);
    }
    for (which, name) in [(0, "rho_d"), (1, "rho_s")] {
        for c in 0..3 {
            let col = (0..n)
                .flat_map(|j| {
                    let w = data.wi[j][2];
                    let x = if which == 0 { w / PI } else { w * spec[j] };
                    [0, 1, 2].map(|cc| if cc == c { x } else { 0.0 })
                })
                .collect();
            cols.push(col);
            names.push(name.to_string());
        }
    }
    // Columns that are not finite are left out; zero ones are undetermined by themselves.
    let norms: Vec<f64> = cols
        .iter()
        .map(|c| c.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    let biggest = norms
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max);
    let mut flat = vec![false; cols.len()];
    let mut kept = Vec::new();
    for (i, &nm) in norms.iter().enumerate() {
        if !nm.is_finite() {
            continue;
        }
        if nm <= 1e-12 * biggest {
            flat[i] = true;
        } else {
            kept.push(i);
        }
    }
    let m = kept.len();
    let mut g = vec![vec![0.0; m]; m];
    for a in 0..m {
        for b in a..m {
            let (ca, cb) = (&cols[kept[a]], &cols[kept[b]]);
            let dot: f64 = ca.iter().zip(cb).map(|(x, y)| x * y).sum();
            g[a][b] = dot / (norms[kept[a]] * norms[kept[b]]);
            g[b][a] = g[a][b];
        }
    }
    let (eig, vecs) = jacobi_eigen(g);
    for (j, &l) in eig.iter().enumerate() {
        if l < FLAT_TOL * FLAT_TOL {
            for (a, &i) in kept.iter().enumerate() {
                if vecs[a][j].abs() > 0.05 {
                    flat[i] = true;
                }
            }
        }
    }
    let mut out: Vec<String> = Vec::new();
    for (i, name) in names.into_iter().enumerate() {
        if flat[i] && !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// Eigenvalues and eigenvectors (the columns of the second result) of the symmetric matrix
/// `a`, by cyclic Jacobi rotations. Written here for the at most a dozen by a dozen matrices of
/// [`undetermined`]: no linear-algebra crate is a dependency of this workspace.
pub fn jacobi_eigen(mut a: Vec<Vec<f64>>) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = a.len();
    let mut v: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|p| ((p + 1)..n).map(move |q| (p, q)))
            .map(|(p, q)| a[p][q] * a[p][q])
            .sum();
        let scale: f64 = (0..n).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-32 * scale || off == 0.0 {
            break;
        }
        for p in 0..n {
            for q in (p + 1)..n {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (x, y) = (row[p], row[q]);
                    row[p] = c * x - s * y;
                    row[q] = s * x + c * y;
                }
                let (lo, hi) = a.split_at_mut(q);
                for (x, y) in lo[p].iter_mut().zip(hi[0].iter_mut()) {
                    (*x, *y) = (c * *x - s * *y, s * *x + c * *y);
                }
                for row in v.iter_mut() {
                    let (x, y) = (row[p], row[q]);
                    row[p] = c * x - s * y;
                    row[q] = s * x + c * y;
                }
            }
        }
    }
    ((0..n).map(|i| a[i][i]).collect(), v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_finds_eigenpairs() {
        let a = vec![
            vec![4.0, 1.0, 2.0],
            vec![1.0, 3.0, 0.5],
            vec![2.0, 0.5, 1.0 + 1e-12],
        ];
        let (l, v) = jacobi_eigen(a.clone());
        for j in 0..3 {
            for i in 0..3 {
                let av: f64 = (0..3).map(|k| a[i][k] * v[k][j]).sum();
                assert!((av - l[j] * v[i][j]).abs() < 1e-12, "{l:?}");
            }
        }
        let tr: f64 = l.iter().sum();
        assert!((tr - (8.0 + 1e-12)).abs() < 1e-12);
        // A rank-deficient matrix: one eigenvalue is 0.
        let b = vec![vec![1.0, 1.0], vec![1.0, 1.0]];
        let (l, _) = jacobi_eigen(b);
        assert!(l.iter().any(|x| x.abs() < 1e-15) && l.iter().any(|x| (x - 2.0).abs() < 1e-15));
    }
}
