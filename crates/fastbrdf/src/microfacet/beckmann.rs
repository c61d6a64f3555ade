//! `beckmann` and `beckmann-ct`: the exact Beckmann distribution in two normalisations.
//!
//! - `beckmann`: `D = exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)`, normalised so
//!   that the integral of `D cos theta_h` over the hemisphere is 1 (Walter et al. 2007,
//!   Mitsuba 3's `MicrofacetDistribution`, pbrt). Cost: 3 mul, 1 div, 1 exp.
//! - `beckmann-ct`: `exp(-tan^2 theta_h / m^2) / (4 m^2 cos^4 theta_h)`, the Cook-Torrance form
//!   seed 000 uses (`= beckmann * pi / 4`). Cost: 3 mul, 1 div, 1 exp.
//!
//! `tan^2 = sin^2 / cos^2` with `sin^2` from the half vector (BRDFs) or `(1 - c)(1 + c)`
//! (standalone), avoiding `1 - c^2` cancellation near the peak.
//! Parameters: `alpha` in [0.01, 1] (default 0.3). Below `cos_h = COS_MIN` the value is 0 (the
//! exact value there is below 1e-300). Exact models: no error bound; `beckmann`'s
//! normalisation is tested to 1e-6 for alpha in [0.05, 1].

use crate::error::Result;
use crate::model::{Distribution, Kind, Model, ModelInfo, Ops};
use crate::params::{self, Params};
use crate::real::{Real, sqr};
use crate::registry::Entry;
use crate::vec3::COS_MIN;

pub const INFO: ModelInfo = ModelInfo {
    id: "beckmann",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007 (normalisation of Mitsuba 3, pbrt)",
    ops: Ops::new(4, 0, 2, 0, 1),
    bounds: &[],
    f32_bound: 3e-6,
    note: "integral of D cos theta_h over the hemisphere = 1; f32: 1.4e-6 at alpha = 0.01",
};

pub const INFO_CT: ModelInfo = ModelInfo {
    id: "beckmann-ct",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "exp(-tan^2 theta_h / m^2) / (4 m^2 cos^4 theta_h)",
    source: "Cook & Torrance 1982; seed 000",
    ops: Ops::new(4, 0, 2, 0, 1),
    bounds: &[],
    f32_bound: 3e-6,
    note: "= beckmann * pi / 4 (integral of D cos theta_h = pi / 4); f32: 1.4e-6 at alpha = 0.01",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32, 0>,
    build64: build::<f64, 0>,
};
pub const ENTRY_CT: Entry = Entry {
    info: INFO_CT,
    build32: build::<f32, 1>,
    build64: build::<f64, 1>,
};

/// The exact Beckmann distribution with a chosen constant factor.
#[derive(Clone, Debug)]
pub struct Beckmann<T> {
    inv_alpha2: T,
    scale: T,
}

impl<T: Real> Beckmann<T> {
    /// Normalised Beckmann, `1 / (pi alpha^2)` in front.
    pub fn new(alpha: f64) -> Result<Self> {
        let a = params::check("beckmann", &params::ALPHA, alpha)?;
        Ok(Self {
            inv_alpha2: T::c(1.0 / (a * a)),
            scale: T::c(1.0 / (std::f64::consts::PI * a * a)),
        })
    }
    /// Cook-Torrance's form, `1 / (4 m^2)` in front.
    pub fn cook_torrance(alpha: f64) -> Result<Self> {
        let a = params::check("beckmann-ct", &params::ALPHA, alpha)?;
        Ok(Self {
            inv_alpha2: T::c(1.0 / (a * a)),
            scale: T::c(1.0 / (4.0 * a * a)),
        })
    }
}

impl<T: Real> Distribution<T> for Beckmann<T> {
    #[inline]
    fn d(&self, cos_h: T, sin2_h: T) -> T {
        if !(cos_h >= T::c(COS_MIN)) {
            return T::zero();
        }
        let cos2 = sqr(cos_h);
        let e = (-(sin2_h / cos2) * self.inv_alpha2).exp();
        self.scale * e / sqr(cos2)
    }
}

fn build<T: Real, const CT: u8>(p: &Params) -> Result<Model<T>> {
    let a = p.num("alpha");
    let d = if CT == 1 {
        Beckmann::<T>::cook_torrance(a)?
    } else {
        Beckmann::<T>::new(a)?
    };
    Ok(Model::Distribution(Box::new(d)))
}
