//! BRDF space: `g = f cos_i cos_o` of a configuration on a product grid over pairs of
//! hemisphere directions (f64, the scalar model), and its errors against a reference's.

use super::Config;
use fastbrdf::Model;
use rayon::prelude::*;
use serde::Serialize;

/// The BRDF-space quadrature: `theta` midpoints per hemisphere angle, `phi` (even) azimuths.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Grid {
    pub theta: usize,
    pub phi: usize,
}

impl Grid {
    /// The default: 48 x 48 x 96 pairs (221184).
    pub const DEFAULT: Grid = Grid { theta: 48, phi: 96 };
    /// `--quick`: 16 x 16 x 32 pairs.
    pub const QUICK: Grid = Grid { theta: 16, phi: 32 };
}

/// `g = f cos_i cos_o` of `config` at `alpha` on the grid (f64, scalar model), in the order
/// theta_i, theta_o, phi; and the solid-angle weight of each node (`sin theta_i sin theta_o
/// d theta^2 d phi`, times `2 pi` for `phi_i`; they sum to about `(2 pi)^2`).
fn cosine_weighted(config: &Config, alpha: f64, grid: Grid) -> fastbrdf::Result<Vec<f64>> {
    let spec = config.at(alpha)?;
    // Built once to report a bad configuration; each row builds its own (Send-free models).
    spec.model::<f64>()?;
    let (nt, np) = (grid.theta, grid.phi.max(2) & !1);
    let dt = std::f64::consts::FRAC_PI_2 / nt as f64;
    let rows: Vec<Vec<f64>> = (0..nt)
        .into_par_iter()
        .map(|i| {
            let Ok(Model::Brdf(b)) = spec.model::<f64>() else {
                unreachable!("checked above")
            };
            let ti = (i as f64 + 0.5) * dt;
            let wi = [ti.sin(), 0.0, ti.cos()];
            let mut row = Vec::with_capacity(nt * np);
            for j in 0..nt {
                let to = (j as f64 + 0.5) * dt;
                let (so, co) = to.sin_cos();
                for k in 0..np {
                    let p = std::f64::consts::TAU * k as f64 / np as f64;
                    let wo = [so * p.cos(), so * p.sin(), co];
                    row.push(b.eval(wi, wo) * wi[2] * co);
                }
            }
            row
        })
        .collect();
    Ok(rows.concat())
}

fn weights(grid: Grid) -> Vec<f64> {
    let (nt, np) = (grid.theta, grid.phi.max(2) & !1);
    let dt = std::f64::consts::FRAC_PI_2 / nt as f64;
    let dp = std::f64::consts::TAU / np as f64;
    let mut w = Vec::with_capacity(nt * nt * np);
    for i in 0..nt {
        let si = ((i as f64 + 0.5) * dt).sin();
        for j in 0..nt {
            let sj = ((j as f64 + 0.5) * dt).sin();
            let x = si * sj * dt * dt * dp * std::f64::consts::TAU;
            w.extend(std::iter::repeat_n(x, np));
        }
    }
    w
}

/// BRDF-space errors of one configuration against the reference's values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BrdfError {
    pub max_rel_peak: f64,
    /// Where the maximum is: `theta_i`, `theta_o` and `phi_o - phi_i` in degrees.
    pub max_at_deg: [f64; 3],
    pub rms_rel: f64,
    pub rms_abs: f64,
}

/// The reference's `g = f cos_i cos_o` and the quadrature weights on a grid, computed once
/// per alpha.
pub struct Reference {
    pub grid: Grid,
    pub alpha: f64,
    values: Vec<f64>,
    weights: Vec<f64>,
    peak: f64,
    norm2: f64,
}

impl Reference {
    pub fn new(config: &Config, alpha: f64, grid: Grid) -> fastbrdf::Result<Self> {
        let values = cosine_weighted(config, alpha, grid)?;
        let weights = weights(grid);
        let peak = values.iter().copied().fold(0.0, f64::max);
        let norm2 = values.iter().zip(&weights).map(|(v, w)| w * v * v).sum();
        Ok(Self {
            grid,
            alpha,
            values,
            weights,
            peak,
            norm2,
        })
    }

    /// The errors of `config` against this reference (module documentation).
    pub fn error(&self, config: &Config) -> fastbrdf::Result<BrdfError> {
        let v = cosine_weighted(config, self.alpha, self.grid)?;
        let (mut max, mut at, mut sq) = (0.0f64, 0usize, 0.0f64);
        for (i, ((a, b), w)) in v.iter().zip(&self.values).zip(&self.weights).enumerate() {
            let d = a - b;
            if d.abs() > max {
                (max, at) = (d.abs(), i);
            }
            sq += w * d * d;
        }
        let (nt, np) = (self.grid.theta, self.grid.phi.max(2) & !1);
        let theta = |k: usize| (k as f64 + 0.5) * 90.0 / nt as f64;
        let max_at_deg = [
            theta(at / (nt * np)),
            theta(at / np % nt),
            (at % np) as f64 * 360.0 / np as f64,
        ];
        let total: f64 = self.weights.iter().sum();
        Ok(BrdfError {
            max_rel_peak: max / self.peak,
            max_at_deg,
            rms_rel: (sq / self.norm2).sqrt(),
            rms_abs: (sq / total).sqrt(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pareto_brdf::default_reference;

    #[test]
    fn the_reference_has_zero_error_against_itself() {
        let r = Reference::new(&default_reference(), 0.3, Grid::QUICK).unwrap();
        let e = r.error(&default_reference()).unwrap();
        assert_eq!(
            e,
            BrdfError {
                max_rel_peak: 0.0,
                max_at_deg: [90.0 / 32.0, 90.0 / 32.0, 0.0],
                rms_rel: 0.0,
                rms_abs: 0.0
            }
        );
        assert!(r.peak > 0.0 && r.norm2 > 0.0);
        // The weights integrate the pair measure: (2 pi)^2 within the midpoint rule's error.
        let total: f64 = r.weights.iter().sum();
        let want = std::f64::consts::TAU.powi(2);
        assert!((total / want - 1.0).abs() < 2e-3, "{total} vs {want}");
    }

    #[test]
    fn a_finer_power_is_closer_to_the_power_it_approximates() {
        // (1 + x/g)^g tends to exp(x) as g grows: the power forms tend to `beckmann-pow`'s
        // cos^(2/m^2 - 4) (same normalisation, same G and F: only D differs), monotonically.
        let r = Reference::new(
            &Config::new("beckmann-pow", "smith", "schlick"),
            0.3,
            Grid::QUICK,
        )
        .unwrap();
        let e = |d| r.error(&Config::new(d, "smith", "schlick")).unwrap();
        let (p4, p8, p16) = (
            e("beckmann-power4"),
            e("beckmann-power8"),
            e("beckmann-power16"),
        );
        assert!(
            p16.rms_rel < p8.rms_rel && p8.rms_rel < p4.rms_rel,
            "{p4:?} {p8:?} {p16:?}"
        );
        assert!(p16.max_rel_peak < p8.max_rel_peak && p8.max_rel_peak < p4.max_rel_peak);
        assert!(p16.rms_rel > 0.0);
        // Not so against the exact Beckmann: cos^(2/m^2) is itself an approximation of
        // exp(-tan^2/m^2), and at alpha = 0.3 the coarser powers' error partly cancels its
        // error (measured: power8 closest, power16 furthest). The pi/4 scale of the seeds'
        // normalisation against the energy-normalised `beckmann` is exact.
        let r = Reference::new(
            &Config::new("beckmann", "smith", "schlick"),
            0.3,
            Grid::QUICK,
        )
        .unwrap();
        let e = |d| r.error(&Config::new(d, "smith", "schlick")).unwrap();
        let ct = e("beckmann-ct").rms_rel;
        assert!(
            (ct - (1.0 - std::f64::consts::FRAC_PI_4)).abs() < 1e-9,
            "{ct}"
        );
    }
}
