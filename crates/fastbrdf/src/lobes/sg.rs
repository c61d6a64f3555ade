//! `sg` and `ue4-phong-approx`: one-`exp2` stand-ins for `c^n` used by production engines.
//!
//! - `sg`: `exp2((n / ln 2)(c - 1)) = exp(n (c - 1))`, the spherical-Gaussian form
//!   (Lagarde 2012). Cost: 1 mul, 1 add, 1 exp2.
//! - `ue4-phong-approx`: `exp2(1.4427 (n + 0.775)(c - 1))`, Unreal Engine 4's mobile
//!   approximation (`PhongApprox`). Cost: 1 mul, 1 add, 1 exp2.
//!
//! Parameters: `n` in [1, 10000] (default 20). Error bounds against `pow`: see `INFO`.

use crate::error::Result;
use crate::model::{ErrorBound, Kind, Lobe, Metric, Model, ModelInfo, Ops, Zone};
use crate::params::{self, Params};
use crate::real::Real;
use crate::registry::Entry;

pub const INFO: ModelInfo = ModelInfo {
    id: "sg",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "exp2((n / ln 2)(c - 1))",
    source: "Lagarde 2012, 'Spherical Gaussian approximation for Blinn-Phong, Phong and Fresnel'",
    ops: Ops::new(1, 1, 0, 0, 1),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 1000.0),
            bound: 0.368,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 16.0, 1000.0),
            bound: 0.0173,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 1000.0),
            bound: 0.214,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

pub const INFO_UE4: ModelInfo = ModelInfo {
    id: "ue4-phong-approx",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "exp2(1.4427 (n + 0.775)(c - 1))",
    source: "Unreal Engine 4 mobile shading (PhongApprox), Karis 2014",
    ops: Ops::new(1, 1, 0, 0, 1),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 1000.0),
            bound: 0.17,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 16.0, 1000.0),
            bound: 0.0097,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 1000.0),
            bound: 0.183,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32, 0>,
    build64: build::<f64, 0>,
};
pub const ENTRY_UE4: Entry = Entry {
    info: INFO_UE4,
    build32: build::<f32, 1>,
    build64: build::<f64, 1>,
};

/// `exp2(k (c - 1))`.
#[derive(Clone, Debug)]
pub struct Exp2Lobe<T> {
    k: T,
}

impl<T: Real> Exp2Lobe<T> {
    /// Lagarde's spherical Gaussian, `k = n / ln 2`.
    pub fn sg(n: f64) -> Result<Self> {
        Ok(Self::with_rate(
            params::check("sg", &params::N, n)? / std::f64::consts::LN_2,
        ))
    }
    /// Unreal Engine 4's form, `k = 1.4427 (n + 0.775)`.
    // 1.4427 is UE4's own rounded literal, not a typo for LOG2_E: we reproduce the engine.
    #[allow(clippy::approx_constant)]
    pub fn ue4(n: f64) -> Result<Self> {
        Ok(Self::with_rate(
            1.4427 * (params::check("ue4-phong-approx", &params::N, n)? + 0.775),
        ))
    }
    /// An explicit rate `k` (for fitted variants).
    pub fn with_rate(k: f64) -> Self {
        Self { k: T::c(k) }
    }
}

impl<T: Real> Lobe<T> for Exp2Lobe<T> {
    #[inline]
    fn eval(&self, c: T) -> T {
        let Some(c) = super::arg(c) else {
            return T::zero();
        };
        (self.k * (c - T::one())).exp2()
    }
}

fn build<T: Real, const UE4: u8>(p: &Params) -> Result<Model<T>> {
    let n = p.num("n");
    let l = if UE4 == 1 {
        Exp2Lobe::<T>::ue4(n)?
    } else {
        Exp2Lobe::<T>::sg(n)?
    };
    Ok(Model::Lobe(Box::new(l)))
}
