//! The family traits: what a model family implements (its formula, once, generic over
//! precision and math backend; its WGSL call; its metadata), the defaults they share, and
//! [`Scalar`], a family behind the scalar model traits.
//!
//! A leaf of the registration: it imports only the modules below every family (`math`,
//! `model`, `params`, `real`, `sample`, `vec3`, `wgsl`), never `plan`, a family or the
//! registry. `plan` re-exports everything here (`fastbrdf::plan::LobeForm` is this
//! `LobeForm`) and generates the plan enums from its family lists; a family file implements
//! one of these traits and builds a `plan::Plan` in its `ENTRY`.

use crate::math::{Exact, Math};
use crate::model::{self, PipeOps, ShadowInput};
use crate::real::Real;
use crate::sample::{CosDist, Strategy};
use crate::vec3::{COS_MIN, Pair, V3};
use crate::wgsl::Emit;
use std::fmt::Debug;

/// [`LobeForm::batch`]'s default: clamp `c` into [0, 1], `at`, NaN gives 0.
#[inline(always)]
pub fn clamped_batch<L: LobeForm, M: Math<f32>>(lobe: &L, c: f32) -> f32 {
    // The clamp keeps NaN (`0 > c ? 0 : c` and `1 < x ? 1 : x`: one maxps and one minps
    // each), every lobe maps a NaN argument to NaN or 0, and the final `v > 0 ? v : 0` (one
    // maxps; lobes are non-negative) turns that into the rule's 0: the NaN rule costs no
    // separate compare and blend.
    let x = if 0.0 > c { 0.0 } else { c };
    let x = if 1.0 < x { 1.0 } else { x };
    let v = lobe.at::<f32, M>(x);
    if L::NAN_TO_ZERO || v > 0.0 { v } else { 0.0 }
}

/// [`DistForm::batch`]'s default, `Distribution::eval`'s rules: `cos_h > 1` is treated as 1,
/// NaN and `cos_h < COS_MIN` give 0, `sin^2` as `(1 - c)(1 + c)`.
#[inline(always)]
pub fn clamped_dist_batch<D: DistForm, M: Math<f32>>(dist: &D, c: f32) -> f32 {
    let cc = crate::real::min1(c);
    above_cos_min(c, dist.d::<f32, M>(cc, (1.0 - cc) * (1.0 + cc)))
}

/// `v` where the raw cosine `c` is at least `COS_MIN`, else 0 (NaN included): the last step
/// of every distribution's batch form (`Distribution::eval`'s cut).
#[inline(always)]
pub fn above_cos_min(c: f32, v: f32) -> f32 {
    if c >= COS_MIN as f32 { v } else { 0.0 }
}

/// `min(c, 1)` and `1 - min(c, 1)^2` for the distributions' batch forms: one fused
/// multiply-add on the FMA instruction sets (exact product, one rounding, so no cancellation
/// near 1), `(1 - c)(1 + c)` on SSE2.
#[inline(always)]
pub fn clamp_sin2<M: Math<f32>>(c: f32) -> (f32, f32) {
    let cc = crate::real::min1(c);
    let s2 = if M::FMA {
        M::madd(-cc, cc, 1.0)
    } else {
        (1.0 - cc) * (1.0 + cc)
    };
    (cc, s2)
}

/// A function of one cosine (a specular lobe).
pub trait LobeForm: Copy + Debug + Send + Sync + 'static {
    /// The WGSL functions of its twin: the `.wgsl` file beside the family's Rust file
    /// (`include_str!`), or `""` where there is none. Families sharing a file give it each
    /// (the library takes it once). See `plan::library_sources`.
    const WGSL: &'static str;
    /// The registry id this instance was built as (for WGSL names and messages).
    fn id(&self) -> &'static str;
    /// The value at `c`, already clamped to [0, 1] (see [`model::Lobe::eval`]); the batch
    /// kernels also pass NaN through, for which it must give NaN or 0 (the kernel then makes
    /// it 0, see `NAN_TO_ZERO`).
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T;
    /// Whether `at(NaN)` is exactly 0 (a `pos`/select inside already applies the NaN rule), so
    /// the batch kernel needs no final `max(0, v)`.
    const NAN_TO_ZERO: bool = false;
    /// The batch kernel's value at a raw cosine: [`model::Lobe::eval`]'s rules (clamp to
    /// [0, 1], NaN gives 0) around `at`, branch-free. A family may fold the rules into its
    /// formula where that saves vector operations (issue 13: the power forms, the cubic and
    /// Schlick's lobe clamp once instead of twice); the batch tests hold every override to
    /// the scalar model on NaN, infinities and out-of-range cosines.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        clamped_batch::<Self, M>(self, c)
    }
    /// Whether the batch kernel runs with flush-to-zero set (results below 2^-126 become 0,
    /// and no time is lost to subnormal numbers). The switch costs two MXCSR writes, about
    /// 8 ns a call (8% of a 4096-cosine `power4` batch), and its cost varied between
    /// processes (`power16` at 23.6 or 18.6 G/s, bimodal over `fastbrdf bench` runs), so a
    /// family whose batch form makes subnormals only from rare inputs (cosines below about
    /// 1e-30, within a few ulp of a zero crossing, or in a band of cosines under 2e-4 of
    /// [0, 1] wide) or never says false; its kernel may then return a subnormal value where a
    /// flushing one gives 0.
    fn batch_ftz(&self) -> bool {
        true
    }
    /// The batch kernel's multiply-pipe operations (multiplies and fused multiply-adds) and
    /// divisions per element on the FMA instruction sets, where the registry's `Ops` cannot
    /// give them: a kernel whose vectorised `exp2` is a polynomial of its own length
    /// (`math::fast::EXP2_NONPOS_TIMES_MULS`). `fastbrdf bench` measures such a
    /// kernel against the FMA pipes or the divider with this count. `None` (the default):
    /// not counted.
    fn batch_pipe_ops(&self) -> Option<PipeOps> {
        None
    }
    /// The largest cosine below which the lobe is identically zero (0 when it has none).
    fn zero_below(&self) -> f64 {
        0.0
    }
    /// Cosines where the lobe is not smooth (junctions of piecewise forms).
    fn kinks(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Whether the lobe carries its own energy normalisation (seed 001's `coef(n)`).
    fn normalised(&self) -> bool {
        false
    }
    /// The WGSL call of the lobe's twin on the expression `c`.
    fn wgsl(&self, c: &str, e: &Emit) -> String;
    /// The density proportional to the lobe on `c` in [0, 1], where it inverts in closed
    /// form (`pow`, the power-g forms, the spherical Gaussians): Phong's and Blinn-Phong's
    /// `lobe` strategy. `None`: they sample the exact twin `pow` at the same `n` (`twin`).
    fn cos_dist(&self) -> Option<CosDist> {
        None
    }
    /// Runtime mode: the energy normalisation of Phong and Blinn-Phong with this lobe,
    /// `coef(n) = 1 / (2 pi Int(n))`, `Int(n) = integral_0^1 lobe(c) c dc`, as a WGSL
    /// expression of `p_n` (usually [`norm_by_integral`]: `runtime.wgsl`'s
    /// `fb_rt_lobe_integral_<id>`, which a new lobe must add there).
    fn wgsl_norm(&self, e: &Emit) -> String;
}

/// A microfacet distribution `D(cos theta_h)`.
pub trait DistForm: Copy + Debug + Send + Sync + 'static {
    /// The WGSL functions of its twin: the `.wgsl` file beside the family's Rust file
    /// (`include_str!`), or `""` where there is none. Families sharing a file give it each
    /// (the library takes it once). See `plan::library_sources`.
    const WGSL: &'static str;
    /// Whether `D` depends on the half vector only through `alpha^2 cos^2 theta_h + sin^2
    /// theta_h`-shaped slopes `tan^2 theta_h / alpha^2` (GGX, Beckmann): then its anisotropic
    /// form at `alpha_x`, `alpha_y` is this `d` at `alpha = sqrt(alpha_x alpha_y)` with
    /// `sin2_h` replaced by `h_x^2 alpha_y / alpha_x + h_y^2 alpha_x / alpha_y`
    /// (`cook-torrance`'s `alpha_x`, `alpha_y`; see `brdf::cook_torrance`).
    const ANISO: bool = false;
    /// `D` at `cos_h` in `[COS_MIN, 1]` with `sin2_h = sin^2 theta_h`.
    fn d<T: Real, M: Math<T>>(&self, cos_h: T, sin2_h: T) -> T;
    /// The batch kernels' value at any f32 `cos_h`, with `Distribution::eval`'s rules; the
    /// default is [`clamped_dist_batch`]. A family may fold the rules into its formula (as
    /// [`LobeForm::batch`]); the batch tests hold it to the scalar model everywhere.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        clamped_dist_batch::<Self, M>(self, c)
    }
    /// Whether the batch kernel runs with flush-to-zero set, as [`LobeForm::batch_ftz`].
    fn batch_ftz(&self) -> bool {
        true
    }
    /// The batch kernel's multiply-pipe operations and divisions per element, as
    /// [`LobeForm::batch_pipe_ops`].
    fn batch_pipe_ops(&self) -> Option<PipeOps> {
        None
    }
    /// The WGSL call on the expressions `c` (`cos_h`, in range) and `s2` (`sin^2`).
    fn wgsl(&self, c: &str, s2: &str, e: &Emit) -> String;
    /// How `cook-torrance` samples half vectors for this D (see [`DistSampler`]).
    fn sampler(&self) -> DistSampler;
    /// The id of this D's own Smith shadowing-masking term (the one derived from its slope
    /// distribution: `smith` for Beckmann and its approximations, `smith-ggx` for GGX):
    /// `cook-torrance`'s `g` when not given (`brdf::cook_torrance::SMITH_OF`, which the
    /// parameter resolution reads, is checked against this for every distribution).
    fn smith(&self) -> &'static str;
}

/// How a distribution's half vectors are sampled inside `cook-torrance`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistSampler {
    /// The exact distribution at the family's (isotropic) `alpha`: `D cos` and visible-normal
    /// sampling of this D itself when `exact`, else of its exact twin (`twin`).
    pub micro: crate::sample::Micro,
    /// Whether `micro` has this D's shape (up to a constant factor).
    pub exact: bool,
    /// `D cos theta_h` normalised, inverted in closed form, for a non-exact D where one
    /// exists (`beckmann-pow`: `cos^(2/m^2 - 3)`, for m < 1).
    pub closed: Option<CosDist>,
}

/// A shadowing-masking term.
pub trait ShadowForm: Copy + Debug + Send + Sync + 'static {
    /// The WGSL functions of its twin: the `.wgsl` file beside the family's Rust file
    /// (`include_str!`), or `""` where there is none. Families sharing a file give it each
    /// (the library takes it once). See `plan::library_sources`.
    const WGSL: &'static str;
    /// Whether its batch kernel vectorises (every term now: the exact Beckmann Smith terms'
    /// `erfc` is `math::fast::erfc` since issue 30).
    const SIMD: bool = true;
    /// Whether it uses `cos_h` and `cos_vh` (the V-cavity, Kelemen).
    const HALF_VECTOR: bool = false;
    /// Whether it is a Smith term (exact or approximated) that depends on a direction only
    /// through `alpha^2 tan^2 theta`: then its anisotropic form is `g_pair` at
    /// `alpha = sqrt(alpha_x alpha_y)` on the stretched cosines
    /// `w_z / sqrt(w_z^2 + w_x^2 alpha_x / alpha_y + w_y^2 alpha_y / alpha_x)` (Heitz 2014,
    /// sec. 5; `cook-torrance`'s `alpha_x`, `alpha_y`).
    const ANISO: bool = false;
    /// The two-sided term on a valid pair's cosines (all positive, at most 1; `cos_l` may be
    /// `+inf` for the one-sided term of `v`): the formula, as Cook-Torrance uses it.
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, cos_h: T, cos_vh: T) -> T;
    /// `G`, in [0, 1], with the domain rules of a standalone term (see
    /// [`model::Shadowing::g`]): cosines that are NaN or `<= 0` give 0; without `cos_l`, the
    /// one-sided masking term of `v`.
    #[inline(always)]
    fn g<T: Real, M: Math<T>>(&self, s: &ShadowInput<T>) -> T {
        let z = T::zero();
        let l = s.cos_l.unwrap_or_else(T::infinity);
        let half_ok = !Self::HALF_VECTOR || (s.cos_h > z && s.cos_vh > z);
        if s.cos_v > z && l > z && half_ok {
            self.g_pair::<T, M>(s.cos_v, l, s.cos_h, s.cos_vh)
        } else {
            z
        }
    }
    /// The two-sided term's WGSL expression on `cos_v`, `cos_l`, `cos_h`, `cos_vh`.
    fn wgsl(&self, v: &str, l: &str, h: &str, vh: &str, e: &Emit) -> String;
}

/// A Fresnel term.
pub trait FresnelForm: Copy + Debug + Send + Sync + 'static {
    /// The WGSL functions of its twin: the `.wgsl` file beside the family's Rust file
    /// (`include_str!`), or `""` where there is none. Families sharing a file give it each
    /// (the library takes it once). See `plan::library_sources`.
    const WGSL: &'static str;
    /// Reflectance at `cos` (NaN or negative act as 0, above 1 as 1).
    fn f<T: Real, M: Math<T>>(&self, cos: T) -> T;
    /// The WGSL expression on `c` (non-negative).
    fn wgsl(&self, c: &str, e: &Emit) -> String;
}

/// A split-sum term of image-based lighting: a function of the view's cosine and the
/// roughness `alpha` (both inputs, like an engine's look-up table's axes).
pub trait EnvForm: Copy + Debug + Send + Sync + 'static {
    /// The WGSL functions of its twin (see [`FresnelForm::WGSL`]).
    const WGSL: &'static str;
    /// Whether its batch kernel vectorises (a quadrature loop does not).
    const SIMD: bool = true;
    /// The term at `cos_v` in [0, 1] and `alpha` in the documented range (the callers clamp).
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T;
    /// The WGSL expression on `v` and `a` (already clamped).
    fn wgsl(&self, v: &str, a: &str, e: &Emit) -> String;
}

/// `cos_v` clamped into [0, 1] (NaN to 0) and `alpha` into the documented range of
/// `params::ALPHA` (NaN to its minimum): the lenient rule of every `Env` model, applied
/// before the family's formula (scalar models, batch kernels and WGSL alike).
///
/// Written with generic selects, not `real::pos`/`min1`: in the scalar models (one call per
/// value, into libm's `exp2f` for `env-brdf-approx`) these compile to well-predicted branches,
/// and the concrete selects' `maxss`/`minss` made that path 1.9x slower. The batch kernels use
/// [`env_args_batch`], the same rule with the concrete selects (one `maxps`/`minps` each).
#[inline(always)]
pub fn env_args<T: Real>(cos_v: T, alpha: T) -> (T, T) {
    let (lo, hi) = crate::params::ALPHA.range();
    let d = alpha - T::c(lo);
    let a = if d > T::zero() { d } else { T::zero() } + T::c(lo);
    let v = if cos_v > T::zero() { cos_v } else { T::zero() };
    let v = if v < T::one() { v } else { T::one() };
    (v, a.min(T::c(hi)))
}

/// [`env_args`] for the batch kernels, bit for bit (tested), with `real::pos` and `min1`:
/// the generic selects there reach LLVM's vectoriser as mask blends (the kernel of
/// `env-brdf-approx` 4.3 -> 3.8 G/s).
#[inline(always)]
pub fn env_args_batch(cos_v: f32, alpha: f32) -> (f32, f32) {
    let (lo, hi) = crate::params::ALPHA.range();
    let a = crate::real::pos(alpha - lo as f32) + lo as f32;
    (crate::real::min1(crate::real::pos(cos_v)), a.min(hi as f32))
}

/// A full BRDF of a prepared direction pair.
pub trait BrdfForm: Copy + Debug + Send + Sync + 'static {
    /// The WGSL functions of its twin: the `.wgsl` file beside the family's Rust file
    /// (`include_str!`), or `""` where there is none. Families sharing a file give it each
    /// (the library takes it once). See `plan::library_sources`.
    const WGSL: &'static str;
    /// Whether its batch kernel vectorises.
    fn simd(&self) -> bool {
        true
    }
    /// The value on a pair from [`crate::vec3::pair_setup`]; any value when `valid` is false
    /// (the caller discards it), finite or not.
    fn at_pair<T: Real, M: Math<T>>(&self, p: &Pair<T>) -> T;
    /// The WGSL body of `fn fb_<id>(wi: vec3<f32>, wo: vec3<f32>) -> f32`.
    fn wgsl_body(&self, e: &Emit) -> String;
    /// Whether `f(wi, wo) = f(wo, wi)` (see [`model::Brdf::reciprocal`]).
    fn reciprocal(&self) -> bool {
        true
    }
    /// See [`model::Brdf::mirror_breaks`].
    fn mirror_breaks(&self) -> Vec<f64> {
        Vec::new()
    }
    /// See [`model::Brdf::half_breaks`].
    fn half_breaks(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Whether it claims energy conservation (albedo <= 1), checked by the white furnace.
    fn claims_energy(&self) -> bool {
        false
    }
    /// The sampling strategies it supports (`crate::sample`), its default first.
    fn strategies(&self) -> &'static [Strategy];
    /// A direction `wi` (any length, any side) drawn by strategy `s` (one of
    /// [`Self::strategies`]) given the unit `wo` above the horizon, or `None` (no sample).
    fn sample_wi<T: Real>(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<V3<T>>;
    /// The solid-angle density of [`Self::sample_wi`] at the unit `wi` given the unit `wo`.
    fn pdf_wi<T: Real>(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T;
    /// How far above 1 its albedo may read where it claims energy (0: never above 1; an
    /// energy-compensated BRDF aims at 1 and carries its table's error, `microfacet::ms`).
    fn furnace_tol(&self) -> f64 {
        0.0
    }
}

/// `coef(n) = 1 / (2 pi Int(n))` with `Int(n)` from `runtime.wgsl`'s
/// `fb_rt_lobe_integral_<id>` (the usual [`LobeForm::wgsl_norm`]).
pub fn norm_by_integral(id: &str, e: &Emit) -> String {
    format!(
        "(1.0 / (6.283185307179586 * fb_rt_lobe_integral_{}({})))",
        id.replace('-', "_"),
        e.param("n")
    )
}

/// The lenient lobe argument: `c` clamped to [0, 1]; `None` (value 0) for NaN (`Lobe::eval`'s
/// rule; `lobes::arg`).
#[inline(always)]
pub fn lobe_arg<T: Real>(c: T) -> Option<T> {
    if c.is_nan() {
        None
    } else {
        Some(c.max(T::zero()).min(T::one()))
    }
}

// ---------- the scalar models: a family with the exact backend ----------

/// A family evaluated with the exact backend, behind the scalar model traits.
#[derive(Clone, Debug)]
pub struct Scalar<F>(pub F);

impl<T: Real, L: LobeForm> model::Lobe<T> for Scalar<L> {
    #[inline]
    fn eval(&self, c: T) -> T {
        match lobe_arg(c) {
            Some(c) => self.0.at::<T, Exact>(c),
            None => T::zero(),
        }
    }
    fn zero_below(&self) -> f64 {
        self.0.zero_below()
    }
    fn kinks(&self) -> Vec<f64> {
        self.0.kinks()
    }
}

impl<T: Real, D: DistForm> model::Distribution<T> for Scalar<D> {
    #[inline]
    fn d(&self, cos_h: T, sin2_h: T) -> T {
        if !(cos_h >= T::c(COS_MIN)) {
            return T::zero();
        }
        self.0.d::<T, Exact>(cos_h, sin2_h)
    }
}

impl<T: Real, G: ShadowForm> model::Shadowing<T> for Scalar<G> {
    #[inline]
    fn g(&self, s: &ShadowInput<T>) -> T {
        self.0.g::<T, Exact>(s)
    }
    fn needs_half_vector(&self) -> bool {
        G::HALF_VECTOR
    }
}

impl<T: Real, F: FresnelForm> model::Fresnel<T> for Scalar<F> {
    #[inline]
    fn f(&self, cos: T) -> T {
        self.0.f::<T, Exact>(cos)
    }
}

impl<T: Real, E: EnvForm> model::Env<T> for Scalar<E> {
    #[inline]
    fn e(&self, cos_v: T, alpha: T) -> T {
        let (v, a) = env_args(cos_v, alpha);
        self.0.e::<T, Exact>(v, a)
    }
}

impl<T: Real, B: BrdfForm> model::Brdf<T> for Scalar<B> {
    #[inline]
    fn eval_pair(&self, p: &Pair<T>) -> T {
        self.0.at_pair::<T, Exact>(p)
    }
    fn reciprocal(&self) -> bool {
        self.0.reciprocal()
    }
    fn mirror_breaks(&self) -> Vec<f64> {
        self.0.mirror_breaks()
    }
    fn half_breaks(&self) -> Vec<f64> {
        self.0.half_breaks()
    }
    fn strategies(&self) -> &'static [Strategy] {
        self.0.strategies()
    }
    fn sample(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<crate::sample::Sample<T>> {
        let s = model::Brdf::<T>::resolve(self, s).ok()?;
        if !crate::vec3::above_cos_min(wo) {
            return None;
        }
        let wo = crate::vec3::normalize(wo)?;
        let wi = crate::vec3::normalize(self.0.sample_wi::<T>(wo, u, s)?)?;
        if !crate::vec3::above_cos_min(wi) {
            return None;
        }
        let pdf = self.0.pdf_wi(wo, wi, s);
        if !(pdf > T::zero() && pdf.is_finite()) {
            return None;
        }
        let f = model::Brdf::eval(self, wi, wo);
        Some(crate::sample::Sample {
            wi,
            weight: f * wi[2] / pdf,
            pdf,
        })
    }
    fn pdf(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T {
        let Ok(s) = model::Brdf::<T>::resolve(self, s) else {
            return T::zero();
        };
        if !(crate::vec3::above_cos_min(wo) && crate::vec3::above_cos_min(wi)) {
            return T::zero();
        }
        match (crate::vec3::normalize(wo), crate::vec3::normalize(wi)) {
            (Some(wo), Some(wi)) => {
                let p = self.0.pdf_wi(wo, wi, s);
                if p > T::zero() && p.is_finite() {
                    p
                } else {
                    T::zero()
                }
            }
            _ => T::zero(),
        }
    }
}
