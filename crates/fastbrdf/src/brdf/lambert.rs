//! `lambert`: the ideal diffuse BRDF, `albedo / pi`.
//!
//! Parameters: `albedo` in [0, 1] (default 1). Source: Lambert 1760. Cost: nothing per
//! evaluation (a constant). Albedo equals `albedo` at every incidence (energy conserving).
//! Sampling: cosine-weighted (`cosine`), so every weight is exactly `albedo`.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::BrdfForm;
use crate::math::Math;
use crate::model::{Kind, ModelInfo, Ops};
use crate::params::{ParamKind, ParamSpec};
use crate::plan::Plan;
use crate::real::{K, Real};
use crate::sample::{self, Strategy};
use crate::vec3::{Pair, V3};
use crate::wgsl::{Emit, PAIR};

pub const ALBEDO: ParamSpec = ParamSpec {
    name: "albedo",
    kind: ParamKind::Number {
        min: 0.0,
        max: 1.0,
        default: Some(1.0),
        requires: &[],
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

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Brdf(Lambert::new(p.num("albedo"))?.into()))
});

/// `albedo / pi`.
#[derive(Clone, Copy, Debug)]
pub struct Lambert {
    /// `albedo / pi`.
    value: K,
}

impl Lambert {
    /// `albedo` in [0, 1].
    pub fn new(albedo: f64) -> Result<Self> {
        let albedo = crate::params::check("lambert", &ALBEDO, albedo)?;
        Ok(Self {
            value: K::new(albedo / std::f64::consts::PI),
        })
    }
}

impl BrdfForm for Lambert {
    // No .wgsl file: the body (a constant) is written per instance by `wgsl_body`.
    const WGSL: &'static str = "";
    #[inline(always)]
    fn at_pair<T: Real, M: Math<T>>(&self, _p: &Pair<T>) -> T {
        self.value.t::<T>()
    }
    fn wgsl_body(&self, e: &Emit) -> String {
        format!(
            "{PAIR}    return select(0.0, {}, p.valid);\n",
            e.kx(self.value, "p_albedo * 0.3183098861837907", &["albedo"])
        )
    }
    fn claims_energy(&self) -> bool {
        true
    }
    fn strategies(&self) -> &'static [Strategy] {
        &[Strategy::Cosine]
    }
    fn sample_wi<T: Real>(&self, _wo: V3<T>, u: [T; 2], _s: Strategy) -> Option<V3<T>> {
        Some(sample::cosine(u))
    }
    fn pdf_wi<T: Real>(&self, _wo: V3<T>, wi: V3<T>, _s: Strategy) -> T {
        sample::cosine_pdf(wi)
    }
}
