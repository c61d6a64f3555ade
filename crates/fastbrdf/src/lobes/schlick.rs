//! `schlick` and `schlick-modified`: rational stand-ins for `c^n`.
//!
//! - `schlick`: `c / (n - n c + c)` (Schlick 1994; seeds 001, 003). Value 1 and slope `n` at
//!   `c = 1`, like `c^n`, but a much heavier tail. Cost: 2 mul, 2 add, 1 div.
//! - `schlick-modified`: `2 c / (1.25 (n - n c + 1.25 c)^2)`, exactly as printed in seed 001
//!   (its reference \[15\]). Decision: we keep the printed formula although it is not 1 at the
//!   peak: its value at `c = 1` is `2 / 1.25^3 = 1.024` and its slope there is about `1.64 n`.
//!   No reading of the OCR text that we found gives a peak of 1 with the printed constants, so
//!   we implement it as printed and let the error sweeps show its behaviour.
//!   Cost: 4 mul, 2 add, 1 div.
//!
//! Parameters: `n` in [1, 100000] (default 20). Error bounds against `pow`: see `INFO`.
//! Sampling: no closed-form inverse used; `phong`/`blinn-phong` sample the twin `pow` at the same n (`twin`) and weight by f/pdf.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K, Real, pos};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "schlick",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "c / (n - n c + c)",
    source: "Schlick 1994, 'A fast alternative to Phong's specular model'; seeds 001, 003",
    ops: Ops::new(2, 2, 1, 0, 0),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 1000.0),
            bound: 0.204,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 100000.0),
            bound: 0.204,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 1000.0),
            bound: 0.182,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 100000.0),
            bound: 0.182,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

pub const INFO_MODIFIED: ModelInfo = ModelInfo {
    id: "schlick-modified",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "2 c / (1.25 (n - n c + 1.25 c)^2)",
    source: "seed 001, its reference [15] (Romanyuk et al.)",
    ops: Ops::new(4, 2, 1, 0, 0),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 1000.0),
            bound: 0.133,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 100000.0),
            bound: 0.133,
        },
    ],
    f32_bound: 4e-7,
    note: "implemented as printed in seed 001; its value at c = 1 is 1.024, not 1",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Lobe(Schlick::new(p.num("n"))?.into()))
});
pub const ENTRY_MODIFIED: Entry = Entry::new(INFO_MODIFIED, |p, _| {
    Ok(Plan::Lobe(SchlickModified::new(p.num("n"))?.into()))
});

/// Schlick's rational lobe.
#[derive(Clone, Copy, Debug)]
pub struct Schlick {
    n: K,
}

impl Schlick {
    /// `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: K::new(params::check("schlick", &params::N, n)?),
        })
    }
}

impl LobeForm for Schlick {
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("schlick.wgsl");
    fn id(&self) -> &'static str {
        "schlick"
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        // n - n c + c written as n (1 - c) + c: 1 - c is exact for c >= 0.5.
        c / M::madd(self.n.t::<T>(), T::one() - c, c)
    }
    /// The kernel clamps only c > 1: with n >= 1 the denominator stays positive below c = 0,
    /// so the value there is negative (NaN at -inf) and the final `max(v, 0)` gives the
    /// rule's 0. With FMA the denominator is `fma(c, 1 - n, n)`, one rounding (`1 - n` is
    /// exact for an f32 n in [1, 2^24]) instead of a subtraction and a fused step (issue 13).
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let n = self.n.t::<f32>();
        let x = if 1.0 < c { 1.0 } else { c };
        let d = if M::FMA {
            M::madd(x, 1.0 - n, n)
        } else {
            M::madd(n, 1.0 - x, x)
        };
        pos(x / d)
    }
    /// d is in [1, n] on [0, 1]: c / d is subnormal only for c below n 2^-126.
    fn batch_ftz(&self) -> bool {
        false
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        format!("fb_lobe_schlick({c}, {})", e.kx(self.n, "p_n", &["n"]))
    }
}

/// Seed 001's modified Schlick lobe, as printed.
#[derive(Clone, Copy, Debug)]
pub struct SchlickModified {
    n: K,
}

impl SchlickModified {
    /// `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: K::new(params::check("schlick-modified", &params::N, n)?),
        })
    }
}

impl LobeForm for SchlickModified {
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("schlick.wgsl");
    fn id(&self) -> &'static str {
        "schlick-modified"
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        let d = M::madd(self.n.t::<T>(), T::one() - c, T::c(1.25) * c);
        T::c(2.0) * c / (T::c(1.25) * (d * d))
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        format!(
            "fb_lobe_schlick_modified({c}, {})",
            e.kx(self.n, "p_n", &["n"])
        )
    }
}
