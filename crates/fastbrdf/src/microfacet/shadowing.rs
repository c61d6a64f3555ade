//! Shadowing-masking terms `G`: `v-cavity`, `smith`, `smith-rational`.
//!
//! - `v-cavity` (Cook & Torrance 1982): `G = min(1, 2 NH NV / VH, 2 NH NL / VH)`; the one-sided
//!   term (no `cos_l`) is `min(1, 2 NH NV / VH)`. Cost: 3 mul, 1 div (two-sided 4 mul, 1 div).
//! - `smith`: Smith's G1 for Beckmann, exact: `G1 = 1 / (1 + Lambda(a))`,
//!   `a = 1 / (alpha tan theta)`, `Lambda(a) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))`
//!   (Walter et al. 2007, eq. 25-27). We compute `erf(a) - 1 = -erfc(a)` to avoid cancellation.
//!   Two-sided (with `cos_l`): the separable `G1(v) G1(l)` (Mitsuba 3's convention).
//!   Cost per G1: 3 mul, 2 add, 3 div, 1 sqrt, 2 transcendental (erfc, exp).
//! - `smith-rational`: Walter's rational fit, `G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a +
//!   2.577 a^2)` for `a < 1.6`, else 1 (Walter et al. 2007, eq. 27; Mitsuba 3 uses it for
//!   Beckmann). Documented error against `smith`: see `INFO_RATIONAL`. Cost per G1: 6 mul,
//!   3 add, 2 div, 1 sqrt.
//!
//! Parameters: `alpha` in [0.01, 1] (default 0.3) for the Smith terms; the V-cavity has none.
//! Cosines that are NaN or `<= 0` give 0; a cosine of 1 gives G1 = 1.

use crate::error::Result;
use crate::model::{ErrorBound, Kind, Metric, Model, ModelInfo, Ops, ShadowInput, Shadowing, Zone};
use crate::params::{self, Params};
use crate::real::{Real, sqr};
use crate::registry::Entry;

pub const INFO_VCAVITY: ModelInfo = ModelInfo {
    id: "v-cavity",
    kind: Kind::Shadowing,
    params: &[],
    formula: "min(1, 2 NH NV / VH, 2 NH NL / VH)",
    source: "Cook & Torrance 1982 (after Torrance & Sparrow 1967)",
    ops: Ops::new(4, 0, 1, 0, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "input columns cos_v, cos_h, cos_vh and optional cos_l (two-sided)",
};

pub const INFO_SMITH: ModelInfo = ModelInfo {
    id: "smith",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G1 = 1 / (1 + Lambda(a)), a = 1/(alpha tan theta), Lambda = (erf(a) - 1)/2 + exp(-a^2)/(2 a sqrt(pi)); G = G1(v) G1(l)",
    source: "Smith 1967; Walter et al. 2007 (Beckmann Lambda)",
    ops: Ops::new(3, 2, 3, 1, 2),
    bounds: &[],
    f32_bound: 1e-6,
    note: "two-sided form is separable G1(v) G1(l), as Mitsuba 3",
};

pub const INFO_RATIONAL: ModelInfo = ModelInfo {
    id: "smith-rational",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1",
    source: "Walter et al. 2007, eq. 27 (used by Mitsuba 3 for Beckmann)",
    ops: Ops::new(6, 3, 2, 1, 0),
    bounds: &[ErrorBound {
        reference: "smith",
        metric: Metric::MaxRel,
        zone: Zone::All,
        param: ("alpha", 0.01, 1.0),
        bound: 0.00313,
    }],
    f32_bound: 1e-6,
    note: "",
};

pub const ENTRY_VCAVITY: Entry = Entry {
    info: INFO_VCAVITY,
    build32: build_vcavity::<f32>,
    build64: build_vcavity::<f64>,
};
pub const ENTRY_SMITH: Entry = Entry {
    info: INFO_SMITH,
    build32: build_smith::<f32, 0>,
    build64: build_smith::<f64, 0>,
};
pub const ENTRY_RATIONAL: Entry = Entry {
    info: INFO_RATIONAL,
    build32: build_smith::<f32, 1>,
    build64: build_smith::<f64, 1>,
};

/// Cook and Torrance's V-cavity shadowing.
#[derive(Clone, Debug, Default)]
pub struct VCavity;

impl<T: Real> Shadowing<T> for VCavity {
    #[inline]
    fn g(&self, s: &ShadowInput<T>) -> T {
        let z = T::zero();
        if !(s.cos_v > z && s.cos_h > z && s.cos_vh > z) {
            return z;
        }
        let k = T::c(2.0) * s.cos_h / s.cos_vh;
        let mut g = T::one().min(k * s.cos_v);
        if let Some(cos_l) = s.cos_l {
            if !(cos_l > z) {
                return z;
            }
            g = g.min(k * cos_l);
        }
        g
    }
    fn needs_half_vector(&self) -> bool {
        true
    }
}

/// Smith shadowing for the Beckmann distribution, exact or rational.
#[derive(Clone, Debug)]
pub struct SmithBeckmann<T> {
    alpha: T,
    rational: bool,
}

impl<T: Real> SmithBeckmann<T> {
    /// Exact (erf) form; `alpha` in [0.01, 1].
    pub fn exact(alpha: f64) -> Result<Self> {
        Ok(Self {
            alpha: T::c(params::check("smith", &params::ALPHA, alpha)?),
            rational: false,
        })
    }
    /// Walter's rational form; `alpha` in [0.01, 1].
    pub fn rational(alpha: f64) -> Result<Self> {
        Ok(Self {
            alpha: T::c(params::check("smith-rational", &params::ALPHA, alpha)?),
            rational: true,
        })
    }

    /// One-sided masking `G1` of a direction with cosine `cos` to the normal.
    #[inline]
    pub fn g1(&self, cos: T) -> T {
        let z = T::zero();
        if !(cos > z) {
            return z;
        }
        if cos >= T::one() {
            return T::one();
        }
        let sin = ((T::one() - cos) * (T::one() + cos)).sqrt();
        let a = cos / (self.alpha * sin);
        if self.rational {
            if a >= T::c(1.6) {
                return T::one();
            }
            let a2 = a * a;
            (T::c(3.535) * a + T::c(2.181) * a2) / (T::one() + T::c(2.276) * a + T::c(2.577) * a2)
        } else {
            let lambda = (-a.erfc() + (-a * a).exp() / (a * T::PI().sqrt())) * T::c(0.5);
            T::one() / (T::one() + lambda)
        }
    }
}

impl<T: Real> Shadowing<T> for SmithBeckmann<T> {
    #[inline]
    fn g(&self, s: &ShadowInput<T>) -> T {
        let gv = self.g1(s.cos_v);
        match s.cos_l {
            Some(l) => gv * self.g1(l),
            None => gv,
        }
    }
}

/// `Lambda` and `a` for tests and analysis: `(a, Lambda)` at `cos` in f64.
pub fn smith_lambda(alpha: f64, cos: f64) -> f64 {
    let a = cos / (alpha * (1.0 - sqr(cos)).sqrt());
    (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt())
}

fn build_vcavity<T: Real>(_p: &Params) -> Result<Model<T>> {
    Ok(Model::Shadowing(Box::new(VCavity)))
}

fn build_smith<T: Real, const RATIONAL: u8>(p: &Params) -> Result<Model<T>> {
    let a = p.num("alpha");
    let s = if RATIONAL == 1 {
        SmithBeckmann::<T>::rational(a)?
    } else {
        SmithBeckmann::<T>::exact(a)?
    };
    Ok(Model::Shadowing(Box::new(s)))
}
