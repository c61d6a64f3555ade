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
//! Parameters: `n` in [1, 100000] (default 20). Source: seed 001 (Romanyuk et al., ACIT 2023).
//! Error bounds against `pow`: see the `INFO` constants.
//! Sampling: no closed-form inverse used; `phong`/`blinn-phong` sample the twin `pow` at the same n (`twin`) and weight by f/pdf.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K, Real, min1, pos};
use crate::wgsl::Emit;

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
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 100000.0),
            bound: 0.126,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 1000.0),
            bound: 0.00292,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 100000.0),
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
    f32_bound: 2e-3,
    note: "no clamp: a normalised lobe exceeds 1 near the peak for n > ~3; f32: coef(n) (~0.2 n) times the rounding of flog near its zero, where the value is ~1 and the peak coef(n): 1.5e-4 at n = 10000, 1.55e-3 at n = 1e5 (8e-8 of the peak)",
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

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Lobe(Flog::new(p.num("n"), FlogMode::Plain)?.into()))
});
pub const ENTRY_NORMALIZED: Entry = Entry::new(INFO_NORMALIZED, |p, _| {
    Ok(Plan::Lobe(
        Flog::new(p.num("n"), FlogMode::Normalized)?.into(),
    ))
});
pub const ENTRY_CLAMPED: Entry = Entry::new(INFO_CLAMPED, |p, _| {
    Ok(Plan::Lobe(
        Flog::new(p.num("n"), FlogMode::NormalizedClamped)?.into(),
    ))
});

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
#[derive(Clone, Copy, Debug)]
pub struct Flog {
    n: K,
    coef: K,
    mode: FlogMode,
}

impl Flog {
    /// `n` must be in [1, 100000].
    pub fn new(n: f64, mode: FlogMode) -> Result<Self> {
        let n = params::check("flog", &params::N, n)?;
        let coef = if mode == FlogMode::Plain {
            1.0
        } else {
            seed_coef(n)
        };
        Ok(Self {
            n: K::new(n),
            coef: K::new(coef),
            mode,
        })
    }
}

/// seed 001's energy coefficient of flog, as a WGSL expression of `p_n`.
const FLOG_COEF: &str = "0.197 * (p_n + 1.24) + 0.068 / (0.64 + p_n)";

impl LobeForm for Flog {
    // NaN: `pos` (power, cubic) or the `c > 0` select (flog) gives 0.
    const NAN_TO_ZERO: bool = true;
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("flog.wgsl");
    fn id(&self) -> &'static str {
        match self.mode {
            FlogMode::Plain => "flog",
            FlogMode::Normalized => "flog-normalized",
            FlogMode::NormalizedClamped => "flog-normalized-clamped",
        }
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        // c = 0 gives log2(0) = -inf, then -inf, clipped to 0 below; every c <= 0 is below
        // the zero anyway, and the select keeps 0 there whatever the backend's log2(0) is.
        let f = M::madd(
            T::c(-0.5),
            M::log2(M::madd(-self.n.t::<T>(), M::log2(c), T::one())),
            T::one(),
        );
        let v = pos(self.coef.t::<T>() * f);
        let v = if self.mode == FlogMode::NormalizedClamped {
            min1(v)
        } else {
            v
        };
        if c > T::zero() { v } else { T::zero() }
    }
    fn zero_below(&self) -> f64 {
        zero_cos(self.n.x)
    }
    fn kinks(&self) -> Vec<f64> {
        // The clamp's kink, where coef flog(c) = 1: c = 2^((1 - 2^(2 (1 - 1/coef))) / n)
        // (inside the lobe when coef > 1). Without it as a breakpoint the normalisation
        // integral erred by 8.3e-7 relative at n = 69 (found by the runtime-parameter tests).
        if self.mode == FlogMode::NormalizedClamped && self.coef.x > 1.0 {
            vec![((1.0 - (2.0 * (1.0 - 1.0 / self.coef.x)).exp2()) / self.n.x).exp2()]
        } else {
            Vec::new()
        }
    }
    fn normalised(&self) -> bool {
        self.mode != FlogMode::Plain
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        let coef = if self.mode == FlogMode::Plain {
            "1.0f".to_string()
        } else {
            e.kx(self.coef, FLOG_COEF, &["n"])
        };
        format!(
            "fb_lobe_flog({c}, {}, {coef}, {})",
            e.kx(self.n, "p_n", &["n"]),
            self.mode == FlogMode::NormalizedClamped
        )
    }
}
