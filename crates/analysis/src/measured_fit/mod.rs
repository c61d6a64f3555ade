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
//!
//! Files: [`data`] (the sampled measurements), [`problem`] (the model, what is fixed, free and
//! held), [`search`] (the exact albedos, the metrics, Nelder-Mead and the fit's result),
//! [`flat`] (the identifiability check).

mod data;
mod flat;
mod problem;
mod search;

pub use data::Data;
pub use flat::{jacobi_eigen, undetermined};
pub use problem::{Free, Problem};
pub use search::{Fit, FittedBrdf, albedos, fit, residuals};

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
