//! `pow`: the Phong / Blinn-Phong lobe, the reference of every lobe.
//!
//! Formula: `c^n`. Parameters: `n` in [1, 10000] (default 20).
//! Source: Phong 1975, Blinn 1977; all three seeds.
//! Cost: one `pow` (exp2 and log2 inside). Error: exact (it is the reference).
//! Energy: `Int(n) = integral_0^1 c^n c dc = 1 / (n + 2)`, so `coef(n) = (n + 2) / (2 pi)`.

use crate::error::Result;
use crate::model::{Kind, Lobe, Model, ModelInfo, Ops};
use crate::params::{self, Params};
use crate::real::Real;
use crate::registry::Entry;

pub const INFO: ModelInfo = ModelInfo {
    id: "pow",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "c^n",
    source: "Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003)",
    ops: Ops::new(0, 0, 0, 0, 1),
    bounds: &[],
    f32_bound: 2e-7,
    note: "",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32>,
    build64: build::<f64>,
};

/// `c^n`.
#[derive(Clone, Debug)]
pub struct Pow<T> {
    n: T,
}

impl<T: Real> Pow<T> {
    /// A `c^n` lobe; `n` must be in [1, 10000].
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: T::c(params::check("pow", &params::N, n)?),
        })
    }
}

impl<T: Real> Lobe<T> for Pow<T> {
    #[inline]
    fn eval(&self, c: T) -> T {
        match super::arg(c) {
            Some(c) => c.powf(self.n),
            None => T::zero(),
        }
    }
}

fn build<T: Real>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Lobe(Box::new(Pow::<T>::new(p.num("n"))?)))
}
