//! `lambert`: the ideal diffuse BRDF, `albedo / pi`.
//!
//! Parameters: `albedo` in [0, 1] (default 1). Source: Lambert 1760. Cost: nothing per
//! evaluation (a constant). Albedo equals `albedo` at every incidence (energy conserving).

use crate::error::Result;
use crate::model::{Brdf, Kind, Model, ModelInfo, Ops};
use crate::params::{ParamKind, ParamSpec, Params};
use crate::real::Real;
use crate::registry::Entry;
use crate::vec3::Pair;

pub const ALBEDO: ParamSpec = ParamSpec {
    name: "albedo",
    kind: ParamKind::Number {
        min: 0.0,
        max: 1.0,
        default: Some(1.0),
    },
    doc: "directional-hemispherical reflectance",
};

pub const INFO: ModelInfo = ModelInfo {
    id: "lambert",
    kind: Kind::Brdf,
    params: &[ALBEDO],
    formula: "albedo / pi",
    source: "Lambert 1760",
    ops: Ops::new(0, 0, 0, 0, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32>,
    build64: build::<f64>,
};

/// The Lambertian BRDF.
#[derive(Clone, Debug)]
pub struct Lambert<T> {
    value: T,
}

impl<T: Real> Lambert<T> {
    /// `albedo` in [0, 1].
    pub fn new(albedo: f64) -> Result<Self> {
        let a = crate::params::check("lambert", &ALBEDO, albedo)?;
        Ok(Self {
            value: T::c(a / std::f64::consts::PI),
        })
    }
}

impl<T: Real> Brdf<T> for Lambert<T> {
    #[inline]
    fn eval_pair(&self, _p: &Pair<T>) -> T {
        self.value
    }
}

fn build<T: Real>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Brdf(Box::new(Lambert::<T>::new(p.num("albedo"))?)))
}
