//! The DFG ledger: the error of a split-sum model (`Kind::Env`) against a reference
//! (`env-brdf` by default) over the whole domain, `cos_v` in (0, 1] and `alpha` in [0.005, 1]
//! (`fastbrdf errors --model ID` for an env model, `fastbrdf pareto --env`).
//!
//! Per term (`scale`, `bias`) and for the white furnace (`scale + bias`, the directional
//! albedo with F = 1, what energy compensation divides by):
//! - the max absolute error and where, `(cos_v, alpha)`: the largest on a grid dense at grazing
//!   (`cos_v = (i / 160)^2`, i = 0..160) and in `alpha` (64 values uniform and 64 logarithmic on
//!   [0.005, 1]), refined by three rounds of a 9 x 9 grid around the worst point (each round a
//!   quarter of the spacing);
//! - the mean absolute error, uniform in `(cos_v, alpha)` over the domain (64 x 64 midpoints),
//!   and uniform in `(cos_v, r)`, `r = sqrt(alpha)` the perceptual roughness an engine's table
//!   is indexed by (64 x 64 midpoints each);
//! - for the furnace also the largest gain and loss (signed: `model - reference`).
//!
//! The reference is computed once per [`Reference`] (all cores): 2 x (20608 + 2 x 4096) values of
//! `env-brdf`'s quadrature, about a second in a release build; every model is measured
//! against the same values.

use fastbrdf::{Given, Model, ModelSpec, Result};
use rayon::prelude::*;
use serde::Serialize;

/// The error of one term (or of the furnace sum).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct TermError {
    pub max_abs: f64,
    /// Where the max is.
    pub cos_v: f64,
    pub alpha: f64,
    /// Uniform in `(cos_v, alpha)`.
    pub mean_abs: f64,
    /// Uniform in `(cos_v, r)`, `r = sqrt(alpha)` the perceptual roughness (an engine's table
    /// axis), `r` in [sqrt(0.005), 1].
    pub mean_abs_r: f64,
}

/// The ledger row of one model configuration.
#[derive(Clone, Debug, Serialize)]
pub struct EnvErrors {
    pub scale: TermError,
    pub bias: TermError,
    /// `scale + bias` (F = 1).
    pub furnace: TermError,
    /// The largest `model - reference` of the furnace sum (the albedo overestimated) ...
    pub furnace_gain: f64,
    /// ... and the largest `reference - model` (underestimated).
    pub furnace_loss: f64,
}

/// The reference's terms on the ledger's grids.
pub struct Reference {
    id: String,
    max_grid: Vec<(f64, f64, [f64; 2])>,
    mean_grid: Vec<(f64, f64, [f64; 2])>,
    mean_grid_r: Vec<(f64, f64, [f64; 2])>,
}

fn alpha_min() -> f64 {
    fastbrdf::params::ALPHA.range().0
}

/// `(scale, bias)` models of `id` with the parameters `given` (besides `term`).
fn terms(id: &str, given: &[(&str, Given)]) -> Result<[Model<f64>; 2]> {
    let one = |t: &str| -> Result<Model<f64>> {
        let mut g: Vec<(&str, Given)> = given.to_vec();
        g.push(("term", Given::Choice(t.into())));
        ModelSpec::new(id, &g)?.model()
    };
    Ok([one("scale")?, one("bias")?])
}

fn eval(m: &[Model<f64>; 2], v: f64, a: f64) -> [f64; 2] {
    let e = |m: &Model<f64>| match m {
        Model::Env(e) => e.e(v, a),
        _ => f64::NAN,
    };
    [e(&m[0]), e(&m[1])]
}

impl Reference {
    /// The reference `id` (an env model with default parameters) on the ledger's grids.
    pub fn new(id: &str) -> Result<Self> {
        let r = terms(id, &[])?;
        let amin = alpha_min();
        let alphas: Vec<f64> = (0..64)
            .map(|j| amin + (1.0 - amin) * j as f64 / 63.0)
            .chain((0..64).map(|j| amin * (1.0 / amin).powf(j as f64 / 63.0)))
            .collect();
        let max_pts: Vec<(f64, f64)> = (0..=160)
            .flat_map(|i| {
                let v = (i as f64 / 160.0).powi(2);
                alphas.iter().map(move |&a| (v, a))
            })
            .collect();
        let mean_pts: Vec<(f64, f64)> = (0..64)
            .flat_map(|i| {
                (0..64).map(move |j| {
                    (
                        (i as f64 + 0.5) / 64.0,
                        amin + (1.0 - amin) * (j as f64 + 0.5) / 64.0,
                    )
                })
            })
            .collect();
        let rmin = amin.sqrt();
        let mean_pts_r: Vec<(f64, f64)> = (0..64)
            .flat_map(|i| {
                (0..64).map(move |j| {
                    let r = rmin + (1.0 - rmin) * (j as f64 + 0.5) / 64.0;
                    ((i as f64 + 0.5) / 64.0, r * r)
                })
            })
            .collect();
        let on = |pts: Vec<(f64, f64)>| -> Vec<(f64, f64, [f64; 2])> {
            pts.into_par_iter()
                .map(|(v, a)| (v, a, eval(&r, v, a)))
                .collect()
        };
        Ok(Self {
            id: id.to_string(),
            max_grid: on(max_pts),
            mean_grid: on(mean_pts),
            mean_grid_r: on(mean_pts_r),
        })
    }

    /// The reference's id.
    pub fn id(&self) -> &str {
        &self.id
    }

    /// The ledger row of `id` with parameters `given` (besides `term`).
    pub fn measure(&self, id: &str, given: &[(&str, Given)]) -> Result<EnvErrors> {
        let m = terms(id, given)?;
        let r = terms(&self.id, &[])?;
        let amin = alpha_min();
        // Errors of the three quantities (scale, bias, sum) at one point.
        let errs = |v: f64, a: f64, want: Option<[f64; 2]>| -> [f64; 3] {
            let got = eval(&m, v, a);
            let want = want.unwrap_or_else(|| eval(&r, v, a));
            [
                got[0] - want[0],
                got[1] - want[1],
                got[0] + got[1] - want[0] - want[1],
            ]
        };
        let grid: Vec<[f64; 3]> = self
            .max_grid
            .par_iter()
            .map(|&(v, a, w)| errs(v, a, Some(w)))
            .collect();
        let mut out = [TermError::default(); 3];
        let (mut gain, mut loss) = (0.0f64, 0.0f64);
        for q in 0..3 {
            let (k, e) =
                grid.iter()
                    .enumerate()
                    .map(|(k, e)| (k, e[q].abs()))
                    .fold(
                        (0, -1.0),
                        |b, x| if x.1 > b.1 || x.1.is_nan() { x } else { b },
                    );
            let (mut v, mut a, mut best) = (self.max_grid[k].0, self.max_grid[k].1, e);
            // Refinement: a 9 x 9 grid around the worst point, shrinking.
            let (mut dv, mut da) = (0.02 * v.max(0.01), 0.05 * a);
            for _ in 0..3 {
                let (v0, a0) = (v, a);
                for i in -4..=4 {
                    for j in -4..=4 {
                        let vv = (v0 + dv * i as f64 / 4.0).clamp(0.0, 1.0);
                        let aa = (a0 + da * j as f64 / 4.0).clamp(amin, 1.0);
                        let x = errs(vv, aa, None)[q].abs();
                        if x > best {
                            (v, a, best) = (vv, aa, x);
                        }
                    }
                }
                dv *= 0.25;
                da *= 0.25;
            }
            out[q].max_abs = best;
            out[q].cos_v = v;
            out[q].alpha = a;
        }
        for e in &grid {
            gain = gain.max(e[2]);
            loss = loss.max(-e[2]);
        }
        let mean = |g: &[(f64, f64, [f64; 2])]| -> [f64; 3] {
            let s = g
                .par_iter()
                .map(|&(v, a, w)| errs(v, a, Some(w)).map(f64::abs))
                .reduce(|| [0.0; 3], |x, y| [x[0] + y[0], x[1] + y[1], x[2] + y[2]]);
            s.map(|x| x / g.len() as f64)
        };
        let (ma, mr) = (mean(&self.mean_grid), mean(&self.mean_grid_r));
        for q in 0..3 {
            out[q].mean_abs = ma[q];
            out[q].mean_abs_r = mr[q];
        }
        Ok(EnvErrors {
            scale: out[0],
            bias: out[1],
            furnace: out[2],
            furnace_gain: gain,
            furnace_loss: loss,
        })
    }
}

/// `given` for model `id` from `NAME=VALUE` pairs: a choice parameter's value as a choice, a
/// number's parsed (an unparsable number is an error naming the parameter).
pub fn given_of<'a>(id: &str, pairs: &'a [(String, String)]) -> Result<Vec<(&'a str, Given)>> {
    let e = fastbrdf::registry::find(id)?;
    pairs
        .iter()
        .map(|(k, v)| {
            let choice = e.info.params.iter().any(|p| {
                p.name == k && matches!(p.kind, fastbrdf::params::ParamKind::Choice { .. })
            });
            let g = if choice {
                Given::Choice(v.clone())
            } else {
                Given::Num(v.parse().map_err(|_| fastbrdf::Error::Domain {
                    input: format!("--param {k}"),
                    reason: format!("'{v}' is not a number"),
                })?)
            };
            Ok((k.as_str(), g))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference against itself has no error; Karis's fit has some, its furnace error is
    /// at most the two terms' together, and its mean is below its max.
    #[test]
    fn the_ledger_measures_what_it_says() {
        let r = Reference::new("env-brdf").unwrap();
        let same = r.measure("env-brdf", &[]).unwrap();
        assert!(
            same.scale.max_abs < 1e-12 && same.furnace.mean_abs < 1e-12,
            "{same:?}"
        );
        let k = r.measure("env-brdf-approx", &[]).unwrap();
        assert!(k.scale.max_abs > 0.01 && k.bias.max_abs > 0.001, "{k:?}");
        assert!(k.furnace.max_abs <= k.scale.max_abs + k.bias.max_abs + 1e-12);
        assert!(k.scale.mean_abs < k.scale.max_abs);
        assert!(k.furnace_gain.max(k.furnace_loss) <= k.furnace.max_abs + 1e-12);
    }
}
