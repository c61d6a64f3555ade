//! Batch kernels: evaluate one model with fixed parameters over slices, in f32.
//!
//! Inputs are structures of arrays: one slice of cosines for lobes, distributions and Fresnel
//! terms; six slices (`wi_x, wi_y, wi_z, wo_x, wo_y, wo_z`) for full BRDFs.
//!
//! How it is fast: each model's formula (its family's `at`/`d`/`g`/`f`/`at_pair`, the same
//! source as the scalar model) is instantiated with the `Fast` backend: branch-free,
//! `#[inline(always)]`, over vectorisable elementary functions (`math`: exp2, log2, pow, acos
//! with documented accuracy, no libm calls). The loop over a slice is compiled three times, inside
//! functions with `#[target_feature]` AVX-512, AVX2+FMA, and the x86-64 baseline (SSE2), and
//! LLVM vectorises each; the best one the CPU has is chosen at run time with
//! `is_x86_feature_detected!` (tails are the same loop's remainder). Large batches are split
//! across threads with rayon (`Kernel::eval_par`).
//!
//! Results agree with the scalar models (`Model<f32>`) in meaning, inputs out of the domain
//! included (tested on every model in `tests/batch/`); numerically they differ only by the
//! fast elementary functions' few ulp.
//!
//! Standalone shadowing terms take several cosines: no kernel (an error). Cook-Torrance with
//! the exact Beckmann Smith terms vectorises too: their `erfc` is `math::fast::erfc`
//! (branch-free, <= 4 f32 epsilons; issue 30).
//!
//! Cook-Torrance (`cook_torrance`): a fused kernel per (D, G, F) only for the combinations of
//! its rule (each D with its own vectorised Smith terms, any F; the D-free shadowing terms
//! with `f` = `none` or `schlick`); the others run a generic path of one vectorised pass per
//! part, with the same values (`Kernel::specialised` says which), so a new part adds kernels
//! linearly, not one per combination of the others.

/// The vectorisable elementary functions (moved to `crate::math::fast`; kept here by name).
pub use crate::math::fast as math;

mod cook_torrance;
mod ggx_closed;
pub mod per_element;
pub mod sample;

use crate::brdf::cook_torrance::CookTorrance;
use crate::brdf::phong::LobeBrdf;
use crate::error::{Error, Result};
use crate::math::{Fast, FastFma, Math};
use crate::model::{Kind, PipeOps};
use crate::plan::{
    BrdfForm, BrdfPlan, DistForm, EnvForm, FresnelForm, LobeForm, Plan, with_brdf, with_dist,
    with_env, with_fresnel, with_lobe,
};
use rayon::prelude::*;
use serde::Serialize;
use std::sync::OnceLock;

/// An instruction set a kernel can run with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Isa {
    /// AVX-512 (F, VL, DQ, BW) with FMA: 16 f32 lanes.
    Avx512,
    /// AVX2 with FMA: 8 lanes.
    Avx2Fma,
    /// The x86-64 baseline, SSE2: 4 lanes (also the only option on other architectures,
    /// where the compiler's default vector width applies).
    Sse2,
    /// No SIMD kernel: the scalar model, element by element.
    Scalar,
}

impl Isa {
    /// The best SIMD instruction set this CPU supports (detected once, then cached).
    #[inline]
    pub fn best() -> Self {
        static BEST: OnceLock<Isa> = OnceLock::new();
        *BEST.get_or_init(Self::detect)
    }

    fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512vl")
                && std::is_x86_feature_detected!("avx512dq")
                && std::is_x86_feature_detected!("avx512bw")
                && std::is_x86_feature_detected!("fma")
            {
                return Isa::Avx512;
            }
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                return Isa::Avx2Fma;
            }
        }
        Isa::Sse2
    }

    /// Every SIMD instruction set this CPU supports, best first (no allocation: a slice of a
    /// constant list, from the cached best).
    #[inline]
    pub fn available() -> &'static [Isa] {
        const ALL: [Isa; 3] = [Isa::Avx512, Isa::Avx2Fma, Isa::Sse2];
        let best = ALL.iter().position(|i| *i == Self::best()).unwrap_or(2);
        &ALL[best..]
    }

    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Avx512 => "avx512",
            Isa::Avx2Fma => "avx2+fma",
            Isa::Sse2 => "sse2",
            Isa::Scalar => "scalar",
        }
    }

    /// Whether its kernels use fused multiply-adds (`math::FastFma`): AVX2+FMA and AVX-512
    /// give identical bits; SSE2 rounds twice where they fuse.
    pub fn fma(self) -> bool {
        matches!(self, Isa::Avx512 | Isa::Avx2Fma)
    }

    /// f32 lanes per vector register.
    pub fn lanes(self) -> usize {
        match self {
            Isa::Avx512 => 16,
            Isa::Avx2Fma => 8,
            Isa::Sse2 => 4,
            Isa::Scalar => 1,
        }
    }
}

// ---------- per-element ops: a family's formula with the fast backend ----------

/// An operation on one cosine.
pub trait Op1: Send + Sync + 'static {
    /// Whether the kernel runs with flush-to-zero set (`FlushToZero`; for lobes,
    /// `LobeForm::batch_ftz`).
    fn ftz(&self) -> bool {
        true
    }
    /// Multiply-pipe operations and divisions per element on the FMA instruction sets, where
    /// the family counts them (`LobeForm::batch_pipe_ops`).
    fn pipe_ops(&self) -> Option<PipeOps> {
        None
    }
    fn f<M: Math<f32>>(&self, x: f32) -> f32;
}

/// An operation on two inputs (a split-sum term: `cos_v`, `alpha`).
pub trait Op2: Send + Sync + 'static {
    fn f<M: Math<f32>>(&self, x: f32, y: f32) -> f32;
}

/// An operation on a direction pair (wi, wo), not normalised. `NEAR`: both are known to be
/// of squared length within `vec3::NEAR_ONE` of 1 (`vec3::pair_setup_as`; the same value).
pub trait Op6: Send + Sync + 'static {
    fn f<M: Math<f32>, const NEAR: bool>(&self, wi: [f32; 3], wo: [f32; 3]) -> f32;
}

/// A lobe with `Lobe::eval`'s rules ([`LobeForm::batch`]).
struct LobeOp<L>(L);
impl<L: LobeForm> Op1 for LobeOp<L> {
    // Read once, by `Kernel::new`.
    fn ftz(&self) -> bool {
        self.0.batch_ftz()
    }
    fn pipe_ops(&self) -> Option<PipeOps> {
        self.0.batch_pipe_ops()
    }
    #[inline(always)]
    fn f<M: Math<f32>>(&self, c: f32) -> f32 {
        self.0.batch::<M>(c)
    }
}

/// A distribution with `Distribution::eval`'s rules.
struct DistOp<D>(D);
impl<D: DistForm> Op1 for DistOp<D> {
    fn ftz(&self) -> bool {
        self.0.batch_ftz()
    }
    fn pipe_ops(&self) -> Option<PipeOps> {
        self.0.batch_pipe_ops()
    }
    #[inline(always)]
    fn f<M: Math<f32>>(&self, c: f32) -> f32 {
        self.0.batch::<M>(c)
    }
}

/// A Fresnel term (its own rules for NaN and out-of-range cosines).
struct FresnelOp<F>(F);
impl<F: FresnelForm> Op1 for FresnelOp<F> {
    #[inline(always)]
    fn f<M: Math<f32>>(&self, c: f32) -> f32 {
        self.0.f::<f32, M>(c)
    }
}

/// A split-sum term with `Env::e`'s rules (`plan::env_args`).
struct EnvOp<E>(E);
impl<E: EnvForm> Op2 for EnvOp<E> {
    #[inline(always)]
    fn f<M: Math<f32>>(&self, v: f32, a: f32) -> f32 {
        let (v, a) = crate::plan::env_args_batch(v, a);
        self.0.e::<f32, M>(v, a)
    }
}

/// A BRDF on the pair set-up of the scalar `Pair::new` (in f64, branch-free).
struct BrdfOp<B>(B);
impl<B: BrdfForm> Op6 for BrdfOp<B> {
    #[inline(always)]
    fn f<M: Math<f32>, const NEAR: bool>(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        let (valid, p) = crate::vec3::pair_setup_as::<f32, NEAR>(wi, wo);
        let v = self.0.at_pair::<f32, M>(&p);
        if valid { v } else { 0.0 }
    }
}

#[inline(always)]
fn map1_body<O: Op1, M: Math<f32>>(op: &O, x: &[f32], out: &mut [f32]) {
    for (o, &c) in out.iter_mut().zip(x) {
        *o = op.f::<M>(c);
    }
}

#[inline(always)]
fn map2_body<O: Op2, M: Math<f32>>(op: &O, x: [&[f32]; 2], out: &mut [f32]) {
    for ((o, &a), &b) in out.iter_mut().zip(x[0]).zip(x[1]) {
        *o = op.f::<M>(a, b);
    }
}

/// Pairs per block of [`map6_body`]: the block's columns stay in L1 between its test and
/// its loop.
const NEAR_BLOCK: usize = 256;

/// `op` over the pairs, a block of [`NEAR_BLOCK`] at a time: where every `wi` and `wo` of the
/// block is of unit length to within [`near_one_all`]'s test (what callers pass), the loop
/// normalising the directions by the series alone (`Op6::f` with `NEAR`; the half vector
/// keeps `vec3::rsqrt64`), else the loop choosing per direction (`vec3::inv_len`); each
/// value is the same either way, so none depends on its neighbours.
/// (Folding the test into the loop, with the block redone where it fails, was slower: 3.9
/// against 3.45 ns an element for GGX Cook-Torrance, the loop alone 3.2.)
#[inline(always)]
fn map6_body<O: Op6, M: Math<f32>>(op: &O, w: [&[f32]; 6], out: &mut [f32]) {
    let n = out.len();
    let mut lo = 0;
    while lo < n {
        let hi = (lo + NEAR_BLOCK).min(n);
        let w = w.map(|x| &x[lo..hi]);
        let out = &mut out[lo..hi];
        if near_one_all::<M>(w) {
            map6_loop::<O, M, true>(op, w, out)
        } else {
            map6_loop::<O, M, false>(op, w, out)
        }
        lo = hi;
    }
}

/// The six columns cut to `n` elements as six slices: LLVM then knows every length, and the
/// loops over them vectorise without bounds checks (indexing the array of slices did not).
#[inline(always)]
#[allow(clippy::type_complexity)]
fn six(w: [&[f32]; 6], n: usize) -> (&[f32], &[f32], &[f32], &[f32], &[f32], &[f32]) {
    (
        &w[0][..n],
        &w[1][..n],
        &w[2][..n],
        &w[3][..n],
        &w[4][..n],
        &w[5][..n],
    )
}

/// Whether the f32 squared length of every `wi` and `wo` of these columns is within `2^-21`
/// of 1, which puts their f64 squared lengths (`vec3::pair_setup`'s) within
/// `vec3::NEAR_ONE` (`2^-20`) of 1: however its additions round (fused or not), the f32 sum
/// is within `3 * 2^-24 (1 + 2^-21)` of the exact one, the f64 sum within `2^-51`. NaN and
/// infinite components fail it. Branch-free.
#[inline(always)]
pub(crate) fn near_one_all<M: Math<f32>>(w: [&[f32]; 6]) -> bool {
    let n = w[0].len();
    let (a, b, c, d, e, f) = six(w, n);
    let tol = (crate::vec3::NEAR_ONE * 0.5) as f32;
    let near = |x: f32, y: f32, z: f32| (M::madd(x, x, M::madd(y, y, z * z)) - 1.0).abs() <= tol;
    let mut far = 0u32;
    for i in 0..n {
        far |= u32::from(!(near(a[i], b[i], c[i]) & near(d[i], e[i], f[i])));
    }
    far == 0
}

#[inline(always)]
fn map6_loop<O: Op6, M: Math<f32>, const NEAR: bool>(op: &O, w: [&[f32]; 6], out: &mut [f32]) {
    let n = out.len();
    let (a, b, c, d, e, f) = six(w, n);
    for i in 0..n {
        out[i] = op.f::<M, NEAR>([a[i], b[i], c[i]], [d[i], e[i], f[i]]);
    }
}

macro_rules! isa_variants {
    ($body:ident, $avx512:ident, $avx2:ident, $plain:ident, $bound:ident, $input:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
        unsafe fn $avx512<O: $bound>(op: &O, x: $input, out: &mut [f32]) {
            $body::<O, FastFma>(op, x, out)
        }
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn $avx2<O: $bound>(op: &O, x: $input, out: &mut [f32]) {
            $body::<O, FastFma>(op, x, out)
        }
        fn $plain<O: $bound>(op: &O, x: $input, out: &mut [f32]) {
            $body::<O, Fast>(op, x, out)
        }
    };
}

isa_variants!(map1_body, map1_avx512, map1_avx2, map1_plain, Op1, &[f32]);
isa_variants!(
    map2_body,
    map2_avx512,
    map2_avx2,
    map2_plain,
    Op2,
    [&[f32]; 2]
);
isa_variants!(
    map6_body,
    map6_avx512,
    map6_avx2,
    map6_plain,
    Op6,
    [&[f32]; 6]
);

/// Flush-to-zero for the duration of a kernel call (the denormal policy): results below
/// 2^-126 become 0 instead of subnormal numbers, which cost 1.8x on `power16` at n = 20 (its
/// base^16 underflows near c = 0.2). Subnormal inputs are read as they are (no DAZ), so the
/// f64 pair set-up of tiny vectors is unchanged. The previous MXCSR is restored on drop
/// (panics included). Other architectures: no change.
struct FlushToZero {
    #[cfg(target_arch = "x86_64")]
    saved: u32,
}

impl FlushToZero {
    #[inline]
    fn on() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            let mut saved = 0u32;
            // SAFETY: stmxcsr stores the 32-bit MXCSR into `saved`, a valid u32 on this stack
            // frame; ldmxcsr loads a value whose reserved bits are those MXCSR just had (only
            // bit 15, FTZ, is added), so it cannot fault.
            unsafe {
                std::arch::asm!("stmxcsr [{}]", in(reg) &mut saved, options(nostack, preserves_flags));
                let ftz = saved | (1 << 15);
                std::arch::asm!("ldmxcsr [{}]", in(reg) &ftz, options(nostack, preserves_flags, readonly));
            }
            Self { saved }
        }
        #[cfg(not(target_arch = "x86_64"))]
        Self {}
    }
}

impl Drop for FlushToZero {
    #[inline]
    fn drop(&mut self) {
        // SAFETY: restores the MXCSR value `on` read, which was valid then.
        #[cfg(target_arch = "x86_64")]
        unsafe {
            std::arch::asm!("ldmxcsr [{}]", in(reg) &self.saved, options(nostack, preserves_flags, readonly));
        }
    }
}

fn run1<O: Op1>(isa: Isa, op: &O, x: &[f32], out: &mut [f32]) {
    match isa {
        // SAFETY: `Kernel` only passes an ISA that `Isa::available` reported.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { map1_avx512(op, x, out) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { map1_avx2(op, x, out) },
        _ => map1_plain(op, x, out),
    }
}

fn run2<O: Op2>(isa: Isa, op: &O, x: [&[f32]; 2], out: &mut [f32]) {
    match isa {
        // SAFETY: as in `run1`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { map2_avx512(op, x, out) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { map2_avx2(op, x, out) },
        _ => map2_plain(op, x, out),
    }
}

fn run6<O: Op6>(isa: Isa, op: &O, w: [&[f32]; 6], out: &mut [f32]) {
    match isa {
        // SAFETY: as in `run1`.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe { map6_avx512(op, w, out) },
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => unsafe { map6_avx2(op, w, out) },
        _ => map6_plain(op, w, out),
    }
}

// ---------- kernels ----------

/// The inputs of one batch.
#[derive(Clone, Copy, Debug)]
pub enum Input<'a> {
    /// Cosines (lobes: `cos`; distributions: `cos_h`; Fresnel: `cos_vh`).
    Cos(&'a [f32]),
    /// Direction components `wi_x, wi_y, wi_z, wo_x, wo_y, wo_z` (full BRDFs).
    Dirs([&'a [f32]; 6]),
    /// `cos_v` and `alpha` (split-sum terms, `Kind::Env`).
    Env([&'a [f32]; 2]),
}

impl Input<'_> {
    /// The number of elements (of the first slice).
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> usize {
        match self {
            Input::Cos(x) => x.len(),
            Input::Dirs(w) => w[0].len(),
            Input::Env(x) => x[0].len(),
        }
    }
    /// Elements `lo..hi` of every slice.
    pub fn slice(&self, lo: usize, hi: usize) -> Self {
        match *self {
            Input::Cos(x) => Input::Cos(&x[lo..hi]),
            Input::Dirs(w) => Input::Dirs(w.map(|s| &s[lo..hi])),
            Input::Env(x) => Input::Env(x.map(|s| &s[lo..hi])),
        }
    }
}

/// A compiled kernel (one family, monomorphised; the ISA chosen per call).
pub trait Imp: Send + Sync {
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]);
    fn simd(&self) -> bool {
        true
    }
    /// Whether it runs with flush-to-zero set (the denormal policy, `Kernel::flush_to_zero`).
    fn ftz(&self) -> bool {
        true
    }
    /// Multiply-pipe operations and divisions per element on the FMA instruction sets, where
    /// counted.
    fn pipe_ops(&self) -> Option<PipeOps> {
        None
    }
    /// Whether it is monomorphised for its model's concrete families (`Kernel::specialised`).
    fn specialised(&self) -> bool {
        true
    }
}

struct Map1<O>(O);
impl<O: Op1> Imp for Map1<O> {
    fn pipe_ops(&self) -> Option<PipeOps> {
        self.0.pipe_ops()
    }
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]) {
        if let Input::Cos(x) = *input {
            run1(isa, &self.0, x, out)
        }
    }
    fn ftz(&self) -> bool {
        self.0.ftz()
    }
}

struct Map2<O> {
    op: O,
    simd: bool,
}
impl<O: Op2> Imp for Map2<O> {
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]) {
        if let Input::Env(x) = *input {
            run2(isa, &self.op, x, out)
        }
    }
    fn simd(&self) -> bool {
        self.simd
    }
}

struct Map6<O> {
    op: O,
    simd: bool,
}
impl<O: Op6> Imp for Map6<O> {
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]) {
        if let Input::Dirs(w) = *input {
            run6(isa, &self.op, w, out)
        }
    }
    fn simd(&self) -> bool {
        self.simd
    }
}

/// The kernel of a BRDF family.
pub fn brdf_kernel<B: BrdfForm>(b: B) -> Box<dyn Imp> {
    Box::new(Map6 {
        simd: b.simd(),
        op: BrdfOp(b),
    })
}

/// Cook-Torrance's kernel: specialised (its D, G and F as concrete families, one fused loop)
/// for the combinations of the rule in `batch::cook_torrance`'s header, the generic path (a
/// vectorised pass per part) for the others.
pub fn cook_torrance_kernel(ct: &CookTorrance) -> Box<dyn Imp> {
    cook_torrance::kernel(ct, CtPath::Rule)
}

/// Phong or Blinn-Phong with its lobe as a concrete family.
pub fn lobe_brdf_kernel(b: &LobeBrdf) -> Box<dyn Imp> {
    with_lobe!(&b.lobe, l => brdf_kernel(b.with_lobe(*l)))
}

/// The kernel of a plan; `None` for shadowing terms (several cosines per element).
/// `ct` chooses Cook-Torrance's path.
fn kernel_of(plan: &Plan, ct: CtPath) -> Option<Box<dyn Imp>> {
    Some(match plan {
        Plan::Lobe(l) => with_lobe!(l, x => Box::new(Map1(LobeOp(*x))) as Box<dyn Imp>),
        Plan::Distribution(d) => with_dist!(d, x => Box::new(Map1(DistOp(*x))) as Box<dyn Imp>),
        Plan::Fresnel(f) => with_fresnel!(f, x => Box::new(Map1(FresnelOp(*x))) as Box<dyn Imp>),
        // Composites are instantiated with their parts' concrete families (Cook-Torrance
        // where its rule says, else its generic path; a composite not listed here would run
        // with its parts' plans, matched per element: correct, slower).
        Plan::Brdf(BrdfPlan::CookTorrance(c)) => cook_torrance::kernel(c, ct),
        Plan::Brdf(BrdfPlan::LobeBrdf(b)) => lobe_brdf_kernel(b),
        Plan::Brdf(b) => with_brdf!(b, x => brdf_kernel(*x)),
        Plan::Env(e) => {
            let simd = e.simd();
            with_env!(e, x => Box::new(Map2 { op: EnvOp(*x), simd }) as Box<dyn Imp>)
        }
        Plan::Shadowing(_) => return None,
    })
}

/// How a Cook-Torrance kernel is built ([`Kernel::from_plan_path`]; other models ignore it).
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CtPath {
    /// The rule of `batch::cook_torrance`: specialised where it says, else generic.
    Rule,
    /// Always the generic path (a vectorised pass per part).
    Generic,
    /// The plan's parts matched per element (what runs with an energy compensation).
    PerElement,
}

/// The least estimated single-thread time of the remaining work for which `Kernel::eval_par`
/// uses rayon's pool (see `examples/par_cutoff.rs` for the measurement behind it).
pub const PAR_MIN_WORK: std::time::Duration = std::time::Duration::from_micros(PAR_MIN_WORK_US);
const PAR_MIN_WORK_US: u64 = 100;

/// A model compiled for batch evaluation.
pub struct Kernel {
    id: &'static str,
    kind: Kind,
    imp: Box<dyn Imp>,
    /// Whether calls run with flush-to-zero set (`flush_to_zero`).
    ftz: bool,
    /// Whether a SIMD kernel exists (`imp.simd()`, read once).
    simd: bool,
    /// Whether it is monomorphised for the model's concrete families (`imp.specialised()`).
    specialised: bool,
    /// The instruction set `eval` and `eval_par` run (`Isa::best()`, or the baseline loop for
    /// a scalar fallback, which ignores it), decided once: a call then does no detection, no
    /// check of a caller's choice and no virtual call before the kernel's own.
    run_isa: Isa,
}

impl Kernel {
    /// The kernel of a grey model spec (a coloured one is an error: build one kernel per
    /// channel from `spec.channel_specs()`). Shadowing terms take several cosines: they are
    /// not batchable and are an error here.
    pub fn new(spec: &crate::spec::ModelSpec) -> Result<Self> {
        Self::from_plan(spec.id(), spec.plan()?)
    }

    /// The kernel of a plan (`id` names it in messages).
    pub fn from_plan(id: &'static str, plan: &Plan) -> Result<Self> {
        Self::from_plan_path(id, plan, CtPath::Rule)
    }

    /// As [`Self::from_plan`], with Cook-Torrance's path chosen (tests hold the paths equal
    /// bit for bit, `examples/ct_generic.rs` times them).
    #[doc(hidden)]
    pub fn from_plan_path(id: &'static str, plan: &Plan, ct: CtPath) -> Result<Self> {
        let imp = kernel_of(plan, ct).ok_or_else(|| Error::WrongKind {
            model: id.into(),
            expected: "lobe, distribution, fresnel, brdf or env".into(),
            found: "shadowing".into(),
        })?;
        let simd = imp.simd();
        Ok(Self {
            id,
            kind: plan.kind(),
            ftz: imp.ftz(),
            simd,
            specialised: imp.specialised(),
            run_isa: if simd { Isa::best() } else { Isa::Sse2 },
            imp,
        })
    }

    /// The model id.
    pub fn id(&self) -> &'static str {
        self.id
    }

    /// The kind of input it takes.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// Whether a SIMD kernel exists (else the scalar model runs per element).
    #[inline]
    pub fn simd(&self) -> bool {
        self.simd
    }

    /// Whether the kernel is monomorphised for its model's concrete families: every kernel
    /// but Cook-Torrance's outside the rule of `batch::cook_torrance` (its generic path, one
    /// vectorised pass per part, the same values) and with an energy compensation (the
    /// plan's parts matched per element).
    pub fn specialised(&self) -> bool {
        self.specialised
    }

    /// Whether its calls run with flush-to-zero set (the denormal policy): results below
    /// 2^-126 become 0 and no time is lost to subnormal numbers (a subnormal result cost
    /// `power16` 1.8x at n = 20). The switch (two MXCSR writes, restored on return, panics
    /// included) costs about 8 ns a call and varied between processes, so the lobes whose
    /// batch form makes subnormals only from rare inputs, or never, run without it
    /// (`LobeForm::batch_ftz`: the power forms, `power16` clamping its base at
    /// `lobes::power::base_min` and subtracting that base's power; `cubic`, `schlick`; the
    /// spherical Gaussians, whose `exp2` is built from bits) and may return a subnormal value
    /// where a flushing kernel gives 0; so does `ggx` (`DistForm::batch_ftz`), whose batch form
    /// has no subnormal step.
    /// Other architectures: no switch.
    pub fn flush_to_zero(&self) -> bool {
        self.ftz
    }

    /// Overrides the denormal policy (for measurements: `examples/ftz_band.rs` times both
    /// ways).
    pub fn set_flush_to_zero(&mut self, on: bool) {
        self.ftz = on;
    }

    /// Runs the kernel on this thread under the denormal policy.
    #[inline]
    fn run(&self, isa: Isa, input: &Input, out: &mut [f32]) {
        let _ftz = self.ftz.then(FlushToZero::on);
        self.imp.run(isa, input, out);
    }

    /// Multiply-pipe operations (multiplies and fused multiply-adds) and divisions per
    /// element of this kernel where its family counts them (a vectorised `exp2` whose polynomial the
    /// registry's `Ops` do not see: `LobeForm::batch_pipe_ops`), on an instruction set with
    /// FMA; `None` elsewhere (other families, SSE2, scalar fallbacks).
    pub fn pipe_ops(&self) -> Option<PipeOps> {
        if self.simd && self.run_isa.fma() {
            self.imp.pipe_ops()
        } else {
            None
        }
    }

    /// The instruction set `eval` uses.
    #[inline]
    pub fn isa(&self) -> Isa {
        if self.simd() {
            Isa::best()
        } else {
            Isa::Scalar
        }
    }

    #[inline]
    fn check(&self, input: &Input, out: &[f32]) -> Result<()> {
        let ok_kind = matches!(
            (self.kind, input),
            (Kind::Brdf, Input::Dirs(_))
                | (Kind::Env, Input::Env(_))
                | (
                    Kind::Lobe | Kind::Distribution | Kind::Fresnel,
                    Input::Cos(_)
                )
        );
        if !ok_kind {
            return Err(Error::WrongKind {
                model: self.id.into(),
                expected: match self.kind {
                    Kind::Brdf => "six direction slices".into(),
                    Kind::Env => "two slices (cos_v, alpha)".into(),
                    _ => "one slice of cosines".into(),
                },
                found: "the other input shape".into(),
            });
        }
        let lens_ok = match input {
            Input::Cos(x) => x.len() == out.len(),
            Input::Dirs(w) => w.iter().all(|s| s.len() == out.len()),
            Input::Env(x) => x.iter().all(|s| s.len() == out.len()),
        };
        if !lens_ok {
            return Err(Error::Domain {
                input: "batch".into(),
                reason: format!("input and output lengths differ (output {})", out.len()),
            });
        }
        Ok(())
    }

    /// Evaluates with the best instruction set, on this thread.
    #[inline]
    pub fn eval(&self, input: Input, out: &mut [f32]) -> Result<()> {
        self.check(&input, out)?;
        self.run(self.run_isa, &input, out);
        Ok(())
    }

    /// Evaluates with a given instruction set (one of `Isa::available()`, or `Isa::Scalar`,
    /// which runs the baseline loop). Errors if the CPU lacks it.
    #[inline]
    pub fn eval_with(&self, isa: Isa, input: Input, out: &mut [f32]) -> Result<()> {
        self.check(&input, out)?;
        if isa != Isa::Scalar && !Isa::available().contains(&isa) {
            return Err(Error::Domain {
                input: "isa".into(),
                reason: format!("this CPU does not support {}", isa.name()),
            });
        }
        self.run(
            if isa == Isa::Scalar { Isa::Sse2 } else { isa },
            &input,
            out,
        );
        Ok(())
    }

    /// Evaluates with the best instruction set, split across rayon's threads in chunks of
    /// 16384 elements when the work is worth it: the first chunk is timed on this thread, and
    /// the rest runs on this thread too when it would take less than [`PAR_MIN_WORK`] (waking
    /// the pool costs more than it saves below that; measured by `examples/par_cutoff.rs`).
    /// Results are the same either way (element-wise kernels).
    pub fn eval_par(&self, input: Input, out: &mut [f32]) -> Result<()> {
        self.check(&input, out)?;
        const CHUNK: usize = 16384;
        let isa = self.run_isa;
        let n = input.len();
        let first = n.min(CHUNK);
        let t0 = std::time::Instant::now();
        self.run(isa, &input.slice(0, first), &mut out[..first]);
        let rest = n - first;
        if rest == 0 {
            return Ok(());
        }
        let per_chunk = t0.elapsed();
        let estimate = per_chunk.mul_f64(rest as f64 / first as f64);
        let (input, out) = (input.slice(first, n), &mut out[first..]);
        if estimate < PAR_MIN_WORK || rayon::current_num_threads() < 2 {
            self.run(isa, &input, out);
        } else {
            out.par_chunks_mut(CHUNK).enumerate().for_each(|(i, o)| {
                let lo = i * CHUNK;
                self.run(isa, &input.slice(lo, lo + o.len()), o);
            });
        }
        Ok(())
    }
}
