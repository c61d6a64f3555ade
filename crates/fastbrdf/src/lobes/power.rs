//! `power4`, `power8`, `power16`: `max(0, 1 + (n/g)(c - 1))^g` with `g = 2^k`, evaluated by
//! `k` squarings (Lyon 1993; seed 000's "(1 + x/16)^16" form of `exp`).
//!
//! Since `c^n = exp(n ln c) ~ exp(n (c - 1))` near the peak and `(1 + x/g)^g -> exp(x)`, these
//! match `c^n` in value and slope at `c = 1`; they are exact when `n = g` (the base is then `c`)
//! and zero below `c = 1 - g/n`.
//! Parameters: `n` in [1, 10000] (default 20). Cost: 1 mul, 1 add (constants precomputed) and
//! `k` squarings (k = 2, 3, 4). Error bounds against `pow`: see the `INFO` constants.

use crate::error::Result;
use crate::model::{ErrorBound, Kind, Lobe, Metric, Model, ModelInfo, Ops, Zone};
use crate::params::{self, Params};
use crate::real::{Real, pow2k};
use crate::registry::Entry;

macro_rules! power_info {
    ($id:literal, $k:literal, $formula:literal, $abs:expr, $rel:expr, $abs16:expr, $rel16:expr, $f32:expr) => {
        ModelInfo {
            id: $id,
            kind: Kind::Lobe,
            params: &[params::N],
            formula: $formula,
            source: "Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000",
            ops: Ops::new(1 + $k, 1, 0, 0, 0),
            bounds: &[
                ErrorBound { reference: "pow", metric: Metric::MaxAbs, zone: Zone::All, param: ("n", 1.0, 1000.0), bound: $abs },
                ErrorBound { reference: "pow", metric: Metric::MaxRel, zone: Zone::Epicentre, param: ("n", 1.0, 1000.0), bound: $rel },
                ErrorBound { reference: "pow", metric: Metric::MaxAbs, zone: Zone::All, param: ("n", 16.0, 1000.0), bound: $abs16 },
                ErrorBound { reference: "pow", metric: Metric::MaxRel, zone: Zone::Epicentre, param: ("n", 16.0, 1000.0), bound: $rel16 },
            ],
            f32_bound: $f32,
            note: "",
        }
    };
}

pub const INFO4: ModelInfo = power_info!(
    "power4",
    2,
    "max(0, 1 + (n/4)(c - 1))^4",
    0.317,
    0.173,
    0.0736,
    0.0656,
    3e-7
);
pub const INFO8: ModelInfo = power_info!(
    "power8",
    3,
    "max(0, 1 + (n/8)(c - 1))^8",
    0.344,
    0.194,
    0.0351,
    0.0312,
    5e-7
);
pub const INFO16: ModelInfo = power_info!(
    "power16",
    4,
    "max(0, 1 + (n/16)(c - 1))^16",
    0.357,
    0.204,
    0.0171,
    0.0151,
    1e-6
);

pub const ENTRY4: Entry = Entry {
    info: INFO4,
    build32: build::<f32, 2>,
    build64: build::<f64, 2>,
};
pub const ENTRY8: Entry = Entry {
    info: INFO8,
    build32: build::<f32, 3>,
    build64: build::<f64, 3>,
};
pub const ENTRY16: Entry = Entry {
    info: INFO16,
    build32: build::<f32, 4>,
    build64: build::<f64, 4>,
};

/// `max(0, 1 + s (c - 1))^(2^K)`.
#[derive(Clone, Debug)]
pub struct Power<T, const K: u32> {
    s: T,
    zero: f64,
}

impl<T: Real, const K: u32> Power<T, K> {
    /// The lobe with `s = n / 2^K`; `n` must be in [1, 10000].
    pub fn new(n: f64) -> Result<Self> {
        let n = params::check("power", &params::N, n)?;
        let s = n / f64::from(1u32 << K);
        Ok(Self {
            s: T::c(s),
            zero: (1.0 - 1.0 / s).max(0.0),
        })
    }

    /// The lobe with an explicit slope `s > 0` (for fitted variants).
    pub fn with_slope(s: f64) -> Self {
        Self {
            s: T::c(s),
            zero: (1.0 - 1.0 / s).max(0.0),
        }
    }
}

impl<T: Real, const K: u32> Lobe<T> for Power<T, K> {
    #[inline]
    fn eval(&self, c: T) -> T {
        let Some(c) = super::arg(c) else {
            return T::zero();
        };
        pow2k((T::one() + self.s * (c - T::one())).max(T::zero()), K)
    }
    fn zero_below(&self) -> f64 {
        self.zero
    }
}

fn build<T: Real, const K: u32>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Lobe(Box::new(Power::<T, K>::new(p.num("n"))?)))
}
