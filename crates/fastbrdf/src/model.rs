//! What a model is: its kind, its self-description ([`ModelInfo`]) and its evaluator
//! ([`Model`]), one trait per kind.

use crate::error::{Error, Result};
use crate::params::ParamSpec;
use crate::real::Real;
use crate::sample::{Sample, Strategy};
use crate::vec3::{Pair, V3};
use serde::Serialize;

pub use crate::kind::Kind;

/// Operation counts of one evaluation, with the per-parameter constants precomputed.
/// Comparisons, `min`/`max` and clamps are not counted; `pow` counts as one transcendental.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Ops {
    pub mul: u8,
    pub add: u8,
    pub div: u8,
    pub sqrt: u8,
    pub transcendental: u8,
}

impl Ops {
    /// Builds a count: multiplies, adds, divides, square roots, transcendental calls.
    pub const fn new(mul: u8, add: u8, div: u8, sqrt: u8, transcendental: u8) -> Self {
        Self {
            mul,
            add,
            div,
            sqrt,
            transcendental,
        }
    }
}

/// What a SIMD kernel executes per element on the FMA instruction sets, counted from its
/// code where the formula's [`Ops`] miss it (the polynomial of a vectorised `exp2`):
/// multiply-pipe operations (multiplies and fused multiply-adds) and divisions. Adds, clamps,
/// compares and integer steps are not counted: on AMD's Zen 4 and 5 they run on other pipes
/// (on Intel's cores float adds and vector shifts share the FMA ports, so the fraction
/// understates the load there).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct PipeOps {
    pub mul: u8,
    pub div: u8,
}

/// How an error is measured.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Metric {
    /// `max |f - ref| / peak`, for every kind, `peak` the reference's largest value over the
    /// sampled inputs at the same parameter value (`accuracy::error`). The peak is exactly 1
    /// for lobes and shadowing terms, so their bounds are absolute too; for distributions,
    /// Fresnel terms, split-sum (env) terms and BRDFs they are relative to the peak
    /// (`accuracy::abs_is_absolute`; `fastbrdf models` prints `abs` or `abs/peak`, its JSON
    /// `"divided_by": "peak"`).
    MaxAbs,
    /// `max |f - ref| / ref`.
    MaxRel,
}

/// Where an error is measured, by the value of the reference relative to its peak.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "zone")]
pub enum Zone {
    /// The whole domain.
    All,
    /// Where the reference is at least half its peak (`c^n >= 0.5` for lobes).
    Epicentre,
    /// Where `lo < reference / peak < hi`.
    Band { lo: f64, hi: f64 },
}

/// A documented error bound against a reference model, enforced by `tests/bounds.rs`.
/// JSON: its fields, and `divided_by` (what the error is divided by: `"peak"` for
/// [`Metric::MaxAbs`], `"reference"` for [`Metric::MaxRel`]).
#[derive(Clone, Copy, Debug)]
pub struct ErrorBound {
    /// The reference model id (same parameters).
    pub reference: &'static str,
    pub metric: Metric,
    pub zone: Zone,
    /// The parameter range the bound holds on: `(name, lo, hi)`.
    pub param: (&'static str, f64, f64),
    /// The bound itself (measured maximum, rounded up).
    pub bound: f64,
}

impl ErrorBound {
    /// What the error is divided by (see [`Metric`]): `"peak"` (the reference's largest
    /// value at the same parameter) or `"reference"` (its value at the same input).
    pub fn divided_by(&self) -> &'static str {
        match self.metric {
            Metric::MaxAbs => "peak",
            Metric::MaxRel => "reference",
        }
    }
}

impl Serialize for ErrorBound {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Json {
            reference: &'static str,
            metric: Metric,
            #[serde(flatten)]
            zone: Zone,
            param: (&'static str, f64, f64),
            bound: f64,
            divided_by: &'static str,
        }
        Json {
            reference: self.reference,
            metric: self.metric,
            zone: self.zone,
            param: self.param,
            bound: self.bound,
            divided_by: self.divided_by(),
        }
        .serialize(s)
    }
}

/// A model's self-description: everything `fastbrdf models` prints.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ModelInfo {
    pub id: &'static str,
    pub kind: Kind,
    pub params: &'static [ParamSpec],
    pub formula: &'static str,
    pub source: &'static str,
    pub ops: Ops,
    /// Error bounds against reference models (empty for references and exact models).
    pub bounds: &'static [ErrorBound],
    /// Documented bound of the f32 evaluation against the f64 one on the same inputs, in the
    /// mixed metric `|v32 - v64| / max(1, |v64|)`, over the whole documented domain.
    pub f32_bound: f64,
    /// A note on conventions or decisions (where this reading differs from a seed).
    pub note: &'static str,
}

impl ModelInfo {
    /// The documented range of `name` when error sweeps may walk it: a numeric parameter, or
    /// the `alpha` input of a split-sum term (`Kind::Env`, whose curves read it as one:
    /// `accuracy::Curve`). `None` for anything else.
    pub fn sweep_range(&self, name: &str) -> Option<(f64, f64)> {
        if self.kind == Kind::Env && name == "alpha" {
            return Some(crate::params::ALPHA.range());
        }
        self.params
            .iter()
            .find(|p| p.name == name)
            .and_then(|p| match p.kind {
                crate::params::ParamKind::Number { min, max, .. } => Some((min, max)),
                crate::params::ParamKind::Choice { .. } => None,
            })
    }
}

/// A function of one cosine.
pub trait Lobe<T: Real>: Send + Sync {
    /// The value at cosine `c`, clamped to [0, 1] first (../shared/MODELS.md): `c < 0` gives
    /// the value at 0, `c > 1` (round-off in a normalised dot product) the value at 1; NaN
    /// gives 0. Finite and non-negative everywhere.
    fn eval(&self, c: T) -> T;
    /// The largest cosine below which the lobe is identically zero (0 when it has none).
    fn zero_below(&self) -> f64 {
        0.0
    }
    /// Cosines where the lobe is not smooth (junctions of piecewise forms), for quadrature.
    fn kinks(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// A microfacet distribution of `cos theta_h`.
pub trait Distribution<T: Real>: Send + Sync {
    /// `D` given `cos theta_h` and `sin^2 theta_h` (both supplied so that callers with the
    /// half vector avoid the cancellation in `1 - cos^2`). Returns 0 for `cos_h < COS_MIN`.
    fn d(&self, cos_h: T, sin2_h: T) -> T;
    /// `D(cos theta_h)`; NaN or `cos_h < COS_MIN` give 0, `cos_h > 1` is treated as 1.
    fn eval(&self, cos_h: T) -> T {
        if !(cos_h >= T::c(crate::vec3::COS_MIN)) {
            return T::zero();
        }
        let c = cos_h.min(T::one());
        self.d(c, (T::one() - c) * (T::one() + c))
    }
}

/// The cosines a shadowing term may use.
#[derive(Clone, Copy, Debug)]
pub struct ShadowInput<T> {
    /// `n.v`.
    pub cos_v: T,
    /// `n.l`; `None` asks for the one-sided (masking) term of `v` alone.
    pub cos_l: Option<T>,
    /// `n.h` (half-vector terms only: V-cavity, Kelemen).
    pub cos_h: T,
    /// `v.h = l.h` (half-vector terms only: V-cavity, Kelemen).
    pub cos_vh: T,
}

/// A shadowing-masking term.
pub trait Shadowing<T: Real>: Send + Sync {
    /// `G`, in [0, 1]. Cosines that are NaN or `<= 0` give 0.
    fn g(&self, s: &ShadowInput<T>) -> T;
    /// Whether the term uses `cos_h` and `cos_vh`.
    fn needs_half_vector(&self) -> bool {
        false
    }
}

/// A Fresnel term.
pub trait Fresnel<T: Real>: Send + Sync {
    /// Reflectance in [0, 1] at the cosine between the view and the microfacet normal;
    /// NaN or negative cosines give the value at 0, cosines above 1 the value at 1.
    fn f(&self, cos_vh: T) -> T;
}

/// A split-sum term of image-based lighting (`Kind::Env`).
pub trait Env<T: Real>: Send + Sync {
    /// The term at `cos_v` (the view's cosine) and `alpha` (the distribution's roughness).
    /// NaN or negative `cos_v` act as 0 and values above 1 as 1; `alpha` is clamped into its
    /// documented range (NaN acts as its smallest value).
    fn e(&self, cos_v: T, alpha: T) -> T;
}

/// A full BRDF of (wi, wo) in the local frame, without the cosine factor.
pub trait Brdf<T: Real>: Send + Sync {
    /// The value on a prepared geometric pair (unit vectors, both above `COS_MIN`).
    fn eval_pair(&self, p: &Pair<T>) -> T;
    /// The value for any `wi`, `wo` (normalised here). Zero vectors, NaN components and
    /// directions below the horizon (`cos theta < COS_MIN`) give 0.
    fn eval(&self, wi: V3<T>, wo: V3<T>) -> T {
        match Pair::new(wi, wo) {
            Some(p) => self.eval_pair(&p),
            None => T::zero(),
        }
    }
    /// Whether `f(wi, wo) = f(wo, wi)` holds (tested on random pairs when it does).
    fn reciprocal(&self) -> bool;
    /// Values of `reflect(wi) . wo` where the BRDF is discontinuous or has a kink (the lobe's
    /// cut and junctions, for lobe-based BRDFs), so that quadrature can split there.
    fn mirror_breaks(&self) -> Vec<f64>;
    /// Values of `cos theta_h` where the BRDF is discontinuous or has a kink (the lobe's cut
    /// and junctions, for `blinn-phong`): where an adversarial search starts.
    fn half_breaks(&self) -> Vec<f64>;
    /// The sampling strategies it supports, its default (`auto`) first (`crate::sample`): a
    /// constant list, so that `sample` and `pdf` resolve `auto` without allocating.
    fn strategies(&self) -> &'static [Strategy];
    /// `s` with `auto` replaced by the default, or an error naming the valid ones.
    fn resolve(&self, s: Strategy) -> std::result::Result<Strategy, String> {
        let all = self.strategies();
        match s {
            Strategy::Auto => Ok(all[0]),
            s if all.contains(&s) => Ok(s),
            s => Err(format!(
                "strategy {s} does not apply to this model; valid: auto, {}",
                all.iter().map(|x| x.name()).collect::<Vec<_>>().join(", ")
            )),
        }
    }
    /// Draws `wi` given `wo` and `u` in [0, 1)^2 by strategy `s`: `None` when `wo` is out of
    /// the domain, `s` does not apply ([`Self::resolve`]), or the draw falls below the horizon
    /// or has density 0 (the strategy's missing mass). The weight is `f(wi, wo) cos_i / pdf`
    /// with this model's own evaluation.
    fn sample(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<Sample<T>>;
    /// The solid-angle density of [`Self::sample`]'s `wi` given `wo` (0 out of the domain or
    /// for a strategy that does not apply).
    fn pdf(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T;
}

/// A built model of any kind, in precision `T`.
pub enum Model<T: Real> {
    Lobe(Box<dyn Lobe<T>>),
    Distribution(Box<dyn Distribution<T>>),
    Shadowing(Box<dyn Shadowing<T>>),
    Fresnel(Box<dyn Fresnel<T>>),
    Brdf(Box<dyn Brdf<T>>),
    Env(Box<dyn Env<T>>),
}

impl<T: Real> Model<T> {
    /// The kind of model.
    pub fn kind(&self) -> Kind {
        match self {
            Model::Lobe(_) => Kind::Lobe,
            Model::Distribution(_) => Kind::Distribution,
            Model::Shadowing(_) => Kind::Shadowing,
            Model::Fresnel(_) => Kind::Fresnel,
            Model::Brdf(_) => Kind::Brdf,
            Model::Env(_) => Kind::Env,
        }
    }

    /// The input columns this model reads: `(required, optional)`.
    pub fn columns(&self) -> (&'static [&'static str], &'static [&'static str]) {
        let half_vector = matches!(self, Model::Shadowing(s) if s.needs_half_vector());
        self.kind().columns(half_vector)
    }

    /// Evaluates with the lenient shading rules (out-of-domain inputs give 0).
    /// `input` holds the required columns in order, then the optional ones (`None` if absent).
    pub fn eval_row(&self, input: &[Option<T>]) -> T {
        let v = |i: usize| input.get(i).copied().flatten().unwrap_or_else(T::nan);
        match self {
            Model::Lobe(l) => l.eval(v(0)),
            Model::Distribution(d) => d.eval(v(0)),
            Model::Shadowing(s) => {
                let needs_h = s.needs_half_vector();
                let (cos_h, cos_vh, l) = if needs_h {
                    (v(1), v(2), 3)
                } else {
                    (T::one(), T::one(), 1)
                };
                s.g(&ShadowInput {
                    cos_v: v(0),
                    cos_l: input.get(l).copied().flatten(),
                    cos_h,
                    cos_vh,
                })
            }
            Model::Fresnel(f) => f.f(v(0)),
            Model::Brdf(b) => b.eval([v(0), v(1), v(2)], [v(3), v(4), v(5)]),
            Model::Env(e) => e.e(v(0), v(1)),
        }
    }

    /// Evaluates with strict checks: inputs outside the documented domain are an error
    /// (used by `fastbrdf eval`, which must say what is wrong rather than print 0).
    pub fn try_eval_row(&self, input: &[Option<T>]) -> Result<T> {
        let (req, opt) = self.columns();
        for (i, name) in req.iter().chain(opt.iter()).enumerate() {
            if let Some(x) = input.get(i).copied().flatten() {
                if !x.is_finite() {
                    return Err(Error::Domain {
                        input: (*name).into(),
                        reason: format!("{x} is not a finite number"),
                    });
                }
                let is_cos = !matches!(self, Model::Brdf(_));
                if let (Model::Env(_), &"alpha") = (self, name) {
                    let (lo, hi) = crate::params::ALPHA.range();
                    if !(x >= T::c(lo) && x <= T::c(hi)) {
                        return Err(Error::Domain {
                            input: (*name).into(),
                            reason: format!("{x} is outside the domain [{lo}, {hi}] of alpha"),
                        });
                    }
                } else if is_cos && !(x >= T::zero() && x <= T::one()) {
                    return Err(Error::Domain {
                        input: (*name).into(),
                        reason: format!("{x} is outside the domain [0, 1] of a cosine"),
                    });
                }
            } else if i < req.len() {
                return Err(Error::Domain {
                    input: (*name).into(),
                    reason: "missing".into(),
                });
            }
        }
        if let Model::Brdf(_) = self {
            let w = |o: usize| {
                [
                    input[o].unwrap(),
                    input[o + 1].unwrap(),
                    input[o + 2].unwrap(),
                ]
            };
            for (name, v) in [("wi", w(0)), ("wo", w(3))] {
                match crate::vec3::normalize(v) {
                    None => {
                        return Err(Error::Domain {
                            input: name.into(),
                            reason: "zero-length vector".into(),
                        });
                    }
                    Some(u) if !crate::vec3::above_cos_min(v) => {
                        return Err(Error::Domain {
                            input: name.into(),
                            reason: format!(
                                "below the horizon or grazing (cos theta = {} < {}): the local frame's normal is +z and both directions point away from the surface",
                                u[2],
                                crate::vec3::COS_MIN
                            ),
                        });
                    }
                    Some(_) => {}
                }
            }
        }
        Ok(self.eval_row(input))
    }
}
