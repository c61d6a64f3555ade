//! `beckmann-pow` and `beckmann-power4/8/16`: seed 000's one-function Beckmann forms.
//!
//! Seed 000 replaces `exp(-tan^2 theta / m^2)` by `cos^(2/m^2) theta` (equal to second order
//! in theta), so that with the `1 / cos^4` factor
//! - `beckmann-pow`: `D = cos^(2/m^2 - 4) theta_h / (4 m^2)` (one `pow`), and then replaces the
//!   power by `(1 + x/g)^g` (Lyon 1993):
//! - `beckmann-power{g}`: `D = max(0, 1 + ((2/m^2 - 4)/g)(cos theta_h - 1))^g / (4 m^2)`,
//!   `g = 4, 8, 16` (k = 2, 3, 4 squarings).
//!
//! All approximate `beckmann-ct` (the same `1 / (4 m^2)` normalisation).
//! Warning, by construction: for `m > 1/sqrt(2)` the exponent `2/m^2 - 4` is negative, so
//! `beckmann-pow` grows without bound as `cos theta_h -> 0` while the exact D goes to 0; the
//! power forms stay bounded (their base exceeds 1) but are also far from the exact value
//! there. Below `cos_h = COS_MIN` every form returns 0. `cos theta_h - 1` is computed as
//! `-sin^2 / (1 + cos)`, exact in f32 near the peak.
//! Parameters: `alpha` (= m) in [0.01, 1] (default 0.3). Source: seed 000 (Romanyuk et al.).
//! Cost: `beckmann-pow` 1 mul and 1 pow; power forms 2 mul, 2 add, 1 div and k squarings.
//! Error bounds against `beckmann-ct`: see the `INFO` constants.

use crate::error::Result;
use crate::model::{Distribution, ErrorBound, Kind, Metric, Model, ModelInfo, Ops, Zone};
use crate::params::{self, Params};
use crate::real::{Real, pow2k};
use crate::registry::Entry;
use crate::vec3::COS_MIN;

pub const INFO: ModelInfo = ModelInfo {
    id: "beckmann-pow",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "cos^(2/m^2 - 4) theta_h / (4 m^2)",
    source: "seed 000 ('one function' D)",
    ops: Ops::new(1, 0, 0, 0, 1),
    bounds: &[
        ErrorBound {
            reference: "beckmann-ct",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 0.6),
            bound: 0.403,
        },
        ErrorBound {
            reference: "beckmann-ct",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 1.0),
            bound: 4.65,
        },
    ],
    f32_bound: 1e-6,
    note: "unbounded as cos theta_h -> 0 for m > 1/sqrt(2) (negative exponent), by the seed's construction",
};

macro_rules! power_info {
    ($id:literal, $k:literal, $formula:literal, $b06:expr, $b1:expr) => {
        ModelInfo {
            id: $id,
            kind: Kind::Distribution,
            params: &[params::ALPHA],
            formula: $formula,
            source: "seed 000 (D4, D8, D16); Lyon 1993",
            ops: Ops::new(2 + $k, 2, 1, 0, 0),
            bounds: &[
                ErrorBound {
                    reference: "beckmann-ct",
                    metric: Metric::MaxRel,
                    zone: Zone::Epicentre,
                    param: ("alpha", 0.05, 0.6),
                    bound: $b06,
                },
                ErrorBound {
                    reference: "beckmann-ct",
                    metric: Metric::MaxRel,
                    zone: Zone::Epicentre,
                    param: ("alpha", 0.05, 1.0),
                    bound: $b1,
                },
            ],
            f32_bound: 8e-6,
            note: "f32: 3.7e-6 (power4) at alpha = 0.01",
        }
    };
}

pub const INFO4: ModelInfo = power_info!(
    "beckmann-power4",
    2,
    "max(0, 1 + ((2/m^2 - 4)/4)(cos theta_h - 1))^4 / (4 m^2)",
    0.438,
    2.37
);
pub const INFO8: ModelInfo = power_info!(
    "beckmann-power8",
    3,
    "max(0, 1 + ((2/m^2 - 4)/8)(cos theta_h - 1))^8 / (4 m^2)",
    0.447,
    2.55
);
pub const INFO16: ModelInfo = power_info!(
    "beckmann-power16",
    4,
    "max(0, 1 + ((2/m^2 - 4)/16)(cos theta_h - 1))^16 / (4 m^2)",
    0.452,
    2.65
);

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build_pow::<f32>,
    build64: build_pow::<f64>,
};
pub const ENTRY4: Entry = Entry {
    info: INFO4,
    build32: build_power::<f32, 2>,
    build64: build_power::<f64, 2>,
};
pub const ENTRY8: Entry = Entry {
    info: INFO8,
    build32: build_power::<f32, 3>,
    build64: build_power::<f64, 3>,
};
pub const ENTRY16: Entry = Entry {
    info: INFO16,
    build32: build_power::<f32, 4>,
    build64: build_power::<f64, 4>,
};

/// The exponent `2 / m^2 - 4` of seed 000's forms.
pub fn exponent(alpha: f64) -> f64 {
    2.0 / (alpha * alpha) - 4.0
}

/// `cos^(2/m^2 - 4) theta_h / (4 m^2)`.
#[derive(Clone, Debug)]
pub struct BeckmannPow<T> {
    e: T,
    scale: T,
}

impl<T: Real> BeckmannPow<T> {
    /// `alpha` must be in [0.01, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        let a = params::check("beckmann-pow", &params::ALPHA, alpha)?;
        Ok(Self {
            e: T::c(exponent(a)),
            scale: T::c(1.0 / (4.0 * a * a)),
        })
    }
}

impl<T: Real> Distribution<T> for BeckmannPow<T> {
    #[inline]
    fn d(&self, cos_h: T, _sin2_h: T) -> T {
        if !(cos_h >= T::c(COS_MIN)) {
            return T::zero();
        }
        self.scale * cos_h.powf(self.e)
    }
}

/// `max(0, 1 + (e/g)(cos theta_h - 1))^g / (4 m^2)` with `g = 2^K`.
#[derive(Clone, Debug)]
pub struct BeckmannPower<T, const K: u32> {
    s: T,
    scale: T,
}

impl<T: Real, const K: u32> BeckmannPower<T, K> {
    /// `alpha` must be in [0.01, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        let a = params::check("beckmann-power", &params::ALPHA, alpha)?;
        Ok(Self::with_slope(exponent(a) / f64::from(1u32 << K), a))
    }
    /// An explicit slope `s` in `1 + s (cos - 1)` (for fitted variants).
    pub fn with_slope(s: f64, alpha: f64) -> Self {
        Self {
            s: T::c(s),
            scale: T::c(1.0 / (4.0 * alpha * alpha)),
        }
    }
}

impl<T: Real, const K: u32> Distribution<T> for BeckmannPower<T, K> {
    #[inline]
    fn d(&self, cos_h: T, sin2_h: T) -> T {
        if !(cos_h >= T::c(COS_MIN)) {
            return T::zero();
        }
        let cos_minus_1 = -sin2_h / (T::one() + cos_h);
        self.scale * pow2k((T::one() + self.s * cos_minus_1).max(T::zero()), K)
    }
}

fn build_pow<T: Real>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Distribution(Box::new(BeckmannPow::<T>::new(
        p.num("alpha"),
    )?)))
}

fn build_power<T: Real, const K: u32>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Distribution(Box::new(BeckmannPower::<T, K>::new(
        p.num("alpha"),
    )?)))
}
