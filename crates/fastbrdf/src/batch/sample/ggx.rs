//! The SIMD path of Cook-Torrance with GGX (isotropic or anisotropic) and its default
//! strategy, visible-normal sampling (Heitz 2018): `Micro::sample_vndf` / `pdf_vndf` and the
//! steps of `Brdf::<f32>::sample` / `pdf` around them, written branch-free over f32 lanes and
//! compiled inside `#[target_feature]` loops (AVX-512, AVX2+FMA, SSE2) as the eval kernels
//! are (`batch`'s header), so that LLVM vectorises them.
//!
//! The same operations in the same order as the scalar code (IEEE `+ - * / sqrt`, the f64
//! domain cuts of `vec3::above_cos_min`, the normalisation of `vec3::unit`), except for the
//! azimuth's `sin_cos(2 pi u1)`, which is [`sincos_2pi`] here (libm there). Hence:
//! - `pdf` (a density of given directions) is the scalar one bit for bit;
//! - `sample`'s `wi` is the scalar one up to the propagation of `sincos_2pi`'s error (and of
//!   the scalar's own rounding of `2 pi u1` before its `sin_cos`): the tests bound it;
//! - its `pdf` is the scalar density at its `wi` bit for bit, and its weight is
//!   `f cos_i / pdf` with `f` from the SIMD eval kernel (`Kernel`), whose values differ from
//!   the scalar model's by the fast elementary functions' few ulp.
//!
//! Each block of [`SUB`] elements first runs a fast form of those steps: `vec3::unit` as its
//! direct `v / |v|` ([`unit_direct`], what it computes where `|v|^2` is in its direct range)
//! and the f64 horizon test `above_cos_min` as an f32 comparison ([`horizon`], the f64
//! answer away from `COS_MIN` by more than its margin). Where every element of the block is
//! in those ranges (all but degenerate inputs and cosines within 1e-5 of `COS_MIN`) its
//! values are the exact steps' bit for bit; else the block is redone on the exact steps. So
//! the values above hold unchanged, at about half the cost (no f64 square roots and
//! divisions, no divisions by 1).

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
}

impl Vndf {
    pub fn new(m: &crate::sample::Micro) -> Self {
        Self {
            ax: m.ax as f32,
            ay: m.ay as f32,
            k: (1.0 / (std::f64::consts::PI * m.ax * m.ay)) as f32,
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
        let nh = [
            p1 * t1[0] + p2 * t2[0] + pz * vh[0],
            p1 * t1[1] + p2 * t2[1] + pz * vh[1],
            p1 * t1[2] + p2 * t2[2] + pz * vh[2],
        ];
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
        if !sample_run::<true>(v, wo, u, &mut outs) {
            sample_run::<false>(v, wo, u, &mut outs);
        }
        lo = hi;
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
fn pdf_body(v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]) {
    let n = out.len();
    let mut lo = 0;
    while lo < n {
        let hi = (lo + SUB).min(n);
        let (wo, wi) = (wo.map(|x| &x[lo..hi]), wi.map(|x| &x[lo..hi]));
        let out = &mut out[lo..hi];
        if !pdf_run::<true>(v, wo, wi, out) {
            pdf_run::<false>(v, wo, wi, out);
        }
        lo = hi;
    }
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

/// `weight = f cos_i / pdf` (0 where `pdf` is 0), in place over `f`.
#[inline(always)]
fn weight_body(wiz: &[f32], pdf: &[f32], f: &mut [f32]) {
    let n = f.len();
    let (wiz, pdf) = (&wiz[..n], &pdf[..n]);
    for i in 0..n {
        let w = f[i] * wiz[i] / pdf[i];
        f[i] = if pdf[i] > 0.0 { w } else { 0.0 };
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
variants!(pdf_body, pdf_avx512, pdf_avx2, pdf_plain, (v: &Vndf, wo: [&[f32]; 3], wi: [&[f32]; 3], out: &mut [f32]));
variants!(weight_body, weight_avx512, weight_avx2, weight_plain, (wiz: &[f32], pdf: &[f32], f: &mut [f32]));

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

/// The weight from `f` in place.
pub fn weight_block(isa: Isa, wiz: &[f32], pdf: &[f32], f: &mut [f32]) {
    match isa {
        // SAFETY: as in `sample_block`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { weight_avx512(wiz, pdf, f) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { weight_avx2(wiz, pdf, f) },
        _ => weight_plain(wiz, pdf, f),
    }
}
