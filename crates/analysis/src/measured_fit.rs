//! Fitting a registry BRDF to measured data (MERL `.binary`, `fastbrdf::measured`), as Ngan,
//! Durand and Matusik 2005 do: the fitted model is, per colour channel c,
//!
//! `f_c(wi, wo) = rho_d[c] / pi + rho_s[c] * spec(wi, wo; theta)`
//!
//! with the specular model's own numeric parameters `theta` shared by the three channels and
//! the six albedos per channel (all >= 0).
//!
//! Data: the valid MERL bins (all three channels measured) whose centre directions
//! (`measured::bin_centre`, `from_half_diff`) both lie within 80 degrees of the normal (Ngan et
//! al. drop the grazing data the same way); a fixed-seed (SplitMix64, [`SEED`]) subsample of
//! `samples` of them (all when fewer), so a fit is deterministic.
//!
//! Metrics, over the N samples k and the three channels c, with `cos = wi.z` (the incident
//! cosine), `m` the measured and `f` the model value:
//! - `ngan-l2` (Ngan et al. 2005): `sqrt( sum (cos (m - f))^2 / (3 N) )`;
//! - `low-log` (Low et al. 2012): `sqrt( sum (ln(1 + cos m) - ln(1 + cos f))^2 / (3 N) )`;
//! - `max` (this project's maximum error): `max |cos (m - f)|`.
//!
//! Optimiser: argmin's Nelder-Mead (a maintained crate; derivative-free, so any registry model
//! and every metric, smooth or not, work the same way), in an unbounded variable `u` mapped onto
//! each parameter's documented range by `t = (1 - cos u) / 2` (logarithmically for ranges
//! spanning more than a factor 20, such as `n` and `alpha`), from [`Options::restarts`] starts
//! (the parameters' defaults, then a Kronecker low-discrepancy sequence over the ranges), the
//! best then polished by one more Nelder-Mead from a small simplex.
//!
//! For `ngan-l2` the albedos are solved exactly, not searched: given `theta`, the squared error
//! separates per channel into a linear least-squares problem in `(rho_d, rho_s)` with both
//! non-negative, solved in closed form (the 2 x 2 normal equations, or the best one-variable
//! solution on the boundary when the unconstrained one is negative: an exact non-negative
//! least squares for two variables). The simplex then only searches `theta` (variable
//! projection). For `low-log` and `max` the albedos are not linear: the `ngan-l2` fit is
//! computed first and Nelder-Mead then searches `theta` and the six albedos together from it.
//!
//! Identifiability. Some parameters trade against the albedos exactly: Schlick's `f90` scales
//! the Fresnel term's grazing end as `rho_s` scales the whole lobe, so with `f0`, `f90` and
//! `rho_s` all free only the products `rho_s f0` and `rho_s f90` are determined (exact data
//! made with f0 0.04, rho_s 1 were fitted as f0 0.0316, f90 0.791, rho_s 1.265). Such
//! parameters ([`HELD`]) stay at their default unless asked for ([`Problem::with_free`]).
//! Every fit is then checked ([`Fit::undetermined`]): the Jacobian of the weighted model values
//! `cos f` with respect to the free parameters and the six albedos is taken at the optimum
//! (central differences), its columns scaled to unit length, and a singular value below
//! [`FLAT_TOL`] (a direction along which the model moves by less than 1e-5 of what any one
//! parameter alone does) names the parameters of that direction as not determined by the data.
//! A parameter whose column is zero (a lobe parameter when every `rho_s` is 0) is one too.

use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use fastbrdf::measured::{self, MeasuredBrdf};
use fastbrdf::params::ParamKind;
use fastbrdf::{Brdf, Kind, Model, registry};
use std::cell::Cell;
use std::f64::consts::PI;

/// The subsample's seed.
pub const SEED: u64 = 0x6d65_726c_2d66_6974;
/// The default number of sampled bins.
pub const DEFAULT_SAMPLES: usize = 8000;
/// Bins whose incident or outgoing direction is further than this from the normal are left out.
pub const MAX_THETA_DEG: f64 = 80.0;

/// Numeric parameters held at their default by a search unless asked for by name
/// ([`Problem::with_free`]), with the reason: each trades exactly against the albedos.
pub const HELD: &[(&str, &str)] = &[(
    "f90",
    "Schlick's f90 scales the grazing reflectance as rho_s scales the lobe: with f0, f90 and rho_s all free only their products are determined",
)];

/// A singular value of the column-normalised Jacobian below this is a flat direction: the
/// parameters along it are not determined by the data (see the module documentation). Exact
/// trade-offs measure ~1e-10 (the finite differences' error); the least determined parameter
/// of a well-posed fit in the tests (Cook-Torrance's f0 against rho_s) is far above it.
pub const FLAT_TOL: f64 = 1e-5;

/// A fitting metric (see the module documentation for the formulas).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    NganL2,
    LowLog,
    Max,
}

impl Metric {
    pub const ALL: [Metric; 3] = [Metric::NganL2, Metric::LowLog, Metric::Max];

    pub fn name(self) -> &'static str {
        match self {
            Metric::NganL2 => "ngan-l2",
            Metric::LowLog => "low-log",
            Metric::Max => "max",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// The three metrics of one model against the data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Residuals {
    pub ngan_l2: f64,
    pub low_log: f64,
    pub max: f64,
}

impl Residuals {
    pub fn get(&self, m: Metric) -> f64 {
        match m {
            Metric::NganL2 => self.ngan_l2,
            Metric::LowLog => self.low_log,
            Metric::Max => self.max,
        }
    }
}

/// The sampled measurements: directions (unit, local frame) and R, G, B values.
#[derive(Clone, Debug)]
pub struct Data {
    pub wi: Vec<[f64; 3]>,
    pub wo: Vec<[f64; 3]>,
    pub value: Vec<[f64; 3]>,
    /// Valid bins within [`MAX_THETA_DEG`] before subsampling.
    pub eligible: usize,
}

/// SplitMix64: a small, well-known generator, enough for a deterministic subsample.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

impl Data {
    /// At most `samples` of the eligible bins of `b` (see the module documentation), in bin
    /// order, chosen by a fixed-seed partial Fisher-Yates shuffle. `samples = 0`: all.
    pub fn from_measured(b: &MeasuredBrdf, samples: usize) -> Self {
        let cos_max = MAX_THETA_DEG.to_radians().cos();
        let mut eligible = Vec::new();
        for i in 0..measured::SAMPLES {
            if (0..3).any(|c| b.sample(c, i) < 0.0) {
                continue;
            }
            let (th, td, pd) = measured::bin_of(i);
            let (a, d, p) = measured::bin_centre(th, td, pd);
            let (wi, wo) = measured::from_half_diff(a, d, p);
            if wi[2] >= cos_max && wo[2] >= cos_max {
                eligible.push(i);
            }
        }
        let total = eligible.len();
        if samples > 0 && samples < total {
            let mut rng = SplitMix(SEED);
            for k in 0..samples {
                let j = k + (rng.next() % (total - k) as u64) as usize;
                eligible.swap(k, j);
            }
            eligible.truncate(samples);
            eligible.sort_unstable();
        }
        let mut d = Data {
            wi: Vec::with_capacity(eligible.len()),
            wo: Vec::with_capacity(eligible.len()),
            value: Vec::with_capacity(eligible.len()),
            eligible: total,
        };
        for i in eligible {
            let (th, td, pd) = measured::bin_of(i);
            let (a, dd, p) = measured::bin_centre(th, td, pd);
            let (wi, wo) = measured::from_half_diff(a, dd, p);
            d.wi.push(wi);
            d.wo.push(wo);
            d.value.push([0, 1, 2].map(|c| b.sample(c, i)));
        }
        d
    }

    pub fn len(&self) -> usize {
        self.wi.len()
    }

    pub fn is_empty(&self) -> bool {
        self.wi.is_empty()
    }
}

/// A fitted (or searched) numeric parameter and its documented range.
#[derive(Clone, Debug)]
pub struct Free {
    pub name: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    /// The default, where the first start begins.
    pub default: f64,
}

impl Free {
    fn value(&self, u: f64) -> f64 {
        let t = (0.5 - 0.5 * u.cos()).clamp(0.0, 1.0);
        let v = if self.log {
            (self.lo.ln() + t * (self.hi.ln() - self.lo.ln())).exp()
        } else {
            self.lo + t * (self.hi - self.lo)
        };
        v.clamp(self.lo, self.hi)
    }

    fn u_of_t(t: f64) -> f64 {
        (1.0 - 2.0 * t.clamp(0.0, 1.0)).acos()
    }

    fn t_of(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

/// What is fitted: a registry BRDF, its fixed parameters (choices and values given by the
/// user) and its free numeric parameters.
#[derive(Clone, Debug)]
pub struct Problem {
    pub id: String,
    pub fixed: Vec<(String, String)>,
    pub free: Vec<Free>,
    /// Parameters of [`HELD`] the model reads that a search left at their default (name,
    /// value): not fitted, and not in `fixed`.
    pub held: Vec<(&'static str, f64)>,
}

impl Problem {
    /// Model `id` (a BRDF) with `fixed` parameters; with `search`, every other numeric
    /// parameter that has a default and whose required choices hold is free, except those of
    /// [`HELD`] (left at their default), otherwise none is (defaults are used). Errors: an
    /// unknown id, a non-BRDF kind, an invalid parameter.
    pub fn new(id: &str, fixed: &[(String, String)], search: bool) -> Result<Self, String> {
        Self::with_free(id, fixed, search, &[])
    }

    /// [`Problem::new`], with the [`HELD`] parameters named in `also` fitted too. Errors also:
    /// a name in `also` that is not one of the model's numeric parameters, or that `fixed`
    /// gives.
    pub fn with_free(
        id: &str,
        fixed: &[(String, String)],
        search: bool,
        also: &[String],
    ) -> Result<Self, String> {
        let e = registry::find(id).map_err(|e| e.to_string())?;
        for name in also {
            let short = fastbrdf_io::shorten(name, 40);
            match e.info.params.iter().find(|p| p.name == name) {
                Some(p) if matches!(p.kind, ParamKind::Number { .. }) => {}
                Some(_) => return Err(format!("{short} is a choice, not a number to fit")),
                None => return Err(format!("{} has no parameter '{short}'", e.info.id)),
            }
            if fixed.iter().any(|(k, _)| k == name) {
                return Err(format!(
                    "{short} is both fixed (--param) and asked to be fitted"
                ));
            }
        }
        if e.info.kind != Kind::Brdf {
            return Err(format!(
                "{id} is a {} model; fitting measured data needs a BRDF (see `fastbrdf models --kind brdf`)",
                format!("{:?}", e.info.kind).to_lowercase()
            ));
        }
        let given = |name: &str| {
            fixed
                .iter()
                .find(|(k, _)| k == name)
                .map(|(_, v)| v.clone())
        };
        // The choices in force (given or default), for `requires`.
        let choice = |name: &str| {
            given(name).or_else(|| {
                e.info
                    .params
                    .iter()
                    .find(|p| p.name == name)
                    .and_then(|p| match p.kind {
                        ParamKind::Choice { default, .. } => Some(default.to_string()),
                        ParamKind::Number { .. } => None,
                    })
            })
        };
        let mut free = Vec::new();
        let mut held = Vec::new();
        if search {
            for p in e.info.params {
                if given(p.name).is_some() {
                    continue;
                }
                let ParamKind::Number {
                    min,
                    max,
                    default: Some(default),
                    ..
                } = p.kind
                else {
                    continue;
                };
                if !(p.allowed(choice) && max > min) {
                    continue;
                }
                // Probed below like the others; moved to `held` if the model reads it.
                held.push(
                    HELD.iter().any(|(n, _)| *n == p.name) && !also.iter().any(|a| a == p.name),
                );
                free.push(Free {
                    name: p.name,
                    lo: min,
                    hi: max,
                    log: min > 0.0 && max / min > 20.0,
                    default,
                });
            }
        }
        let mut problem = Self {
            id: e.info.id.to_string(),
            fixed: fixed.to_vec(),
            free,
            held: Vec::new(),
        };
        let defaults: Vec<f64> = problem.free.iter().map(|f| f.default).collect();
        let base = problem.model(&defaults).map_err(|e| e.to_string())?;
        // A parameter the chosen configuration does not read (cook-torrance's eta and k beside
        // f = schlick) would be a flat direction of the search: it stays at its default. It is
        // found by probing: moved to two other points of its range, the model is unchanged at
        // every probe direction.
        let probes: Vec<([f64; 3], [f64; 3])> = (0..24)
            .map(|i| {
                let th = 0.05 + 0.06 * i as f64;
                let td = 0.1 + 0.055 * ((i * 7) % 24) as f64;
                measured::from_half_diff(th.min(1.3), td.min(1.35), 0.3 + 0.12 * i as f64)
            })
            .collect();
        let mut used = Vec::new();
        for (i, f) in problem.free.iter().enumerate() {
            let mut reads = false;
            for t in [0.3, 0.8] {
                let mut v = defaults.clone();
                v[i] = f.value(Free::u_of_t(t));
                let Ok(m) = problem.model(&v) else {
                    reads = true;
                    break;
                };
                reads |= probes
                    .iter()
                    .any(|&(wi, wo)| m.eval(wi, wo) != base.eval(wi, wo));
            }
            used.push(reads);
        }
        let all = std::mem::take(&mut problem.free);
        for ((f, used), held) in all.into_iter().zip(used).zip(held) {
            match (used, held) {
                (false, _) => {}
                (true, true) => problem.held.push((f.name, f.default)),
                (true, false) => problem.free.push(f),
            }
        }
        // A name in `also` that did not change what is fitted is refused: a silent no-op would
        // let the user believe it was fitted (or that the model reads it).
        for name in also {
            let short = fastbrdf_io::shorten(name, 40);
            let Some(p) = e.info.params.iter().find(|p| p.name == name) else {
                continue;
            };
            let ParamKind::Number {
                min,
                max,
                default,
                requires,
            } = p.kind
            else {
                continue;
            };
            let why = if !search {
                format!("nothing is fitted without a search, so {short} is not either")
            } else if !p.allowed(choice) {
                let need: Vec<String> = requires
                    .iter()
                    .map(|(c, vals)| format!("{c} = {}", vals.join(" or ")))
                    .collect();
                format!(
                    "{short} is not read with these choices (it needs {}); nothing to fit",
                    need.join(" and ")
                )
            } else if default.is_none() || max <= min {
                format!("{short} has no default and range to search from; give it with --param")
            } else if !problem.free.iter().any(|f| f.name == name.as_str()) {
                let with: Vec<String> = problem
                    .fixed
                    .iter()
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect();
                format!(
                    "{} {} does not read {short} (moving it changes nothing); nothing to fit",
                    e.info.id,
                    if with.is_empty() {
                        "with its default choices".to_string()
                    } else {
                        format!("with {}", with.join(" "))
                    }
                )
            } else if !HELD.iter().any(|(n, _)| n == name) {
                let held: Vec<&str> = HELD.iter().map(|(n, _)| *n).collect();
                format!(
                    "{short} is fitted already; --free only adds the parameters held at their default ({})",
                    held.join(", ")
                )
            } else {
                continue;
            };
            return Err(format!("--free {short}: {why}"));
        }
        Ok(problem)
    }

    /// The parameters as text: the fixed ones, then the free ones at `values`.
    pub fn params(&self, values: &[f64]) -> Vec<(String, String)> {
        let mut p = self.fixed.clone();
        p.extend(
            self.free
                .iter()
                .zip(values)
                .map(|(f, v)| (f.name.to_string(), format!("{v}"))),
        );
        p
    }

    /// The specular model at `values` (one per free parameter).
    pub fn model(&self, values: &[f64]) -> fastbrdf::Result<Box<dyn Brdf<f64>>> {
        let p = self.params(values);
        let given: Vec<(&str, &str)> = p.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        match registry::build::<f64>(&self.id, &given)? {
            Model::Brdf(b) => Ok(b),
            _ => unreachable!("checked to be a BRDF"),
        }
    }

    /// The specular values at every sample, or `None` when one is not finite.
    fn spec(&self, data: &Data, values: &[f64]) -> Option<Vec<f64>> {
        let b = self.model(values).ok()?;
        let s: Vec<f64> = data
            .wi
            .iter()
            .zip(&data.wo)
            .map(|(&wi, &wo)| b.eval(wi, wo))
            .collect();
        s.iter().all(|x| x.is_finite()).then_some(s)
    }
}

/// The non-negative least-squares albedos `(rho_d, rho_s)` of each channel given the specular
/// values `spec` (exact: see the module documentation).
pub fn albedos(data: &Data, spec: &[f64]) -> [[f64; 2]; 3] {
    [0, 1, 2].map(|c| {
        let (mut a11, mut a12, mut a22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for ((wi, v), &sk) in data.wi.iter().zip(&data.value).zip(spec) {
            let w = wi[2];
            let (x1, x2, y) = (w / PI, w * sk, w * v[c]);
            a11 += x1 * x1;
            a12 += x1 * x2;
            a22 += x2 * x2;
            r1 += x1 * y;
            r2 += x2 * y;
        }
        // SSE(a, b) - sum y^2 = -2 (a r1 + b r2) + a^2 a11 + 2 a b a12 + b^2 a22.
        let sse = |a: f64, b: f64| {
            -2.0 * (a * r1 + b * r2) + a * a * a11 + 2.0 * a * b * a12 + b * b * a22
        };
        let mut best = (0.0, 0.0);
        let mut cands = vec![];
        let det = a11 * a22 - a12 * a12;
        // Nearly collinear columns (a Lambert-like specular): only the boundary solutions.
        if det > 1e-12 * a11 * a22 {
            let a = (r1 * a22 - r2 * a12) / det;
            let b = (r2 * a11 - r1 * a12) / det;
            if a >= 0.0 && b >= 0.0 {
                cands.push((a, b));
            }
        }
        if a11 > 0.0 {
            cands.push(((r1 / a11).max(0.0), 0.0));
        }
        if a22 > 0.0 {
            cands.push((0.0, (r2 / a22).max(0.0)));
        }
        let mut e = 0.0;
        for (a, b) in cands {
            let s = sse(a, b);
            if s < e {
                (e, best) = (s, (a, b));
            }
        }
        [best.0, best.1]
    })
}

/// The three metrics of the model `rho_d / pi + rho_s spec` (per channel) against the data.
pub fn residuals(data: &Data, spec: &[f64], alb: &[[f64; 2]; 3]) -> Residuals {
    let (mut l2, mut lg, mut mx) = (0.0f64, 0.0f64, 0.0f64);
    for ((wi, v), &sk) in data.wi.iter().zip(&data.value).zip(spec) {
        let w = wi[2];
        for (c, a) in alb.iter().enumerate() {
            let m = v[c];
            let f = a[0] / PI + a[1] * sk;
            let d = w * (m - f);
            l2 += d * d;
            mx = mx.max(d.abs());
            let l = (w * m).ln_1p() - (w * f).ln_1p();
            lg += l * l;
        }
    }
    let n = (3 * data.len()).max(1) as f64;
    Residuals {
        ngan_l2: (l2 / n).sqrt(),
        low_log: (lg / n).sqrt(),
        max: mx,
    }
}

/// How the search runs.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub metric: Metric,
    /// Nelder-Mead starts (at least 1).
    pub restarts: usize,
    /// Iterations per Nelder-Mead run.
    pub max_iters: u64,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            metric: Metric::NganL2,
            restarts: 6,
            max_iters: 200,
        }
    }
}

/// A fit's result.
#[derive(Clone, Debug)]
pub struct Fit {
    pub problem: Problem,
    pub metric: Metric,
    /// The free parameters' fitted values, in `problem.free`'s order.
    pub values: Vec<f64>,
    /// Per channel R, G, B.
    pub rho_d: [f64; 3],
    pub rho_s: [f64; 3],
    pub residuals: Residuals,
    /// Objective evaluations (each one model evaluation per sample).
    pub evaluations: u64,
    /// Nelder-Mead runs made (starts and polishes).
    pub runs: usize,
    pub samples: usize,
    /// The fitted quantities the data do not determine (see the module documentation): free
    /// parameter names and `rho_d` / `rho_s` (any channel), in that order; empty when every
    /// one is determined.
    pub undetermined: Vec<String>,
}

impl Fit {
    /// The model's parameters as text (fixed, then fitted).
    pub fn params(&self) -> Vec<(String, String)> {
        self.problem.params(&self.values)
    }

    /// The fitted RGB BRDF, for rendering.
    pub fn brdf(&self) -> fastbrdf::Result<FittedBrdf> {
        Ok(FittedBrdf {
            model: self.problem.model(&self.values)?,
            rho_d: self.rho_d,
            rho_s: self.rho_s,
        })
    }
}

/// A fitted model with its albedos: `rho_d[c] / pi + rho_s[c] spec`, evaluated in f64 and
/// rounded to f32 for the renderer.
pub struct FittedBrdf {
    pub model: Box<dyn Brdf<f64>>,
    pub rho_d: [f64; 3],
    pub rho_s: [f64; 3],
}

impl FittedBrdf {
    pub fn eval_rgb(&self, wi: [f64; 3], wo: [f64; 3]) -> [f64; 3] {
        if !(wi[2] > 0.0 && wo[2] > 0.0) {
            return [0.0; 3];
        }
        let s = self.model.eval(wi, wo);
        [0, 1, 2].map(|c| self.rho_d[c] / PI + self.rho_s[c] * s)
    }
}

impl fastbrdf_render::scene::RgbBrdf for FittedBrdf {
    fn eval_rgb(&self, wi: [f32; 3], wo: [f32; 3]) -> [f32; 3] {
        FittedBrdf::eval_rgb(self, wi.map(f64::from), wo.map(f64::from)).map(|v| v as f32)
    }
}

/// The objective over the unbounded vector `x`: the free parameters' `u`, then (joint
/// search) the six albedos (their absolute values).
struct Objective<'a> {
    problem: &'a Problem,
    data: &'a Data,
    metric: Metric,
    joint: bool,
    /// Evaluations, shared by the copies handed to argmin.
    evals: &'a Cell<u64>,
}

impl Objective<'_> {
    fn values(&self, x: &[f64]) -> Vec<f64> {
        self.problem
            .free
            .iter()
            .zip(x)
            .map(|(f, &u)| f.value(u))
            .collect()
    }

    /// (cost, albedos) at `x`.
    fn eval(&self, x: &[f64]) -> (f64, [[f64; 2]; 3]) {
        self.evals.set(self.evals.get() + 1);
        let values = self.values(x);
        let Some(spec) = self.problem.spec(self.data, &values) else {
            return (f64::INFINITY, [[0.0; 2]; 3]);
        };
        let alb = if self.joint {
            let k = self.problem.free.len();
            [0, 1, 2].map(|c| [x[k + 2 * c].abs(), x[k + 2 * c + 1].abs()])
        } else {
            albedos(self.data, &spec)
        };
        let r = residuals(self.data, &spec, &alb).get(self.metric);
        (if r.is_finite() { r } else { f64::INFINITY }, alb)
    }
}

impl CostFunction for Objective<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.eval(x).0)
    }
}

/// One Nelder-Mead run from `x0` with per-coordinate steps `step`; the best point and cost.
fn nelder_mead(obj: &Objective, x0: &[f64], step: &[f64], iters: u64) -> (Vec<f64>, f64) {
    if x0.is_empty() {
        return (Vec::new(), obj.eval(x0).0);
    }
    let mut simplex = vec![x0.to_vec()];
    for i in 0..x0.len() {
        let mut v = x0.to_vec();
        v[i] += step[i];
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(1e-12)
        .expect("a non-negative tolerance");
    let run = Executor::new(
        Objective {
            problem: obj.problem,
            data: obj.data,
            metric: obj.metric,
            joint: obj.joint,
            evals: obj.evals,
        },
        solver,
    )
    .configure(|s| s.max_iters(iters))
    .run();
    match run {
        Ok(r) => {
            let best = r.state().get_best_param().cloned().unwrap_or(x0.to_vec());
            let cost = r.state().get_best_cost();
            (best, cost)
        }
        Err(_) => (x0.to_vec(), obj.eval(x0).0),
    }
}

/// The `j`-th start in `[0, 1]^d`: the defaults for `j = 0`, then a Kronecker sequence.
fn start(free: &[Free], j: usize) -> Vec<f64> {
    const ALPHAS: [f64; 8] = [
        0.618_033_988_749_894_9,
        0.414_213_562_373_095,
        0.732_050_807_568_877_2,
        0.236_067_977_499_79,
        0.645_751_311_064_590_6,
        0.316_624_790_355_4,
        0.123_105_625_617_66,
        0.358_898_943_540_674,
    ];
    free.iter()
        .enumerate()
        .map(|(i, f)| {
            let t = if j == 0 {
                f.t_of(f.default)
            } else {
                (0.5 + j as f64 * ALPHAS[i % ALPHAS.len()]).fract()
            };
            Free::u_of_t(t.clamp(0.02, 0.98))
        })
        .collect()
}

/// Fits `problem` to `data` with `opts`; `progress(done, total)` after each Nelder-Mead run.
pub fn fit(
    problem: &Problem,
    data: &Data,
    opts: &Options,
    progress: &dyn Fn(usize, usize),
) -> Result<Fit, String> {
    if data.is_empty() {
        return Err("no valid measured sample within 80 degrees of the normal".into());
    }
    let k = problem.free.len();
    let restarts = opts.restarts.max(1);
    let joint = opts.metric != Metric::NganL2;
    let total = restarts + 1 + usize::from(joint) * 2;
    let counter = Cell::new(0u64);
    let l2 = Objective {
        problem,
        data,
        metric: Metric::NganL2,
        joint: false,
        evals: &counter,
    };
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut runs = 0;
    let starts = if k == 0 { 1 } else { restarts };
    for j in 0..starts {
        let x0 = start(&problem.free, j);
        let r = nelder_mead(&l2, &x0, &vec![0.4; k], opts.max_iters);
        runs += 1;
        progress(runs, total);
        if best.as_ref().is_none_or(|b| r.1 < b.1) {
            best = Some(r);
        }
    }
    let (mut x, _) = best.expect("at least one start");
    if k > 0 {
        x = nelder_mead(&l2, &x, &vec![0.05; k], opts.max_iters).0;
        runs += 1;
    }
    progress(runs, total);
    let (_, mut alb) = l2.eval(&x);
    if joint {
        let obj = Objective {
            problem,
            data,
            metric: opts.metric,
            joint: true,
            evals: &counter,
        };
        let mut xj = x.clone();
        xj.extend(alb.iter().flatten());
        let mut step = vec![0.2; k];
        step.extend(alb.iter().flatten().map(|a| 0.2 * a + 1e-3));
        for scale in [1.0, 0.1] {
            let s: Vec<f64> = step.iter().map(|v| v * scale).collect();
            xj = nelder_mead(&obj, &xj, &s, opts.max_iters * 2).0;
            runs += 1;
            progress(runs, total);
        }
        // Keep the joint result only where it improves the chosen metric.
        let before = {
            let values = l2.values(&x);
            let spec = problem
                .spec(data, &values)
                .expect("finite at the l2 optimum");
            residuals(data, &spec, &alb).get(opts.metric)
        };
        let (cost, a) = obj.eval(&xj);
        if cost < before {
            x = xj[..k].to_vec();
            alb = a;
        }
    }
    let values = l2.values(&x);
    let spec = problem
        .spec(data, &values)
        .ok_or("the model is not finite at the optimum")?;
    let undetermined = undetermined(problem, data, &values, &spec, &alb);
    Ok(Fit {
        undetermined,
        problem: problem.clone(),
        metric: opts.metric,
        residuals: residuals(data, &spec, &alb),
        values,
        rho_d: alb.map(|a| a[0]),
        rho_s: alb.map(|a| a[1]),
        evaluations: counter.get(),
        runs,
        samples: data.len(),
    })
}

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

    /// Cook-Torrance (f = schlick, d = ggx) tabulated exactly with f0 0.04, f90 1 and rho_s 1.
    fn schlick_data() -> Data {
        let params = [
            ("f", "schlick"),
            ("d", "ggx"),
            ("alpha", "0.3"),
            ("f0", "0.04"),
        ];
        let Model::Brdf(b) = registry::build::<f64>("cook-torrance", &params).unwrap() else {
            panic!("a BRDF")
        };
        let kd = [0.05, 0.04, 0.03];
        let bytes = measured::merl_bytes(|th, td, pd| {
            let (wi, wo) = measured::from_half_diff(th, td, pd);
            if wi[2] <= 0.0 || wo[2] <= 0.0 {
                return [-1.0; 3];
            }
            let s = b.eval(wi, wo);
            [0, 1, 2].map(|c| kd[c] / PI + s)
        });
        let m = MeasuredBrdf::from_reader(&bytes[..], std::path::Path::new("s.binary")).unwrap();
        Data::from_measured(&m, 1500)
    }

    fn fixed(p: &[(&str, &str)]) -> Vec<(String, String)> {
        p.iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    }

    /// Issue 27: with f90 free only products of f0, f90 and rho_s were determined (f0 0.0316,
    /// f90 0.791, rho_s 1.265 on these data, no warning). f90 is now held at 1 and the fit
    /// recovers f0 and rho_s; asking for f90 is reported as undetermined.
    #[test]
    fn schlick_f90_is_held_and_a_degenerate_request_is_reported() {
        let data = schlick_data();
        let fx = fixed(&[("f", "schlick"), ("d", "ggx")]);
        let problem = Problem::new("cook-torrance", &fx, true).unwrap();
        let names: Vec<&str> = problem.free.iter().map(|f| f.name).collect();
        assert_eq!(names, ["alpha", "f0"]);
        assert_eq!(problem.held, [("f90", 1.0)]);
        let r = fit(&problem, &data, &Options::default(), &|_, _| {}).unwrap();
        assert!((r.values[1] - 0.04).abs() < 0.02 * 0.04, "{:?}", r.values);
        assert!((r.values[0] - 0.3).abs() < 0.02 * 0.3, "{:?}", r.values);
        for c in 0..3 {
            assert!((r.rho_s[c] - 1.0).abs() < 0.02, "{:?}", r.rho_s);
        }
        assert!(r.undetermined.is_empty(), "{:?}", r.undetermined);
        // Asked for, f90 is fitted, and the fit says what it cannot determine.
        let free = Problem::with_free("cook-torrance", &fx, true, &["f90".into()]).unwrap();
        let names: Vec<&str> = free.free.iter().map(|f| f.name).collect();
        assert_eq!(names, ["alpha", "f0", "f90"]);
        let d = fit(&free, &data, &Options::default(), &|_, _| {}).unwrap();
        assert_eq!(d.undetermined, ["f0", "f90", "rho_s"], "{d:?}");
        // Bad requests.
        assert!(Problem::with_free("cook-torrance", &fx, true, &["nope".into()]).is_err());
        assert!(Problem::with_free("cook-torrance", &fx, true, &["d".into()]).is_err());
        let both = fixed(&[("f", "schlick"), ("f90", "1")]);
        assert!(Problem::with_free("cook-torrance", &both, true, &["f90".into()]).is_err());
    }

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
