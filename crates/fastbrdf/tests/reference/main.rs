//! Every model against an independent f64 evaluation of its printed formula (written here
//! from ../shared/MODELS.md and the seeds, naively: monomial cubics with the seed's closed-form
//! coefficients, complex arithmetic for Fresnel, Simpson's rule for normalisation), on grids
//! covering the whole domain (n in [1, 1000] and beyond, alpha in [0.005, 1]) with the edges.
//!
//! One test binary in topic files: `lobes`, `microfacet` (distributions, shadowing, Fresnel),
//! `brdfs`, `env` (split-sum terms); the registry-wide check that every model has a reference
//! is here.

#[path = "../common/mod.rs"]
mod common;

mod brdfs;
mod env;
mod gltf;
mod lobes;
mod microfacet;

use common::{ALPHA_VALUES, N_VALUES, Rng, build, direction_pairs};
use fastbrdf::accuracy::lobe_samples;
use fastbrdf::lobes::tuned;
use fastbrdf::{Model, registry};
use num_complex::Complex64;
use std::f64::consts::PI;

use lobes::*;
use microfacet::*;

pub(crate) fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

pub(crate) fn dotv(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Fresnel terms, split-sum terms and BRDFs with an independent reference formula in this
/// test's files (lobes, distributions and shadowing terms have theirs in `ref_lobe`,
/// `ref_distribution` and `ref_shadowing`, which panic on an unknown id).
const REFERENCED: &[&str] = &[
    "fresnel-none",
    "fresnel-schlick",
    "fresnel-schlick-sg",
    "fresnel-schlick-sg-tuned",
    "env-brdf",
    "env-brdf-approx",
    "env-brdf-approx-tuned",
    "env-brdf-materialx",
    "env-brdf-materialx-tuned",
    "env-brdf-table",
    // The sheen albedo rows: their independent reference (adaptive quadrature of the lobe)
    // is tests/sheen_albedo.rs.
    "sheen-albedo",
    "sheen-albedo-table",
    "sheen-albedo-khronos",
    "sheen-albedo-tuned",
    "fresnel-dielectric",
    "fresnel-conductor",
    "cook-torrance",
    "gltf-pbr",
    "ward",
    "ward-pow",
    "ward-power16",
    "lambert",
    "phong",
    "blinn-phong",
];

/// A model added to the registry without an independent f64 reference here fails this test
/// (rather than being skipped silently by the tests above).
#[test]
fn every_registered_model_has_an_independent_reference() {
    for e in registry::all() {
        match e.info.kind {
            fastbrdf::Kind::Lobe => {
                let _ = ref_lobe(e.info.id, 20.0, 0.9);
            }
            fastbrdf::Kind::Distribution => {
                let _ = ref_distribution(e.info.id, 0.3, 0.9);
            }
            fastbrdf::Kind::Shadowing => {
                let _ = ref_shadowing(e.info.id, 0.3, "alpha-half", 0.5, Some(0.6), 0.9, 0.9);
            }
            _ => assert!(
                REFERENCED.contains(&e.info.id),
                "{}: no independent reference formula in tests/reference/",
                e.info.id
            ),
        }
    }
}
