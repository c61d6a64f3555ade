//! `gauss`: the Gaussian lobe of seed 001, `exp(-n theta^2 / 2)` with `theta = acos(c)`.
//!
//! Parameters: `n` in [1, 10000] (default 20). Source: seed 001 (its reference [10]).
//! Cost: 2 mul, 1 acos, 1 exp. For small angles `cos^n theta ~ exp(-n theta^2 / 2)`, so it
//! matches `pow` near the peak and has a lighter tail. Error bounds against `pow`: see `INFO`.

use crate::error::Result;
use crate::model::{ErrorBound, Kind, Lobe, Metric, Model, ModelInfo, Ops, Zone};
use crate::params::{self, Params};
use crate::real::{Real, sqr};
use crate::registry::Entry;

pub const INFO: ModelInfo = ModelInfo {
    id: "gauss",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "exp(-n theta^2 / 2), theta = acos(c)",
    source: "seed 001 (Gauss BRDF, its reference [10])",
    ops: Ops::new(2, 0, 0, 0, 2),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 1000.0),
            bound: 0.292,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 1000.0),
            bound: 0.156,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32>,
    build64: build::<f64>,
};

/// The Gaussian lobe.
#[derive(Clone, Debug)]
pub struct Gauss<T> {
    half_n: T,
}

impl<T: Real> Gauss<T> {
    /// `n` must be in [1, 10000].
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            half_n: T::c(0.5 * params::check("gauss", &params::N, n)?),
        })
    }
}

impl<T: Real> Lobe<T> for Gauss<T> {
    #[inline]
    fn eval(&self, c: T) -> T {
        let Some(c) = super::arg(c) else {
            return T::zero();
        };
        (-self.half_n * sqr(c.acos())).exp()
    }
}

fn build<T: Real>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Lobe(Box::new(Gauss::<T>::new(p.num("n"))?)))
}
