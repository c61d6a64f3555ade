//! The math backends a formula is written over: each model's formula is written once,
//! generic over `T: Real` and `M: Math<T>`, and instantiated twice:
//! - [`Exact`]: the precision's own functions (Rust's libm-backed `powf`, `exp`, ...), for the
//!   scalar models in f32 and f64 (the analysis path and the reference for everything else);
//! - [`Fast`]: the vectorisable approximations of [`fast`] (at most 2 ulp, no libm calls,
//!   branch-free), f32 only, for the SIMD batch kernels.
//!
//! Everything else in a formula (`+`, `*`, `/`, `sqrt`, `min`, `max`, comparisons) is IEEE
//! arithmetic, the same in both backends.

pub mod fast;

use crate::real::Real;
use fast as math;

/// The elementary functions a formula may call.
pub trait Math<T: Real> {
    /// Whether `madd` is one fused multiply-add (one rounding): a family's batch form may then
    /// fold a subtraction into it where the fused step is exact enough (`LobeForm::batch`).
    const FMA: bool = false;
    fn pow(x: T, y: T) -> T;
    /// `pow` for `x` in [0, 1], not NaN, and `y >= 1` (the clamped `pow` lobe): a backend may
    /// skip `pow`'s NaN, negative and subnormal-input handling and give 0 below 2^-126.
    fn pow_unit(x: T, y: T) -> T {
        Self::pow(x, y)
    }
    fn exp(x: T) -> T;
    fn exp2(x: T) -> T;
    fn log2(x: T) -> T;
    fn acos(x: T) -> T;
    /// The complementary error function (`Fast`: the branch-free [`fast::erfc`], which
    /// vectorises; `Exact`: libm's).
    fn erfc(x: T) -> T;
    /// `exp2(x)` for `x <= 0` (a NaN gives NaN or 0): the vector backends skip the overflow
    /// and NaN branches.
    fn exp2_nonpos(x: T) -> T {
        Self::exp2(x)
    }
    /// `exp(x)` for `x <= 0`, as `exp2_nonpos`.
    fn exp_nonpos(x: T) -> T {
        Self::exp(x)
    }
    /// `s 2^x` for `x <= 0` and `s` in [1/4, 2^64]: the vector backends fold `s` into the
    /// polynomial and give 0 where `x < -123` (see [`fast::exp2_nonpos_times`]).
    fn exp2_nonpos_times(x: T, s: T) -> T {
        s * Self::exp2_nonpos(x)
    }
    /// `exp2(x)` for `x <= 0`, 0 for NaN and `x <= -127`; the vector backends drop the final
    /// select and may return a value off by up to 2^-126 (never negative) where the exact one
    /// is below 2^-125.5 (see [`fast::exp2_nonpos_tail`]). `x > 0` is unspecified there: the
    /// caller clamps first.
    fn exp2_nonpos_tail(x: T) -> T {
        Self::exp2_nonpos(x)
    }
    /// `a b + c`: two roundings in `Exact` and `Fast` (the scalar models keep their documented
    /// f32 behaviour; SSE2 has no FMA), one in `FastFma`.
    fn madd(a: T, b: T, c: T) -> T;
}

/// The precision's exact functions.
#[derive(Clone, Copy, Debug)]
pub struct Exact;

impl<T: Real> Math<T> for Exact {
    #[inline(always)]
    fn pow(x: T, y: T) -> T {
        x.powf(y)
    }
    #[inline(always)]
    fn exp(x: T) -> T {
        x.exp()
    }
    #[inline(always)]
    fn exp2(x: T) -> T {
        x.exp2()
    }
    #[inline(always)]
    fn log2(x: T) -> T {
        x.log2()
    }
    #[inline(always)]
    fn acos(x: T) -> T {
        x.acos()
    }
    #[inline(always)]
    fn erfc(x: T) -> T {
        x.erfc()
    }
    #[inline(always)]
    fn madd(a: T, b: T, c: T) -> T {
        a * b + c
    }
}

/// The batch kernels' vectorisable f32 functions ([`fast`]).
#[derive(Clone, Copy, Debug)]
pub struct Fast;

impl Math<f32> for Fast {
    #[inline(always)]
    fn pow(x: f32, y: f32) -> f32 {
        math::pow(x, y)
    }
    #[inline(always)]
    fn exp(x: f32) -> f32 {
        math::exp(x)
    }
    #[inline(always)]
    fn exp2(x: f32) -> f32 {
        math::exp2(x)
    }
    #[inline(always)]
    fn log2(x: f32) -> f32 {
        math::log2(x)
    }
    #[inline(always)]
    fn acos(x: f32) -> f32 {
        math::acos(x)
    }
    #[inline(always)]
    fn erfc(x: f32) -> f32 {
        math::erfc(x)
    }
    #[inline(always)]
    fn madd(a: f32, b: f32, c: f32) -> f32 {
        a * b + c
    }
    #[inline(always)]
    fn exp2_nonpos(x: f32) -> f32 {
        math::exp2_nonpos(x)
    }
    #[inline(always)]
    fn exp_nonpos(x: f32) -> f32 {
        math::exp_nonpos(x)
    }
    #[inline(always)]
    fn exp2_nonpos_times(x: f32, s: f32) -> f32 {
        math::exp2_nonpos_times(x, s)
    }
    #[inline(always)]
    fn exp2_nonpos_tail(x: f32) -> f32 {
        math::exp2_nonpos_tail(x)
    }
}

/// `Fast` with fused multiply-adds, in the formulas and in the polynomials of
/// [`fast::fma`]: for the kernels compiled for AVX2+FMA and AVX-512, where `mul_add` is one
/// instruction (elsewhere it would call libm's `fmaf`).
#[derive(Clone, Copy, Debug)]
pub struct FastFma;

impl Math<f32> for FastFma {
    const FMA: bool = true;
    #[inline(always)]
    fn pow(x: f32, y: f32) -> f32 {
        fast::fma::pow(x, y)
    }
    #[inline(always)]
    fn pow_unit(x: f32, y: f32) -> f32 {
        fast::fma::pow_unit(x, y)
    }
    #[inline(always)]
    fn exp(x: f32) -> f32 {
        fast::fma::exp(x)
    }
    #[inline(always)]
    fn exp2(x: f32) -> f32 {
        fast::fma::exp2(x)
    }
    #[inline(always)]
    fn log2(x: f32) -> f32 {
        fast::fma::log2(x)
    }
    #[inline(always)]
    fn acos(x: f32) -> f32 {
        fast::fma::acos(x)
    }
    #[inline(always)]
    fn erfc(x: f32) -> f32 {
        fast::fma::erfc(x)
    }
    #[inline(always)]
    fn madd(a: f32, b: f32, c: f32) -> f32 {
        a.mul_add(b, c)
    }
    #[inline(always)]
    fn exp2_nonpos(x: f32) -> f32 {
        fast::fma::exp2_nonpos(x)
    }
    #[inline(always)]
    fn exp_nonpos(x: f32) -> f32 {
        fast::fma::exp_nonpos(x)
    }
    #[inline(always)]
    fn exp2_nonpos_times(x: f32, s: f32) -> f32 {
        fast::fma::exp2_nonpos_times(x, s)
    }
    #[inline(always)]
    fn exp2_nonpos_tail(x: f32) -> f32 {
        fast::fma::exp2_nonpos_tail(x)
    }
}
