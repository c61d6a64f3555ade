//! `rational` and `cubic-rational`: seed 003's fall-off form and its piecewise design.
//!
//! - `rational`: `c / (a - b c)` with `a = 2 n 0.5^(1/n)`, `b = 2n - 2`: value 0.5 and the slope
//!   of `c^n` at `q = 0.5^(1/n)`, meant for the fall-off zone `c^n < 0.5`. We evaluate the
//!   denominator as `2 n (q - c) + 2 c` (the same number; `q - c = (q - 1) - (c - 1)` keeps
//!   f32 accurate where `2n q` and `(2n - 2) c` nearly cancel). The denominator is positive on
//!   [0, 1] for every n >= 1 because `n (1 - q) < ln 2 < 1`. Cost: 2 mul, 3 add, 1 div.
//! - `cubic-rational`: `cubic` where `c >= q` (the epicentre, `c^n >= 0.5`), `rational` below:
//!   the seed's epicentre + fall-off design. Continuous with a continuous slope at `q`.
//!   Cost: the cubic or the rational, plus one compare.
//!
//! Parameters: `n` in [1, 10000] (default 20). Error bounds against `pow`: see `INFO`.

use super::cubic::{Cubic, CubicShape};
use crate::error::Result;
use crate::model::{ErrorBound, Kind, Lobe, Metric, Model, ModelInfo, Ops, Zone};
use crate::params::{self, Params};
use crate::real::Real;
use crate::registry::Entry;

pub const INFO: ModelInfo = ModelInfo {
    id: "rational",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "c / (a - b c), a = 2 n 0.5^(1/n), b = 2n - 2",
    source: "seed 003 (fall-off zone approximation g)",
    ops: Ops::new(2, 3, 1, 0, 0),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Band { lo: 0.42, hi: 0.5 },
            param: ("n", 2.0, 1000.0),
            bound: 0.0138,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Band { lo: 0.37, hi: 0.42 },
            param: ("n", 2.0, 1000.0),
            bound: 0.0386,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Band { lo: 0.27, hi: 0.37 },
            param: ("n", 2.0, 1000.0),
            bound: 0.146,
        },
    ],
    f32_bound: 1e-6,
    note: "denominator evaluated as 2n(q - c) + 2c for f32 accuracy",
};

pub const INFO_CUBIC_RATIONAL: ModelInfo = ModelInfo {
    id: "cubic-rational",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "cubic(c) for c >= 0.5^(1/n), rational(c) below",
    source: "seed 003 (epicentre + fall-off design)",
    ops: Ops::new(3, 4, 0, 0, 0),
    bounds: &[ErrorBound {
        reference: "pow",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("n", 2.0, 1000.0),
        bound: 0.102,
    }],
    f32_bound: 1e-6,
    note: "cost is the cubic branch; the rational branch is 2 mul, 3 add, 1 div",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32, 0>,
    build64: build::<f64, 0>,
};
pub const ENTRY_CUBIC_RATIONAL: Entry = Entry {
    info: INFO_CUBIC_RATIONAL,
    build32: build::<f32, 1>,
    build64: build::<f64, 1>,
};

/// Seed 003's rational fall-off lobe, matched to `c^n` at the level `c^n = level` (the seed:
/// 0.5): `level c / (n (q - c) + c)`, which at 0.5 is the seed's `c / (2n (q - c) + 2c)`
/// (bit for bit: the factor 2 is exact).
#[derive(Clone, Debug)]
pub struct Rational<T> {
    n: T,
    xq: T,
    level: T,
}

impl<T: Real> Rational<T> {
    /// `n` must be in [1, 10000].
    pub fn new(n: f64) -> Result<Self> {
        let n = params::check("rational", &params::N, n)?;
        Ok(Self::at_level(n, 0.5))
    }

    /// Matched at the level `c^n = level`.
    pub fn at_level(n: f64, level: f64) -> Self {
        Self {
            n: T::c(n),
            xq: T::c((level.ln() / n).exp_m1()),
            level: T::c(level),
        }
    }
}

impl<T: Real> Lobe<T> for Rational<T> {
    #[inline]
    fn eval(&self, c: T) -> T {
        let Some(c) = super::arg(c) else {
            return T::zero();
        };
        let x = c - T::one();
        self.level * c / (self.n * (self.xq - x) + c)
    }
}

/// Seed 003's piecewise lobe: cubic in the epicentre, rational in the fall-off.
#[derive(Clone, Debug)]
pub struct CubicRational<T> {
    cubic: Cubic<T>,
    rational: Rational<T>,
    q: T,
    q64: f64,
}

impl<T: Real> CubicRational<T> {
    /// `n` must be in [1, 10000].
    pub fn new(n: f64) -> Result<Self> {
        let n = params::check("cubic-rational", &params::N, n)?;
        Ok(Self::at_level(n, 0.5))
    }

    /// With the junction at the level `c^n = level` (the seed: 0.5).
    pub fn at_level(n: f64, level: f64) -> Self {
        let q64 = level.powf(1.0 / n);
        Self {
            cubic: Cubic::from_shape(CubicShape::hermite_at(n, level)),
            rational: Rational::at_level(n, level),
            q: T::c(q64),
            q64,
        }
    }
}

impl<T: Real> Lobe<T> for CubicRational<T> {
    #[inline]
    fn eval(&self, c: T) -> T {
        let Some(c) = super::arg(c) else {
            return T::zero();
        };
        if c >= self.q {
            self.cubic.eval(c)
        } else {
            self.rational.eval(c)
        }
    }
    fn kinks(&self) -> Vec<f64> {
        vec![self.q64]
    }
}

fn build<T: Real, const PIECEWISE: u8>(p: &Params) -> Result<Model<T>> {
    let n = p.num("n");
    Ok(Model::Lobe(if PIECEWISE == 1 {
        Box::new(CubicRational::<T>::new(n)?)
    } else {
        Box::new(Rational::<T>::new(n)?)
    }))
}
