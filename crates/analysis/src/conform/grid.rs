//! The direction pairs the value checks run on: a deterministic grid (every pair of its
//! directions, `z` exactly 1 and exactly 0 included) and uniform random pairs of the upper
//! hemisphere (uniform in solid angle: the RMS of `reference` is their mean).

use super::Config;
use fastbrdf::sample::Rng;
use std::f64::consts::TAU;

/// Pairs `(wi[k], wo[k])`; the random ones from `random_from` on.
pub struct Pairs {
    pub wi: Vec<[f64; 3]>,
    pub wo: Vec<[f64; 3]>,
    pub random_from: usize,
}

/// The direction at `theta_deg` from the normal and azimuth `phi` (radians): `z` is exactly 1
/// at 0 degrees and exactly 0 at 90.
pub fn direction(theta_deg: f64, phi: f64) -> [f64; 3] {
    if theta_deg == 0.0 {
        return [0.0, 0.0, 1.0];
    }
    let (s, z) = if theta_deg == 90.0 {
        (1.0, 0.0)
    } else {
        theta_deg.to_radians().sin_cos()
    };
    let (sp, cp) = phi.sin_cos();
    [s * cp, s * sp, z]
}

/// The grid's directions: every theta at `grid_phi` azimuths (theta 0 once).
pub fn grid_directions(cfg: &Config) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for &t in &cfg.grid_theta_deg {
        if t == 0.0 {
            out.push(direction(0.0, 0.0));
            continue;
        }
        for j in 0..cfg.grid_phi {
            out.push(direction(t, TAU * j as f64 / cfg.grid_phi as f64));
        }
    }
    out
}

/// A uniform direction of the upper hemisphere.
pub fn uniform(r: &mut Rng) -> [f64; 3] {
    let [a, b] = r.pair();
    let z = a;
    let s = (1.0 - z * z).max(0.0).sqrt();
    let (sp, cp) = (TAU * b).sin_cos();
    [s * cp, s * sp, z]
}

/// Every pair of the grid, then `random_pairs` uniform pairs.
pub fn pairs(cfg: &Config) -> Pairs {
    let g = grid_directions(cfg);
    let mut wi = Vec::with_capacity(g.len() * g.len() + cfg.random_pairs);
    let mut wo = Vec::with_capacity(wi.capacity());
    for a in &g {
        for b in &g {
            wi.push(*a);
            wo.push(*b);
        }
    }
    let random_from = wi.len();
    let mut r = Rng::new(cfg.seed);
    for _ in 0..cfg.random_pairs {
        wi.push(uniform(&mut r));
        wo.push(uniform(&mut r));
    }
    Pairs {
        wi,
        wo,
        random_from,
    }
}
