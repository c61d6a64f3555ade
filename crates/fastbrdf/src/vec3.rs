//! Direction helpers in the local shading frame: normal = +z, `wi` and `wo` both point away
//! from the surface. Plain `[T; 3]` arrays keep every formula generic over `f32`/`f64`
//! (glam's types are concrete per precision; see ARCHITECTURE.md).

use crate::real::{Real, sqr};

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

/// The branch-free core of [`normalize`], shared with the batch kernels (`batch::ops`), so that
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
}

/// `2^-20` (about 9.5e-7, 89.99995 degrees), exactly representable in f32 and f64 so that
/// both precisions draw the line at the same input.
/// Cosines below this count as grazing: full BRDFs return 0 when `cos theta_i` or
/// `cos theta_o` is below it, and distributions return 0 when `cos theta_h` is below it.
/// It keeps `1 / (cos_i cos_o)` finite in f32 and removes the pole that the seed's
/// `beckmann-pow` has at `cos theta_h = 0` when `alpha > 1/sqrt(2)`.
pub const COS_MIN: f64 = 1.0 / 1_048_576.0;

impl<T: Real> Pair<T> {
    /// Normalises `wi` and `wo` and builds the half vector. `None` (the BRDF is 0) when either
    /// vector is zero or not finite, or lies below `COS_MIN` (back-facing or grazing).
    #[inline]
    pub fn new(wi: V3<T>, wo: V3<T>) -> Option<Self> {
        let wi = normalize(wi)?;
        let wo = normalize(wo)?;
        let cmin = T::c(COS_MIN);
        if !(wi[2] >= cmin && wo[2] >= cmin) {
            return None;
        }
        // For unit wi, wo: wi.h = wo.h = |wi + wo| / 2. Taking it from the length (rather than
        // a dot product) is cheaper and exactly symmetric in (wi, wo), so every BRDF built on
        // a Pair is reciprocal to the last bit.
        let s = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
        let len = dot(s, s).sqrt();
        if !(len > T::zero()) {
            return None;
        }
        let h = [s[0] / len, s[1] / len, s[2] / len];
        Some(Self {
            wi,
            wo,
            h,
            cos_i: wi[2],
            cos_o: wo[2],
            cos_h: h[2],
            sin2_h: sqr(h[0]) + sqr(h[1]),
            cos_ih: T::c(0.5) * len,
        })
    }
}
