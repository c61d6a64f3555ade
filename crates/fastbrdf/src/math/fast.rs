//! Branch-free f32 elementary functions that LLVM vectorises (no libm calls, no branches
//! that cannot become selects): the fair exact baseline of the SIMD kernels.
//!
//! Accuracy against f64 for f32 inputs (measured by `tests/batch/`):
//! - `exp2`: relative error <= 2 ulp (split `x = k + f` exactly, degree-7 Taylor polynomial of
//!   `2^f` on [-0.5, 0.5], truncation 5e-9). Exactly 0 below -126 (where the result would be
//!   subnormal: the exponent addition cannot build those), +inf from 128.
//! - `log2_wide` (f64 result) for x in (0, 4): absolute error <= 1e-12 (atanh series to t^15 in
//!   f64 on |t| <= 0.1716); `log2` is it rounded to f32 (<= 1 ulp). `log2(0) = -inf`;
//!   negative inputs give NaN (callers clamp first). With FMA, `fma::log2` is f32 arithmetic
//!   (the same series to t^11): at most one f32 epsilon, 2.6x faster in `flog`.
//! - `pow(x, y) = 2^(y log2 x)` for x in [0, 1], y in (0, 1e5]: the product in f64, its integer
//!   part split off exactly, so relative error <= 2 ulp where the result is normal. With FMA,
//!   `fma::pow` reaches the same bound in double-f32 arithmetic (no f64 lane; `pow_fma`).
//! - `exp`: relative error <= 2 ulp for x in [-87, 88] (Cody-Waite reduction in f32).
//! - `exp2_nonpos_times(x, s)` (`s 2^x`) and `exp2_nonpos_tail(x)` (`2^x` without the final
//!   select): degree-6 minimax polynomial by Horner, <= 3 ulp where the result is normal
//!   (about 1 f32 epsilon measured: `cargo test -p fastbrdf --test batch exponential --
//!   --nocapture` prints each); see each for its tail.
//! - `acos` on [0, 1]: absolute error <= 2e-8 plus f32 rounding (Abramowitz and Stegun 4.4.46).
//! - `erfc`: relative error <= 4 f32 epsilons where the result is normal (`x <= 9.1`),
//!   absolute <= 2^-126 beyond; one polynomial over the half-line, no range branch (see it).
//!
//! Rounding to the nearest integer uses the 1.5 * 2^23 (2^52) trick instead of `floor`, because
//! `floor` is a libm call under plain SSE2.

/// `2^x`.
/// `1.5 * 2^23`: `t = MAGIC + k` holds the integer `k` in its low bits.
const MAGIC: f32 = 12_582_912.0;
/// `ln 2` in two parts (Cody-Waite): `LN2_HI` has trailing zero bits, so `k LN2_HI` is exact.
const LN2_HI: f32 = 0.693_359_4; // 0x3f318000
const LN2_LO: f32 = -2.121_944_4e-4;
/// `exp(r)` on the reduced range: Taylor coefficients to degree 7.
const EXP_C: [f32; 8] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
];

/// `a b + c`: fused (one rounding) when `F`, else two roundings. Fused is used only inside
/// the FMA instruction sets' kernels, where `mul_add` is one instruction; elsewhere it would
/// call libm's `fmaf`.
#[inline(always)]
fn madd<const F: bool>(a: f32, b: f32, c: f32) -> f32 {
    if F { a.mul_add(b, c) } else { a * b + c }
}

#[inline(always)]
fn madd64<const F: bool>(a: f64, b: f64, c: f64) -> f64 {
    if F { a.mul_add(b, c) } else { a * b + c }
}

/// The functions with fused multiply-adds in their polynomials (for kernels compiled for
/// AVX2+FMA and AVX-512; same accuracy bound, tested).
pub mod fma {
    #[inline(always)]
    pub fn exp2(x: f32) -> f32 {
        super::exp2_g::<true>(x)
    }
    #[inline(always)]
    pub fn exp(x: f32) -> f32 {
        super::exp_g::<true>(x)
    }
    #[inline(always)]
    pub fn exp2_nonpos(x: f32) -> f32 {
        super::exp2_nonpos_g::<true>(x)
    }
    #[inline(always)]
    pub fn exp_nonpos(x: f32) -> f32 {
        super::exp_nonpos_g::<true>(x)
    }
    #[inline(always)]
    pub fn exp2_nonpos_times(x: f32, s: f32) -> f32 {
        super::exp2_nonpos_times_g::<true>(x, s)
    }
    #[inline(always)]
    pub fn exp2_nonpos_tail(x: f32) -> f32 {
        super::exp2_nonpos_tail_g::<true>(x)
    }
    #[inline(always)]
    pub fn log2(x: f32) -> f32 {
        super::log2_g::<true>(x)
    }
    #[inline(always)]
    pub fn log2_wide(x: f32) -> f64 {
        super::log2_wide_g::<true>(x)
    }
    /// `x^y` in double-f32 arithmetic (16 lanes a vector where the f64 form has 8): see
    /// [`super::pow_fma`].
    #[inline(always)]
    pub fn pow(x: f32, y: f32) -> f32 {
        super::pow_fma::<false>(x, y)
    }
    /// `pow` for `x` in [0, 1] (not NaN) and `y >= 1`, the `pow` lobe's use after its clamp:
    /// one select instead of three (the underflow test also covers `x = 0` and subnormal
    /// `x`), and results below 2^-126 are 0. Same bound above that (tested).
    #[inline(always)]
    pub fn pow_unit(x: f32, y: f32) -> f32 {
        super::pow_fma::<true>(x, y)
    }
    #[inline(always)]
    pub fn acos(x: f32) -> f32 {
        super::acos_g::<true>(x)
    }
    /// [`super::erfc`] with fused multiply-adds (the exact `a^2` residual in one of them).
    #[inline(always)]
    pub fn erfc(x: f32) -> f32 {
        super::erfc_g::<true>(x)
    }
}

#[inline(always)]
pub fn exp2(x: f32) -> f32 {
    exp2_g::<false>(x)
}

/// Multiply-pipe operations of [`fma::exp2_nonpos_times`] and [`fma::exp2_nonpos_tail`] per
/// element: six fused multiply-adds (degree 6 by Horner; the scale is folded into the
/// coefficients outside the loop, `2^k` added to the exponent bits).
pub const EXP2_NONPOS_TIMES_MULS: u8 = 6;

/// `exp2(x)` for `x <= 0` (the lobes' and distributions' exponents): no overflow or NaN
/// branch; NaN gives 0 (the clamp `x > -127 ? x : -127` maps it below the range). Same
/// accuracy as `exp2` on `[-126, 0]`, 0 below.
#[inline(always)]
pub fn exp2_nonpos(x: f32) -> f32 {
    exp2_nonpos_g::<false>(x)
}

#[inline(always)]
fn exp2_nonpos_g<const F: bool>(x: f32) -> f32 {
    let xc = if x > -127.0 { x } else { -127.0 };
    let t = xc + MAGIC;
    let (k, ki) = unmagic(t);
    let r = scale2::<F>(ki, xc - k);
    if xc >= -126.0 { r } else { 0.0 }
}

/// `s 2^x` for `x <= 0` and a scale `s` in [1/4, 2^64] (a distribution's normalisation), in
/// one step: `s` is folded into the polynomial's coefficients (loop-invariant, so a kernel
/// computes them once) and `2^k` added to the exponent bits, so the scale and the power of
/// two cost no multiply. `2^f` on [-1/2, 1/2] is the degree-6 minimax polynomial
/// [`EXP2_C6`] (relative error 1.6e-8 with its f32 coefficients, where `exp2`'s degree 7 has
/// 7e-9: by Horner six fused multiply-adds where `exp2`'s Estrin takes nine multiply-pipe
/// operations, for well under one ulp). The
/// result is normal down to `x = -123` (`s 2^f >= 2^-3`); below that, and for NaN, it is 0
/// (the exact value there is below `1.1e-37 s`). Relative error <= 3 ulp (tested).
#[inline(always)]
pub fn exp2_nonpos_times(x: f32, s: f32) -> f32 {
    exp2_nonpos_times_g::<false>(x, s)
}

/// `2^f` on [-1/2, 1/2] with `c0 = 1`: the minimax polynomial of degree 6 for the relative
/// error (Remez exchange in 40-digit arithmetic): 1.97e-9 before rounding to f32, 1.6e-8
/// after (c1's rounding dominates; a refit with c1 fixed at its f32 value did no better
/// once c2..c6 were rounded too).
pub const EXP2_C6: [f32; 7] = [
    1.0,
    // 0.693147202855 rounds to the same f32 as ln 2 (2e-8 away: most of the 1.6e-8).
    std::f32::consts::LN_2,
    0.240_226_48,
    0.055_503_324,
    0.009_618_437,
    0.001_339_887_4,
    0.000_153_533_62,
];

#[inline(always)]
fn exp2_nonpos_times_g<const F: bool>(x: f32, s: f32) -> f32 {
    let xc = if x > -127.0 { x } else { -127.0 };
    let r = scaled_exp2_c6::<F>(xc, s);
    if xc >= -123.0 { r } else { 0.0 }
}

/// `s 2^xc` for `xc` in [-127, 0], the exponent field unchecked: `2^f` by [`EXP2_C6`] with
/// `s` folded into the coefficients (loop-invariant; `s = 1` folds away), `2^k` added to the
/// exponent bits. Horner: six fused multiply-adds where Estrin's scheme takes eight
/// multiply-pipe operations (two squarings); the loops that call this overlap iterations
/// enough that the longer chain costs nothing (`beckmann` 5% faster, `sg` 9% faster than
/// with Estrin, in `fastbrdf bench`) and it rounds less (0.6-1.05 f32 epsilons in the
/// batch tests' prints where Estrin gave 1.4-1.6).
#[inline(always)]
fn scaled_exp2_c6<const F: bool>(xc: f32, s: f32) -> f32 {
    let (k, ki) = unmagic(xc + MAGIC);
    scaled_exp2_c6_at::<F>(xc - k, ki, s)
}

/// `s 2^(k + f)` for a reduced `f` in about [-1/2, 1/2] and the integer `k` as `ki`, the
/// exponent field unchecked: [`scaled_exp2_c6`]'s polynomial and exponent addition, for
/// callers with their own reduction ([`pow_fma`]).
#[inline(always)]
fn scaled_exp2_c6_at<const F: bool>(f: f32, ki: i32, s: f32) -> f32 {
    let c = EXP2_C6.map(|c| c * s);
    let mut p = c[6];
    for &ci in c[..6].iter().rev() {
        p = madd::<F>(p, f, ci);
    }
    add_exponent(p, ki)
}

/// `2^x` for `x <= 0` without the final select of [`exp2_nonpos_times`] (`s = 1`): the
/// spherical Gaussians' kernels, where that compare-and-blend took 19% of the time (`sg`
/// 9.1 -> 11.3 G/s in `fastbrdf bench`). The clamp `x > -127 ? x : -127` maps NaN and
/// everything below to -127, where `k = -127`, `f = 0`, the polynomial is exactly 1 and
/// adding -127 to its exponent field gives the bits of +0: exactly 0 there. Above -125.5
/// the result is `exp2_nonpos_times(x, 1)` before its select (same polynomial, <= 3 ulp); in
/// between, where the exact value is below 2^-125.5 = 1.7e-38, the exponent addition
/// reaches the exponent field's 0 and leaves a subnormal bit pattern: non-negative, finite,
/// off by at most 2^-126 = 1.2e-38 (tested). No subnormal arithmetic happens (the bits are
/// built by an integer add). `x > 0` is outside the contract: about `2^x` below 128, `+inf`
/// at 128, negative garbage above and NaN for `+inf` (every caller clamps its argument to
/// `<= 0` first).
#[inline(always)]
pub fn exp2_nonpos_tail(x: f32) -> f32 {
    exp2_nonpos_tail_g::<false>(x)
}

#[inline(always)]
fn exp2_nonpos_tail_g<const F: bool>(x: f32) -> f32 {
    scaled_exp2_c6::<F>(if x > -127.0 { x } else { -127.0 }, 1.0)
}

/// `exp(x)` for `x <= 0`, as [`exp2_nonpos`] (`x log2 e` then the same reduction; the
/// extra rounding of the product keeps it within 2 ulp on `[-87, 0]`, tested).
#[inline(always)]
pub fn exp_nonpos(x: f32) -> f32 {
    exp_nonpos_g::<false>(x)
}

#[inline(always)]
fn exp_nonpos_g<const F: bool>(x: f32) -> f32 {
    // Cody-Waite as `exp`: k from x log2 e, r = x - k ln 2 in two parts, exp(r) by the
    // polynomial, scaled by 2^k; below -87.3 the result is 0 (flushed anyway).
    let xc = if x > -87.3 { x } else { -87.3 };
    let t = madd::<F>(xc, std::f32::consts::LOG2_E, MAGIC);
    let (k, ki) = unmagic(t);
    let r = madd::<F>(-k, LN2_LO, madd::<F>(-k, LN2_HI, xc));
    let p = estrin7::<F>(r, &EXP_C);
    let s = f32::from_bits(((ki + 127) << 23) as u32);
    if xc > -87.3 { p * s } else { 0.0 }
}

#[inline(always)]
fn exp2_g<const F: bool>(x: f32) -> f32 {
    let xc = x.clamp(-127.0, 128.0);
    let t = xc + MAGIC;
    let (k, ki) = unmagic(t);
    let r = scale2::<F>(ki, xc - k);
    let r = if xc < -126.0 { 0.0 } else { r };
    let r = if x >= 128.0 { f32::INFINITY } else { r };
    if x.is_nan() { x } else { r }
}

/// `c0 + c1 x + ... + c7 x^7` by Estrin's scheme: dependency depth 3 instead of Horner's 7,
/// with the same kind of IEEE operations (so every instruction set gets the same bits).
#[inline(always)]
fn estrin7<const F: bool>(x: f32, c: &[f32; 8]) -> f32 {
    let x2 = x * x;
    let x4 = x2 * x2;
    let a = madd::<F>(c[1], x, c[0]);
    let b = madd::<F>(c[3], x, c[2]);
    let d = madd::<F>(c[5], x, c[4]);
    let e = madd::<F>(c[7], x, c[6]);
    madd::<F>(x4, madd::<F>(x2, e, d), madd::<F>(x2, b, a))
}

/// `2^(k + f)` for an integer `k` in [-126, 128] and `f` in [-0.5, 0.5], where the result is
/// normal or +inf: the exponent addition has no subnormal form (at `k = -126` with `f < 0`, or
/// `k = -127`, it would build a wrong bit pattern), so callers give 0 below `k + f = -126`.
#[inline(always)]
fn scale2<const F: bool>(ki: i32, f: f32) -> f32 {
    const C: [f32; 8] = [
        1.0,
        std::f32::consts::LN_2,
        0.240_226_5,
        0.055_504_11,
        0.009_618_129,
        0.001_333_355_8,
        0.000_154_035_3,
        0.000_015_252_734,
    ];
    add_exponent(estrin7::<F>(f, &C), ki)
}

/// `p 2^ki` by adding `ki` to the exponent field (exact where both `p` and the result are
/// normal: the callers keep them so).
#[inline(always)]
fn add_exponent(p: f32, ki: i32) -> f32 {
    f32::from_bits((p.to_bits() as i32).wrapping_add(ki << 23) as u32)
}

/// For `t = x + MAGIC` (rounded, |x| < 2^22): the integer `k` nearest `x`, as an f32 and as
/// an i32. No float-to-int conversion (Rust's saturating `as` blocks vectorisation): `k` is
/// read from the bits of `t`.
#[inline(always)]
fn unmagic(t: f32) -> (f32, i32) {
    (
        t - MAGIC,
        (t.to_bits() as i32).wrapping_sub(MAGIC.to_bits() as i32),
    )
}

/// `2^a` for an f64 exponent, rounded to f32: the integer part is split off in f64, so the
/// argument's own rounding does not enter.
#[inline(always)]
fn exp2_wide<const F: bool>(a: f64) -> f32 {
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 1.5 * 2^52
    let ac = a.clamp(-127.0, 128.0);
    let t = ac + MAGIC;
    let k = t - MAGIC;
    let ki = (t.to_bits() as i64).wrapping_sub(MAGIC.to_bits() as i64) as i32;
    let r = scale2::<F>(ki, (ac - k) as f32);
    let r = if ac < -126.0 { 0.0 } else { r };
    let r = if a >= 128.0 { f32::INFINITY } else { r };
    if a.is_nan() { f32::NAN } else { r }
}

/// `e^x`, in f32 only: `k = round(x / ln 2)`, `r = x - k ln2_hi - k ln2_lo` (Cody and Waite;
/// `k ln2_hi` is exact because ln2_hi has 9 significant bits and |k| <= 128), `e^r` by its
/// Taylor polynomial of degree 7 on |r| <= 0.347 (truncation 5e-9).
#[inline(always)]
pub fn exp(x: f32) -> f32 {
    exp_g::<false>(x)
}

#[inline(always)]
fn exp_g<const F: bool>(x: f32) -> f32 {
    let xc = x.clamp(-88.5, 88.8);
    let t = xc * std::f32::consts::LOG2_E + MAGIC;
    let (k, ki) = unmagic(t);
    let r = (xc - k * LN2_HI) - k * LN2_LO;
    let p = estrin7::<F>(r, &EXP_C);
    // 2^k may be 2^-127 or 2^128 at the ends: scale in two halves to stay finite.
    let h = ki >> 1;
    let s1 = f32::from_bits(((h + 127) << 23) as u32);
    let s2 = f32::from_bits(((ki - h + 127) << 23) as u32);
    let r = p * s1 * s2;
    let r = if x < -88.5 { 0.0 } else { r };
    let r = if x > 88.8 { f32::INFINITY } else { r };
    if x.is_nan() { x } else { r }
}

/// `x = 2^e m` with `m` in [2^-1/2, 2^1/2), read from the bits (exact; a subnormal `x` gives
/// `e = -127` or -126 and its mantissa bits as `m`, which the callers' `x < 2^-126` select
/// overrides). The reduction of every `log2` form here.
#[inline(always)]
fn split(x: f32) -> (i32, f32) {
    let bits = x.to_bits();
    let e = ((bits >> 23) & 0xff) as i32 - 127;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000); // [1, 2)
    let big = m > std::f32::consts::SQRT_2;
    let m = if big { m * 0.5 } else { m };
    (if big { e + 1 } else { e }, m)
}

/// `log2(x)` in f64 for an f32 `x >= 0` (normal or zero; subnormals are treated as zero).
#[inline(always)]
pub fn log2_wide(x: f32) -> f64 {
    log2_wide_g::<false>(x)
}

#[inline(always)]
fn log2_wide_g<const F: bool>(x: f32) -> f64 {
    // The f32 split is exact, and no f32 lies between f32's SQRT_2 and sqrt(2): the same
    // reduction as comparing in f64.
    let (e, m) = split(x);
    let (e, m) = (f64::from(e), f64::from(m));
    let t = (m - 1.0) / (m + 1.0);
    let t2 = t * t;
    const K: f64 = 2.0 * std::f64::consts::LOG2_E;
    // Estrin's scheme (depth 3 instead of 7: the loop is latency-bound otherwise).
    let t4 = t2 * t2;
    let t8 = t4 * t4;
    let p01 = madd64::<F>(t2, 1.0 / 3.0, 1.0);
    let p23 = madd64::<F>(t2, 1.0 / 7.0, 1.0 / 5.0);
    let p45 = madd64::<F>(t2, 1.0 / 11.0, 1.0 / 9.0);
    let p67 = madd64::<F>(t2, 1.0 / 15.0, 1.0 / 13.0);
    let s = t * madd64::<F>(t8, madd64::<F>(t4, p67, p45), madd64::<F>(t4, p23, p01));
    let r = madd64::<F>(K, s, e);
    let r = if x < f32::MIN_POSITIVE {
        f64::NEG_INFINITY
    } else {
        r
    };
    if x >= 0.0 { r } else { f64::NAN }
}

/// `log2(x)` for x >= 0 (see `log2_wide`).
#[inline(always)]
pub fn log2(x: f32) -> f32 {
    log2_wide(x) as f32
}

/// `log2(x)` for x >= 0 in f32 arithmetic, for the FMA instruction sets (`fma::log2`, the
/// kernels' `log2`: `flog`'s two calls; issue 13: the f64 form ran at 1.9 G/s a core, 8
/// lanes a vector with conversions both ways; SSE2 keeps it). With `x = 2^e m`, `m` in
/// [2^-1/2, 2^1/2): `t = (m - 1) / (m + 1)`, `|t| <= 0.1716` (`m - 1` exact), `log2 m =
/// (2 / ln 2)(t + t^3/3 + ... + t^11/11)` (truncation 5e-11 relative), then `e + log2 m` with
/// 2 / ln 2 as head and tail. At most one f32 epsilon (1.2e-7) absolute below 1 and relative
/// above (measured 1.0e-7, `tests/batch/`). `-inf` for `x < 2^-126` (subnormals as zero,
/// as `log2_wide`), NaN for NaN and negative `x`.
#[inline(always)]
fn log2_g<const F: bool>(x: f32) -> f32 {
    // 2 / ln 2 as f32 head and tail.
    const KH: f32 = (2.0 * std::f64::consts::LOG2_E) as f32;
    const KL: f32 = (2.0 * std::f64::consts::LOG2_E - KH as f64) as f32;
    let (e, m) = split(x);
    let e = e as f32;
    let t = (m - 1.0) / (m + 1.0);
    let t2 = t * t;
    let p = madd::<F>(
        t2 * t2,
        madd::<F>(t2, 1.0 / 11.0, 1.0 / 9.0) * t2 + 1.0 / 7.0,
        madd::<F>(t2, 1.0 / 5.0, 1.0 / 3.0),
    );
    // r = t + t^3 p; e + (KH + KL) r with the tail first.
    let r = madd::<F>(t * t2, p, t);
    let v = madd::<F>(KH, r, madd::<F>(KL, r, e));
    let v = if x < f32::MIN_POSITIVE {
        f32::NEG_INFINITY
    } else {
        v
    };
    if x >= 0.0 { v } else { f32::NAN }
}

/// `x^y` for x in [0, 1] and y > 0 (the lobes' and distributions' use), `0^y = 0`.
#[inline(always)]
pub fn pow(x: f32, y: f32) -> f32 {
    exp2_wide::<false>(y as f64 * log2_wide(x))
}

/// `x^y` for x in [0, 1] and y in (0, 1e5], for the FMA instruction sets: the same 2-ulp
/// bound as [`pow`] without any f64 lane (issue 13: the f64 form ran at 8x a scalar `powf`
/// loop, 8 lanes a vector with conversions both ways).
///
/// The result is normal only where `|y log2 x| <= 126`, so `log2 x` needs about 31 bits
/// relative, not f64's 52: it is carried as an unevaluated sum `hi + lo` of two f32s
/// (double-f32), whose error-free steps need a fused multiply-add (hence FMA only; SSE2
/// keeps the f64 form and its own bits). With `x = 2^e m`, `m` in [2^-1/2, 2^1/2), and a
/// centre `c` of three (2^-1/3, 1, 2^1/3; `log2 c` split as a 16-bit head, so `e + head` is
/// exact, and an f32 tail), `t = (m - c) / (m + c)` has `|t| <= 0.058`, `ln(m / c) = 2 atanh
/// t = 2t + 2t^3 (1/3 + t^2/5 + t^4/7 + t^6/9)` (truncation 2^-40 relative), `t` itself as
/// `t + t_lo` from the exact residual `fma(-t, m + c, m - c)`, and `m + c`'s own rounding
/// recovered exactly. The centre 1 keeps the absolute error proportional to `t` near
/// `x = 1`, where large `y` need it. Then `y (hi + lo)` splits into an integer `k` and
/// `f` in about [-0.5, 0.5], and `2^f` is [`EXP2_C6`] by Horner ([`scaled_exp2_c6_at`]).
/// Measured over every normal f32 `x` in (0, 1] at y = 1, 2, 20, 200, 1234.5, 1e4, 99999,
/// 1e5: at most 0.74 f32 epsilons relative (1.44 with [`scale2`]'s degree-7 Estrin
/// polynomial, which cost three more multiply-pipe operations: `pow` 6-8% faster), against
/// 1.40 for the f64 form (`cargo run --release -p fastbrdf --example pow_ulp`;
/// `tests/batch/` checks 2 on a grid).
/// 0 for `x` below 2^-126 (subnormals as zero, as `log2_wide`), NaN for NaN or negative `x`.
///
/// `UNIT`: `x` is in [0, 1] and not NaN and `y >= 1` (`fma::pow_unit`). Then `x = 0` and
/// subnormal `x` have `log2 x <= -126`, so `y log2 x > -126` is the only test needed, and it
/// also keeps `k >= -126`, where the exponent addition of [`scale2`] gives a normal number.
#[inline(always)]
pub(crate) fn pow_fma<const UNIT: bool>(x: f32, y: f32) -> f32 {
    const MAGIC: f32 = 12_582_912.0; // 1.5 * 2^23
    // log2 e as f32 head and tail.
    const KH: f32 = std::f32::consts::LOG2_E;
    const KL: f32 = (std::f64::consts::LOG2_E - std::f32::consts::LOG2_E as f64) as f32;
    // The centres 2^(+-1/3) as f32, their log2 as a 16-bit head and an f32 tail, and the
    // interval edges 2^(+-1/6).
    const C_UP: f32 = 1.259_921_1;
    const C_DN: f32 = 0.793_700_5;
    const LC_HEAD: f32 = 0.333_328_25; // exactly 21845 / 65536
    const LC_TAIL_UP: f32 = 5.113_766e-6;
    const LC_TAIL_DN: f32 = -5.104_004e-6;
    const EDGE_UP: f32 = 1.122_462;
    const EDGE_DN: f32 = 0.890_898_7;
    let (e, m) = split(x);
    let e = e as f32;
    let up = m >= EDGE_UP;
    let dn = m < EDGE_DN;
    let c = if up {
        C_UP
    } else if dn {
        C_DN
    } else {
        1.0
    };
    let lc_head = if up {
        LC_HEAD
    } else if dn {
        -LC_HEAD
    } else {
        0.0
    };
    let lc_tail = if up {
        LC_TAIL_UP
    } else if dn {
        LC_TAIL_DN
    } else {
        0.0
    };
    // t + t_lo = (m - c) / (m + c): m - c and den - c are exact (Sterbenz), so den_lo is
    // den's rounding error; the residual of t * den is exact with a fused multiply-add.
    let num = m - c;
    let den = m + c;
    let den_lo = m - (den - c);
    let inv = 1.0 / den;
    let t = num * inv;
    let r = madd::<true>(-t, den_lo, madd::<true>(-t, den, num));
    let t_lo = r * inv;
    let t2 = t * t;
    let p = madd::<true>(
        t2 * t2,
        madd::<true>(t2, 1.0 / 9.0, 1.0 / 7.0),
        madd::<true>(t2, 1.0 / 5.0, 1.0 / 3.0),
    );
    // ln(m / c) = hi + lo; times log2 e in double-f32.
    let hi = 2.0 * t;
    let lo = 2.0 * madd::<true>(t * t2, p, t_lo * (1.0 + t2));
    let l_hi = hi * KH;
    let l_lo = madd::<true>(hi, KH, -l_hi) + madd::<true>(hi, KL, lo * KH);
    // + e + log2 c: |e + head| >= 1/3 > |l_hi| or e + head = 0, so Fast2Sum is exact.
    let se = e + lc_head;
    let s = se + l_hi;
    let l_lo = l_lo + ((se - s) + l_hi) + lc_tail;
    // y log2 x = p_hi + p_lo, split as k + f with k from their rounded sum.
    let p_hi = y * s;
    let p_lo = madd::<true>(y, s, -p_hi) + y * l_lo;
    // Below -126 the result is 0 (selected last), so the rounding trick, exact for
    // |pa| < 2^22, may give anything there: no clamp.
    let pa = p_hi + p_lo;
    let tk = pa + MAGIC;
    let (k, ki) = unmagic(tk);
    let v = scaled_exp2_c6_at::<true>((p_hi - k) + p_lo, ki, 1.0);
    if UNIT {
        return if pa > -126.0 { v } else { 0.0 };
    }
    let v = if pa >= -126.0 { v } else { 0.0 };
    let v = if x >= f32::MIN_POSITIVE { v } else { 0.0 };
    if x >= 0.0 { v } else { f32::NAN }
}

/// `acos(x)` for x in [0, 1].
#[inline(always)]
pub fn acos(x: f32) -> f32 {
    acos_g::<false>(x)
}

#[inline(always)]
#[allow(clippy::approx_constant)]
fn acos_g<const F: bool>(x: f32) -> f32 {
    const A: [f32; 8] = [
        1.570_796_3, // A&S's fitted 1.5707963050, one f32 ulp below pi/2 on purpose
        -0.214_598_8,
        0.088_978_99,
        -0.050_174_303,
        0.030_891_88,
        -0.017_088_126,
        0.006_670_09,
        -0.001_262_491_1,
    ];
    let p = estrin7::<F>(x, &A);
    let y = 1.0 - x;
    (if y > 0.0 { y } else { 0.0 }).sqrt() * p
}

/// `P(t) ~ (1 + 2a) erfcx(a)` at `t = (a - 2) / (a + 2)`, `a` in [0, 10] (`t` in [-1, 2/3]),
/// `erfcx(a) = exp(a^2) erfc(a)`: degree 9, fitted for the relative error by iteratively
/// reweighted least squares in f64 against `exp(a^2) erfc(a)` (4000 Chebyshev nodes), each
/// coefficient rounded to f32 in turn and the later ones refitted: 1.5e-8 relative after
/// rounding (the mapping and the factor `1 + 2a` are N. Juffa's; the coefficients are ours).
const ERFC_P: [f32; 10] = [
    1.276_978_4,
    -0.092_763_916,
    -0.166_030_93,
    0.164_054_56,
    -0.054_207_89,
    -0.008_057_79,
    0.008_641_981_5,
    0.001_314_43,
    -0.001_240_209_6,
    -0.000_405_941_4,
];

/// The complementary error function, branch-free: for `a = |x|` (clamped to 10, where
/// `erfc` is below f32's smallest subnormal), `erfc(a) = exp(-a^2) P(t) / (1 + 2a)` with
/// [`ERFC_P`], one polynomial over the whole half-line (no range split, so no branch to
/// turn into selects); `exp(-a^2)` as `exp(-s) (1 - d)` with `s = a^2` rounded and `d`
/// its exact residual (a fused multiply-add, else Dekker's split of `a` into 12-bit
/// halves), so the rounding of `a^2` (up to 5e-6 relative at `a = 9`) does not enter.
/// `x < 0` gives `2 - erfc(|x|)`; NaN gives NaN, `+inf` 0, `-inf` 2.
///
/// Accuracy against f64 (`tests/batch_smith.rs`, every f32 in [-10, 10] on a dense grid):
/// relative error <= 4 f32 epsilons (4.8e-7) where `erfc(x) >= 2^-126` (`x <= 9.1`), absolute
/// <= 2^-126 beyond (subnormal results; 0 from 9.34). Cost: 2 div, 10 fma (Horner), 5 mul
/// or fma, a vectorised `exp` of a non-positive argument; no libm call.
#[inline(always)]
pub fn erfc(x: f32) -> f32 {
    erfc_g::<false>(x)
}

#[inline(always)]
fn erfc_g<const F: bool>(x: f32) -> f32 {
    let ax = x.abs();
    // NaN and everything from 10 up to 10: t stays finite (no inf / inf).
    let a = if ax < 10.0 { ax } else { 10.0 };
    let t = (a - 2.0) / (a + 2.0);
    let mut p = ERFC_P[9];
    for &c in ERFC_P[..9].iter().rev() {
        p = madd::<F>(p, t, c);
    }
    let erfcx = p / madd::<F>(2.0, a, 1.0);
    let s = a * a;
    // d = a^2 - s exactly (|d| <= 2^-18 for a <= 10).
    let d = if F {
        a.mul_add(a, -s)
    } else {
        let hi = f32::from_bits(a.to_bits() & 0xffff_f000);
        let lo = a - hi;
        // hi^2 is exact (12 significant bits), hi^2 - s exact (Sterbenz); lo (a + hi) is
        // a^2 - hi^2 up to its own rounding (2^-24 of at most 0.05).
        (hi * hi - s) + lo * (a + hi)
    };
    let e = exp_nonpos_g::<F>(-s);
    let r = madd::<F>(-e, d, e) * erfcx;
    let r = if x < 0.0 { 2.0 - r } else { r };
    if x.is_nan() { x } else { r }
}
