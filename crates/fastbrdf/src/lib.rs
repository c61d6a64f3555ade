//! fastbrdf: exact and approximate specular reflectance models, in f32 and f64.
//!
//! Every model of the three seed papers (logarithmic, cubic, rational and power stand-ins for
//! `cos^n`; one-function Beckmann and Ward forms) sits beside the exact models and the
//! industry's approximations. Each model lives in one file whose `//!` header gives its
//! formula, parameters, source, cost and error bound; [`registry`] lists them all.
//!
//! ```
//! use fastbrdf::{Model, ModelSpec};
//! // A lobe by id with its parameter given as text (as the CLI does), parsed and validated
//! // once into a spec, then built in f32.
//! let spec = ModelSpec::parse("flog", &[("n", "20")]).unwrap();
//! let Model::Lobe(flog) = spec.model::<f32>().unwrap() else { panic!() };
//! assert!((flog.eval(1.0) - 1.0).abs() < 1e-6);
//! // A plan from a typed constructor (coefficients in f64), evaluated in f64.
//! let plan = fastbrdf::plan::Plan::Distribution(
//!     fastbrdf::microfacet::beckmann::Beckmann::new(0.3).unwrap().into(),
//! );
//! let Model::Distribution(d) = plan.model::<f64>() else { panic!() };
//! assert!((d.eval(1.0) - 1.0 / (std::f64::consts::PI * 0.09)).abs() < 1e-12);
//! ```
//!
//! Conventions: local shading frame with the normal along +z; `wi` and `wo` both point away
//! from the surface; full BRDFs are returned without the cosine factor. Out-of-domain inputs
//! give 0 by the rules written on each trait ([`Lobe::eval`], [`Distribution::eval`],
//! [`Brdf::eval`]); invalid parameters are an [`Error`] at construction.

// Guards are written `if !(x >= lo)` on purpose: the negated form also catches NaN, which is
// the point of a guard (pbrt's style). The lint's suggested rewrite would let NaN through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod accuracy;
pub mod batch;
pub mod brdf;
pub mod chi2;
pub mod colour;
pub mod entry;
pub mod error;
pub mod forms;
pub mod kind;
pub mod lobes;
pub mod math;
pub mod measured;
pub mod microfacet;
pub mod model;
pub mod par;
pub mod params;
pub mod plan;
pub mod quad;
pub mod real;
pub mod registry;
pub mod sample;
pub mod spec;
pub mod user;
pub mod vec3;
pub mod wgsl;

pub use error::{Error, Result};
pub use model::{
    Brdf, Distribution, ErrorBound, Fresnel, Kind, Lobe, Metric, Model, ModelInfo, Ops, PipeOps,
    Shadowing, Zone,
};
pub use real::Real;
pub use spec::{Given, ModelSpec};
