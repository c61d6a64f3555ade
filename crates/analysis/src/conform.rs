//! `fastbrdf conform` (issue 31): the checks a renderer's BSDF must pass, on any
//! [`UserBrdf`] (a registry model through [`fastbrdf::user::Builtin`], a user's GPU shader, a
//! Python object). Nothing here knows which: every check calls the trait, in batches of
//! thousands of rows ([`Config::batch`]), because the evaluators behind it are slow per call.
//!
//! The checks, in order (each a [`Check`] with its number and, where it has one, its place):
//!
//! - `finite`: `f` is finite on a deterministic grid of direction pairs (theta from 0 to 90
//!   degrees with `z` exactly 1 and exactly 0, 8 azimuths, every pair, mirror and coincident
//!   pairs included) and on [`Config::random_pairs`] uniform pairs of the upper hemisphere.
//! - `non-negative`: the least finite value on the same set is >= 0.
//! - `non-finite-input`: directions with a NaN or infinite component (each component of `wi`
//!   and of `wo`, and whole vectors) give finite, non-negative values.
//! - `reciprocity`: `max |f(wi, wo) - f(wo, wi)| cos theta_i cos theta_o` over the set (where
//!   both are finite), relative to the peak of `f cos theta_i cos theta_o`, <=
//!   [`Config::reciprocity_tol`]. The cosines (symmetric, as `f` must be) keep the
//!   `1 / (cos cos)` of grazing pairs (1e7 for GGX at alpha = 0.01) from swamping the peak and
//!   with it the tolerance: the difference is measured in the transport a renderer sees.
//! - `energy`: the directional albedo `a(wo) = integral f(wi, wo) cos theta_i dwi` at
//!   [`Config::energy_angles_deg`] (grazing included), per channel, <= 1 +
//!   [`Config::energy_tol`]: polar coordinates around the peak (the mirror direction, `wo` or
//!   the normal, whichever `f` is largest at), split at `u = 1 - 10^-k` and at the horizon,
//!   Gauss-Legendre panels doubled until the albedo settles ([`energy`]).
//! - `reference` (with a reference model): max absolute error relative to the reference's
//!   peak (the verdict, <= [`Config::reference_tol`]), max relative error where the
//!   reference exceeds [`Config::reference_floor`] of its peak, and the RMS error over solid
//!   angle (the uniform random pairs).
//! - with [`UserBrdf::samples`], at each of [`Config::sample_angles_deg`] ([`sampling`]):
//!   `chi2` (the sampler's histogram against its pdf, Mitsuba's test with `fastbrdf::chi2`'s
//!   sizes, the pdf integrated per bin in batched refinement rounds, Bonferroni over the
//!   angles; the pdf is divided by `max(1, its integral)` so that a pdf whose mass is wrong
//!   fails `pdf-integral`, not this), `weight` (`weight == f cos / pdf` per sample, max
//!   relative deviation), `pdf-integral` (<= 1 + [`Config::pdf_integral_tol`]; the summary
//!   says whether it is 1, the sampler covering the hemisphere), `pdf-coverage` (no pair of
//!   the value set with `f cos > coverage_threshold * peak` and `pdf == 0`: the estimator
//!   would be biased), `pdf-sample` (`pdf(wo, wi)` of each drawn `wi` equals the pdf the
//!   sampler reported, within [`Config::pdf_sample_tol`] relative).
//!
//! JSON: numbers that are not finite (a NaN albedo, a NaN direction) serialise as `null`
//! (serde_json's rule); the summary line carries them as text.

mod energy;
mod eval;
mod grid;
mod sampling;
mod values;

use fastbrdf::user::UserBrdf;
use serde::Serialize;

pub use eval::Batched;
pub use values::Agreement;

/// Sizes and tolerances of one run.
#[derive(Clone, Debug)]
pub struct Config {
    /// `"ci"` or `"full"`.
    pub mode: &'static str,
    /// Uniform random pairs of the upper hemisphere besides the grid.
    pub random_pairs: usize,
    /// Thetas of the grid, degrees (0 and 90 are exact: `z` = 1 and 0).
    pub grid_theta_deg: Vec<f64>,
    /// Azimuths of the grid.
    pub grid_phi: usize,
    pub seed: u64,
    /// Most rows per call of the model.
    pub batch: usize,
    /// `reciprocity`: max difference of `f cos cos` relative to its peak.
    pub reciprocity_tol: f64,
    /// `energy`: angles of `wo`, degrees.
    pub energy_angles_deg: Vec<f64>,
    /// `energy`: how far above 1 an albedo may read.
    pub energy_tol: f64,
    /// `energy`: the quadrature stops when two rounds agree to this (relative).
    pub energy_rel: f64,
    /// `energy`: the most refinement rounds (each doubles the panels in both variables).
    pub energy_rounds: usize,
    /// `reference`: max absolute error relative to the reference's peak.
    pub reference_tol: f64,
    /// `reference`: the relative error counts where the reference exceeds this fraction of
    /// its peak.
    pub reference_floor: f64,
    /// Sampling checks: angles of `wo`, degrees.
    pub sample_angles_deg: Vec<f64>,
    /// `chi2`: bins, samples, seed, integration cells, significance.
    pub chi2: fastbrdf::chi2::Config,
    /// `chi2`: the most integration cells per bin and axis.
    pub chi2_max_sub: usize,
    /// `weight`: max relative deviation of the reported weight from `f cos / pdf`.
    pub weight_tol: f64,
    /// `pdf-integral`: how far above 1 the integral may read; within it of 1 the sampler
    /// covers the hemisphere.
    pub pdf_integral_tol: f64,
    /// `pdf-coverage`: `f cos` above this fraction of its peak needs `pdf > 0`.
    pub coverage_threshold: f64,
    /// `pdf-sample`: max relative difference of `pdf(wo, wi)` and the reported pdf.
    pub pdf_sample_tol: f64,
}

impl Config {
    /// CI sizes: seconds per model.
    pub fn ci() -> Self {
        Self {
            mode: "ci",
            random_pairs: 20_000,
            grid_theta_deg: vec![
                0.0, 1.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.9, 89.99, 90.0,
            ],
            grid_phi: 8,
            seed: 31,
            batch: 1 << 14,
            reciprocity_tol: 1e-3,
            energy_angles_deg: vec![0.0, 30.0, 60.0, 80.0, 89.0],
            energy_tol: 1e-3,
            energy_rel: 1e-4,
            energy_rounds: 6,
            reference_tol: 1e-3,
            reference_floor: 1e-3,
            sample_angles_deg: vec![0.0, 45.0, 80.0],
            chi2: fastbrdf::chi2::Config::ci(),
            chi2_max_sub: 128,
            weight_tol: 1e-3,
            pdf_integral_tol: 1e-3,
            coverage_threshold: 1e-4,
            pdf_sample_tol: 1e-3,
        }
    }

    /// More of everything: Mitsuba's chi-square sizes (`fastbrdf::chi2::Config::full`), ten
    /// times the random pairs, more angles, a finer grid.
    pub fn full() -> Self {
        let mut theta: Vec<f64> = (0..=18).map(|k| k as f64 * 5.0).collect();
        theta.extend([0.1, 1.0, 87.0, 89.0, 89.5, 89.9, 89.99, 89.999]);
        theta.sort_by(f64::total_cmp);
        Self {
            mode: "full",
            random_pairs: 200_000,
            grid_theta_deg: theta,
            grid_phi: 16,
            energy_angles_deg: vec![
                0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 75.0, 80.0, 85.0, 87.0, 89.0, 89.5,
            ],
            energy_rounds: 7,
            sample_angles_deg: vec![0.0, 20.0, 45.0, 60.0, 75.0, 85.0, 89.0],
            chi2: fastbrdf::chi2::Config::full(),
            chi2_max_sub: 128,
            ..Self::ci()
        }
    }
}

/// A check's verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    Pass,
    Fail,
    Skip,
}

impl Status {
    /// `PASS`, `FAIL`, `SKIP`.
    pub fn label(self) -> &'static str {
        match self {
            Status::Pass => "PASS",
            Status::Fail => "FAIL",
            Status::Skip => "SKIP",
        }
    }
}

/// Where a check's number was found: a direction pair, or an angle of `wo` (energy and the
/// sampling checks), and the channel. Absent fields are left out of the JSON.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct At {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wi: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wo: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub theta_o_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub channel: Option<usize>,
}

/// One check's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct Check {
    pub check: &'static str,
    pub status: Status,
    /// The number the verdict is on (see the module docs for each check's).
    pub value: f64,
    /// The limit it is held to.
    pub limit: f64,
    /// One human line with the number.
    pub summary: String,
    pub at: Option<At>,
}

impl Check {
    fn new(check: &'static str, pass: bool, value: f64, limit: f64, summary: String) -> Self {
        Self {
            check,
            status: if pass { Status::Pass } else { Status::Fail },
            value,
            limit,
            summary,
            at: None,
        }
    }

    fn skip(check: &'static str, why: &str) -> Self {
        Self {
            check,
            status: Status::Skip,
            value: f64::NAN,
            limit: f64::NAN,
            summary: why.to_string(),
            at: None,
        }
    }

    fn at(mut self, at: Option<At>) -> Self {
        self.at = at;
        self
    }
}

/// What a run found.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub model: String,
    pub mode: &'static str,
    /// No check failed.
    pub passed: bool,
    pub checks: Vec<Check>,
}

impl Report {
    /// The names of the checks that failed.
    pub fn failed(&self) -> Vec<&'static str> {
        self.checks
            .iter()
            .filter(|c| c.status == Status::Fail)
            .map(|c| c.check)
            .collect()
    }
}

/// The names of every check, in the order [`run`] reports them.
pub const CHECKS: [&str; 11] = [
    "finite",
    "non-negative",
    "non-finite-input",
    "reciprocity",
    "energy",
    "reference",
    "chi2",
    "weight",
    "pdf-integral",
    "pdf-coverage",
    "pdf-sample",
];

/// Runs every check on `model` (and `reference` against it when given). `progress` is told
/// the name of each check as it starts. `Err`: an evaluator failed (its message, with the
/// model's name and the call).
pub fn run(
    model: &dyn UserBrdf,
    reference: Option<&dyn UserBrdf>,
    cfg: &Config,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Report, String> {
    let m = Batched::new(model, cfg.batch)?;
    let mut checks = Vec::new();
    progress("finite");
    let set = grid::pairs(cfg);
    let v = values::Values::eval(&m, &set)?;
    checks.push(v.finite(&set));
    progress("non-negative");
    checks.push(v.non_negative(&set));
    progress("non-finite-input");
    checks.push(values::non_finite_input(&m)?);
    progress("reciprocity");
    checks.push(v.reciprocity(&m, &set, cfg)?);
    progress("energy");
    checks.push(energy::check(&m, cfg)?);
    match reference {
        Some(r) => {
            progress("reference");
            let r = Batched::new(r, cfg.batch)?;
            checks.push(v.reference(&r, &set, cfg)?);
        }
        None => checks.push(Check::skip("reference", "no reference model given")),
    }
    if model.samples() {
        checks.extend(sampling::checks(&m, &set, &v, cfg, progress)?);
    } else {
        for c in &CHECKS[6..] {
            checks.push(Check::skip(c, "the model does not sample"));
        }
    }
    Ok(Report {
        model: model.name(),
        mode: cfg.mode,
        passed: checks.iter().all(|c| c.status != Status::Fail),
        checks,
    })
}

/// The directional albedo `integral f(wi, wo) cos theta_i dwi` per channel at `wo`
/// `theta_o_deg` from the normal (azimuth 0), as `energy` computes it, and whether its
/// refinement rounds settled to `cfg.energy_rel`.
pub fn albedo(
    model: &dyn UserBrdf,
    theta_o_deg: f64,
    cfg: &Config,
) -> Result<(Vec<f64>, bool), String> {
    let a = energy::albedo(&Batched::new(model, cfg.batch)?, wo_at(theta_o_deg), cfg)?;
    Ok((a.value, a.converged))
}

/// How `model` agrees with `reference` on the `reference` check's pair set (the numbers that
/// check holds to its limit): `fastbrdf errors` for users' models.
pub fn agreement(
    model: &dyn UserBrdf,
    reference: &dyn UserBrdf,
    cfg: &Config,
) -> Result<Agreement, String> {
    let m = Batched::new(model, cfg.batch)?;
    let set = grid::pairs(cfg);
    let v = values::Values::eval(&m, &set)?;
    v.agreement(&Batched::new(reference, cfg.batch)?, &set, cfg)
}

/// `x` in 3 significant digits (`NaN`, `inf` as such).
fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        format!("{x}")
    } else if (1e-3..1e4).contains(&x.abs()) {
        let s = format!("{x:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{x:.2e}")
    }
}

/// A direction as `(x, y, z)`.
fn dir(w: [f64; 3]) -> String {
    format!("({}, {}, {})", num(w[0]), num(w[1]), num(w[2]))
}

/// ` at wi=(..) wo=(..)`.
fn pair_text(wi: [f64; 3], wo: [f64; 3]) -> String {
    format!(" at wi={} wo={}", dir(wi), dir(wo))
}

fn pair_at(wi: [f64; 3], wo: [f64; 3]) -> Option<At> {
    Some(At {
        wi: Some(wi),
        wo: Some(wo),
        ..At::default()
    })
}

/// `wo` at `deg` from the normal, azimuth 0 (exact at 0 and 90 degrees).
fn wo_at(deg: f64) -> [f64; 3] {
    grid::direction(deg, 0.0)
}
