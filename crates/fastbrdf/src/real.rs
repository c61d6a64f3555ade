//! The scalar type every model is written over: `f32` (the shading path) or `f64`
//! (the analysis path). Each formula is written once, generically, and the two precisions
//! are tested against each other (see `tests/precision.rs`).

use num_traits::{Float, FloatConst};
use std::fmt::{Debug, Display};

/// A floating-point scalar: `f32` or `f64`.
pub trait Real: Float + FloatConst + Debug + Display + Default + Send + Sync + 'static {
    /// Converts an `f64` constant (a model parameter or a precomputed coefficient).
    fn c(x: f64) -> Self;
    /// Converts back to `f64` (for reporting).
    fn f64(self) -> f64;
    /// The error function.
    fn erf(self) -> Self;
    /// The complementary error function, `1 - erf(x)`, accurate for large `x`.
    fn erfc(self) -> Self;
    /// `x64` in f64, `x32` in f32: a coefficient's precomputed rounding ([`K`]).
    fn pick(x64: f64, x32: f32) -> Self;
    /// [`pos`] written on the concrete type. The same select written generically (`x >
    /// T::zero()`, through `PartialOrd`) reaches LLVM in another shape: where a formula
    /// clamps a value into [0, 1], it fused the two selects into mask compares and blends
    /// (`fresnel-schlick`'s kernel ran at 15 G/s instead of 32 on 4096 cosines, issue 13).
    fn sel_pos(self) -> Self;
    /// [`min1`] written on the concrete type (see `sel_pos`).
    fn sel_min1(self) -> Self;
}

/// The concrete selects behind [`pos`] and [`min1`], one `maxps` and one `minps`.
macro_rules! concrete_selects {
    () => {
        #[inline(always)]
        fn sel_pos(self) -> Self {
            if self > 0.0 { self } else { 0.0 }
        }
        #[inline(always)]
        fn sel_min1(self) -> Self {
            if self < 1.0 { self } else { 1.0 }
        }
    };
}

/// A per-parameter coefficient, computed once in f64 with its f32 rounding beside it, so that
/// neither precision converts it per evaluation (the scalar models and the batch kernels read
/// `t::<T>()`; the WGSL generator and the analysis read the f64 `x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct K {
    pub x: f64,
    r: f32,
}

impl K {
    /// The coefficient `x`.
    #[inline]
    pub fn new(x: f64) -> Self {
        Self { x, r: x as f32 }
    }
    /// A coefficient whose f32 value is not the rounding of its f64 value (the low part of a
    /// two-float sum, which differs per precision).
    #[inline]
    pub fn pair(x64: f64, x32: f32) -> Self {
        Self { x: x64, r: x32 }
    }
    /// The coefficient in precision `T` (rounded once, at construction, for f32).
    #[inline(always)]
    pub fn t<T: Real>(self) -> T {
        T::pick(self.x, self.r)
    }
}

impl From<K> for f64 {
    fn from(k: K) -> f64 {
        k.x
    }
}

impl Real for f32 {
    #[inline(always)]
    fn c(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn erf(self) -> Self {
        libm::erff(self)
    }
    #[inline]
    fn erfc(self) -> Self {
        libm::erfcf(self)
    }
    #[inline(always)]
    fn pick(_x64: f64, x32: f32) -> Self {
        x32
    }
    concrete_selects!();
}

impl Real for f64 {
    #[inline(always)]
    fn c(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn f64(self) -> f64 {
        self
    }
    #[inline]
    fn erf(self) -> Self {
        libm::erf(self)
    }
    #[inline]
    fn erfc(self) -> Self {
        libm::erfc(self)
    }
    #[inline(always)]
    fn pick(x64: f64, _x32: f32) -> Self {
        x64
    }
    concrete_selects!();
}

/// Squares a value (pbrt's `Sqr`).
#[inline(always)]
pub fn sqr<T: Real>(x: T) -> T {
    x * x
}

/// `max(x, 0)`, mapping NaN to 0. Written as the select `x > 0 ? x : 0`, which is one
/// `maxps` on x86 (Rust's `max` must also handle a NaN first operand: three instructions).
#[inline(always)]
pub fn pos<T: Real>(x: T) -> T {
    x.sel_pos()
}

/// `min(x, 1)` as the select `x < 1 ? x : 1` (one `minps`; NaN gives 1, as Rust's `min`).
#[inline(always)]
pub fn min1<T: Real>(x: T) -> T {
    x.sel_min1()
}

/// `x^(2^k)` by `k` squarings.
#[inline(always)]
pub fn pow2k<T: Real>(mut x: T, k: u32) -> T {
    for _ in 0..k {
        x = x * x;
    }
    x
}
