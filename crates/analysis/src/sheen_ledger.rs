//! The sheen rows of the DFG ledger (`fastbrdf errors --model sheen-albedo-*`, `fastbrdf
//! pareto --sheen`): each sheen albedo model (`fastbrdf::microfacet::sheen_albedo`) against
//! `sheen-albedo` (the quadrature) at the same visibility `v`, over `mu` (= `cos_v`) in
//! [0.001, 1] and `alpha` in [0.07, 1] (below 0.001 every row reads its value at 0.001).
//!
//! - the albedo `E`: the max absolute error and where `(mu, alpha)`, the largest on a grid
//!   dense at grazing (`mu = 0.001 + 0.999 (i / 160)^2`, i = 0..160) and in `alpha` (64 values
//!   uniform and 64 logarithmic on [0.07, 1]), refined by three rounds of a 9 x 9 grid around
//!   the worst point; the mean absolute error uniform in `(mu, alpha)` (64 x 64 midpoints) and
//!   uniform in `(mu, sqrt(alpha))`;
//! - the furnace consequence for `gltf-pbr`: a white Lambertian base under a white sheen
//!   (`sheen_max = 1`) reflects `A(mu_o) = E(mu_o) + 2 int_0^1 S mu_i dmu_i` with the scaling
//!   `S = max(0, min(1 - E(mu_o), 1 - E(mu_i)))`; with the row's `E` in `S` (the sheen lobe
//!   itself unchanged), `A' - A` is what the approximation does to the white furnace: its max
//!   absolute value and where (on the grid, not refined), its mean (the same two weightings),
//!   its largest gain and loss, and the largest `A'` (above 1: energy created). The integral:
//!   128 midpoints in `mu_i` (the kink of `min` costs at most ~1e-5).
//!
//! The reference is computed once per visibility ([`Reference::new`], all cores): about 90000
//! quadratures of 2304 points, a few seconds in a release build.

use crate::env_errors::TermError;
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::microfacet::sheen::ALPHA_MIN;
use fastbrdf::microfacet::sheen_albedo::MU_MIN;
use fastbrdf::params::ParamKind;
use fastbrdf::{Error, Given, Model, ModelSpec, Result, registry};
use rayon::prelude::*;
use serde::Serialize;
use std::time::Duration;

/// The reference model of every sheen row.
pub const REFERENCE: &str = fastbrdf::microfacet::sheen_albedo::REFERENCE;

/// Midpoints of the furnace's `mu_i` rule.
const NODES: usize = 128;

/// Whether `id` is a sheen albedo row (measured here, not against `env-brdf`).
pub fn is_sheen(id: &str) -> bool {
    fastbrdf::microfacet::sheen_albedo::IDS.contains(&id)
}

/// The ledger row of one configuration.
#[derive(Clone, Debug, Serialize)]
pub struct SheenErrors {
    /// The reference's visibility.
    pub v: String,
    /// `E` against the reference.
    pub albedo: TermError,
    /// `A' - A`, the white furnace of `gltf-pbr`'s Lambertian base under the sheen.
    pub furnace: TermError,
    /// The largest `A' - A` (the base too bright) ...
    pub furnace_gain: f64,
    /// ... and the largest `A - A'` (too dark).
    pub furnace_loss: f64,
    /// The largest `A'` (above 1: the approximation creates energy) ...
    pub furnace_peak: f64,
    /// ... and the largest `A` (the exact scaling's).
    pub furnace_peak_exact: f64,
}

/// One `alpha` of a grid: the reference at its `mu` values and at the furnace's nodes.
struct Column {
    alpha: f64,
    mus: Vec<f64>,
    at_mus: Vec<f64>,
    at_nodes: Vec<f64>,
}

/// The reference on the ledger's grids, for one visibility.
pub struct Reference {
    v: String,
    max_grid: Vec<Column>,
    mean_grid: Vec<Column>,
    mean_grid_r: Vec<Column>,
}

fn node(k: usize) -> f64 {
    (k as f64 + 0.5) / NODES as f64
}

fn env(spec: &ModelSpec) -> Result<Model<f64>> {
    let m = spec.model()?;
    match m {
        Model::Env(_) => Ok(m),
        _ => Err(Error::Domain {
            input: spec.id().to_string(),
            reason: "not a sheen albedo model".into(),
        }),
    }
}

fn eval(m: &Model<f64>, mu: f64, alpha: f64) -> f64 {
    match m {
        Model::Env(e) => e.e(mu, alpha),
        _ => f64::NAN,
    }
}

/// The white furnace `A(mu_o)` with `E` (the sheen lobe's) and `Es` (the scaling's) at the
/// view `mu_o` and at the nodes.
fn furnace(e_o: f64, es_o: f64, es_nodes: &[f64]) -> f64 {
    let s: f64 = es_nodes
        .iter()
        .enumerate()
        .map(|(k, &es_i)| (1.0 - es_o).min(1.0 - es_i).max(0.0) * node(k))
        .sum();
    e_o + 2.0 * s / NODES as f64
}

impl Reference {
    /// `sheen-albedo` at visibility `v` (`charlie`, `neubelt`) on the ledger's grids.
    pub fn new(v: &str) -> Result<Self> {
        let r = env(&ModelSpec::new(
            REFERENCE,
            &[("v", Given::Choice(v.into()))],
        )?)?;
        let span = 1.0 - ALPHA_MIN;
        let max_alphas: Vec<f64> = (0..64)
            .map(|j| ALPHA_MIN + span * j as f64 / 63.0)
            .chain((0..64).map(|j| ALPHA_MIN * (1.0 / ALPHA_MIN).powf(j as f64 / 63.0)))
            .collect();
        let max_mus: Vec<f64> = (0..=160)
            .map(|i| MU_MIN + (1.0 - MU_MIN) * (i as f64 / 160.0).powi(2))
            .collect();
        let mid = |i: usize| (i as f64 + 0.5) / 64.0;
        let mean_mus: Vec<f64> = (0..64).map(|i| MU_MIN + (1.0 - MU_MIN) * mid(i)).collect();
        let mean_alphas: Vec<f64> = (0..64).map(|j| ALPHA_MIN + span * mid(j)).collect();
        let rmin = ALPHA_MIN.sqrt();
        let mean_alphas_r: Vec<f64> = (0..64)
            .map(|j| (rmin + (1.0 - rmin) * mid(j)).powi(2))
            .collect();
        let columns = |alphas: &[f64], mus: &[f64]| -> Vec<Column> {
            alphas
                .par_iter()
                .map(|&alpha| Column {
                    alpha,
                    mus: mus.to_vec(),
                    at_mus: mus.iter().map(|&m| eval(&r, m, alpha)).collect(),
                    at_nodes: (0..NODES).map(|k| eval(&r, node(k), alpha)).collect(),
                })
                .collect()
        };
        Ok(Self {
            v: v.to_string(),
            max_grid: columns(&max_alphas, &max_mus),
            mean_grid: columns(&mean_alphas, &mean_mus),
            mean_grid_r: columns(&mean_alphas_r, &mean_mus),
        })
    }

    /// The reference's visibility.
    pub fn v(&self) -> &str {
        &self.v
    }

    /// The row of `spec` (a sheen albedo model) against this reference.
    pub fn measure(&self, spec: &ModelSpec) -> Result<SheenErrors> {
        let m = env(spec)?;
        let r = env(&ModelSpec::new(
            REFERENCE,
            &[("v", Given::Choice(self.v.clone()))],
        )?)?;
        // Per column: (albedo errors, furnace errors (A' - A), A' values, A values) per mu.
        type Col = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);
        let on = |cols: &[Column]| -> Vec<Col> {
            cols.par_iter()
                .map(|c| {
                    let es_nodes: Vec<f64> =
                        (0..NODES).map(|k| eval(&m, node(k), c.alpha)).collect();
                    let mut out: Col = Default::default();
                    for (&mu, &want) in c.mus.iter().zip(&c.at_mus) {
                        let got = eval(&m, mu, c.alpha);
                        let a1 = furnace(want, got, &es_nodes);
                        let a0 = furnace(want, want, &c.at_nodes);
                        out.0.push(got - want);
                        out.1.push(a1 - a0);
                        out.2.push(a1);
                        out.3.push(a0);
                    }
                    out
                })
                .collect()
        };
        let grid = on(&self.max_grid);
        let worst = |q: usize| -> (f64, f64, f64) {
            let mut best = (-1.0, 0.0, 0.0);
            for (c, col) in self.max_grid.iter().zip(&grid) {
                let errs = if q == 0 { &col.0 } else { &col.1 };
                for (&mu, &e) in c.mus.iter().zip(errs) {
                    if e.abs() > best.0 || e.is_nan() {
                        best = (e.abs(), mu, c.alpha);
                    }
                }
            }
            best
        };
        let (mut best, mut mu, mut alpha) = worst(0);
        // Refinement of the albedo's max: a 9 x 9 grid around the worst point, shrinking.
        let (mut dm, mut da) = (0.02 * mu.max(0.01), 0.05 * alpha);
        for _ in 0..3 {
            let (m0, a0) = (mu, alpha);
            for i in -4..=4 {
                for j in -4..=4 {
                    let mm = (m0 + dm * i as f64 / 4.0).clamp(MU_MIN, 1.0);
                    let aa = (a0 + da * j as f64 / 4.0).clamp(ALPHA_MIN, 1.0);
                    let x = (eval(&m, mm, aa) - eval(&r, mm, aa)).abs();
                    if x > best {
                        (mu, alpha, best) = (mm, aa, x);
                    }
                }
            }
            dm *= 0.25;
            da *= 0.25;
        }
        let (fbest, fmu, falpha) = worst(1);
        let mean = |cols: &[Column]| -> [f64; 2] {
            let g = on(cols);
            let n: usize = g.iter().map(|c| c.0.len()).sum();
            let s = g.iter().fold([0.0; 2], |s, c| {
                [
                    s[0] + c.0.iter().map(|e| e.abs()).sum::<f64>(),
                    s[1] + c.1.iter().map(|e| e.abs()).sum::<f64>(),
                ]
            });
            s.map(|x| x / n as f64)
        };
        let (ma, mr) = (mean(&self.mean_grid), mean(&self.mean_grid_r));
        let flat = |f: fn(&Col) -> &Vec<f64>| grid.iter().flat_map(f).copied();
        Ok(SheenErrors {
            v: self.v.clone(),
            albedo: TermError {
                max_abs: best,
                cos_v: mu,
                alpha,
                mean_abs: ma[0],
                mean_abs_r: mr[0],
            },
            furnace: TermError {
                max_abs: fbest,
                cos_v: fmu,
                alpha: falpha,
                mean_abs: ma[1],
                mean_abs_r: mr[1],
            },
            furnace_gain: flat(|c| &c.1).fold(0.0, f64::max),
            furnace_loss: flat(|c| &c.1).fold(0.0, |a, e| a.max(-e)),
            furnace_peak: flat(|c| &c.2).fold(0.0, f64::max),
            furnace_peak_exact: flat(|c| &c.3).fold(0.0, f64::max),
        })
    }
}

/// The visibility a configuration is measured at: its own `v`, else Charlie's (the fits
/// without `v` were fitted to it).
pub fn v_of(spec: &ModelSpec) -> String {
    match spec.get("v") {
        Some(Given::Choice(v)) => v.clone(),
        _ => "charlie".into(),
    }
}

/// One configuration of the ledger.
#[derive(Clone, Debug, Serialize)]
pub struct SheenRow {
    pub model: &'static str,
    /// Its choices, `NAME=VALUE`.
    pub params: Vec<(String, String)>,
    /// Operation counts, `mul/add/div/sqrt/transcendental`.
    pub ops: String,
    pub ns_per_eval: f64,
    pub errors: SheenErrors,
    pub pareto: bool,
}

impl SheenRow {
    /// `model` or `model:v=neubelt,bits=8`.
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            self.model.to_string()
        } else {
            let p: Vec<String> = self
                .params
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect();
            format!("{}:{}", self.model, p.join(","))
        }
    }
}

/// Every configuration of every sheen row: `(id, choices)`.
pub fn configs() -> Vec<(&'static str, Vec<(String, String)>)> {
    let mut out = vec![];
    for e in registry::all().iter().filter(|e| is_sheen(e.info.id)) {
        let mut sets: Vec<Vec<(String, String)>> = vec![vec![]];
        for p in e.info.params {
            if let ParamKind::Choice { options, .. } = p.kind {
                sets = sets
                    .iter()
                    .flat_map(|s| {
                        options.names().iter().map(move |o| {
                            let mut s = s.clone();
                            s.push((p.name.to_string(), o.to_string()));
                            s
                        })
                    })
                    .collect();
            }
        }
        out.extend(sets.into_iter().map(|s| (e.info.id, s)));
    }
    out
}

/// The spec of `id` with choices `params`.
pub fn spec(id: &str, params: &[(String, String)]) -> Result<ModelSpec> {
    let g: Vec<(&str, Given)> = params
        .iter()
        .map(|(k, v)| (k.as_str(), Given::Choice(v.clone())))
        .collect();
    ModelSpec::new(id, &g)
}

/// Nanoseconds per evaluation of the batch kernel of `spec` (4096 pairs of `mu` and `alpha`
/// over the domain, one core, measured now; the quadrature on 64 of them).
pub fn ns_per_eval(spec: &ModelSpec) -> Result<f64> {
    let k = Kernel::new(spec)?;
    let n = 4096;
    let cos: Vec<f32> = (0..n).map(|i| (i as f32 + 0.5) / n as f32).collect();
    let alpha: Vec<f32> = (0..n)
        .map(|i| 0.07 + 0.93 * ((i * 37) % n) as f32 / n as f32)
        .collect();
    let mut out = vec![0.0f32; n];
    let m = if spec.id() == REFERENCE { 64 } else { n };
    let t = crate::speed::time(
        || {
            k.eval(Input::Env([&cos[..m], &alpha[..m]]), &mut out[..m])
                .expect("sizes match")
        },
        Duration::from_millis(60),
    );
    Ok(t / m as f64 * 1e9)
}

/// Every row against the reference of its visibility, the front marked per visibility,
/// cheapest first. `progress` is called once per configuration.
pub fn rows(progress: &(dyn Fn() + Sync)) -> Result<Vec<SheenRow>> {
    let refs = [Reference::new("charlie")?, Reference::new("neubelt")?];
    let mut rows = vec![];
    for (id, params) in configs() {
        let s = spec(id, &params)?;
        let info = &registry::find(id)?.info;
        let o = info.ops;
        let ns = ns_per_eval(&s)?;
        // A row without `v` (Khronos' fit) is measured at both visibilities: gltf-pbr's
        // `sheen_albedo = fit` reads it with either.
        let own_v = info.params.iter().any(|p| p.name == "v");
        for r in &refs {
            if own_v && r.v() != v_of(&s) {
                continue;
            }
            rows.push(SheenRow {
                model: info.id,
                ops: format!(
                    "{}/{}/{}/{}/{}",
                    o.mul, o.add, o.div, o.sqrt, o.transcendental
                ),
                ns_per_eval: ns,
                errors: r.measure(&s)?,
                params: params.clone(),
                pareto: false,
            });
        }
        progress();
    }
    mark_front(&mut rows);
    Ok(rows)
}

/// Marks, among the rows of one visibility, those no other beats on both cost and the albedo's
/// max error; sorts by visibility, then cheapest first.
pub fn mark_front(rows: &mut [SheenRow]) {
    for i in 0..rows.len() {
        let (ci, ei, vi) = (
            rows[i].ns_per_eval,
            rows[i].errors.albedo.max_abs,
            rows[i].errors.v.clone(),
        );
        rows[i].pareto = !rows.iter().enumerate().any(|(j, r)| {
            let (c, e) = (r.ns_per_eval, r.errors.albedo.max_abs);
            j != i && r.errors.v == vi && c <= ci && e <= ei && (c < ci || e < ei)
        });
    }
    rows.sort_by(|a, b| {
        a.errors
            .v
            .cmp(&b.errors.v)
            .then(a.ns_per_eval.total_cmp(&b.ns_per_eval))
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sheen rows are the four sheen albedo models and none of the split-sum ones; every
    /// configuration is listed once; the reference against itself has no error; Khronos' fit
    /// has the grazing error of its fixed `(1 - mu)^3`; with the exact `E` the furnace never
    /// exceeds 1 (Charlie's albedo is below 1: `A <= E + (1 - E)`), with the fit it does.
    #[test]
    fn the_sheen_ledger_measures_what_it_says() {
        for id in [
            "sheen-albedo",
            "sheen-albedo-table",
            "sheen-albedo-khronos",
            "sheen-albedo-tuned",
        ] {
            assert!(is_sheen(id), "{id}");
        }
        assert!(!is_sheen("env-brdf") && !is_sheen("env-brdf-table") && !is_sheen("gltf-pbr"));
        assert_eq!(configs().len(), 2 + 2 * 3 + 1 + 2);
        assert!(
            crate::pareto_env::configs()
                .iter()
                .all(|(id, _)| !is_sheen(id))
        );
        let r = Reference::new("charlie").unwrap();
        let same = r.measure(&spec(REFERENCE, &[]).unwrap()).unwrap();
        assert!(
            same.albedo.max_abs < 1e-12 && same.furnace.max_abs < 1e-12,
            "{same:?}"
        );
        assert!(same.furnace_peak_exact <= 1.0 + 1e-9 && same.furnace_peak_exact > 0.99);
        let k = r
            .measure(&spec("sheen-albedo-khronos", &[]).unwrap())
            .unwrap();
        assert!(k.albedo.max_abs > 0.3 && k.albedo.cos_v < 0.01, "{k:?}");
        assert!(k.albedo.mean_abs < k.albedo.max_abs && k.furnace.mean_abs > 0.0);
        assert!(
            k.furnace_peak > 1.2 && k.furnace_gain.max(k.furnace_loss) <= k.furnace.max_abs + 1e-12
        );
    }
}
