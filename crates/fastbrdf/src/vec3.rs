//! Direction helpers in the local shading frame: normal = +z, `wi` and `wo` both point away
//! from the surface. Plain `[T; 3]` arrays keep every formula generic over `f32`/`f64`
//! (glam's types are concrete per precision; see ARCHITECTURE.md).

use crate::real::Real;

/// A 3-vector in the local shading frame.
pub type V3<T> = [T; 3];

/// Dot product.
#[inline(always)]
pub fn dot<T: Real>(a: V3<T>, b: V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Unit vector along `v`, or `None` when `v` is zero, infinite or has a NaN component.
/// Scale-safe: any finite non-zero `v` (tiny, huge or subnormal components) has a direction.
#[inline]
pub fn normalize<T: Real>(v: V3<T>) -> Option<V3<T>> {
    let (u, valid) = unit(v);
    if valid { Some(u) } else { None }
}

/// `2^-100` and `2^100`: between them `|v|^2` is computed without overflow or loss to
/// underflow, and `v` is normalised as it is.
const LEN2_LO: f64 = 7.888_609_052_210_118e-31;
const LEN2_HI: f64 = 1.267_650_600_228_229_4e30;

/// The branch-free core of [`normalize`], shared with the batch kernels (`batch`), so that
/// both round alike: `(unit vector, valid)`. When `|v|^2` lies outside
/// [`2^-100`, `2^100`] (where it would overflow, underflow or lose bits to subnormals), `v` is
/// first divided by its largest `|component|`; inside, the arithmetic is the plain
/// `v / sqrt(v.v)`. `valid` is false for zero, infinite and NaN vectors.
#[inline(always)]
pub fn unit<T: Real>(v: V3<T>) -> (V3<T>, bool) {
    let len2 = dot(v, v);
    let safe = len2 >= T::c(LEN2_LO) && len2 <= T::c(LEN2_HI);
    let m = v[0].abs().max(v[1].abs()).max(v[2].abs());
    let d = if safe { T::one() } else { m };
    let s = [v[0] / d, v[1] / d, v[2] / d];
    let l2 = dot(s, s);
    let inv = T::one() / l2.sqrt();
    let valid = m > T::zero() && m.is_finite() && l2.is_finite();
    ([s[0] * inv, s[1] * inv, s[2] * inv], valid)
}

/// Mirror direction of `w` about the normal: `2 (w.n) n - w`.
#[inline(always)]
pub fn reflect<T: Real>(w: V3<T>) -> V3<T> {
    [-w[0], -w[1], w[2]]
}

/// The geometry of one (wi, wo) pair that every full BRDF needs.
#[derive(Clone, Copy, Debug)]
pub struct Pair<T> {
    /// Unit incident direction.
    pub wi: V3<T>,
    /// Unit outgoing direction.
    pub wo: V3<T>,
    /// Unit half vector `normalize(wi + wo)`.
    pub h: V3<T>,
    /// `cos theta_i = wi.z`.
    pub cos_i: T,
    /// `cos theta_o = wo.z`.
    pub cos_o: T,
    /// `cos theta_h = h.z`.
    pub cos_h: T,
    /// `sin^2 theta_h = h.x^2 + h.y^2`, computed without cancellation near the peak.
    pub sin2_h: T,
    /// `wi.h = wo.h`.
    pub cos_ih: T,
    /// `reflect(wi).wo`, the cosine of the Phong lobe.
    pub cos_r: T,
    /// `cos_h` and `cos_r` before their rounding to `T`: lobe-based BRDFs decide their
    /// lobe's cut on these, so that f32 and f64 decide alike (a cosine within half an f32
    /// ulp below a cut rounds onto it).
    pub cos_h64: f64,
    pub cos_r64: f64,
}

/// `2^-20` (about 9.5e-7, 89.99995 degrees), exactly representable in f32 and f64 so that
/// both precisions draw the line at the same input.
/// Cosines below this count as grazing: full BRDFs return 0 when `cos theta_i` or
/// `cos theta_o` is below it, and distributions return 0 when `cos theta_h` is below it.
/// It keeps `1 / (cos_i cos_o)` finite in f32 and removes the pole that the seed's
/// `beckmann-pow` has at `cos theta_h = 0` when `alpha > 1/sqrt(2)`.
pub const COS_MIN: f64 = 1.0 / 1_048_576.0;

/// Whether the direction of `v` (any length) lies at or above [`COS_MIN`], decided as the
/// pair set-up decides ([`pair_setup`]): on `v` normalised in f64, which is the same
/// arithmetic for f32 and f64 models fed the same f32 input, so both fall on the same side
/// of the cut (rounding the normalised `z` in each precision put them on opposite sides,
/// where the BRDF jumps from its whole value to 0; issue 11). `false` for NaN, zero and
/// infinite vectors.
#[inline(always)]
pub fn above_cos_min<T: Real>(v: V3<T>) -> bool {
    let (u, valid) = unit64::<T, false>(v);
    valid && u[2] >= COS_MIN
}

/// `1 / sqrt(x)` for a positive normal f64 `x`, within 1.5 ulps of `1.0 / x.sqrt()`: a seed from the bits (the
/// exponent halved and negated, Lomont's constant for f64: within 3.5%) and four Newton steps
/// (the error squares each step: 3.5e-2, 1.8e-3, 4.9e-6, 3.6e-11, below f64's rounding).
/// Multiplications and additions only, the same bits on every instruction set and in the
/// scalar and batch code: a square root and a division per vector in f64 were most of the
/// pair set-up's time in the batch kernels (AVX-512 divides f64 at 8 lanes in 16 cycles, takes
/// square roots in 24). Not finite, zero, negative or subnormal `x`: a meaningless value (the
/// callers' validity flags cover them).
#[inline(always)]
pub fn rsqrt64(x: f64) -> f64 {
    let half = 0.5 * x;
    let mut y = f64::from_bits(0x5fe6_eb50_c7b5_37a9u64.wrapping_sub(x.to_bits() >> 1));
    for _ in 0..3 {
        y *= 1.5 - half * y * y;
    }
    // The last step as a correction to y: its rounding is the correction's, a fraction of an
    // ulp of y, where 1.5 - x y^2 / 2 rounds to an ulp of 1.5 (1.4 ulps at worst where four
    // plain steps reach 1.9).
    y + y * (0.5 - half * y * y)
}

/// `|v|^2 - 1` within which [`inv_len`] takes [`rsqrt_near_one`]: `2^-20`, exact in f32 and
/// f64. Unit vectors rounded to f32 (what renderers and numpy callers pass) lie within a few
/// `2^-24` of it.
pub const NEAR_ONE: f64 = 1.0 / 1_048_576.0;

/// `1 / sqrt(x)` for `x` within [`NEAR_ONE`] of 1: the series `1 - d/2 + 3 d^2 / 8` in
/// `d = x - 1` (exact by Sterbenz's lemma), truncated after a term of at most `0.32 d^3`
/// (`2.8e-19` relative, a 400th of an ulp), then one rounding in the final addition: within
/// 0.51 ulps of `1.0 / x.sqrt()`'s exact value (tested), where [`rsqrt64`] is within 1.5. Two
/// multiplications and two additions, where [`rsqrt64`] takes 13 and 6 in a chain of four
/// Newton steps: most of the f64 pair set-up's time in the batch kernels (issue 30).
#[inline(always)]
pub fn rsqrt_near_one(x: f64) -> f64 {
    let d = x - 1.0;
    1.0 + d * (-0.5 + 0.375 * d)
}

/// `1 / sqrt(len2)` for a positive normal `len2`: [`rsqrt_near_one`] within [`NEAR_ONE`] of 1,
/// [`rsqrt64`] elsewhere, a function of `len2` alone (the scalar code branches, the batch
/// loops select per lane). `NEAR`: the caller knows that `len2` is within [`NEAR_ONE`] of 1
/// (the batch kernels test whole blocks in f32 first), so only the series is
/// computed: the same value.
#[inline(always)]
pub fn inv_len<const NEAR: bool>(len2: f64) -> f64 {
    if NEAR || (len2 - 1.0).abs() <= NEAR_ONE {
        rsqrt_near_one(len2)
    } else {
        rsqrt64(len2)
    }
}

/// `v` in f64, normalised directly when `|v|^2` is a normal f64 (always, for f32
/// components, whose squares neither overflow nor underflow in f64: a compile-time choice,
/// so that the batch kernels carry no branch), scale-safely ([`unit`]) otherwise; `1/|v|` by
/// [`inv_len`] (`NEAR` as there). The same arithmetic for f32 and f64 models fed the same
/// f32 input.
#[inline(always)]
pub(crate) fn unit64<T: Real, const NEAR: bool>(v: V3<T>) -> (V3<f64>, bool) {
    let v = v.map(|c| c.f64());
    let len2 = dot(v, v);
    if std::mem::size_of::<T>() == 4 || (f64::MIN_POSITIVE..=f64::MAX).contains(&len2) {
        let inv = inv_len::<NEAR>(len2);
        (
            [v[0] * inv, v[1] * inv, v[2] * inv],
            len2 > 0.0 && len2.is_finite(),
        )
    } else {
        unit(v)
    }
}

/// The set-up of a [`Pair`] and whether it is valid, shared by the scalar models and the
/// batch kernels (so that both round alike). It is computed in f64 whatever `T` is, then
/// rounded once to `T`: in f32, normalising `wi` and `wo` separately and adding them loses
/// the half vector's x and y to cancellation for back-to-back pairs near grazing (errors of
/// 10^7 relative in narrow-lobe BRDFs, issue 11), and a cosine rounded differently in f32
/// and f64 can fall on opposite sides of a lobe's cut. Rounded from f64, every quantity is
/// within half an ulp of exact, and rounding is monotonic, so a comparison against a
/// threshold representable in `T` (a cut, `COS_MIN`) decides as in f64.
#[inline(always)]
pub fn pair_setup<T: Real>(wi: V3<T>, wo: V3<T>) -> (bool, Pair<T>) {
    pair_setup_as::<T, false>(wi, wo)
}

/// [`pair_setup`] for a caller that knows both `|wi|^2` and `|wo|^2` to be within
/// [`NEAR_ONE`] of 1 (`NEAR`; the batch kernels test whole blocks in f32 first): the
/// same values, without [`rsqrt64`] for the two directions (the half vector keeps it). A
/// length outside that range with `NEAR` gives a wrong value, unchecked: crate-private.
#[inline(always)]
pub(crate) fn pair_setup_as<T: Real, const NEAR: bool>(wi: V3<T>, wo: V3<T>) -> (bool, Pair<T>) {
    let (ui, vi) = unit64::<T, NEAR>(wi);
    let (uo, vo) = unit64::<T, NEAR>(wo);
    // The f64 unit vectors are the same for f32 and f64 models fed the same f32 input, so
    // this cut decides alike in both (as `above_cos_min` does for any input).
    let above = ui[2] >= COS_MIN && uo[2] >= COS_MIN;
    // For unit wi, wo: wi.h = wo.h = |wi + wo| / 2. Taking it from the length (rather than a
    // dot product) is cheaper and exactly symmetric in (wi, wo), so every BRDF built on a
    // Pair is reciprocal to the last bit.
    let s = [ui[0] + uo[0], ui[1] + uo[1], ui[2] + uo[2]];
    // |s|^2 is at least 2 COS_MIN^2 for valid pairs (both z >= COS_MIN): normal.
    let len2 = dot(s, s);
    let inv_len = rsqrt64(len2);
    let len = len2 * inv_len;
    let h = [s[0] * inv_len, s[1] * inv_len, s[2] * inv_len];
    let valid = above && vi && vo && len2 > 0.0;
    let cos_r = dot(reflect(ui), uo);
    let t = |x: f64| T::c(x);
    (
        valid,
        Pair {
            wi: ui.map(t),
            wo: uo.map(t),
            h: h.map(t),
            cos_i: t(ui[2]),
            cos_o: t(uo[2]),
            cos_h: t(h[2]),
            sin2_h: t(h[0] * h[0] + h[1] * h[1]),
            cos_ih: t(0.5 * len),
            cos_r: t(cos_r),
            cos_h64: h[2],
            cos_r64: cos_r,
        },
    )
}

impl<T: Real> Pair<T> {
    /// Whether a Phong (`blinn` false: the lobe of `reflect(wi).wo`) or Blinn-Phong (`blinn`:
    /// of `n.h`) lobe with cut `zero` is cut here. Decided on the f64 cosine, so f32 and f64
    /// models (and the batch kernels) cut at the same inputs; `zero = 0` means no cut.
    #[inline(always)]
    pub fn lobe_cut(&self, zero: f64, blinn: bool) -> bool {
        zero > 0.0 && (if blinn { self.cos_h64 } else { self.cos_r64 }) < zero
    }

    /// Normalises `wi` and `wo` and builds the half vector ([`pair_setup`], in f64). `None`
    /// (the BRDF is 0) when either vector is zero or not finite, or lies below `COS_MIN`
    /// (back-facing or grazing).
    #[inline]
    pub fn new(wi: V3<T>, wo: V3<T>) -> Option<Self> {
        let (valid, p) = pair_setup(wi, wo);
        if valid { Some(p) } else { None }
    }
}

#[cfg(test)]
mod rsqrt_tests {
    use super::rsqrt64;

    /// Within 1.5 ulps of `1.0 / x.sqrt()` (itself within an ulp of exact) over the whole
    /// normal range: every exponent, 2,000 mantissas each, and the extremes (measured: 1.38).
    #[test]
    fn rsqrt64_is_within_one_and_a_half_ulps_over_the_normal_range() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut worst = 0.0f64;
        let mut check = |x: f64| {
            let exact = 1.0 / x.sqrt();
            let err = ((rsqrt64(x) - exact) / exact).abs() / f64::EPSILON;
            worst = worst.max(err);
            assert!(
                err <= 1.5,
                "rsqrt64({x:e}) = {:e}, 1/sqrt {exact:e}",
                rsqrt64(x)
            );
        };
        for e in -1022i64..=1023 {
            for _ in 0..2000 {
                seed = seed
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let bits = (((e + 1023) as u64) << 52) | (seed >> 12);
                check(f64::from_bits(bits));
            }
        }
        for x in [
            f64::MIN_POSITIVE,
            f64::MAX,
            1.0,
            2.0,
            4.0,
            0.25,
            1.0 - f64::EPSILON,
        ] {
            check(x);
        }
        eprintln!("worst: {worst} ulps");
    }

    /// `rsqrt_near_one(x)`'s error in ulps of the result, from the exact residual
    /// `1 - x y^2` (error-free products by fused multiply-adds): `y = (1 - e/2 + ...) / sqrt(x)`.
    fn near_one_ulps(x: f64) -> f64 {
        let y = super::rsqrt_near_one(x);
        let (p, p_lo) = (y * y, y.mul_add(y, -(y * y)));
        let q = p * x;
        let q_lo = p.mul_add(x, -q) + p_lo * x;
        let e = (q - 1.0) + q_lo;
        let ulp = if y < 1.0 {
            f64::EPSILON / 2.0
        } else {
            f64::EPSILON
        };
        (0.5 * e * y).abs() / ulp
    }

    /// Within 0.51 ulps of exact over its whole range (`|x - 1| <= 2^-20`: random points, the
    /// ends and the neighbours of 1); `inv_len` takes it there, with or without `NEAR`, and
    /// `rsqrt64` just outside.
    #[test]
    fn the_series_near_one_is_within_half_an_ulp_and_taken_only_there() {
        use super::{NEAR_ONE, inv_len, rsqrt_near_one};
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut worst = 0.0f64;
        let mut xs = vec![
            1.0,
            1.0 + NEAR_ONE,
            1.0 - NEAR_ONE,
            1.0 + f64::EPSILON,
            1.0 - f64::EPSILON / 2.0,
        ];
        for _ in 0..1_000_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            xs.push(1.0 + NEAR_ONE * (2.0 * u - 1.0));
        }
        for x in xs {
            let err = near_one_ulps(x);
            worst = worst.max(err);
            assert!(err <= 0.51, "rsqrt_near_one({x:e}): {err} ulps");
            let y = rsqrt_near_one(x);
            assert_eq!(inv_len::<true>(x).to_bits(), y.to_bits(), "{x:e}");
            assert_eq!(inv_len::<false>(x).to_bits(), y.to_bits(), "{x:e}");
        }
        for x in [
            1.0 + NEAR_ONE + f64::EPSILON,
            1.0 - NEAR_ONE - f64::EPSILON / 2.0,
            2.0,
            0.25,
        ] {
            assert_eq!(inv_len::<false>(x).to_bits(), rsqrt64(x).to_bits(), "{x:e}");
        }
        eprintln!("worst: {worst} ulps");
    }

    /// `pair_setup_as::<_, true>` (the series for both directions) is `pair_setup` to the
    /// bit, f64 fields included, on inputs of unit length to within `NEAR_ONE` (its
    /// precondition: the pairs outside it are skipped): f32 unit vectors, f64 ones, and f64
    /// ones stretched to near the ends of the range.
    #[test]
    fn the_near_one_set_up_is_the_set_up() {
        use super::{NEAR_ONE, Pair, pair_setup, pair_setup_as};
        fn same<T: crate::Real>(a: (bool, Pair<T>), b: (bool, Pair<T>)) -> bool {
            let f = |p: &Pair<T>| {
                let mut v: Vec<f64> = [p.cos_i, p.cos_o, p.cos_h, p.sin2_h, p.cos_ih, p.cos_r]
                    .iter()
                    .chain(&p.wi)
                    .chain(&p.wo)
                    .chain(&p.h)
                    .map(|x| x.f64())
                    .collect();
                v.extend([p.cos_h64, p.cos_r64]);
                v.into_iter().map(f64::to_bits).collect::<Vec<_>>()
            };
            a.0 == b.0 && f(&a.1) == f(&b.1)
        }
        let near = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - 1.0).abs() <= NEAR_ONE;
        let pairs = crate::accuracy::direction_pairs(20_000, 5);
        let mut checked = [0usize; 2];
        for (k, (wi, wo)) in pairs.into_iter().enumerate() {
            let (a32, b32) = (wi.map(|x| x as f32), wo.map(|x| x as f32));
            if near(a32.map(f64::from)) && near(b32.map(f64::from)) {
                let (x, y) = (pair_setup(a32, b32), pair_setup_as::<f32, true>(a32, b32));
                assert!(same(x, y), "#{k} f32");
                checked[0] += 1;
            }
            let s = [
                1.0,
                (1.0 + 0.9 * NEAR_ONE).sqrt(),
                (1.0 - 0.9 * NEAR_ONE).sqrt(),
            ][k % 3];
            let (a, b) = (wi.map(|x| x * s), wo.map(|x| x * s));
            if near(a) && near(b) {
                assert!(
                    same(pair_setup(a, b), pair_setup_as::<f64, true>(a, b)),
                    "#{k} f64"
                );
                checked[1] += 1;
            }
        }
        assert!(
            checked.iter().all(|&c| c > 19_000),
            "{checked:?} of 20,000 checked"
        );
    }
}
