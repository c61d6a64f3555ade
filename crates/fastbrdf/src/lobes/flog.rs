//! `flog`, `flog-normalized`, `flog-normalized-clamped`: seed 001's logarithmic lobe.
//!
//! - `flog`: `max(0, 1 - 0.5 log2(1 - n log2 c))`. Value 1 and slope `n / (2 ln 2) * ...` at
//!   `c = 1`; it reaches zero where `1 - n log2 c = 4`, i.e. `c^n = 1/8`, `c = 2^(-3/n)`
//!   (= `exp(-2.0794 / n)`; the seed rounds this to `exp(-2.08 / n)`). Cost: 2 mul, 2 add,
//!   2 log2.
//! - `flog-normalized`: `coef(n) flog(c)` with seed 001's fitted energy coefficient
//!   `coef(n) = 0.197 (n + 1.24) + 0.068 / (0.64 + n)` (precomputed per `n`). The value exceeds
//!   1 near the peak for n > ~3: that is what normalisation means, so no clamp here.
//!   Energy: used as a Phong lobe, its albedo at normal incidence is `coef(n) 2 pi Int(n)`,
//!   which we measure just below 1 (0.99871 at n = 1000, 0.99999 at n = 1): the seed's rounded
//!   coefficient conserves energy and loses at most 1.3e-3 of it (`tests/energy.rs`).
//! - `flog-normalized-clamped`: the seed's GLSL snippet verbatim, `min(max(coef flog, 0), 1)`.
//!   The clamp throws energy away; it exists only to reproduce the seed's pictures.
//!
//! Parameters: `n` in [1, 10000] (default 20). Source: seed 001 (Romanyuk et al., ACIT 2023).
//! Error bounds against `pow`: see the `INFO` constants.

use crate::error::Result;
use crate::model::{ErrorBound, Kind, Lobe, Metric, Model, ModelInfo, Ops, Zone};
use crate::params::{self, Params};
use crate::real::Real;
use crate::registry::Entry;

/// Seed 001's fitted normalisation coefficient (its Fig. 8 formula, as rounded in the paper).
pub fn seed_coef(n: f64) -> f64 {
    0.197 * (n + 1.24) + 0.068 / (0.64 + n)
}

/// The cosine at which `flog` reaches zero: `2^(-3/n)`.
pub fn zero_cos(n: f64) -> f64 {
    (-3.0 / n).exp2()
}

pub const INFO: ModelInfo = ModelInfo {
    id: "flog",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "max(0, 1 - 0.5 log2(1 - n log2 c))",
    source: "seed 001 (Romanyuk, Zavalniuk et al., ACIT 2023), its reference [10]",
    ops: Ops::new(2, 2, 0, 0, 2),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 1000.0),
            bound: 0.126,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 1000.0),
            bound: 0.00292,
        },
    ],
    f32_bound: 2e-7,
    note: "zero at c = 2^(-3/n) = exp(-2.0794/n); the seed rounds the constant to 2.08",
};

pub const INFO_NORMALIZED: ModelInfo = ModelInfo {
    id: "flog-normalized",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "coef(n) flog(c), coef(n) = 0.197 (n + 1.24) + 0.068 / (0.64 + n)",
    source: "seed 001, section III (coef fitted with TuringBot)",
    ops: Ops::new(3, 2, 0, 0, 2),
    bounds: &[],
    f32_bound: 3e-4,
    note: "no clamp: a normalised lobe exceeds 1 near the peak for n > ~3; f32: coef(n) ~ 2000 times the rounding of flog near its zero (1.5e-4 at n = 10000)",
};

pub const INFO_CLAMPED: ModelInfo = ModelInfo {
    id: "flog-normalized-clamped",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "min(1, max(0, coef(n) flog(c)))",
    source: "seed 001, Fig. 10 (its GLSL snippet)",
    ops: Ops::new(3, 2, 0, 0, 2),
    bounds: &[],
    f32_bound: 2.5e-4,
    note: "the seed's GLSL clamp to [0, 1]: loses energy for n > ~3; kept only to reproduce the seed; f32: as flog-normalized (1.3e-4 at n = 10000)",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32, 0>,
    build64: build::<f64, 0>,
};
pub const ENTRY_NORMALIZED: Entry = Entry {
    info: INFO_NORMALIZED,
    build32: build::<f32, 1>,
    build64: build::<f64, 1>,
};
pub const ENTRY_CLAMPED: Entry = Entry {
    info: INFO_CLAMPED,
    build32: build::<f32, 2>,
    build64: build::<f64, 2>,
};

/// How `Flog` scales its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlogMode {
    /// `flog` itself.
    Plain,
    /// `coef(n) flog`.
    Normalized,
    /// `min(1, coef(n) flog)`, the seed's GLSL.
    NormalizedClamped,
}

/// Seed 001's logarithmic lobe.
#[derive(Clone, Debug)]
pub struct Flog<T> {
    n: T,
    coef: T,
    clamp: bool,
    zero: f64,
}

impl<T: Real> Flog<T> {
    /// `n` must be in [1, 10000].
    pub fn new(n: f64, mode: FlogMode) -> Result<Self> {
        let n = params::check("flog", &params::N, n)?;
        let coef = if mode == FlogMode::Plain {
            1.0
        } else {
            seed_coef(n)
        };
        Ok(Self {
            n: T::c(n),
            coef: T::c(coef),
            clamp: mode == FlogMode::NormalizedClamped,
            zero: zero_cos(n),
        })
    }
}

impl<T: Real> Lobe<T> for Flog<T> {
    #[inline]
    fn eval(&self, c: T) -> T {
        // c = 0 would give log2(0) = -inf; every c <= 0 is below the zero anyway.
        let Some(c) = super::arg(c).filter(|c| *c > T::zero()) else {
            return T::zero();
        };
        let f = T::one() - T::c(0.5) * (T::one() - self.n * c.log2()).log2();
        let v = (self.coef * f).max(T::zero());
        if self.clamp { v.min(T::one()) } else { v }
    }
    fn zero_below(&self) -> f64 {
        self.zero
    }
}

fn build<T: Real, const MODE: u8>(p: &Params) -> Result<Model<T>> {
    let mode = match MODE {
        0 => FlogMode::Plain,
        1 => FlogMode::Normalized,
        _ => FlogMode::NormalizedClamped,
    };
    Ok(Model::Lobe(Box::new(Flog::<T>::new(p.num("n"), mode)?)))
}
