//! Plans: a model instance as data, built once from its parameters by its family.
//!
//! A plan holds every per-parameter coefficient, computed once in f64 (rounded to the
//! evaluation precision where it is used, `T::c`). Three consumers read it, and each matches
//! on the plan enums exhaustively (through the `with_*!` macros generated from the family
//! lists below), never on a model id:
//! - the scalar models ([`Model`], f32 and f64): the family's formula with the [`Exact`]
//!   backend;
//! - the SIMD batch kernels (`batch`): the same formula with the [`crate::math::Fast`]
//!   backend, monomorphised per family (and per D, G, F combination inside Cook-Torrance);
//! - the WGSL generator: the family's `wgsl` method, which writes the call of its WGSL twin
//!   with the coefficients as literals, storage reads or runtime expressions ([`Emit`]).
//!
//! A new variant of an existing family is a new builder (one registry line and an `Entry`);
//! a new family implements one of the `*Form` traits below and adds one line to its family
//! list here; the compiler then asks for every method (formula, WGSL call, metadata) and for
//! its WGSL twin (`WGSL`: the `.wgsl` file beside its Rust file, which the WGSL library
//! collects from the family lists: [`library_sources`]).

use crate::error::{Error, Result};
use crate::math::{Exact, Math};
use crate::model::{self, Kind, Model, PipeOps, ShadowInput};
use crate::params::{Params, Value};
use crate::real::Real;
use crate::sample::{CosDist, Strategy};
use crate::vec3::{COS_MIN, Pair, V3};
use crate::wgsl::Emit;
use std::fmt::Debug;

use crate::brdf::{cook_torrance, lambert, phong, ward};
use crate::lobes::{cubic, flog, gauss, pow, power, rational, schlick, sg};
use crate::microfacet::{
    beckmann, beckmann_pow, env_brdf, fresnel, ggx, kelemen_neumann, ms, shadowing, smith_ggx,
};

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
    /// (the library takes it once). See [`library_sources`].
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
    /// (the library takes it once). See [`library_sources`].
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
    /// (the library takes it once). See [`library_sources`].
    const WGSL: &'static str;
    /// Whether its batch kernel vectorises (the exact Smith term calls libm's `erfc`).
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
    /// (the library takes it once). See [`library_sources`].
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
    /// (the library takes it once). See [`library_sources`].
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

/// Shared helpers (`fb_clamp01`, `fb_powr`, `fb_pair`, `FB_COS_MIN`, ...): `src/common.wgsl`.
pub const COMMON: &str = include_str!("common.wgsl");

/// The lobes with runtime parameters (`fb_rt_*`, issue 12): `src/runtime.wgsl`. Its fitted
/// integrals are generated by `cargo run -p fastbrdf-gpu --example gen_runtime_fits -- --write`.
pub const RUNTIME: &str = include_str!("runtime.wgsl");

/// The WGSL library, in dependency order, as (name for messages, source): `common.wgsl`, then
/// each kind's header (`<kind>/mod.wgsl`, comments only) and its families' files in the order of
/// their family lists (lobes, distributions, shadowing, Fresnel, BRDFs), then `runtime.wgsl`.
/// A file shared by several families comes once. Adding a family adds its file here through its
/// line in the family list; nothing else lists the files.
pub fn library_sources() -> Vec<(&'static str, &'static str)> {
    let mut out = Vec::new();
    let mut add = |list: Vec<(&'static str, &'static str)>| {
        for (name, src) in list {
            push_source(&mut out, name, src);
        }
    };
    add(vec![
        ("common.wgsl", COMMON),
        ("lobes/mod.wgsl", include_str!("lobes/mod.wgsl")),
    ]);
    add(LobePlan::wgsl_sources());
    add(vec![(
        "microfacet/mod.wgsl",
        include_str!("microfacet/mod.wgsl"),
    )]);
    add(DistPlan::wgsl_sources());
    add(ShadowPlan::wgsl_sources());
    add(FresnelPlan::wgsl_sources());
    add(vec![("brdf/mod.wgsl", include_str!("brdf/mod.wgsl"))]);
    add(BrdfPlan::wgsl_sources());
    add(EnvPlan::wgsl_sources());
    // Generated from its table (`microfacet::ms::wgsl_source`), so not a family's `WGSL`.
    add(vec![("microfacet/ms.wgsl", ms::wgsl_source())]);
    add(vec![("runtime.wgsl", RUNTIME)]);
    out
}

// ---------- the family lists: one line per family ----------

/// Adds `src` to `out` unless it is empty or already there (families that share a `.wgsl` file).
pub(crate) fn push_source(
    out: &mut Vec<(&'static str, &'static str)>,
    name: &'static str,
    src: &'static str,
) {
    if !src.is_empty() && !out.iter().any(|(_, s)| *s == src) {
        out.push((name, src));
    }
}

/// Declares a plan enum with one variant per family, a `with_*!` macro that matches a plan and
/// runs an expression with the concrete family (the batch kernels use it to monomorphise), and
/// the list's WGSL sources (`wgsl_sources`, from each family's `$form::WGSL`). The enum's
/// implementation of the family trait (dispatch) is written below.
macro_rules! families {
    ($d:tt $plan:ident: $form:ident, $with:ident { $($v:ident($t:ty)),* $(,)? }) => {
        #[derive(Clone, Copy, Debug)]
        pub enum $plan { $($v($t)),* }
        $(impl From<$t> for $plan { fn from(x: $t) -> Self { $plan::$v(x) } })*
        impl $plan {
            /// The WGSL sources of this list's families, in list order, each file once (by
            /// content; families without one are left out), named by the first family that
            /// gives it (for messages).
            pub fn wgsl_sources() -> Vec<(&'static str, &'static str)> {
                let mut out: Vec<(&'static str, &'static str)> = Vec::new();
                $(push_source(&mut out, stringify!($t), <$t as $form>::WGSL);)*
                out
            }
        }
        #[allow(unused_macros)]
        macro_rules! $with {
            ($d p:expr, $d f:ident => $d body:expr) => {
                match $d p { $($crate::plan::$plan::$v($d f) => $d body),* }
            };
        }
        #[allow(unused_imports)]
        pub(crate) use $with;
    };
}

families!($ LobePlan: LobeForm, with_lobe {
    Pow(pow::Pow),
    Schlick(schlick::Schlick),
    SchlickModified(schlick::SchlickModified),
    Gauss(gauss::Gauss),
    Flog(flog::Flog),
    Cubic(cubic::Cubic),
    Rational(rational::Rational),
    CubicRational(rational::CubicRational),
    Power4(power::Power<2>),
    Power8(power::Power<3>),
    Power16(power::Power<4>),
    Exp2(sg::Exp2Lobe),
});

families!($ DistPlan: DistForm, with_dist {
    Beckmann(beckmann::Beckmann),
    BeckmannPow(beckmann_pow::BeckmannPow),
    BeckmannPower4(beckmann_pow::BeckmannPower<2>),
    BeckmannPower8(beckmann_pow::BeckmannPower<3>),
    BeckmannPower16(beckmann_pow::BeckmannPower<4>),
    Ggx(ggx::Ggx),
});

families!($ ShadowPlan: ShadowForm, with_shadow {
    VCavity(shadowing::VCavity),
    Smith(shadowing::Smith),
    SmithRational(shadowing::SmithRational),
    SmithBeckmannCorrelated(shadowing::SmithBeckmannCorrelated),
    SmithGgx(smith_ggx::SmithGgx),
    SmithGgxCorrelated(smith_ggx::SmithGgxCorrelated),
    SmithGgxCorrelatedFast(smith_ggx::HammonFast),
    SmithGgxJointApprox(smith_ggx::JointApprox),
    SchlickGgx(smith_ggx::SchlickGgx),
    Kelemen(kelemen_neumann::Kelemen),
    Neumann(kelemen_neumann::Neumann),
});

families!($ FresnelPlan: FresnelForm, with_fresnel {
    None(fresnel::NoFresnel),
    Schlick(fresnel::Schlick),
    SchlickSg(fresnel::SchlickSg),
    Dielectric(fresnel::Dielectric),
    Conductor(fresnel::Conductor),
});

families!($ BrdfPlan: BrdfForm, with_brdf {
    CookTorrance(cook_torrance::CookTorrance),
    Ward(ward::Ward<0>),
    WardPow(ward::Ward<1>),
    WardPower16(ward::Ward<2>),
    Lambert(lambert::Lambert),
    LobeBrdf(phong::LobeBrdf),
});

families!($ EnvPlan: EnvForm, with_env {
    Dfg(env_brdf::Dfg),
    Approx(env_brdf::Approx),
});

/// A model instance of any kind.
#[derive(Clone, Copy, Debug)]
pub enum Plan {
    Lobe(LobePlan),
    Distribution(DistPlan),
    Shadowing(ShadowPlan),
    Fresnel(FresnelPlan),
    Brdf(BrdfPlan),
    Env(EnvPlan),
}

// ---------- plan enums implement their family trait by dispatch ----------

impl LobeForm for LobePlan {
    /// A plan's sources are its list's: [`Self::wgsl_sources`].
    const WGSL: &'static str = "";
    fn id(&self) -> &'static str {
        with_lobe!(self, l => l.id())
    }
    #[inline]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        with_lobe!(self, l => l.at::<T, M>(c))
    }
    fn zero_below(&self) -> f64 {
        with_lobe!(self, l => l.zero_below())
    }
    fn kinks(&self) -> Vec<f64> {
        with_lobe!(self, l => l.kinks())
    }
    fn normalised(&self) -> bool {
        with_lobe!(self, l => l.normalised())
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        with_lobe!(self, l => l.wgsl(c, e))
    }
    fn wgsl_norm(&self, e: &Emit) -> String {
        with_lobe!(self, l => l.wgsl_norm(e))
    }
    fn cos_dist(&self) -> Option<CosDist> {
        with_lobe!(self, l => l.cos_dist())
    }
}

impl LobePlan {
    /// The scalar lobe in precision `T` (the family's formula with the exact backend).
    pub fn model<T: Real>(&self) -> Box<dyn model::Lobe<T>> {
        with_lobe!(self, x => Box::new(Scalar(*x)))
    }
}

impl DistForm for DistPlan {
    /// A plan's sources are its list's: [`Self::wgsl_sources`].
    const WGSL: &'static str = "";
    #[inline]
    fn d<T: Real, M: Math<T>>(&self, cos_h: T, sin2_h: T) -> T {
        with_dist!(self, d => d.d::<T, M>(cos_h, sin2_h))
    }
    fn wgsl(&self, c: &str, s2: &str, e: &Emit) -> String {
        with_dist!(self, d => d.wgsl(c, s2, e))
    }
    fn sampler(&self) -> DistSampler {
        with_dist!(self, d => d.sampler())
    }
    fn smith(&self) -> &'static str {
        with_dist!(self, d => d.smith())
    }
}

impl DistPlan {
    /// [`DistForm::ANISO`] of the family.
    pub fn aniso(&self) -> bool {
        fn of<D: DistForm>(_: &D) -> bool {
            D::ANISO
        }
        with_dist!(self, d => of(d))
    }
}

impl ShadowPlan {
    /// [`ShadowForm::ANISO`] of the family.
    pub fn aniso(&self) -> bool {
        fn of<G: ShadowForm>(_: &G) -> bool {
            G::ANISO
        }
        with_shadow!(self, g => of(g))
    }
    /// Whether the term uses `cos_h` and `cos_vh`.
    pub fn needs_half_vector(&self) -> bool {
        fn of<G: ShadowForm>(_: &G) -> bool {
            G::HALF_VECTOR
        }
        with_shadow!(self, g => of(g))
    }
    /// Whether its batch kernel vectorises.
    pub fn simd(&self) -> bool {
        fn of<G: ShadowForm>(_: &G) -> bool {
            G::SIMD
        }
        with_shadow!(self, g => of(g))
    }
}

impl ShadowForm for ShadowPlan {
    /// A plan's sources are its list's: [`Self::wgsl_sources`].
    const WGSL: &'static str = "";
    #[inline]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, cos_h: T, cos_vh: T) -> T {
        with_shadow!(self, g => g.g_pair::<T, M>(cos_v, cos_l, cos_h, cos_vh))
    }
    #[inline]
    fn g<T: Real, M: Math<T>>(&self, s: &ShadowInput<T>) -> T {
        with_shadow!(self, g => g.g::<T, M>(s))
    }
    fn wgsl(&self, v: &str, l: &str, h: &str, vh: &str, e: &Emit) -> String {
        with_shadow!(self, g => g.wgsl(v, l, h, vh, e))
    }
}

impl FresnelForm for FresnelPlan {
    /// A plan's sources are its list's: [`Self::wgsl_sources`].
    const WGSL: &'static str = "";
    #[inline]
    fn f<T: Real, M: Math<T>>(&self, cos: T) -> T {
        with_fresnel!(self, f => f.f::<T, M>(cos))
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        with_fresnel!(self, f => f.wgsl(c, e))
    }
}

impl EnvForm for EnvPlan {
    /// A plan's sources are its list's: [`Self::wgsl_sources`].
    const WGSL: &'static str = "";
    #[inline]
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T {
        with_env!(self, x => x.e::<T, M>(cos_v, alpha))
    }
    fn wgsl(&self, v: &str, a: &str, e: &Emit) -> String {
        with_env!(self, x => x.wgsl(v, a, e))
    }
}

impl EnvPlan {
    /// Whether its batch kernel vectorises.
    pub fn simd(&self) -> bool {
        fn of<E: EnvForm>(_: &E) -> bool {
            E::SIMD
        }
        with_env!(self, x => of(x))
    }
}

impl BrdfForm for BrdfPlan {
    /// A plan's sources are its list's: [`Self::wgsl_sources`].
    const WGSL: &'static str = "";
    fn simd(&self) -> bool {
        with_brdf!(self, b => b.simd())
    }
    #[inline]
    fn at_pair<T: Real, M: Math<T>>(&self, p: &Pair<T>) -> T {
        with_brdf!(self, b => b.at_pair::<T, M>(p))
    }
    fn wgsl_body(&self, e: &Emit) -> String {
        with_brdf!(self, b => b.wgsl_body(e))
    }
    fn reciprocal(&self) -> bool {
        with_brdf!(self, b => b.reciprocal())
    }
    fn mirror_breaks(&self) -> Vec<f64> {
        with_brdf!(self, b => b.mirror_breaks())
    }
    fn half_breaks(&self) -> Vec<f64> {
        with_brdf!(self, b => b.half_breaks())
    }
    fn claims_energy(&self) -> bool {
        with_brdf!(self, b => b.claims_energy())
    }
    fn furnace_tol(&self) -> f64 {
        with_brdf!(self, b => b.furnace_tol())
    }
    fn strategies(&self) -> &'static [Strategy] {
        with_brdf!(self, b => b.strategies())
    }
    fn sample_wi<T: Real>(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<V3<T>> {
        with_brdf!(self, b => b.sample_wi(wo, u, s))
    }
    fn pdf_wi<T: Real>(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T {
        with_brdf!(self, b => b.pdf_wi(wo, wi, s))
    }
}

impl Plan {
    /// The kind of model.
    pub fn kind(&self) -> Kind {
        match self {
            Plan::Lobe(_) => Kind::Lobe,
            Plan::Distribution(_) => Kind::Distribution,
            Plan::Shadowing(_) => Kind::Shadowing,
            Plan::Fresnel(_) => Kind::Fresnel,
            Plan::Brdf(_) => Kind::Brdf,
            Plan::Env(_) => Kind::Env,
        }
    }

    /// The scalar model in precision `T` (the family's formula with the exact backend).
    pub fn model<T: Real>(&self) -> Model<T> {
        match self {
            Plan::Lobe(l) => Model::Lobe(l.model()),
            Plan::Distribution(d) => Model::Distribution(with_dist!(d, x => Box::new(Scalar(*x)))),
            Plan::Shadowing(g) => Model::Shadowing(with_shadow!(g, x => Box::new(Scalar(*x)))),
            Plan::Fresnel(f) => Model::Fresnel(with_fresnel!(f, x => Box::new(Scalar(*x)))),
            Plan::Brdf(b) => Model::Brdf(with_brdf!(b, x => Box::new(Scalar(*x)))),
            Plan::Env(e) => Model::Env(with_env!(e, x => Box::new(Scalar(*x)))),
        }
    }

    /// How far above 1 the albedo of a model that claims energy may read
    /// ([`BrdfForm::furnace_tol`]; 0 for every other kind).
    pub fn furnace_tol(&self) -> f64 {
        match self {
            Plan::Brdf(b) => b.furnace_tol(),
            _ => 0.0,
        }
    }

    /// Whether `f(wi, wo) = f(wo, wi)` (true for every kind but a non-reciprocal BRDF).
    pub fn reciprocal(&self) -> bool {
        match self {
            Plan::Brdf(b) => b.reciprocal(),
            _ => true,
        }
    }

    /// Whether the model claims energy conservation (a normalised BRDF or lobe): the models
    /// `fastbrdf albedo` holds to the white-furnace test.
    pub fn claims_energy(&self) -> bool {
        match self {
            Plan::Lobe(l) => l.normalised(),
            Plan::Brdf(b) => b.claims_energy(),
            Plan::Distribution(_) | Plan::Shadowing(_) | Plan::Fresnel(_) | Plan::Env(_) => false,
        }
    }

    /// The lobe plan, or an error naming `model`.
    pub fn lobe(self, model: &str) -> Result<LobePlan> {
        match self {
            Plan::Lobe(l) => Ok(l),
            other => Err(wrong_kind(model, "lobe", other.kind())),
        }
    }
    /// The distribution plan, or an error naming `model`.
    pub fn distribution(self, model: &str) -> Result<DistPlan> {
        match self {
            Plan::Distribution(d) => Ok(d),
            other => Err(wrong_kind(model, "distribution", other.kind())),
        }
    }
    /// The shadowing plan, or an error naming `model`.
    pub fn shadowing(self, model: &str) -> Result<ShadowPlan> {
        match self {
            Plan::Shadowing(g) => Ok(g),
            other => Err(wrong_kind(model, "shadowing", other.kind())),
        }
    }
    /// The Fresnel plan, or an error naming `model`.
    pub fn fresnel(self, model: &str) -> Result<FresnelPlan> {
        match self {
            Plan::Fresnel(f) => Ok(f),
            other => Err(wrong_kind(model, "fresnel", other.kind())),
        }
    }
}

fn wrong_kind(model: &str, expected: &str, found: Kind) -> Error {
    Error::WrongKind {
        model: model.into(),
        expected: expected.into(),
        found: found.name().into(),
    }
}

// ---------- the scalar models: a family with the exact backend ----------

/// A family evaluated with the exact backend, behind the scalar model traits.
#[derive(Clone, Debug)]
pub struct Scalar<F>(pub F);

impl<T: Real, L: LobeForm> model::Lobe<T> for Scalar<L> {
    #[inline]
    fn eval(&self, c: T) -> T {
        match crate::lobes::arg(c) {
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

/// Builds the plans of sub-models (Cook-Torrance's D, G and F; Phong's lobe) by id: the
/// registry implements it, so that no family imports the registry (no module cycle).
pub trait Models {
    /// The plan of model `id`, each of its parameters (numbers and choices) taken from
    /// `given` (by name) where it gives one, else its default. A composite hands its parts
    /// every value it holds, so each option of a part is reachable through it (the registry
    /// adds the parts' parameters the composite does not declare: `registry::all`).
    fn plan(&self, id: &str, given: &dyn Fn(&str) -> Option<Value>) -> Result<Plan>;

    /// Lobe `id` at exponent `n` (Phong's and Blinn-Phong's `lobe`); an error for another
    /// kind.
    fn lobe(&self, id: &str, n: f64) -> Result<LobePlan> {
        self.plan(id, &|name| (name == "n").then_some(Value::Num(n)))?
            .lobe(id)
    }
}

/// A family's builder: parameters (validated) to plan.
pub type PlanFn = fn(&Params, &dyn Models) -> Result<Plan>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wgsl::Emit;

    /// The `fb_*` functions `code` calls.
    fn calls(code: &str) -> Vec<String> {
        let mut out = Vec::new();
        for (i, _) in code.match_indices("fb_") {
            if code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let name: String = code[i..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if code[i + name.len()..].starts_with('(') {
                out.push(name);
            }
        }
        out
    }

    fn defines(src: &str, name: &str) -> bool {
        src.lines().any(|l| l.starts_with(&format!("fn {name}(")))
    }

    fn lobe_src<L: LobeForm>(_: &L) -> &'static str {
        L::WGSL
    }
    fn dist_src<D: DistForm>(_: &D) -> &'static str {
        D::WGSL
    }
    fn shadow_src<G: ShadowForm>(_: &G) -> &'static str {
        G::WGSL
    }
    fn fresnel_src<F: FresnelForm>(_: &F) -> &'static str {
        F::WGSL
    }
    fn env_src<E: EnvForm>(_: &E) -> &'static str {
        E::WGSL
    }

    /// Every model's WGSL call names a function of its own family's `.wgsl` file (or a shared
    /// helper of `common.wgsl`; runtime parameters: of `runtime.wgsl`), and every BRDF body's
    /// calls are in the library: the twin sits beside its Rust family.
    #[test]
    fn every_family_calls_its_own_twin() {
        let library: Vec<&str> = library_sources().iter().map(|(_, s)| *s).collect();
        for e in crate::registry::all() {
            let id = e.info.id;
            let plan = crate::registry::plan(id, &[]).expect("default plan");
            for runtime in [false, true] {
                let emit = if runtime {
                    Emit::runtime()
                } else {
                    Emit::literals()
                };
                let (code, own) = match plan {
                    Plan::Lobe(l) => (l.wgsl("c", &emit), with_lobe!(l, x => lobe_src(&x))),
                    Plan::Distribution(d) => {
                        (d.wgsl("c", "s2", &emit), with_dist!(d, x => dist_src(&x)))
                    }
                    Plan::Shadowing(g) => (
                        g.wgsl("v", "l", "h", "vh", &emit),
                        with_shadow!(g, x => shadow_src(&x)),
                    ),
                    Plan::Fresnel(f) => {
                        (f.wgsl("c", &emit), with_fresnel!(f, x => fresnel_src(&x)))
                    }
                    Plan::Brdf(b) => (b.wgsl_body(&emit), ""),
                    Plan::Env(x) => (x.wgsl("v", "a", &emit), with_env!(x, y => env_src(&y))),
                };
                for name in calls(&code) {
                    let ok = if matches!(plan, Plan::Brdf(_)) {
                        library.iter().any(|s| defines(s, &name))
                    } else {
                        defines(own, &name)
                            || defines(COMMON, &name)
                            || (runtime && defines(RUNTIME, &name))
                    };
                    assert!(
                        ok,
                        "{id} (runtime: {runtime}) calls {name}, not in its .wgsl file"
                    );
                }
            }
        }
    }

    #[test]
    fn library_sources_come_once_and_start_with_common() {
        let s = library_sources();
        assert_eq!(s[0].1, COMMON);
        assert_eq!(s.last().unwrap().1, RUNTIME);
        for (i, (a, x)) in s.iter().enumerate() {
            for (b, y) in &s[i + 1..] {
                assert!(x != y, "{a} and {b} are the same file");
            }
        }
        // Every family file of the lists is there (Ward's three forms share one file).
        assert!(s.iter().any(|(_, x)| defines(x, "fb_brdf_ward_power16")));
    }
}
