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
}

/// Squares a value (pbrt's `Sqr`).
#[inline(always)]
pub fn sqr<T: Real>(x: T) -> T {
    x * x
}

/// `max(x, 0)`, mapping NaN to 0.
#[inline(always)]
pub fn pos<T: Real>(x: T) -> T {
    if x > T::zero() { x } else { T::zero() }
}

/// `x^(2^k)` by `k` squarings.
#[inline(always)]
pub fn pow2k<T: Real>(mut x: T, k: u32) -> T {
    for _ in 0..k {
        x = x * x;
    }
    x
}
