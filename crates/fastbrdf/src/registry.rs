//! The registry: every model id with its self-description and its builders.
//! Adding a model means one new file (or constant) and one line in [`REGISTRY`].

use crate::brdf::{cook_torrance, lambert, phong, ward};
use crate::error::{Error, Result};
use crate::lobes::{cubic, flog, gauss, pow, power, rational, schlick, sg, tuned};
use crate::microfacet::{beckmann, beckmann_pow, fresnel, shadowing};
use crate::model::{Model, ModelInfo};
use crate::params::Params;
use crate::real::Real;
use std::any::Any;

/// A builder of a model in one precision.
pub type BuildFn<T> = fn(&Params) -> Result<Model<T>>;

/// One registry line: the description and a builder per precision.
#[derive(Clone, Copy)]
pub struct Entry {
    pub info: ModelInfo,
    pub build32: BuildFn<f32>,
    pub build64: BuildFn<f64>,
}

/// Every model, in display order.
pub static REGISTRY: &[Entry] = &[
    // Lobes (reference: pow).
    pow::ENTRY,
    schlick::ENTRY,
    schlick::ENTRY_MODIFIED,
    gauss::ENTRY,
    flog::ENTRY,
    flog::ENTRY_NORMALIZED,
    flog::ENTRY_CLAMPED,
    cubic::ENTRY,
    cubic::ENTRY3,
    rational::ENTRY,
    rational::ENTRY_CUBIC_RATIONAL,
    power::ENTRY4,
    power::ENTRY8,
    power::ENTRY16,
    sg::ENTRY,
    sg::ENTRY_UE4,
    tuned::ENTRY_POWER4,
    tuned::ENTRY_POWER8,
    tuned::ENTRY_POWER16,
    tuned::ENTRY_SG,
    tuned::ENTRY_CUBIC_RATIONAL,
    // Microfacet distributions (reference: beckmann / beckmann-ct).
    beckmann::ENTRY,
    beckmann::ENTRY_CT,
    beckmann_pow::ENTRY,
    beckmann_pow::ENTRY4,
    beckmann_pow::ENTRY8,
    beckmann_pow::ENTRY16,
    // Shadowing-masking.
    shadowing::ENTRY_VCAVITY,
    shadowing::ENTRY_SMITH,
    shadowing::ENTRY_RATIONAL,
    // Fresnel.
    fresnel::ENTRY_NONE,
    fresnel::ENTRY_SCHLICK,
    fresnel::ENTRY_DIELECTRIC,
    fresnel::ENTRY_CONDUCTOR,
    // Full BRDFs.
    cook_torrance::ENTRY,
    ward::ENTRY,
    ward::ENTRY_POW,
    ward::ENTRY_POWER16,
    lambert::ENTRY,
    phong::ENTRY,
    phong::ENTRY_BLINN,
];

/// Every registry entry.
pub fn all() -> &'static [Entry] {
    REGISTRY
}

/// The entry of `id`.
pub fn find(id: &str) -> Result<&'static Entry> {
    REGISTRY
        .iter()
        .find(|e| e.info.id == id)
        .ok_or_else(|| Error::UnknownModel(id.into()))
}

/// Builds model `id` in precision `T` from `(name, value)` text pairs; missing parameters
/// take their defaults. Errors name the model, the parameter and the expected range.
pub fn build<T: Real>(id: &str, given: &[(&str, &str)]) -> Result<Model<T>> {
    let e = find(id)?;
    let p = Params::resolve(e.info.id, e.info.params, given)?;
    build_resolved(e, &p)
}

/// Builds from already resolved parameters.
pub fn build_resolved<T: Real>(e: &Entry, p: &Params) -> Result<Model<T>> {
    let any: Box<dyn Any> = if std::any::TypeId::of::<T>() == std::any::TypeId::of::<f32>() {
        Box::new((e.build32)(p)?)
    } else {
        Box::new((e.build64)(p)?)
    };
    Ok(*any
        .downcast::<Model<T>>()
        .expect("Real is implemented for f32 and f64 only"))
}
