//! Cook-Torrance's batch kernels: specialised for the (D, G, F) combinations that matter, a
//! generic path for the rest (issue 28: every new part multiplied the compiled kernels).
//!
//! The rule. A combination gets its own kernel (`CookTorrance<D, G, F>` with the concrete
//! families, one fused loop per instruction set) when its shadowing term vectorises
//! (`ShadowForm::SIMD`) and
//! - (a) G is one of D's own Smith terms, the forms of the Smith term of D's slope
//!   distribution (`DistForm::smith` names the exact one) but the exact Beckmann ones
//!   (below): the Beckmann family (`beckmann`,
//!   `beckmann-ct`, `beckmann-pow`, `beckmann-power4/8/16`) with `smith-rational`; `ggx` with
//!   `smith-ggx`, `smith-ggx-correlated`, `smith-ggx-correlated-fast(-tuned)`,
//!   `smith-ggx-joint-approx`, `schlick-ggx`; with every Fresnel term; or
//! - (b) G has no slope distribution (`v-cavity`, `kelemen`, `neumann`: not a Smith term,
//!   `ShadowForm::ANISO` false), with every D and `f` = `none` or `schlick`.
//!
//! Of (a), `ggx` with `smith-ggx` or `smith-ggx-correlated` and `f` = `none` or `schlick`,
//! isotropic, is not the product of its parts but their closed form (`batch::ggx_closed`:
//! 1.6x faster, within 2.5e-6 of f64 with `f = none`, not the parts' bits; 4 kernels, 12
//! loops, beside the fused ones of the same triples, which the anisotropic models run).
//!
//! The exact Beckmann Smith terms (`smith`, `smith-beckmann-correlated`) vectorise since
//! issue 30 (`math::fast::erfc`, branch-free, over the `Fast` backends) but take the generic
//! path: their `erfc` and `exp` dominate, and fused kernels for them (built and timed, the
//! Beckmann family x both terms x 5 F, 50 more combinations) ran at the generic path's
//! speed: 8.35 / 8.33 ns (default `cook-torrance`), 8.71 / 8.52 (`smith-beckmann-correlated`),
//! 8.61 / 8.71 (`f = schlick`) fused / generic, against 346-377 per element (`cargo run
//! --release -p fastbrdf --example smith_simd`; AVX-512, 4099 pairs, one thread, a 2-core
//! machine under a load of 6-8).
//!
//! That holds every configuration the benches (`benches/seed000.rs`, `fastbrdf bench`'s seed
//! 000 rows) and `pareto --brdf`'s default table time on a specialised kernel, its exact
//! reference (`ggx`, `smith-ggx-correlated`, `dielectric`) and the engines' forms (GGX with its
//! Smith terms, Schlick or the spherical-Gaussian Schlick). Every other combination (a D with
//! another distribution's Smith term, the exact Beckmann Smith terms, the D-free terms with
//! the costlier Fresnel forms) runs the generic path: the same formulas, bit for bit
//! (`tests/kernels.rs`), as vectorised passes over blocks of [`BLOCK`] pairs, each part
//! monomorphised once per instruction set (linear in the parts):
//! 1. the pair set-up (`vec3::pair_setup`, the anisotropic stretch where given) into scratch
//!    arrays: `cos_h`, `sin^2 theta_h`, G's two cosines, `wi.h`, `cos_i cos_o`, validity;
//! 2. `t = F(wi.h)`; 3. `t *= D` (0 below `COS_MIN`); 4. `t *= G`;
//! 5. `out = valid ? t k / (cos_i cos_o) : 0`,
//!
//! in the order `single_scattering` multiplies (`F D G k / (cos_i cos_o)`), so each value is
//! the specialised kernel's. Cost: 1.05-1.11x the specialised kernel's time on the five
//! specialised configurations of `examples/ct_generic.rs` (geometric mean 1.07 and 1.08 in two
//! runs; AVX-512, 4099 pairs, a 2-core machine under a load of 7-10: `cargo run --release -p
//! fastbrdf --example ct_generic`). Before issue 30, where G called libm's `erfc`, the
//! generic path's G pass was a scalar loop (the default `cook-torrance` in 65-186 ns); now
//! every pass vectorises (above).
//!
//! Kernels (loops compiled per instruction set, x3; `tests/kernels.rs` prints the count of
//! specialised combinations): specialised, (a) 5 Beckmann-family D families x 1 G x 5 F +
//! 1 x 5 x 5 = 50 and (b) 6 D x 3 G x 2 F = 36: 86 combinations of 6 x 11 x 5 = 330 (258
//! loops instead of 990); generic: 25 passes (the set-up, isotropic and anisotropic, 5 F,
//! 6 D, 11 G, the finish; 75 loops). The symbol table of `examples/par_cutoff` (which links
//! every kernel) counts 694 AVX-512/AVX2 BRDF loops before and 206 after (the SSE2 ones are
//! inlined), 50 generic passes; its release binary went from 5.32 to 2.41 MB. A new D costs
//! its (a) combinations (its own vectorised Smith terms x every F), 3 x 2 for (b) and one D
//! pass; a new G one G pass, plus its (a) combinations if it is a Smith term of a listed D; a
//! new F one F pass and one combination per (a) pair: linear in the parts.

use super::{CtPath, Imp, Input, Isa, Map6, Op6, brdf_kernel};
use crate::brdf::cook_torrance::{Aniso, CookTorrance};
use crate::forms::{BrdfForm, DistForm, FresnelForm, ShadowForm};
use crate::math::{Fast, FastFma, Math};
use crate::microfacet::ms::Ms;
use crate::plan::{DistPlan, FresnelPlan, ShadowPlan, with_dist, with_fresnel, with_shadow};
use crate::vec3::COS_MIN;

/// Pairs per block of the generic path: its scratch arrays (8 of `BLOCK` f32) stay in L1.
pub const BLOCK: usize = 256;

/// Cook-Torrance without energy compensation, on the pair set-up of the scalar `Pair::new`:
/// `CookTorrance::single_scattering`, so the loop holds no branch on `ms`.
struct CtOp<D, G, F>(CookTorrance<D, G, F>);
impl<D: DistForm, G: ShadowForm, F: FresnelForm> Op6 for CtOp<D, G, F> {
    #[inline(always)]
    fn f<M: Math<f32>, const NEAR: bool>(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        let (valid, p) = crate::vec3::pair_setup_as::<f32, NEAR>(wi, wo);
        let v = self.0.single_scattering::<f32, M>(&p);
        if valid { v } else { 0.0 }
    }
}

/// The specialised kernel of `ct` re-instantiated with the concrete families `d`, `g`, `f`.
fn fused<D: DistForm, G: ShadowForm, F: FresnelForm>(
    ct: &CookTorrance,
    d: D,
    g: G,
    f: F,
) -> Box<dyn Imp> {
    let ct = CookTorrance {
        d,
        g,
        f,
        k: ct.k,
        ms: ct.ms,
        aniso: ct.aniso,
    };
    Box::new(Map6 {
        simd: ct.simd(),
        op: CtOp(ct),
    })
}

/// (a): this D and G with every Fresnel term.
macro_rules! every_f {
    ($ct:expr, $d:expr, $g:expr) => {
        with_fresnel!(&$ct.f, f => fused($ct, *$d, *$g, *f))
    };
}

/// (b): this G and F with every distribution.
macro_rules! every_d {
    ($ct:expr, $g:expr, $f:expr) => {
        with_dist!(&$ct.d, d => fused($ct, *d, *$g, *$f))
    };
}

/// The specialised kernel of `ct` where the rule (module header) gives one.
fn specialised(ct: &CookTorrance) -> Option<Box<dyn Imp>> {
    use DistPlan as D;
    use FresnelPlan as F;
    use ShadowPlan as G;
    Some(match (&ct.d, &ct.g, &ct.f) {
        // (a) The Beckmann family with its rational Smith term (the exact `smith` and
        // `smith-beckmann-correlated` vectorise too, but run the generic path at the same
        // speed: module header).
        (D::Beckmann(d), G::SmithRational(g), _) => every_f!(ct, d, g),
        (D::BeckmannPow(d), G::SmithRational(g), _) => every_f!(ct, d, g),
        (D::BeckmannPower4(d), G::SmithRational(g), _) => every_f!(ct, d, g),
        (D::BeckmannPower8(d), G::SmithRational(g), _) => every_f!(ct, d, g),
        (D::BeckmannPower16(d), G::SmithRational(g), _) => every_f!(ct, d, g),
        // (a) GGX with its Smith terms.
        (D::Ggx(d), G::SmithGgx(g), F::None(f)) if closed(ct, d.alpha2(), g.alpha2()) => {
            super::ggx_closed::kernel::<_, false>(d.alpha2(), ct.k.x, *f)
        }
        (D::Ggx(d), G::SmithGgx(g), F::Schlick(f)) if closed(ct, d.alpha2(), g.alpha2()) => {
            super::ggx_closed::kernel::<_, false>(d.alpha2(), ct.k.x, *f)
        }
        (D::Ggx(d), G::SmithGgxCorrelated(g), F::None(f)) if closed(ct, d.alpha2(), g.alpha2()) => {
            super::ggx_closed::kernel::<_, true>(d.alpha2(), ct.k.x, *f)
        }
        (D::Ggx(d), G::SmithGgxCorrelated(g), F::Schlick(f))
            if closed(ct, d.alpha2(), g.alpha2()) =>
        {
            super::ggx_closed::kernel::<_, true>(d.alpha2(), ct.k.x, *f)
        }
        (D::Ggx(d), G::SmithGgx(g), _) => every_f!(ct, d, g),
        (D::Ggx(d), G::SmithGgxCorrelated(g), _) => every_f!(ct, d, g),
        (D::Ggx(d), G::SmithGgxCorrelatedFast(g), _) => every_f!(ct, d, g),
        (D::Ggx(d), G::SmithGgxJointApprox(g), _) => every_f!(ct, d, g),
        (D::Ggx(d), G::SchlickGgx(g), _) => every_f!(ct, d, g),
        // (b) The terms without a slope distribution, with no Fresnel term or Schlick's.
        (_, G::VCavity(g), F::None(f)) => every_d!(ct, g, f),
        (_, G::VCavity(g), F::Schlick(f)) => every_d!(ct, g, f),
        (_, G::Kelemen(g), F::None(f)) => every_d!(ct, g, f),
        (_, G::Kelemen(g), F::Schlick(f)) => every_d!(ct, g, f),
        (_, G::Neumann(g), F::None(f)) => every_d!(ct, g, f),
        (_, G::Neumann(g), F::Schlick(f)) => every_d!(ct, g, f),
        _ => return None,
    })
}

/// Whether GGX's closed form applies: isotropic, D's and G's slopes the same. (With an energy
/// compensation, `kernel` never asks the rule.)
fn closed(ct: &CookTorrance, d: f64, g: f64) -> bool {
    ct.aniso.is_none() && d == g
}

/// Cook-Torrance's kernel: specialised where the rule gives one (module header), else the
/// generic path (`path` may force either of the others, for tests and measurements). With
/// an energy compensation (only GGX with the correlated Smith term; its table reads make it
/// a scalar fallback anyway) the plan's own parts run, matched per element: one
/// instantiation, not one per combination.
pub(super) fn kernel(ct: &CookTorrance, path: CtPath) -> Box<dyn Imp> {
    if ct.ms != Ms::None || path == CtPath::PerElement {
        return Box::new(Unspecialised(brdf_kernel(*ct)));
    }
    if path == CtPath::Rule
        && let Some(k) = specialised(ct)
    {
        return k;
    }
    Box::new(Generic {
        ct: *ct,
        simd: ct.g.simd(),
    })
}

/// A kernel that runs the plan's parts (matched per element): not specialised.
struct Unspecialised(Box<dyn Imp>);
impl Imp for Unspecialised {
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]) {
        self.0.run(isa, input, out)
    }
    fn simd(&self) -> bool {
        self.0.simd()
    }
    fn specialised(&self) -> bool {
        false
    }
}

// ---------- the generic path ----------

/// One block's intermediate values (the first `n` of each array are live).
struct Scratch {
    cos_h: [f32; BLOCK],
    /// `sin^2 theta_h`, stretched when anisotropic.
    sin2_h: [f32; BLOCK],
    /// G's `cos_v` and `cos_l`: `cos_o` and `cos_i`, stretched when anisotropic.
    g_v: [f32; BLOCK],
    g_l: [f32; BLOCK],
    cos_ih: [f32; BLOCK],
    /// `cos_i cos_o` (the real cosines).
    denom: [f32; BLOCK],
    /// The pair is valid (1) or not (0): u32, the lanes' width.
    valid: [u32; BLOCK],
    /// The product so far.
    t: [f32; BLOCK],
}

/// One pass of the generic path over the first `n` elements of a block.
trait Pass: Sync {
    fn run<M: Math<f32>>(&self, s: &mut Scratch, n: usize);
}

macro_rules! pass_variants {
    ($($isa:ident: $feat:literal),*) => {$(
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feat)]
        unsafe fn $isa<P: Pass>(p: &P, s: &mut Scratch, n: usize) {
            p.run::<FastFma>(s, n)
        }
    )*};
}
pass_variants!(
    pass_avx512: "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma",
    pass_avx2: "avx2,fma"
);

fn pass<P: Pass>(isa: Isa, p: &P, s: &mut Scratch, n: usize) {
    match isa {
        // SAFETY: `Kernel` only passes an ISA that `Isa::available` reported.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { pass_avx512(p, s, n) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { pass_avx2(p, s, n) },
        _ => p.run::<Fast>(s, n),
    }
}

/// 1. The pair set-up of a block (`ANISO`: with the stretch of `aniso`).
struct Setup<'a, const ANISO: bool> {
    w: [&'a [f32]; 6],
    aniso: Aniso,
}
impl<const ANISO: bool> Pass for Setup<'_, ANISO> {
    /// The directions normalised by the series alone where the block's inputs are all of
    /// unit length (as `batch::map6_body`; the half vector keeps `vec3::rsqrt64`).
    #[inline(always)]
    fn run<M: Math<f32>>(&self, s: &mut Scratch, n: usize) {
        let w = self.w.map(|x| &x[..n]);
        if super::near_one_all::<M>(w) {
            self.fill::<M, true>(w, s, n)
        } else {
            self.fill::<M, false>(w, s, n)
        }
    }
}

impl<const ANISO: bool> Setup<'_, ANISO> {
    #[inline(always)]
    fn fill<M: Math<f32>, const NEAR: bool>(&self, w: [&[f32]; 6], s: &mut Scratch, n: usize) {
        let (ch, s2, gv, gl) = (
            &mut s.cos_h[..n],
            &mut s.sin2_h[..n],
            &mut s.g_v[..n],
            &mut s.g_l[..n],
        );
        let (cih, den, ok) = (&mut s.cos_ih[..n], &mut s.denom[..n], &mut s.valid[..n]);
        for i in 0..n {
            let (valid, p) = crate::vec3::pair_setup_as::<f32, NEAR>(
                [w[0][i], w[1][i], w[2][i]],
                [w[3][i], w[4][i], w[5][i]],
            );
            // `single_scattering`'s arguments: the stretched ones into D and G only.
            let (sin2, v, l) = if ANISO {
                let a = &self.aniso;
                (
                    a.sin2_h::<f32, M>(p.h),
                    a.cos::<f32, M>(p.wo),
                    a.cos::<f32, M>(p.wi),
                )
            } else {
                (p.sin2_h, p.cos_o, p.cos_i)
            };
            ch[i] = p.cos_h;
            s2[i] = sin2;
            gv[i] = v;
            gl[i] = l;
            cih[i] = p.cos_ih;
            den[i] = p.cos_i * p.cos_o;
            ok[i] = u32::from(valid);
        }
    }
}

/// 2. `t = F(wi.h)`.
struct FPass<F>(F);
impl<F: FresnelForm> Pass for FPass<F> {
    #[inline(always)]
    fn run<M: Math<f32>>(&self, s: &mut Scratch, n: usize) {
        for (t, &c) in s.t[..n].iter_mut().zip(&s.cos_ih[..n]) {
            *t = self.0.f::<f32, M>(c);
        }
    }
}

/// 3. `t *= D`, 0 below `COS_MIN`.
struct DPass<D>(D);
impl<D: DistForm> Pass for DPass<D> {
    #[inline(always)]
    fn run<M: Math<f32>>(&self, s: &mut Scratch, n: usize) {
        let (t, ch, s2) = (&mut s.t[..n], &s.cos_h[..n], &s.sin2_h[..n]);
        for i in 0..n {
            let d = self.0.d::<f32, M>(ch[i], s2[i]);
            let d = if ch[i] >= COS_MIN as f32 { d } else { 0.0 };
            t[i] *= d;
        }
    }
}

/// 4. `t *= G`.
struct GPass<G>(G);
impl<G: ShadowForm> Pass for GPass<G> {
    #[inline(always)]
    fn run<M: Math<f32>>(&self, s: &mut Scratch, n: usize) {
        let (t, gv, gl) = (&mut s.t[..n], &s.g_v[..n], &s.g_l[..n]);
        let (ch, cih) = (&s.cos_h[..n], &s.cos_ih[..n]);
        for i in 0..n {
            t[i] *= self.0.g_pair::<f32, M>(gv[i], gl[i], ch[i], cih[i]);
        }
    }
}

/// 5. `t = valid ? t k / (cos_i cos_o) : 0` (`k` rounded to f32).
struct Finish(f32);
impl Pass for Finish {
    #[inline(always)]
    fn run<M: Math<f32>>(&self, s: &mut Scratch, n: usize) {
        let (t, den, ok) = (&mut s.t[..n], &s.denom[..n], &s.valid[..n]);
        for i in 0..n {
            let v = t[i] * self.0 / den[i];
            t[i] = if ok[i] != 0 { v } else { 0.0 };
        }
    }
}

/// The generic path's kernel: the plan's parts, each pass matched once per block.
struct Generic {
    ct: CookTorrance,
    simd: bool,
}

impl Generic {
    fn block(&self, isa: Isa, w: [&[f32]; 6], out: &mut [f32], s: &mut Scratch) {
        let n = out.len();
        match self.ct.aniso {
            None => {
                let aniso = Aniso {
                    x_over_y: crate::real::K::new(1.0),
                    y_over_x: crate::real::K::new(1.0),
                };
                pass(isa, &Setup::<false> { w, aniso }, s, n)
            }
            Some(aniso) => pass(isa, &Setup::<true> { w, aniso }, s, n),
        }
        with_fresnel!(&self.ct.f, f => pass(isa, &FPass(*f), s, n));
        with_dist!(&self.ct.d, d => pass(isa, &DPass(*d), s, n));
        with_shadow!(&self.ct.g, g => pass(isa, &GPass(*g), s, n));
        pass(isa, &Finish(self.ct.k.t::<f32>()), s, n);
        out.copy_from_slice(&s.t[..n]);
    }
}

impl Imp for Generic {
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]) {
        let Input::Dirs(w) = *input else { return };
        let mut s = Scratch {
            cos_h: [0.0; BLOCK],
            sin2_h: [0.0; BLOCK],
            g_v: [0.0; BLOCK],
            g_l: [0.0; BLOCK],
            cos_ih: [0.0; BLOCK],
            denom: [0.0; BLOCK],
            valid: [0; BLOCK],
            t: [0.0; BLOCK],
        };
        for (b, o) in out.chunks_mut(BLOCK).enumerate() {
            let lo = b * BLOCK;
            let wb = w.map(|x| &x[lo..lo + o.len()]);
            self.block(isa, wb, o, &mut s);
        }
    }
    fn simd(&self) -> bool {
        self.simd
    }
    fn specialised(&self) -> bool {
        false
    }
}
