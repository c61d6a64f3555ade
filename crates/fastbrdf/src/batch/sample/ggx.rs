//! The SIMD path of Cook-Torrance with GGX (isotropic or anisotropic) and its default
//! strategy, visible-normal sampling (Heitz 2018): `Micro::sample_vndf` / `pdf_vndf` and the
//! steps of `Brdf::<f32>::sample` / `pdf` around them, written branch-free over f32 lanes and
//! compiled inside `#[target_feature]` loops (AVX-512, AVX2+FMA, SSE2) as the eval kernels
//! are (`batch`'s header), so that LLVM vectorises them.
//!
//! Three tiers, tried per block of [`SUB`] elements, each element's value depending on its own
//! inputs alone (where a tier is unsure of one element, the block is redone on the next tier
//! and the earlier tier's values put back where it was sure):
//!
//! 1. **The unit tier** (issue 30), for inputs of squared length within [`NEAR`] of 1 (what
//!    renderers and numpy callers pass): closed forms, no normalisation (one Newton step from
//!    1, [`near_unit`]). `pdf` is `k |h|^4 / (2 H^2 (wo.z + sqrt(A)))` on the unnormalised
//!    half vector (one square root and one division; the scalar steps take three and ten;
//!    its sums of products fused on the FMA instruction sets, which give the same bits as
//!    each other, and the horizon decided on the smaller cosine: on one AVX-512 thread
//!    1.78-1.80 to 1.51-1.72 ns a density over `direction_pairs`, some of whose blocks take
//!    the exact tiers, `examples/eval_speed.rs`);
//!    `sample` draws as the fast steps do up to the microfacet normal, reflects without
//!    renormalising `wi`, takes the density at that normal and, where the model has it in
//!    closed form (no Fresnel term, no energy compensation, `smith-ggx` or
//!    `smith-ggx-correlated`: `Vndf::weight`), the weight `4 k G2 / G1(wo)` in place of the
//!    eval kernel's `f cos_i / pdf`. Values: not the scalar model's bits; `pdf` within
//!    `1e-6 (1 + 1 / (alpha |wo + wi|))` relative of the scalar model's (the half vector's
//!    direction, rounded differently, moves `D` by up to about `2 / alpha` times its angle),
//!    the weight within 1e-5 of the f64 model's beyond the scalar sampler's own error (it is
//!    in fact about 40x closer to f64 than the scalar `f cos_i / pdf`: its `D` cancels), both
//!    tested (`tests/batch_sample_unit.rs`, 5e-7 and 6e-7 measured). Unsure (next tier) where
//!    an input is not near unit length, a cosine is within the margin of `COS_MIN` (for `pdf`,
//!    the smaller of the two), the pair is nearly opposite, `wo.h` or `h.z` is below 1e-3, or
//!    `wi.z` is within 1e-5 of 0.
//! 2. **The fast steps**: the scalar steps with `vec3::unit` as its direct `v / |v|`
//!    ([`unit_direct`], what it computes where `|v|^2` is in its direct range) and the f64
//!    horizon test `above_cos_min` as an f32 comparison ([`horizon`], the f64 answer away from
//!    `COS_MIN` by more than its margin): the exact steps' values bit for bit where sure.
//! 3. **The exact steps**: the same operations in the same order as the scalar code (IEEE
//!    `+ - * / sqrt`, the f64 domain cuts of `vec3::above_cos_min`, the normalisation of
//!    `vec3::unit`), except for the azimuth's `sin_cos(2 pi u1)`, which is [`sincos_2pi`]
//!    here (libm there). Hence, on tiers 2 and 3:
//!    - `pdf` (a density of given directions) is the scalar one bit for bit;
//!    - `sample`'s `wi` is the scalar one up to the propagation of `sincos_2pi`'s error (and
//!      of the scalar's own rounding of `2 pi u1` before its `sin_cos`): the tests bound it;
//!    - its `pdf` is the scalar density at its `wi` bit for bit, and its weight is
//!      `f cos_i / pdf` with `f` from the SIMD eval kernel (`Kernel`), whose values differ
//!      from the scalar model's by the fast elementary functions' few ulp.

use crate::math::{Fast, FastFma, Math};
use crate::vec3::{COS_MIN, V3, above_cos_min, unit};

/// `sin(2 pi u)` and `cos(2 pi u)` for `u` in [0, 1] (the unit interval of turns), branch-free
/// and vectorisable: the quarter turn nearest `u` is taken exactly (`u - q/4` is exact in f32
/// by Sterbenz's lemma), the rest, within an eighth of a turn, goes through Cephes' `sinf` /
/// `cosf` polynomials (degree 7 and 8 on [-pi/4, pi/4]), and the quadrant swaps and negates
/// them. Accuracy: within 1.2e-7 of the exact values (absolute; tested against f64 on 2^20
/// points of [0, 1] and the quarter turns, which are exact). Outside [0, 1] the quadrant
/// arithmetic does not hold: callers clamp first (`sample::unit_interval`).
#[inline(always)]
pub fn sincos_2pi(u: f32) -> (f32, f32) {
    let q = (u * 4.0 + 0.5) as i32;
    let r = u - q as f32 * 0.25;
    let x = r * std::f32::consts::TAU;
    let z = x * x;
    let s = x + x * z * ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1);
    let c = 1.0 - 0.5 * z + z * z * ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2);
    let swap = q & 1 != 0;
    let (s, c) = if swap { (c, s) } else { (s, c) };
    let s = if q & 2 != 0 { -s } else { s };
    let c = if (q + 1) & 2 != 0 { -c } else { c };
    (s, c)
}

/// The constants of one GGX visible-normal sampler (`Micro` with kind GGX).
#[derive(Clone, Copy, Debug)]
pub struct Vndf {
    /// The slopes along x and y, rounded to f32 as the scalar's `T::c(ax)`.
    pub ax: f32,
    pub ay: f32,
    /// `1 / (pi ax ay)` (in f64, then rounded, as `Micro::d`).
    pub k: f32,
    /// `1 / ax^2`, `1 / ay^2` (the unit tier's `D`).
    iax2: f32,
    iay2: f32,
    /// The unit tier's weight `F G2 / G1` where the model's terms give it in closed form
    /// ([`Weight`]), else `None` (the weight comes from the eval kernel).
    pub weight: Option<Weight>,
}

/// The unit tier's closed-form weight of a Cook-Torrance with GGX, no Fresnel term and no
/// energy compensation: `f cos_i / pdf = 4 k G2(wo, wi) / G1(wo)` (Heitz 2018, sec. 3), `k`
/// the model's denominator constant (1/4 for microfacet theory's `4 cos_i cos_o`).
#[derive(Clone, Copy, Debug)]
pub struct Weight {
    /// `4 k`.
    pub scale: f32,
    /// `smith-ggx-correlated` (`G2 = 2 / (S(o) + S(i))`), else `smith-ggx` (`G1(o) G1(i)`).
    pub correlated: bool,
}

impl Vndf {
    pub fn new(m: &crate::sample::Micro) -> Self {
        Self {
            ax: m.ax as f32,
            ay: m.ay as f32,
            k: (1.0 / (std::f64::consts::PI * m.ax * m.ay)) as f32,
            iax2: (1.0 / (m.ax * m.ax)) as f32,
            iay2: (1.0 / (m.ay * m.ay)) as f32,
            weight: None,
        }
    }

    /// `Micro::pdf_vndf(wo, h) / (4 wo.h)` of the unit `wo`, `wi` (`CookTorrance::pdf_wi`
    /// with `sample::half`), 0 where the scalar code returns 0; not yet checked for being
    /// positive and finite. With `FAST` ([`unit_of`]) the flag says whether the value is
    /// the exact path's (the half vector's length in the direct range), else it is true.
    #[inline(always)]
    fn pdf_unit<const FAST: bool>(&self, wo: V3<f32>, wi: V3<f32>) -> (f32, bool) {
        let (ax, ay) = (self.ax, self.ay);
        // sample::half.
        let (h, hv) = unit_of::<FAST>([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
        let d = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2];
        let ok = hv && h[2] > 0.0 && d > 0.0 && wo[2] > 0.0;
        // Micro::g1 (GGX lambda).
        let a2t2 = ((wo[0] * ax) * (wo[0] * ax) + (wo[1] * ay) * (wo[1] * ay)) / (wo[2] * wo[2]);
        let lambda = ((1.0 + a2t2).sqrt() - 1.0) * 0.5;
        let g1 = 1.0 / (1.0 + lambda);
        // Micro::d.
        let q = ((h[0] / ax) * (h[0] / ax) + (h[1] / ay) * (h[1] / ay)) / (h[2] * h[2]);
        let c2 = h[2] * h[2];
        let t = c2 * (1.0 + q);
        let dh = self.k / (t * t);
        let ph = g1 * d * dh / wo[2];
        let p = ph / (4.0 * d);
        (if ok { p } else { 0.0 }, hv || !FAST)
    }

    /// `Brdf::<f32>::pdf(wo, wi, Vndf)` (raw directions).
    #[inline(always)]
    pub fn pdf(&self, wo: V3<f32>, wi: V3<f32>) -> f32 {
        let valid = above_cos_min(wo) && above_cos_min(wi);
        let (wo, vo) = unit(wo);
        let (wi, vi) = unit(wi);
        let (p, _) = self.pdf_unit::<false>(wo, wi);
        if valid && vo && vi && p > 0.0 && p.is_finite() {
            p
        } else {
            0.0
        }
    }

    /// [`Self::pdf`] without its f64 horizon checks and scale-safe normalisations
    /// ([`unit_direct`], [`horizon`]): `(value, sure)`, the value [`Self::pdf`]'s bit for bit
    /// where `sure`.
    #[inline(always)]
    fn pdf_fast(&self, wo: V3<f32>, wi: V3<f32>) -> (f32, bool) {
        let (wo, so) = unit_direct(wo);
        let (wi, si) = unit_direct(wi);
        let ((ao, co), (ai, ci)) = (horizon(wo[2]), horizon(wi[2]));
        let valid = ao && ai;
        let (p, sh) = self.pdf_unit::<true>(wo, wi);
        let p = if valid && p > 0.0 && p.is_finite() {
            p
        } else {
            0.0
        };
        (p, so && si && co && ci && (sh || !valid))
    }

    /// The unit tier of [`Self::pdf`] (module header): `(value, sure)`. Both inputs of
    /// squared length within [`NEAR`] of 1 are normalised by [`near_unit`]'s one Newton step
    /// (no square root, no division), and the density is the closed form of
    /// `G1(wo) D(h) / (4 wo.z)` on the unnormalised half vector `h = wo + wi`:
    /// `k |h|^4 / (2 H^2 (wo.z + sqrt(A)))`, `H = h_x^2 / ax^2 + h_y^2 / ay^2 + h_z^2`,
    /// `A = wo.z^2 + (ax wo.x)^2 + (ay wo.y)^2` (one square root, one division; the scalar
    /// steps take three and ten), its sums of products fused where `M` fuses. Not sure (the
    /// caller takes the exact tiers) where an input is not near unit length, the smaller
    /// cosine is within the margin of `COS_MIN` ([`horizon`]; below it, the pair is 0 whatever
    /// the other), the pair is nearly opposite (`|h|^2 < 1e-4`) or the value is outside
    /// [1e-30, 1e30].
    #[inline(always)]
    fn pdf_unit_tier<M: Math<f32>>(&self, wo: V3<f32>, wi: V3<f32>) -> (f32, bool) {
        let (o, no) = near_unit::<M>(wo);
        let (i, ni) = near_unit::<M>(wi);
        // The smaller cosine decides: both above `COS_MIN` (and clear of its margin), or one
        // surely below. (A NaN here is not near unit length: not sure either way.)
        let (valid, clear) = horizon(if o[2] < i[2] { o[2] } else { i[2] });
        let h = [o[0] + i[0], o[1] + i[1], o[2] + i[2]];
        let l = sum_sq::<M>(h);
        let hh = M::madd(
            h[2],
            h[2],
            M::madd(h[1] * self.iay2, h[1], h[0] * self.iax2 * h[0]),
        );
        let so = sum_sq::<M>([self.ax * o[0], self.ay * o[1], o[2]]).sqrt();
        let p = self.k * (l * l) / (2.0 * (hh * hh) * (o[2] + so));
        let fine = l >= L_MIN && (P_MIN..=P_MAX).contains(&p);
        (
            if valid { p } else { 0.0 },
            no && ni && clear && (fine || !valid),
        )
    }

    /// `sqrt(w.z^2 + (ax w.x)^2 + (ay w.y)^2)`: GGX's `S(w) = sqrt(1 + a^2 tan^2)` times
    /// `w.z`, for `w` of any length (`1 + Lambda = (1 + S) / 2`).
    #[inline(always)]
    fn s_num(&self, w: V3<f32>) -> f32 {
        let (x, y) = (self.ax * w[0], self.ay * w[1]);
        (w[2] * w[2] + x * x + y * y).sqrt()
    }

    /// The unit tier of `sample` (module header): `(wo normalised, wi, pdf, weight, sure)`,
    /// zeros for no sample; the weight is NaN where [`Self::weight`] is `None` (the caller
    /// takes it from the eval kernel). `wo` near unit length is normalised by [`near_unit`];
    /// the draw is the fast steps' ([`Self::sample_as`]) up to the microfacet normal `h`; `wi`,
    /// reflected about `h`, is unit to a few ulp and not renormalised; the density is
    /// `G1(wo) D(h) / (4 wo.z)` at that `h` (`D` from the stretched normal before its
    /// normalisation: `k |n_s|^4 / |n|^4`, no square root) and the weight
    /// `4 k G2 / G1(wo)`. Not sure where `wo` is not near unit length or its cosine near
    /// `COS_MIN`, `wi.z` is within 1e-5 of 0 (its absolute error, a few 1e-7, decides the
    /// horizon there), `wo.h` or `h.z` is below 1e-3 (the scalar sampler's `h`, recomputed
    /// from `wi`, is ill-conditioned there) or the density is outside [1e-30, 1e30].
    #[inline(always)]
    fn sample_unit_tier(&self, wo: V3<f32>, u: [f32; 2]) -> ([V3<f32>; 2], [f32; 2], bool) {
        let (ax, ay) = (self.ax, self.ay);
        let (wo, no) = near_unit::<Fast>(wo);
        let (valid_o, co) = horizon(wo[2]);
        let mut sure = no && co;
        // `Micro::sample_vndf`: the stretched view direction (its length is `s(wo)`,
        // [`Self::s_num`], reused below), the normal drawn about it.
        let v = [ax * wo[0], ay * wo[1], wo[2]];
        let lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        let so = lv.sqrt();
        let inv = 1.0 / so;
        sure &= (LEN2_LO..=LEN2_HI).contains(&lv);
        let vh = [v[0] * inv, v[1] * inv, v[2] * inv];
        let nh = sample_disk(vh, u.map(crate::sample::unit_interval));
        // The unstretched normal `hs` (not normalised: `h = hs / |hs|`) and `wi` reflected
        // about it, `2 (wo.hs) hs / |hs|^2 - wo`: no square root.
        let hs = [ax * nh[0], ay * nh[1], nh[2].max(0.0)];
        let len2 = hs[0] * hs[0] + hs[1] * hs[1] + hs[2] * hs[2];
        sure &= (LEN2_LO..=LEN2_HI).contains(&len2);
        let dh = wo[0] * hs[0] + wo[1] * hs[1] + wo[2] * hs[2];
        let k = (dh + dh) / len2;
        let wi = [k * hs[0] - wo[0], k * hs[1] - wo[1], k * hs[2] - wo[2]];
        let above = wi[2] >= COS_MIN as f32;
        sure &= wi[2] >= WIZ_BAND || wi[2] < -WIZ_BAND;
        // `wo.h >= GEOM_MIN` and `h.z >= GEOM_MIN`, squared (both sides positive).
        let g2 = GEOM_MIN * GEOM_MIN * len2;
        let fine = dh > 0.0 && dh * dh >= g2 && hs[2] * hs[2] >= g2;
        // The density `G1(wo) D(h) / (4 wo.z) = D(h) / (2 (wo.z + s(wo)))`, `D(h) = k_D
        // |hs|^4 / |n|^4`, and the weight `4 k G2 / G1(wo)` with `G1(w) = 2 w.z / (w.z +
        // s(w))`: for the correlated term `G2 = 2 w_o.z w_i.z / (w_i.z s(wo) + w_o.z s(wi))`,
        // for the separable one `G1(wo) G1(wi)`: both `wi.z (wo.z + t) / (wi.z t + wo.z
        // s(wi))`, `t = s(wo)` or `wo.z` (a loop-invariant select); NaN without a closed
        // form. One division for the two.
        let (scale, correlated) = match self.weight {
            Some(w) => (w.scale, w.correlated),
            None => (f32::NAN, false),
        };
        let t = if correlated { so } else { wo[2] };
        let si = self.s_num(wi);
        let n2 = nh[0] * nh[0] + nh[1] * nh[1] + hs[2] * hs[2];
        let (pn, pd) = (self.k * (len2 * len2), (n2 * n2) * (2.0 * (wo[2] + so)));
        let (wn, wd) = (scale * wi[2] * (wo[2] + t), wi[2] * t + wo[2] * si);
        let r = 1.0 / (pd * wd);
        let (p, w) = (pn * wd * r, wn * pd * r);
        let ok = valid_o && above && dh > 0.0 && hs[2] > 0.0 && p > 0.0 && p.is_finite();
        sure &= (fine && (P_MIN..=P_MAX).contains(&p)) || !(valid_o && above);
        (
            [wo, if ok { wi } else { [0.0; 3] }],
            [if ok { p } else { 0.0 }, if ok { w } else { 0.0 }],
            sure,
        )
    }

    /// `Brdf::<f32>::sample(wo, u, Vndf)` up to the weight: `(wo normalised, wi, pdf, sure)`,
    /// with `wi = 0` and `pdf = 0` for no sample. With `FAST` as [`Self::pdf_fast`]: `sure`
    /// says whether the others are the exact path's bit for bit (always true without it).
    #[inline(always)]
    fn sample_as<const FAST: bool>(
        &self,
        wo: V3<f32>,
        u: [f32; 2],
    ) -> (V3<f32>, V3<f32>, f32, bool) {
        let (ax, ay) = (self.ax, self.ay);
        let (valid_o, wo, vo, mut sure) = if FAST {
            let (wo, so) = unit_direct(wo);
            let (above, clear) = horizon(wo[2]);
            (above, wo, true, so && clear)
        } else {
            let valid_o = above_cos_min(wo);
            let (wo, vo) = unit(wo);
            (valid_o, wo, vo, true)
        };
        let u = u.map(crate::sample::unit_interval);
        // Micro::sample_vndf, GGX.
        let (vh, ok) = unit_of::<FAST>([ax * wo[0], ay * wo[1], wo[2]]);
        sure &= ok || !FAST;
        let vh = if ok { vh } else { [0.0, 0.0, 1.0] };
        let nh = sample_disk(vh, u);
        let (h, ok) = unit_of::<FAST>([ax * nh[0], ay * nh[1], nh[2].max(0.0)]);
        sure &= ok || !FAST;
        let h = if ok { h } else { [0.0, 0.0, 1.0] };
        // sample::reflect_about.
        let d = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2];
        let k = d + d;
        let wi = [k * h[0] - wo[0], k * h[1] - wo[1], k * h[2] - wo[2]];
        // Brdf::sample: normalise, the horizon, the density.
        let (wi, vi) = unit_of::<FAST>(wi);
        let above = if FAST {
            // `wi` is unit to an ulp or two: its f64 renormalisation moves its z by less
            // than `horizon`'s margin.
            let (above, clear) = horizon(wi[2]);
            sure &= vi && clear;
            above
        } else {
            above_cos_min(wi)
        };
        let vi = vi || FAST;
        let (p, sh) = self.pdf_unit::<FAST>(wo, wi);
        sure &= sh;
        let ok = valid_o && vo && d > 0.0 && vi && above && p > 0.0 && p.is_finite();
        (
            wo,
            if ok { wi } else { [0.0; 3] },
            if ok { p } else { 0.0 },
            sure,
        )
    }
}

/// `Micro::sample_vndf`'s normal in the stretched space: the point `u` of the unit disk
/// projected onto the hemisphere about the unit stretched view direction `vh` (its half
/// disk warped by `vh.z`), in the scalar code's operations (`sincos_2pi` for the azimuth).
#[inline(always)]
fn sample_disk(vh: V3<f32>, u: [f32; 2]) -> V3<f32> {
    let lensq = vh[0] * vh[0] + vh[1] * vh[1];
    let inv = 1.0 / lensq.sqrt();
    let t1 = if lensq > 0.0 {
        [-vh[1] * inv, vh[0] * inv, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let t2 = [
        vh[1] * t1[2] - vh[2] * t1[1],
        vh[2] * t1[0] - vh[0] * t1[2],
        vh[0] * t1[1] - vh[1] * t1[0],
    ];
    let r = u[0].sqrt();
    let (sp, cp) = sincos_2pi(u[1]);
    let p1 = r * cp;
    let p2 = r * sp;
    let s = 0.5 * (1.0 + vh[2]);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
    let pz = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    [
        p1 * t1[0] + p2 * t2[0] + pz * vh[0],
        p1 * t1[1] + p2 * t2[1] + pz * vh[1],
        p1 * t1[2] + p2 * t2[2] + pz * vh[2],
    ]
}

/// The unit tier's range of `|v|^2 - 1` ([`near_unit`]): there one Newton step from 1
/// gives `1 / |v|` within `3 e^2 / 8 < 2.3e-8` (relative), under half an ulp.
pub const NEAR: f32 = 1.0 / 4096.0;
/// The unit tier's smallest `|wo + wi|^2` (pdf): nearer to opposite, the half vector's
/// direction is too ill-conditioned for its value to track the scalar one.
const L_MIN: f32 = 1e-4;
/// The unit tier's range of densities (the scalar model's, within ulps, is then positive and
/// finite too).
const P_MIN: f32 = 1e-30;
const P_MAX: f32 = 1e30;
/// `sample`'s unit tier: `wi.z` within this of 0 is decided by the exact tiers.
const WIZ_BAND: f32 = 1e-5;
/// `sample`'s unit tier: the smallest `wo.h` and `h.z` it decides.
const GEOM_MIN: f32 = 1e-3;

/// `v` of squared length `l` near 1 divided by its length as one Newton step from 1,
/// `v (3 - l) / 2` (exact to `3 (l - 1)^2 / 8`), and whether `|l - 1| <= NEAR` (where it is
/// below half an ulp: the unit tier's inputs). NaN: not near.
#[inline(always)]
fn near_unit<M: Math<f32>>(v: V3<f32>) -> (V3<f32>, bool) {
    let l = sum_sq::<M>(v);
    let s = M::madd(-0.5, l, 1.5);
    ([v[0] * s, v[1] * s, v[2] * s], (l - 1.0).abs() <= NEAR)
}

/// `v.x^2 + v.y^2 + v.z^2`, fused where `M` fuses; unfused (`Fast`), the plain sum's
/// order and bits (`sample`'s unit tier keeps them).
#[inline(always)]
fn sum_sq<M: Math<f32>>(v: V3<f32>) -> f32 {
    M::madd(v[2], v[2], M::madd(v[1], v[1], v[0] * v[0]))
}

/// `vec3::unit`'s range of `|v|^2` normalised directly (its `LEN2_LO`, `LEN2_HI`: 2^-100,
/// 2^100, exact in f32).
const LEN2_LO: f32 = 7.888_609_052_210_118e-31_f64 as f32;
const LEN2_HI: f32 = 1.267_650_600_228_229_4e30_f64 as f32;

/// `v / |v|` as `vec3::unit` computes it where `|v|^2` is in its direct range (there its
/// divisions by 1 change nothing and its validity flag is true), and whether it is: where
/// it is not (zero, tiny, huge, infinite or NaN components) the caller takes the exact path.
#[inline(always)]
fn unit_direct(v: V3<f32>) -> (V3<f32>, bool) {
    let len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let safe = (LEN2_LO..=LEN2_HI).contains(&len2);
    let inv = 1.0 / len2.sqrt();
    ([v[0] * inv, v[1] * inv, v[2] * inv], safe)
}

/// [`unit_direct`] with `FAST` (its flag: direct), else `vec3::unit` (its flag: valid).
#[inline(always)]
fn unit_of<const FAST: bool>(v: V3<f32>) -> (V3<f32>, bool) {
    if FAST { unit_direct(v) } else { unit(v) }
}

/// `vec3::above_cos_min` of a vector whose f32 unit z is `c` (from [`unit_direct`], or of
/// a unit vector): `(above, sure)`. The f64 cosine of `above_cos_min` and `c` differ by a
/// few f32 ulp (relative, about 3e-7 at most); away from `COS_MIN` by more than 1e-5
/// (relative) the answer is the f64 one, else `sure` is false.
#[inline(always)]
#[allow(clippy::manual_range_contains)] // NaN: not sure (`!contains` would say sure)
fn horizon(c: f32) -> (bool, bool) {
    const M: f32 = COS_MIN as f32;
    const HI: f32 = (COS_MIN * (1.0 + 1e-5)) as f32;
    const LO: f32 = (COS_MIN * (1.0 - 1e-5)) as f32;
    (c >= M, c >= HI || c < LO)
}

// ---------- the loops, compiled per instruction set ----------

/// Slices of one block, all of the same length.
pub struct SampleBlock<'a> {
    pub wo: [&'a [f32]; 3],
    pub u: [&'a [f32]; 2],
    /// `wo` normalised (the eval kernel's input).
    pub won: [&'a mut [f32]; 3],
    pub wi: [&'a mut [f32]; 3],
    pub pdf: &'a mut [f32],
    /// The unit tier's weight; NaN where the caller computes it (`f cos_i / pdf` with the
    /// eval kernel): elements of the exact tiers, or every element without `Vndf::weight`.
    pub weight: &'a mut [f32],
}

/// Elements per try of the fast path: where one of them is unsure, these are redone on the
/// exact path.
const SUB: usize = 128;

#[inline(always)]
fn sample_body(v: &Vndf, b: SampleBlock<'_>) {
    let n = b.pdf.len();
    let [nx, ny, nz] = b.won;
    let [ix, iy, iz] = b.wi;
    let mut lo = 0;
    while lo < n {
        let hi = (lo + SUB).min(n);
        let wo = b.wo.map(|x| &x[lo..hi]);
        let u = b.u.map(|x| &x[lo..hi]);
        let mut outs = (
            [&mut nx[lo..hi], &mut ny[lo..hi], &mut nz[lo..hi]],
            [&mut ix[lo..hi], &mut iy[lo..hi], &mut iz[lo..hi]],
            &mut b.pdf[lo..hi],
        );
        let weight = &mut b.weight[lo..hi];
        if !sample_run_unit(v, wo, u, &mut outs, weight) {
            // Some element is unsure: the exact tiers for all, then the unit tier's values
            // back where it was sure (each element's value depends on it alone).
            if !sample_run::<true>(v, wo, u, &mut outs) {
                sample_run::<false>(v, wo, u, &mut outs);
            }
            sample_merge_unit(v, wo, u, &mut outs, weight);
        }
        lo = hi;
    }
}

/// [`Vndf::sample_unit_tier`] over slices of equal length: whether every element was sure.
#[inline(always)]
fn sample_run_unit(
    v: &Vndf,
    wo: [&[f32]; 3],
    u: [&[f32]; 2],
    (won, wi, pdf): &mut SampleOuts<'_>,
    weight: &mut [f32],
) -> bool {
    let n = pdf.len();
    let (ox, oy, oz) = (&wo[0][..n], &wo[1][..n], &wo[2][..n]);
    let (u0, u1) = (&u[0][..n], &u[1][..n]);
    let [nx, ny, nz] = won;
    let (nx, ny, nz) = (&mut nx[..n], &mut ny[..n], &mut nz[..n]);
    let [ix, iy, iz] = wi;
    let (ix, iy, iz) = (&mut ix[..n], &mut iy[..n], &mut iz[..n]);
    let (pdf, weight) = (&mut pdf[..n], &mut weight[..n]);
    let mut unsure = 0u32;
    for i in 0..n {
        let ([o, w], [p, f], sure) = v.sample_unit_tier([ox[i], oy[i], oz[i]], [u0[i], u1[i]]);
        (nx[i], ny[i], nz[i]) = (o[0], o[1], o[2]);
        (ix[i], iy[i], iz[i]) = (w[0], w[1], w[2]);
        (pdf[i], weight[i]) = (p, f);
        unsure |= u32::from(!sure);
    }
    unsure == 0
}

/// After the exact tiers: the unit tier's values where it is sure, NaN weights elsewhere.
#[inline(always)]
fn sample_merge_unit(
    v: &Vndf,
    wo: [&[f32]; 3],
    u: [&[f32]; 2],
    (won, wi, pdf): &mut SampleOuts<'_>,
    weight: &mut [f32],
) {
    for i in 0..pdf.len() {
        let ([o, w], [p, f], sure) =
            v.sample_unit_tier([wo[0][i], wo[1][i], wo[2][i]], [u[0][i], u[1][i]]);
        if sure {
            (won[0][i], won[1][i], won[2][i]) = (o[0], o[1], o[2]);
            (wi[0][i], wi[1][i], wi[2][i]) = (w[0], w[1], w[2]);
            (pdf[i], weight[i]) = (p, f);
        } else {
            weight[i] = f32::NAN;
        }
    }
}

/// `won`, `wi` and `pdf` of a sub-block.
type SampleOuts<'a> = ([&'a mut [f32]; 3], [&'a mut [f32]; 3], &'a mut [f32]);

/// [`Vndf::sample_as`] over slices of equal length: whether every element was sure.
#[inline(always)]
fn sample_run<const FAST: bool>(
    v: &Vndf,
    wo: [&[f32]; 3],
    u: [&[f32]; 2],
    (won, wi, pdf): &mut SampleOuts<'_>,
) -> bool {
    let n = pdf.len();
    let (ox, oy, oz) = (&wo[0][..n], &wo[1][..n], &wo[2][..n]);
    let (u0, u1) = (&u[0][..n], &u[1][..n]);
    let [nx, ny, nz] = won;
    let (nx, ny, nz) = (&mut nx[..n], &mut ny[..n], &mut nz[..n]);
    let [ix, iy, iz] = wi;
    let (ix, iy, iz) = (&mut ix[..n], &mut iy[..n], &mut iz[..n]);
    let pdf = &mut pdf[..n];
    let mut unsure = 0u32;
    for i in 0..n {
        let (wo, wi, p, sure) = v.sample_as::<FAST>([ox[i], oy[i], oz[i]], [u0[i], u1[i]]);
        nx[i] = wo[0];
        ny[i] = wo[1];
        nz[i] = wo[2];
        ix[i] = wi[0];
        iy[i] = wi[1];
        iz[i] = wi[2];
        pdf[i] = p;
        unsure |= u32::from(!sure);
    }
    unsure == 0
}

#[inline(always)]
fn pdf_body<M: Math<f32>>(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
    let n = out.len();
    let mut lo = 0;
    while lo < n {
        let hi = (lo + SUB).min(n);
        let (wo, wi) = (wo.map(|x| &x[lo..hi]), wi.map(|x| &x[lo..hi]));
        let out = &mut out[lo..hi];
        if !pdf_run_unit::<M>(v, wo, wi, out) {
            // As in `sample_body`: the exact tiers, then the unit tier where it is sure.
            if !pdf_run::<true>(v, wo, wi, out) {
                pdf_run::<false>(v, wo, wi, out);
            }
            for (i, o) in out.iter_mut().enumerate() {
                let a = [wo[0][i], wo[1][i], wo[2][i]];
                let (p, sure) = v.pdf_unit_tier::<M>(a, [wi[0][i], wi[1][i], wi[2][i]]);
                if sure {
                    *o = p;
                }
            }
        }
        lo = hi;
    }
}

/// [`Vndf::pdf_unit_tier`] over slices of equal length: whether every element was sure.
#[inline(always)]
fn pdf_run_unit<M: Math<f32>>(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) -> bool {
    let n = out.len();
    let (ox, oy, oz) = (&wo[0][..n], &wo[1][..n], &wo[2][..n]);
    let (ix, iy, iz) = (&wi[0][..n], &wi[1][..n], &wi[2][..n]);
    let mut unsure = 0u32;
    for i in 0..n {
        let (p, sure) = v.pdf_unit_tier::<M>([ox[i], oy[i], oz[i]], [ix[i], iy[i], iz[i]]);
        out[i] = p;
        unsure |= u32::from(!sure);
    }
    unsure == 0
}

/// [`Vndf::pdf_fast`] (`FAST`) or [`Vndf::pdf`] over slices of equal length: whether every
/// element was sure. (Not a closure: closures do not inherit `#[target_feature]`.)
#[inline(always)]
fn pdf_run<const FAST: bool>(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) -> bool {
    let n = out.len();
    let (ox, oy, oz) = (&wo[0][..n], &wo[1][..n], &wo[2][..n]);
    let (ix, iy, iz) = (&wi[0][..n], &wi[1][..n], &wi[2][..n]);
    let mut unsure = 0u32;
    for i in 0..n {
        let (a, b) = ([ox[i], oy[i], oz[i]], [ix[i], iy[i], iz[i]]);
        let (p, sure) = if FAST {
            v.pdf_fast(a, b)
        } else {
            (v.pdf(a, b), true)
        };
        out[i] = p;
        unsure |= u32::from(!sure);
    }
    unsure == 0
}

/// `weight = f cos_i / pdf` (0 where `pdf` is 0) where `weight` is NaN (the unit tier left
/// it to the eval kernel's `f`).
#[inline(always)]
fn weight_body(wiz: &[f32], pdf: &[f32], f: &[f32], weight: &mut [f32]) {
    let n = weight.len();
    let (wiz, pdf, f) = (&wiz[..n], &pdf[..n], &f[..n]);
    for i in 0..n {
        let w = f[i] * wiz[i] / pdf[i];
        let w = if pdf[i] > 0.0 { w } else { 0.0 };
        weight[i] = if weight[i].is_nan() { w } else { weight[i] };
    }
}

macro_rules! variants {
    ($body:ident, $avx512:ident, $avx2:ident, $plain:ident, ($($a:ident: $t:ty),*)) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
        unsafe fn $avx512($($a: $t),*) {
            $body($($a),*)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn $avx2($($a: $t),*) {
            $body($($a),*)
        }
        fn $plain($($a: $t),*) {
            $body($($a),*)
        }
    };
}

variants!(sample_body, sample_avx512, sample_avx2, sample_plain, (v: &Vndf, b: SampleBlock<'_>));
/// `pdf_body` with fused multiply-adds in its AVX-512 and AVX2+FMA loops (the same bits in
/// both), without in the baseline loop (as the eval kernels' SSE2 loops).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
unsafe fn pdf_avx512(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
    pdf_body::<FastFma>(v, wo, wi, out)
}
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn pdf_avx2(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
    pdf_body::<FastFma>(v, wo, wi, out)
}
fn pdf_plain(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
    pdf_body::<Fast>(v, wo, wi, out)
}
variants!(weight_body, weight_avx512, weight_avx2, weight_plain, (wiz: &[f32], pdf: &[f32], f: &[f32], weight: &mut [f32]));

use crate::batch::Isa;

/// [`Vndf::sample`] over a block, with instruction set `isa` (one `Isa::available` gave).
pub fn sample_block(isa: Isa, v: &Vndf, b: SampleBlock<'_>) {
    match isa {
        // SAFETY: the caller passes an instruction set this CPU supports (`Isa::best`).
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { sample_avx512(v, b) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { sample_avx2(v, b) },
        _ => sample_plain(v, b),
    }
}

/// [`Vndf::pdf`] over slices of equal length.
pub fn pdf_block(isa: Isa, v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
    match isa {
        // SAFETY: as in `sample_block`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { pdf_avx512(v, wo, wi, out) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { pdf_avx2(v, wo, wi, out) },
        _ => pdf_plain(v, wo, wi, out),
    }
}

/// The weight from the eval kernel's `f` where the unit tier left it NaN.
pub fn weight_block(isa: Isa, wiz: &[f32], pdf: &[f32], f: &[f32], weight: &mut [f32]) {
    match isa {
        // SAFETY: as in `sample_block`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { weight_avx512(wiz, pdf, f, weight) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { weight_avx2(wiz, pdf, f, weight) },
        _ => weight_plain(wiz, pdf, f, weight),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::{Micro, MicroKind};

    /// `pdf_block` on every instruction set this CPU has (the fused unit tier on AVX-512 and
    /// AVX2+FMA, the unfused one on SSE2): the FMA sets give the same bits, and every set
    /// stays within the unit tier's bound of the exact density (`Vndf::pdf`),
    /// `1e-6 (1 + 1 / (alpha |wo + wi|))` relative, and is 0 where it is.
    #[test]
    fn pdf_block_on_every_instruction_set_keeps_the_unit_tiers_bound() {
        for (ax, ay) in [(0.3, 0.3), (0.005, 0.005), (1.0, 1.0), (0.1, 0.4)] {
            let v = Vndf::new(&Micro {
                kind: MicroKind::Ggx,
                ax,
                ay,
            });
            // `accuracy::direction_pairs`: unit pairs over the hemisphere, grazing ones among
            // them (some take the exact tiers).
            let (mut wo, mut wi): ([Vec<f32>; 3], [Vec<f32>; 3]) = Default::default();
            for (o, i) in crate::accuracy::direction_pairs(20_000, 5) {
                for k in 0..3 {
                    wo[k].push(o[k] as f32);
                    wi[k].push(i[k] as f32);
                }
            }
            let n = wo[0].len();
            fn refs(w: &[Vec<f32>; 3]) -> [&[f32]; 3] {
                [&w[0][..], &w[1][..], &w[2][..]]
            }
            let mut fused: Option<Vec<f32>> = None;
            for &isa in Isa::available() {
                let mut out = vec![-1.0f32; n];
                pdf_block(isa, &v, refs(&wo), refs(&wi), &mut out);
                for i in 0..n {
                    let (o, w) = (
                        [wo[0][i], wo[1][i], wo[2][i]],
                        [wi[0][i], wi[1][i], wi[2][i]],
                    );
                    let want = v.pdf(o, w);
                    assert_eq!(
                        want == 0.0,
                        out[i] == 0.0,
                        "{} #{i}: {} {want}",
                        isa.name(),
                        out[i]
                    );
                    if want != 0.0 {
                        let h = (0..3)
                            .map(|k| (o[k] as f64 + w[k] as f64).powi(2))
                            .sum::<f64>();
                        let rel = (out[i] as f64 - want as f64).abs() / want as f64;
                        let bound = 1e-6 * (1.0 + 1.0 / (ax.min(ay) * h.sqrt()));
                        assert!(
                            rel <= bound,
                            "{} #{i}: {} {want} ({rel:.2e})",
                            isa.name(),
                            out[i]
                        );
                    }
                }
                if isa.fma() {
                    match &fused {
                        None => fused = Some(out),
                        Some(f) => assert!(
                            f.iter().zip(&out).all(|(a, b)| a.to_bits() == b.to_bits()),
                            "{} differs from the other FMA set",
                            isa.name()
                        ),
                    }
                }
            }
        }
    }
}
