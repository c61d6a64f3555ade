//! The per-element operations of the batch kernels: the scalar models' formulas, in the same
//! arrangement (so f32 results agree), written branch-free over `math`'s vectorisable
//! functions. Each op is `#[inline(always)]` so that it is compiled inside the ISA-specific
//! loops of `super`.

// `x.max(0.0).min(1.0)` maps NaN to 0 as the scalar twins do; `clamp` would propagate NaN.
#![allow(clippy::manual_clamp)]

use super::math;
use crate::vec3::COS_MIN;

/// An operation on one cosine.
pub trait Op1: Send + Sync + 'static {
    fn f(&self, x: f32) -> f32;
}

/// An operation on a direction pair (wi, wo), not normalised.
pub trait Op6: Send + Sync + 'static {
    fn f(&self, wi: [f32; 3], wo: [f32; 3]) -> f32;
}

// ---------- lobes ----------

/// Clamp to [0, 1] (NaN becomes 0 here; `finish` restores 0 for NaN inputs).
#[inline(always)]
fn clamp01(c: f32) -> f32 {
    c.max(0.0).min(1.0)
}

#[inline(always)]
fn finish(c: f32, v: f32) -> f32 {
    if c.is_nan() { 0.0 } else { v }
}

#[inline(always)]
fn pow2k(mut x: f32, k: u32) -> f32 {
    for _ in 0..k {
        x *= x;
    }
    x
}

pub struct Pow {
    pub n: f32,
}
impl Op1 for Pow {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        finish(c, math::pow(clamp01(c), self.n))
    }
}

pub struct Schlick {
    pub n: f32,
}
impl Op1 for Schlick {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let x = clamp01(c);
        finish(c, x / (self.n * (1.0 - x) + x))
    }
}

pub struct SchlickModified {
    pub n: f32,
}
impl Op1 for SchlickModified {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let x = clamp01(c);
        let d = self.n * (1.0 - x) + 1.25 * x;
        finish(c, 2.0 * x / (1.25 * (d * d)))
    }
}

pub struct Gauss {
    pub half_n: f32,
}
impl Op1 for Gauss {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let t = math::acos(clamp01(c));
        finish(c, math::exp(-self.half_n * (t * t)))
    }
}

pub struct Flog {
    pub n: f32,
    pub coef: f32,
    pub clamp: bool,
}
impl Op1 for Flog {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let x = clamp01(c);
        let f = 1.0 - 0.5 * math::log2(1.0 - self.n * math::log2(x));
        let v = (self.coef * f).max(0.0);
        let v = if self.clamp { v.min(1.0) } else { v };
        finish(c, if x > 0.0 { v } else { 0.0 })
    }
}

pub struct Cubic {
    pub d1: f32,
    pub d2: f32,
    pub d3: f32,
    pub x1: f32,
    pub x2: f32,
    pub cut: f32,
}
impl Op1 for Cubic {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let cc = clamp01(c);
        let x = cc - 1.0;
        let p = 1.0 + x * (self.d1 + (x - self.x1) * (self.d2 + (x - self.x2) * self.d3));
        finish(c, if cc < self.cut { 0.0 } else { p.max(0.0) })
    }
}

pub struct Rational {
    pub n: f32,
    pub xq: f32,
    pub level: f32,
}
impl Op1 for Rational {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let cc = clamp01(c);
        let x = cc - 1.0;
        finish(c, self.level * cc / (self.n * (self.xq - x) + cc))
    }
}

pub struct CubicRational {
    pub cubic: Cubic,
    pub rational: Rational,
    pub q: f32,
}
impl Op1 for CubicRational {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let cc = clamp01(c);
        let a = self.cubic.f(cc);
        let b = self.rational.f(cc);
        finish(c, if cc >= self.q { a } else { b })
    }
}

pub struct Power<const K: u32> {
    pub s: f32,
}
impl<const K: u32> Op1 for Power<K> {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let cc = clamp01(c);
        finish(c, pow2k((1.0 + self.s * (cc - 1.0)).max(0.0), K))
    }
}

pub struct Exp2Lobe {
    pub k: f32,
}
impl Op1 for Exp2Lobe {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        finish(c, math::exp2(self.k * (clamp01(c) - 1.0)))
    }
}

// ---------- distributions (input cos theta_h) ----------

/// D given cos and sin^2 of theta_h (cos >= COS_MIN and <= 1 already).
pub trait DOp: Send + Sync + 'static {
    fn d(&self, cos_h: f32, sin2_h: f32) -> f32;
}

pub struct Beckmann {
    pub inv_alpha2: f32,
    pub scale: f32,
}
impl DOp for Beckmann {
    #[inline(always)]
    fn d(&self, c: f32, s2: f32) -> f32 {
        let c2 = c * c;
        // One division instead of two (the scalar model divides twice; the results differ by
        // at most an ulp or two, within the batch tolerance).
        let inv_c2 = 1.0 / c2;
        self.scale * math::exp(-(s2 * inv_c2) * self.inv_alpha2) * (inv_c2 * inv_c2)
    }
}

pub struct BeckmannPow {
    pub e: f32,
    pub scale: f32,
}
impl DOp for BeckmannPow {
    #[inline(always)]
    fn d(&self, c: f32, _s2: f32) -> f32 {
        self.scale * math::pow(c, self.e)
    }
}

pub struct BeckmannPower<const K: u32> {
    pub s: f32,
    pub scale: f32,
}
impl<const K: u32> DOp for BeckmannPower<K> {
    #[inline(always)]
    fn d(&self, c: f32, s2: f32) -> f32 {
        let cm1 = -s2 / (1.0 + c);
        self.scale * pow2k((1.0 + self.s * cm1).max(0.0), K)
    }
}

/// A distribution as an op on `cos theta_h`, with the scalar model's domain rules.
pub struct Dist<D>(pub D);
impl<D: DOp> Op1 for Dist<D> {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        let cc = c.min(1.0);
        let v = self.0.d(cc, (1.0 - cc) * (1.0 + cc));
        if c >= COS_MIN as f32 { v } else { 0.0 }
    }
}

// ---------- Fresnel (input cos between view and microfacet normal) ----------

pub trait FOp: Send + Sync + 'static {
    fn fr(&self, c: f32) -> f32;
}

pub struct FNone;
impl FOp for FNone {
    #[inline(always)]
    fn fr(&self, _c: f32) -> f32 {
        1.0
    }
}

pub struct FSchlick {
    pub f0: f32,
}
impl FOp for FSchlick {
    #[inline(always)]
    fn fr(&self, c: f32) -> f32 {
        let m = 1.0 - clamp01(c);
        let m2 = m * m;
        self.f0 + (1.0 - self.f0) * (m2 * m2 * m)
    }
}

pub struct FDielectric {
    pub p: crate::microfacet::fresnel::Consts<f32>,
}
impl FOp for FDielectric {
    #[inline(always)]
    fn fr(&self, c: f32) -> f32 {
        // The scalar model's arrangement, the same source (branch-free after inlining).
        crate::microfacet::fresnel::dielectric(c, &self.p)
    }
}

pub struct FConductor {
    pub p: crate::microfacet::fresnel::Consts<f32>,
}
impl FOp for FConductor {
    #[inline(always)]
    fn fr(&self, c: f32) -> f32 {
        crate::microfacet::fresnel::conductor(c, &self.p)
    }
}

/// A Fresnel term as an op (the scalar model's rule: NaN or negative cosines act as 0).
pub struct Fres<F>(pub F);
impl<F: FOp> Op1 for Fres<F> {
    #[inline(always)]
    fn f(&self, c: f32) -> f32 {
        self.0.fr(if c >= 0.0 { c } else { 0.0 })
    }
}

// ---------- shadowing (as used by Cook-Torrance) ----------

pub trait GOp: Send + Sync + 'static {
    /// Two-sided G from n.v (wo), n.l (wi), n.h and v.h.
    fn g(&self, cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32;
}

pub struct VCavity;
impl GOp for VCavity {
    #[inline(always)]
    fn g(&self, cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32 {
        let k = 2.0 * cos_h / cos_vh;
        1f32.min(k * cos_v).min(k * cos_l)
    }
}

pub struct SmithRational {
    pub alpha: f32,
}
impl SmithRational {
    #[inline(always)]
    fn g1(&self, c: f32) -> f32 {
        let sin = ((1.0 - c) * (1.0 + c)).max(0.0).sqrt();
        let a = c / (self.alpha * sin);
        let a2 = a * a;
        let g = (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
        if a >= 1.6 || c >= 1.0 { 1.0 } else { g }
    }
}
impl GOp for SmithRational {
    #[inline(always)]
    fn g(&self, cos_v: f32, cos_l: f32, _cos_h: f32, _cos_vh: f32) -> f32 {
        self.g1(cos_v) * self.g1(cos_l)
    }
}

// ---------- full BRDFs ----------

pub struct CookTorrance<D, G, F> {
    pub d: D,
    pub g: G,
    pub fr: F,
    pub k: f32,
}
impl<D: DOp, G: GOp, F: FOp> Op6 for CookTorrance<D, G, F> {
    #[inline(always)]
    fn f(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        // The scalar `Pair::new`'s set-up (in f64), branch-free.
        let (valid, p) = crate::vec3::pair_setup(wi, wo);
        let (ci, co, h, s2, cih) = (p.cos_i, p.cos_o, p.h, p.sin2_h, p.cos_ih);
        let d = self.d.d(h[2], s2);
        let d = if h[2] >= COS_MIN as f32 { d } else { 0.0 };
        let g = self.g.g(co, ci, h[2], cih);
        let v = self.fr.fr(cih) * d * g * self.k / (ci * co);
        if valid { v } else { 0.0 }
    }
}

/// Which exponential factor a Ward kernel uses: 0 exact, 1 pow, 2 power16.
pub struct Ward<const FORM: u8> {
    pub inv_ax2: f32,
    pub inv_ay2: f32,
    pub e: f32,
    pub scale: f32,
}
impl<const FORM: u8> Op6 for Ward<FORM> {
    #[inline(always)]
    fn f(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        let (valid, p) = crate::vec3::pair_setup(wi, wo);
        let (ci, co, h, s2) = (p.cos_i, p.cos_o, p.h, p.sin2_h);
        let lobe = match FORM {
            0 => math::exp(
                -(h[0] * h[0] * self.inv_ax2 + h[1] * h[1] * self.inv_ay2) / (h[2] * h[2]),
            ),
            1 => math::pow(h[2], self.e),
            _ => pow2k((1.0 + self.e * (-s2 / (1.0 + h[2]))).max(0.0), 4),
        };
        let v = self.scale * lobe / (ci * co).sqrt();
        if valid { v } else { 0.0 }
    }
}

pub struct Lambert {
    pub value: f32,
}
impl Op6 for Lambert {
    #[inline(always)]
    fn f(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        let (valid, _) = crate::vec3::pair_setup(wi, wo);
        if valid { self.value } else { 0.0 }
    }
}

pub struct LobeBrdf<L> {
    pub lobe: L,
    /// The lobe's cut, decided on the f64 cosine as the scalar model does.
    pub zero: f64,
    pub coef: f32,
    pub blinn: bool,
    pub normalized: bool,
}
impl<L: Op1> Op6 for LobeBrdf<L> {
    #[inline(always)]
    fn f(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        let (valid, p) = crate::vec3::pair_setup(wi, wo);
        let (h, cih, rdotwo) = (p.h, p.cos_ih, p.cos_r);
        let cut = p.lobe_cut(self.zero, self.blinn);
        let v = if self.blinn {
            let l = self.lobe.f(h[2]);
            if self.normalized {
                self.coef * l / (4.0 * cih)
            } else {
                l
            }
        } else {
            self.coef * self.lobe.f(rdotwo)
        };
        if valid && !cut { v } else { 0.0 }
    }
}
