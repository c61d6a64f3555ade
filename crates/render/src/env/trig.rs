//! Branch-free f32 `atan2`, `acos` and `sin_cos` for the map's direction <-> position
//! conversions ([`super::dir_to_uv`], [`super::uv_to_dir`]) and the cosine directions.
//!
//! Why not libm's: glibc's `atanf`, `atan2f`, `acosf` and `sincosf` were 10% of an
//! environment render (every sample converts three directions), they are out-of-line calls
//! with branches on the argument's range, and none of them vectorises. These are Cephes'
//! polynomials (Moshier) after a branch-free range reduction: the largest error over the
//! whole domain is a few 1e-7 rad (the unit tests bound it against f64), against a texel of
//! 6e-3 rad on the built-in sky's 1024 x 512 map; a texel choice may flip where a direction
//! lies within that error of a texel's edge, which moves no expectation.

use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// tan(pi / 8): above it, atan's argument is reduced by `atan(a) = pi/4 + atan((a-1)/(a+1))`.
const TAN_PI_8: f32 = 0.414_213_57;

/// atan(t) for |t| <= tan(pi / 8) (Cephes `atanf`'s polynomial).
#[inline(always)]
fn atan_small(t: f32) -> f32 {
    let z = t * t;
    let p = ((8.053_744_5e-2 * z - 1.387_768_6e-1) * z + 1.997_771_1e-1) * z - 3.333_295e-1;
    p * z * t + t
}

/// `y.atan2(x)`: the angle of (x, y) in [-pi, pi], signed zeros as `f32::atan2` treats them
/// (atan2(+-0, -0) = +-pi). Absolute error at most a few 1e-7.
#[inline(always)]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    let a = if hi > 0.0 { lo / hi } else { 0.0 };
    let big = a > TAN_PI_8;
    let t = if big { (a - 1.0) / (a + 1.0) } else { a };
    let p = atan_small(t);
    let mut r = if big { FRAC_PI_4 + p } else { p };
    if ay > ax {
        r = FRAC_PI_2 - r;
    }
    if x.is_sign_negative() {
        r = PI - r;
    }
    r.copysign(y)
}

/// asin(s) for 0 <= s <= 1/2, `z` = s^2 (Cephes `asinf`'s polynomial).
#[inline(always)]
fn asin_small(s: f32, z: f32) -> f32 {
    let p = (((4.216_32e-2 * z + 2.418_131e-2) * z + 4.547_002_6e-2) * z + 7.495_300_3e-2) * z
        + 1.666_675_2e-1;
    p * z * s + s
}

/// `x.clamp(-1, 1).acos()` in [0, pi]. Absolute error at most a few 1e-7.
#[inline(always)]
pub fn acos(x: f32) -> f32 {
    let x = x.clamp(-1.0, 1.0);
    let a = x.abs();
    // Above 1/2: acos(a) = 2 asin(sqrt((1 - a) / 2)); below: pi/2 - asin(a).
    let big = a > 0.5;
    let z = if big { 0.5 * (1.0 - a) } else { a * a };
    let s = if big { z.sqrt() } else { a };
    let p = asin_small(s, z);
    let r = if big { 2.0 * p } else { FRAC_PI_2 - p };
    if x < 0.0 { PI - r } else { r }
}

/// `(x.sin(), x.cos())` for |x| up to a few pi (the renderer's angles lie in [-2 pi, 2 pi]):
/// reduced to [-pi/4, pi/4] by the nearest multiple of pi/2 (pi/2 split in three parts, so
/// that the reduction is exact to f32), then Cephes' `sinf` and `cosf` polynomials.
#[inline(always)]
pub fn sin_cos(x: f32) -> (f32, f32) {
    const DP1: f32 = 1.570_312_5;
    const DP2: f32 = 4.837_513e-4;
    const DP3: f32 = 7.549_79e-8;
    // The nearest multiple (halves away from zero), without `f32::round`: a libm call
    // where the target lacks SSE4.1's rounding instruction.
    let t = x * (2.0 / PI);
    let j = (t + 0.5f32.copysign(t)) as i32 as f32;
    let r = ((x - j * DP1) - j * DP2) - j * DP3;
    let z = r * r;
    let s = ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1) * z * r + r;
    let c = ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2) * z * z - 0.5 * z + 1.0;
    let q = (j as i32) & 3;
    let (s, c) = if q & 1 == 1 { (c, -s) } else { (s, c) };
    if q & 2 == 2 { (-s, -c) } else { (s, c) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over a dense grid of the whole domain (every quadrant, both signs of zero, the axes),
    /// each function's largest absolute error against f64's: a few 1e-7 rad.
    #[test]
    fn the_fast_functions_are_within_a_few_1e7_of_f64() {
        let n = 1_000_000;
        let mut worst = [0.0f64; 4];
        for i in 0..=n {
            let t = -1.0 + 2.0 * i as f64 / n as f64;
            let x = t as f32;
            let e = (acos(x) as f64 - (x as f64).acos()).abs();
            worst[0] = worst[0].max(e);
            // An angle around the circle, and its direction as f32.
            let ang = std::f64::consts::PI * t * 1.0001;
            let (y, xx) = (ang.sin() as f32, ang.cos() as f32);
            let e = (atan2(y, xx) as f64 - (y as f64).atan2(xx as f64)).abs();
            worst[1] = worst[1].max(e);
            // Scaled: the ratio, not the length, matters.
            let e = (atan2(3.0 * y, 3.0 * xx) as f64 - (y as f64).atan2(xx as f64)).abs();
            worst[1] = worst[1].max(e);
            let a = (2.0 * std::f64::consts::PI * t) as f32;
            let (s, c) = sin_cos(a);
            worst[2] = worst[2].max((s as f64 - (a as f64).sin()).abs());
            worst[3] = worst[3].max((c as f64 - (a as f64).cos()).abs());
        }
        eprintln!("largest errors: acos, atan2, sin, cos {worst:?}");
        assert!(worst[0] <= 4e-7, "acos {}", worst[0]);
        assert!(worst[1] <= 4e-7, "atan2 {}", worst[1]);
        assert!(worst[2] <= 2e-7 && worst[3] <= 2e-7, "sin_cos {worst:?}");
        for (y, x) in [
            (0.0f32, 0.0f32),
            (-0.0, 0.0),
            (0.0, -0.0),
            (-0.0, -0.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 1.0),
            (0.0, -1.0),
            (1.0, 1.0),
            (-1.0, -1.0),
        ] {
            let (a, b) = (atan2(y, x), y.atan2(x));
            assert!((a - b).abs() <= 2.5e-7, "atan2({y}, {x}) = {a}, not {b}");
        }
        assert_eq!(acos(1.0), 0.0);
        assert!((acos(-1.0) - PI).abs() <= 2.5e-7);
        assert!((acos(1.5) - 0.0).abs() == 0.0 && (acos(-1.5) - PI).abs() <= 2.5e-7);
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
    }
}
