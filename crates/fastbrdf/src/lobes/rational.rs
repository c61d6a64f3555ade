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
//! Parameters: `n` in [1, 100000] (default 20). Error bounds against `pow`: see `INFO`.
//! Sampling: no closed-form inverse used; `phong`/`blinn-phong` sample the twin `pow` at the same n (`twin`) and weight by f/pdf.

use super::cubic::{Cubic, CubicShape};
use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K, Real};
use crate::wgsl::Emit;

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
            zone: Zone::Band { lo: 0.42, hi: 0.5 },
            param: ("n", 2.0, 100000.0),
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
            zone: Zone::Band { lo: 0.37, hi: 0.42 },
            param: ("n", 2.0, 100000.0),
            bound: 0.0387,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Band { lo: 0.27, hi: 0.37 },
            param: ("n", 2.0, 1000.0),
            bound: 0.146,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Band { lo: 0.27, hi: 0.37 },
            param: ("n", 2.0, 100000.0),
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
        param: ("n", 2.0, 100000.0),
        bound: 0.102,
    }],
    f32_bound: 1e-6,
    note: "cost is the cubic branch; the rational branch is 2 mul, 3 add, 1 div",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Lobe(Rational::new(p.num("n"))?.into()))
});
pub const ENTRY_CUBIC_RATIONAL: Entry = Entry::new(INFO_CUBIC_RATIONAL, |p, _| {
    Ok(Plan::Lobe(CubicRational::new(p.num("n"))?.into()))
});

/// Seed 003's rational fall-off lobe, matched to `c^n` at the level `c^n = level` (the seed:
/// 0.5): `level c / (n (q - c) + c)`, which at 0.5 is the seed's `c / (2n (q - c) + 2c)`
/// (bit for bit: the factor 2 is exact).
#[derive(Clone, Copy, Debug)]
pub struct Rational {
    n: K,
    /// `q - 1 = level^(1/n) - 1`, with `expm1`.
    xq: K,
    level: K,
}

impl Rational {
    /// `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        let n = params::check("rational", &params::N, n)?;
        Ok(Self::at_level(n, 0.5))
    }

    /// Matched at the level `c^n = level`.
    pub fn at_level(n: f64, level: f64) -> Self {
        Self {
            n: K::new(n),
            xq: K::new((level.ln() / n).exp_m1()),
            level: K::new(level),
        }
    }

    /// `(peak, g)` of the WGSL twin's fold-proof form `peak c / (1 + g (1 - c))` (see
    /// `fb_lobe_rational`): `d0 = 1 + n xq`, `peak = level / d0`, `g = (n - 1) / d0`.
    pub(crate) fn wgsl_args(&self, e: &Emit) -> String {
        let (n, xq, level) = (self.n.x, self.xq.x, self.level.x);
        let d0 = 1.0 + n * xq;
        format!("{}, {}", e.constant(level / d0), e.constant((n - 1.0) / d0))
    }
}

impl LobeForm for Rational {
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("rational.wgsl");
    fn id(&self) -> &'static str {
        "rational"
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        let x = c - T::one();
        self.level.t::<T>() * c / M::madd(self.n.t::<T>(), self.xq.t::<T>() - x, c)
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        if e.is_runtime() {
            format!("fb_rt_rational({c}, {})", e.param("n"))
        } else {
            format!("fb_lobe_rational({c}, {})", self.wgsl_args(e))
        }
    }
}

/// Seed 003's piecewise lobe: cubic in the epicentre, rational in the fall-off.
#[derive(Clone, Copy, Debug)]
pub struct CubicRational {
    cubic: Cubic,
    rational: Rational,
    /// The junction `level^(1/n)`.
    q: K,
    /// The level from the minimax fit of `lobes::tuned` rather than 0.5.
    tuned: bool,
}

impl CubicRational {
    /// `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        let n = params::check("cubic-rational", &params::N, n)?;
        Ok(Self::at_level(n, 0.5))
    }

    /// The tuned lobe (junction level `tuned::cubic_rational_level`); `n` in [1, 100000].
    pub fn tuned(n: f64) -> Result<Self> {
        let n = params::check("cubic-rational-tuned", &params::N, n)?;
        Ok(Self {
            tuned: true,
            ..Self::at_level(n, super::fits::cubic_rational_level(n))
        })
    }

    /// With the junction at the level `c^n = level` (the seed: 0.5).
    pub fn at_level(n: f64, level: f64) -> Self {
        Self {
            cubic: Cubic::from_shape(CubicShape::hermite_at(n, level)),
            rational: Rational::at_level(n, level),
            q: K::new(level.powf(1.0 / n)),
            tuned: false,
        }
    }
}

impl LobeForm for CubicRational {
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("rational.wgsl");
    fn id(&self) -> &'static str {
        if self.tuned {
            "cubic-rational-tuned"
        } else {
            "cubic-rational"
        }
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        let a = self.cubic.at::<T, M>(c);
        let b = self.rational.at::<T, M>(c);
        if c >= self.q.t::<T>() { a } else { b }
    }
    /// The batch form (issue 13): the cubic's own batch form above the junction (it clamps
    /// `c > 1` and sends NaN to 0 itself), the rational below on `max(c, 0)`, and one final
    /// `max(0, .)` for NaN (the rational is non-negative on [0, 1]).
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let a = self.cubic.batch::<M>(c);
        let x = if 0.0 > c { 0.0 } else { c };
        let b = self.rational.at::<f32, M>(x);
        let v = if c >= self.q.t::<f32>() { a } else { b };
        if v > 0.0 { v } else { 0.0 }
    }
    fn kinks(&self) -> Vec<f64> {
        vec![self.q.x]
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        if e.is_runtime() {
            let f = if self.tuned {
                "fb_rt_cubic_rational_tuned"
            } else {
                "fb_rt_cubic_rational"
            };
            format!("{f}({c}, {})", e.param("n"))
        } else {
            format!(
                "fb_lobe_cubic_rational({c}, {}, {}, {})",
                self.cubic.wgsl_args(e),
                self.rational.wgsl_args(e),
                e.constant(self.q)
            )
        }
    }
}
