//! fastbrdf-analysis: what a graphics engineer needs before trusting an approximation.
//!
//! - [`errors`]: max absolute, max relative and RMS error of a model against a reference, per
//!   parameter value, with true maxima (dense grid, then golden-section refinement).
//! - [`normalize`]: `Int(n)` and `coef(n) = 1 / (2 pi Int(n))` of a lobe by adaptive f64
//!   quadrature, and least-squares fits of closed forms for `coef(n)`.
//! - [`albedo`]: directional albedo against incidence angle, with a white-furnace verdict.
//! - [`pareto`]: every lobe's error against its SIMD cost, and the Pareto front.
//! - [`pareto_brdf`]: full Cook-Torrance configurations against an exact one: SIMD cost, BRDF-
//!   and image-space error (FLIP), the Pareto front.
//! - [`reproduce`]: every numeric claim of the three seed papers, measured.
//! - [`check`]: every documented bound of the registry re-measured.
//! - [`chi2`]: the chi-square sampling test's sizes, JSON and picture (CLI and Python).
//! - [`conform`]: the checks a renderer's BSDF must pass, on any `UserBrdf` (`fastbrdf conform`).
//! - [`charts`]: the data of every chart and of the seeds' figures.
//! - [`plot`]: the charts drawn (PNG and SVG).
//! - [`measured_fit`]: registry BRDFs fitted to measured (MERL) data: Ngan 2005's L2, Low
//!   2012's log and the maximum error; argmin's Nelder-Mead with exact albedos for L2.
//! - [`measured_json`]: the JSON of `measured info` and `fit-measured` (CLI and Python).
//! - [`model_spec`]: parameter text, a material and a metal as one validated spec (CLI and
//!   Python).
//! - [`render_json`]: the JSON of `compare`, `materials` and `metals` (CLI and Python).
//! - [`materials`]: the 86 MERL materials' published fits (Ngan et al. 2005), embedded.
//! - [`lut`]: the split-sum "DFG" look-up table of an env model (CSV, EXR, PNG).
//! - [`range`]: parsing of `1..1000`, `1..1000:10`, `1,2,5` parameter lists.

// Guards written `if !(x > lo)` also catch NaN, on purpose (see the fastbrdf crate).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod albedo;
pub mod charts;
pub mod check;
pub mod chi2;
pub mod conform;
pub mod env_errors;
pub mod errors;
pub mod fit;
pub mod lut;
pub mod materials;
pub mod measured_fit;
pub mod measured_json;
pub mod model_spec;
pub mod normalize;
pub mod pareto;
pub mod pareto_brdf;
pub mod pareto_env;
pub mod plot;
pub mod range;
pub mod render_json;
pub mod reproduce;
pub mod sheen_ledger;
pub mod simplex;
pub mod speed;

pub use fastbrdf::{Error, Result};

/// A spec's given values as a JSON object: numbers as numbers, choices (`f=schlick`) as their
/// names, `R,G,B` values as their `a,b,c` text (the machine outputs of `albedo`,
/// `fit-measured`, `sample` and the Python package).
pub fn params_json(spec: &fastbrdf::ModelSpec) -> serde_json::Map<String, serde_json::Value> {
    spec.pairs()
        .into_iter()
        .map(|(k, v)| {
            let value = text_json(&v);
            (k, value)
        })
        .collect()
}

/// A value's text as JSON: a number where it reads as a finite one (a choice named by a
/// number, `denominator=4`, too, as these outputs always wrote it), else the text.
pub(crate) fn text_json(v: &str) -> serde_json::Value {
    v.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .map_or_else(|| serde_json::json!(v), |x| serde_json::json!(x))
}
