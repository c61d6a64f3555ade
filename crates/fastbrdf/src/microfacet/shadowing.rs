//! Shadowing-masking terms `G`: `v-cavity`, `smith`, `smith-rational`,
//! `smith-beckmann-correlated`.
//!
//! - `v-cavity` (Cook & Torrance 1982): `G = min(1, 2 NH NV / VH, 2 NH NL / VH)`; the one-sided
//!   term (no `cos_l`) is `min(1, 2 NH NV / VH)`, each side as `2 NH (NV / VH)` (no overflow at
//!   a subnormal `VH`). Cost: 2 mul, 1 div (two-sided 3 mul, 2 div).
//! - `smith`: Smith's G1 for Beckmann, exact: `G1 = 1 / (1 + Lambda(a))`,
//!   `a = 1 / (alpha tan theta)`, `Lambda(a) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))`
//!   (Walter et al. 2007, eq. 25-27). We compute `erf(a) - 1 = -erfc(a)` to avoid cancellation.
//!   Two-sided (with `cos_l`): the separable `G1(v) G1(l)` (Mitsuba 3's convention).
//!   Cost per G1: 3 mul, 2 add, 3 div, 1 sqrt, 2 transcendental (erfc, exp).
//!   Batch kernels (issue 30): the same formula over the `Fast` backend, whose branch-free
//!   `erfc` (`math::fast::erfc`, <= 4 f32 epsilons) vectorises, so both exact Beckmann terms
//!   run SIMD. No cancellation matters there: for large `a` the two terms of `Lambda` cancel,
//!   but `Lambda < 3e-3` from `a = 2` and G1 = 1 / (1 + Lambda) needs only its absolute
//!   error (<= 4 epsilons of `erfc(a) / 2`); G1 against f64 over `a`: see
//!   `tests/batch_smith.rs`.
//! - `smith-rational`: Walter's rational fit, `G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a +
//!   2.577 a^2)` for `a < 1.6`, else 1 (Walter et al. 2007, eq. 27; Mitsuba 3 uses it for
//!   Beckmann). Documented error against `smith`: see `INFO_RATIONAL`. Cost per G1: 6 mul,
//!   3 add, 2 div, 1 sqrt.
//! - `smith-beckmann-correlated`: the height-correlated Smith term for Beckmann,
//!   `G = 1 / (1 + Lambda(v) + Lambda(l))` with `smith`'s exact `Lambda` (Heitz 2014, eq. 99);
//!   one-sided (no `cos_l`): `G1`, as `smith`'s (`Lambda = 0` at `cos >= 1`). Cost: 8 mul,
//!   8 add, 5 div, 2 sqrt, 4 transcendental.
//!   Exact model: no error bound; f32 against f64 1.5e-7 measured (documented 1e-6).
//!
//! Parameters: `alpha` in [0.005, 1] (default 0.3) for the Smith terms; the V-cavity has none.
//! Cosines that are NaN or `<= 0` give 0; a cosine of 1 gives G1 = 1.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::ShadowForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params;
use crate::plan::Plan;
use crate::real::{K, Real, pos, sqr};
use crate::wgsl::Emit;

pub const INFO_VCAVITY: ModelInfo = ModelInfo {
    id: "v-cavity",
    kind: Kind::Shadowing,
    params: &[],
    formula: "min(1, 2 NH NV / VH, 2 NH NL / VH)",
    source: "Cook & Torrance 1982 (after Torrance & Sparrow 1967)",
    ops: Ops::new(3, 0, 2, 0, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "input columns cos_v, cos_h, cos_vh and optional cos_l (two-sided)",
};

pub const INFO_SMITH: ModelInfo = ModelInfo {
    id: "smith",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G1 = 1 / (1 + Lambda(a)), a = 1/(alpha tan theta), Lambda = (erf(a) - 1)/2 + exp(-a^2)/(2 a sqrt(pi)); G = G1(v) G1(l)",
    source: "Smith 1967; Walter et al. 2007 (Beckmann Lambda)",
    ops: Ops::new(3, 2, 3, 1, 2),
    bounds: &[],
    f32_bound: 1e-6,
    note: "two-sided form is separable G1(v) G1(l), as Mitsuba 3",
};

pub const INFO_RATIONAL: ModelInfo = ModelInfo {
    id: "smith-rational",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G1 = (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a < 1.6, else 1",
    source: "Walter et al. 2007, eq. 27 (used by Mitsuba 3 for Beckmann)",
    ops: Ops::new(6, 3, 2, 1, 0),
    bounds: &[ErrorBound {
        reference: "smith",
        metric: Metric::MaxRel,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound: 0.00313,
    }],
    f32_bound: 1e-6,
    note: "",
};

pub const INFO_BECKMANN_CORRELATED: ModelInfo = ModelInfo {
    id: "smith-beckmann-correlated",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G = 1 / (1 + Lambda(v) + Lambda(l)), Lambda as smith's (Beckmann, exact)",
    source: "Heitz 2014, eq. 99 (height-correlated Smith); Walter et al. 2007 (Beckmann Lambda)",
    ops: Ops::new(8, 8, 5, 2, 4),
    bounds: &[],
    f32_bound: 1e-6,
    note: "one-sided (no cos_l): G1, as smith",
};

pub const ENTRY_VCAVITY: Entry =
    Entry::new(INFO_VCAVITY, |_, _| Ok(Plan::Shadowing(VCavity.into())));
pub const ENTRY_SMITH: Entry = Entry::new(INFO_SMITH, |p, _| {
    Ok(Plan::Shadowing(Smith::new(p.num("alpha"))?.into()))
});
pub const ENTRY_RATIONAL: Entry = Entry::new(INFO_RATIONAL, |p, _| {
    Ok(Plan::Shadowing(SmithRational::new(p.num("alpha"))?.into()))
});
pub const ENTRY_BECKMANN_CORRELATED: Entry = Entry::new(INFO_BECKMANN_CORRELATED, |p, _| {
    Ok(Plan::Shadowing(
        SmithBeckmannCorrelated::new(p.num("alpha"))?.into(),
    ))
});

/// Cook and Torrance's V-cavity term.
#[derive(Clone, Copy, Debug, Default)]
pub struct VCavity;

impl ShadowForm for VCavity {
    const HALF_VECTOR: bool = true;
    const WGSL: &'static str = include_str!("shadowing.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, cos_h: T, cos_vh: T) -> T {
        T::one()
            .min(v_cavity_side(cos_v, cos_h, cos_vh))
            .min(v_cavity_side(cos_l, cos_h, cos_vh))
    }
    fn wgsl(&self, v: &str, l: &str, h: &str, vh: &str, _e: &Emit) -> String {
        format!("fb_g_v_cavity({v}, {l}, {h}, {vh})")
    }
}

/// One side of the V-cavity, `2 cos_h cos / cos_vh` (positive cosines, `cos` at most 1 or
/// `+inf`), as `2 cos_h (cos / cos_vh)`: the ratio of the two cosines first, which is at most
/// 1 for `cos <= cos_vh` and overflows only where `cos_vh` is subnormal and `cos` is not;
/// there `(2 cos_h / cos_vh) cos`. (`2 cos_h / cos_vh` first, as before issue 27, overflowed
/// to `+inf` in f32 for every subnormal `cos_vh` and gave `G = 1` where the value is below 1,
/// 0.8425 at the point.)
#[inline(always)]
fn v_cavity_side<T: Real>(cos: T, cos_h: T, cos_vh: T) -> T {
    let two_h = T::c(2.0) * cos_h;
    let r = cos / cos_vh;
    if r.is_finite() {
        two_h * r
    } else {
        two_h / cos_vh * cos
    }
}

/// `a = cos / (alpha sin)` of a direction, for the Smith terms (`cos` in (0, 1)).
#[inline(always)]
fn smith_a<T: Real>(alpha: T, cos: T) -> T {
    let sin = pos((T::one() - cos) * (T::one() + cos)).sqrt();
    cos / (alpha * sin)
}

/// `G1(v) G1(l)` on positive cosines, each side 1 at `cos >= 1` (normal incidence, and the
/// one-sided term's `+inf`).
#[inline(always)]
pub(crate) fn separable<T: Real>(cos_v: T, cos_l: T, g1: impl Fn(T) -> T) -> T {
    let side = |c: T| {
        let g = g1(c);
        if c >= T::one() { T::one() } else { g }
    };
    side(cos_v) * side(cos_l)
}

/// The exact Smith term for Beckmann.
#[derive(Clone, Copy, Debug)]
pub struct Smith {
    alpha: K,
}

impl Smith {
    /// `alpha` in [0.005, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        Ok(Self {
            alpha: K::new(params::check("smith", &params::ALPHA, alpha)?),
        })
    }
}

impl ShadowForm for Smith {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("shadowing.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        // `separable`'s operations, without its closures: LLVM left these (erfc's polynomial
        // inside) out of line, outside the kernels' instruction sets, calling `fmaf`.
        let alpha = self.alpha.t::<T>();
        smith_g1_side::<T, M>(alpha, cos_v) * smith_g1_side::<T, M>(alpha, cos_l)
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let a = e.kx(self.alpha, "p_alpha", &["alpha"]);
        format!("fb_g1_smith({v}, {a}) * fb_g1_smith({l}, {a})")
    }
}

/// One side of `smith`: `1 / (1 + Lambda)`, 1 at `cos >= 1` (as `separable`'s side).
#[inline(always)]
fn smith_g1_side<T: Real, M: Math<T>>(alpha: T, cos: T) -> T {
    let g = T::one() / (T::one() + beckmann_lambda::<T, M>(alpha, cos));
    if cos >= T::one() { T::one() } else { g }
}

/// `Lambda` of one side of `smith-beckmann-correlated`: 0 at `cos >= 1` (normal incidence,
/// and the one-sided term's +inf).
#[inline(always)]
fn lambda_side<T: Real, M: Math<T>>(alpha: T, cos: T) -> T {
    let x = beckmann_lambda::<T, M>(alpha, cos);
    if cos >= T::one() { T::zero() } else { x }
}

/// Beckmann's exact Smith `Lambda` at `cos` in (0, 1): `(exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2`,
/// `a = cos / (alpha sin)` (`erf(a) - 1 = -erfc(a)`, no cancellation).
#[inline(always)]
fn beckmann_lambda<T: Real, M: Math<T>>(alpha: T, cos: T) -> T {
    let a = smith_a(alpha, cos);
    (-M::erfc(a) + M::exp_nonpos(-a * a) / (a * T::PI().sqrt())) * T::c(0.5)
}

/// The exact height-correlated Smith term for Beckmann.
#[derive(Clone, Copy, Debug)]
pub struct SmithBeckmannCorrelated {
    alpha: K,
}

impl SmithBeckmannCorrelated {
    /// `alpha` in [0.005, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        Ok(Self {
            alpha: K::new(params::check(
                "smith-beckmann-correlated",
                &params::ALPHA,
                alpha,
            )?),
        })
    }
}

impl ShadowForm for SmithBeckmannCorrelated {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("shadowing.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        let alpha = self.alpha.t::<T>();
        // 1 + (Lv + Ll): symmetric to the last bit, so Cook-Torrance stays exactly reciprocal.
        // (Functions, not closures: see `Smith::g_pair`.)
        let (lv, ll) = (
            lambda_side::<T, M>(alpha, cos_v),
            lambda_side::<T, M>(alpha, cos_l),
        );
        T::one() / (T::one() + (lv + ll))
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let a = e.kx(self.alpha, "p_alpha", &["alpha"]);
        format!("fb_g_smith_beckmann_correlated({v}, {l}, {a})")
    }
}

/// Walter et al.'s rational fit of the Smith term for Beckmann.
#[derive(Clone, Copy, Debug)]
pub struct SmithRational {
    alpha: K,
}

impl SmithRational {
    /// `alpha` in [0.005, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        Ok(Self {
            alpha: K::new(params::check("smith-rational", &params::ALPHA, alpha)?),
        })
    }
}

impl ShadowForm for SmithRational {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("shadowing.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        separable(cos_v, cos_l, |c| {
            let a = smith_a(self.alpha.t::<T>(), c);
            let a2 = a * a;
            let g = (T::c(3.535) * a + T::c(2.181) * a2)
                / (T::one() + T::c(2.276) * a + T::c(2.577) * a2);
            if a >= T::c(1.6) { T::one() } else { g }
        })
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let a = e.kx(self.alpha, "p_alpha", &["alpha"]);
        format!("fb_g1_smith_rational({v}, {a}) * fb_g1_smith_rational({l}, {a})")
    }
}

/// `Lambda` and `a` for tests and analysis: `(a, Lambda)` at `cos` in f64.
pub fn smith_lambda(alpha: f64, cos: f64) -> f64 {
    let a = cos / (alpha * (1.0 - sqr(cos)).sqrt());
    (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt())
}
