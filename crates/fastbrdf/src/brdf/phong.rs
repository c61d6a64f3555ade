//! `phong` and `blinn-phong`: BRDFs built from any lobe, with or without energy normalisation.
//!
//! Normalisation (`norm = energy`): `coef(n) = 1 / (2 pi Int(n))`,
//! `Int(n) = integral_0^{pi/2} lobe(cos theta) cos theta sin theta dtheta = integral_0^1 lobe(c) c dc`,
//! computed at construction by adaptive f64 quadrature (relative tolerance 1e-12, split at the
//! lobe's zero and kinks), or in closed form for `pow` (`Int = 1 / (n + 2)`).
//!
//! - `phong`: `f = coef(n) lobe(r . wo)` with `r` the mirror direction of `wi`. At normal
//!   incidence `r = n`, so the albedo is exactly `coef(n) 2 pi Int(n) = 1`; elsewhere part of the
//!   lobe falls below the horizon and the albedo is below 1. This is "the lobe used as a
//!   normalised (Blinn-)Phong BRDF" of the seeds' energy argument (seed 001, section III).
//! - `blinn-phong`: the lobe of `n . h`. With `norm = energy` it is the lobe used as a
//!   normalised microfacet distribution `D = coef(n) lobe(n . h)` (the same integral makes
//!   `integral D cos theta_h = 1`), in the Torrance-Sparrow form with F = G = 1:
//!   `f = D / (4 wi . h)`, whose albedo is at most 1. With `norm = none` it is the classic
//!   unnormalised `lobe(n . h)`.
//!
//! Parameters: `lobe` (a lobe id, default `pow`), `n` in [1, 100000] (default 20), `norm`
//! (`energy` or `none`, default `energy`). Cost: the lobe's, plus 3 mul, 2 add (phong) or
//! 1 mul, 1 div (blinn-phong, energy). Reciprocal.
//! Sampling: `lobe` (the lobe's own density inverted in closed form, `LobeForm::cos_dist`:
//! `pow`, power-g forms, spherical Gaussians; around the mirror of `wo` for Phong, the half
//! vector about the normal for Blinn-Phong), `twin` (`pow` at the same `n`; the default for
//! the other lobes), `cosine`.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::{BrdfForm, LobeForm};
use crate::math::{Exact, Math};
use crate::model::{Kind, ModelInfo, Ops};
use crate::params::{self, Options, ParamKind, ParamSpec, Params, Value};
use crate::plan::{LobePlan, Models, Plan};
use crate::quad;
use crate::real::{K, Real, min1, pos};
use crate::sample::{self, CosDist, Strategy};
use crate::vec3::{Pair, V3, reflect};
use crate::wgsl::{Emit, PAIR};

pub const LOBE: ParamSpec = ParamSpec {
    name: "lobe",
    kind: ParamKind::Choice {
        options: Options::Models {
            kind: Kind::Lobe,
            prefix: "",
            follow: None,
        },
        default: "pow",
    },
    doc: "lobe id",
};
pub const NORM: ParamSpec = ParamSpec {
    name: "norm",
    kind: ParamKind::Choice {
        options: Options::List(&["energy", "none"]),
        default: "energy",
    },
    doc: "energy: coef(n) = 1 / (2 pi Int(n)); none: the bare lobe",
};

pub const INFO: ModelInfo = ModelInfo {
    id: "phong",
    kind: Kind::Brdf,
    params: &[LOBE, params::N, NORM],
    formula: "coef(n) lobe(reflect(wi) . wo), coef(n) = 1 / (2 pi Int(n))",
    source: "Phong 1975; Lewis 1994 and Lafortune 1994 (normalisation); seed 001 (coef by Int(n))",
    ops: Ops::new(3, 2, 0, 0, 0),
    bounds: &[],
    f32_bound: 8e3,
    note: "ops are the wrapper's, add the lobe's; albedo at normal incidence = 1 with norm = energy; f32: reflect(wi).wo rounded once to f32 moves flog-normalized-clamped near its zero (slope ~3e6 at n = 1e4, ~3e8 at n = 1e5) by up to 0.3 at n = 1e4 and by its whole height 1 above n ~ 2e4, times coef(n): 85 at n = 1e4, 4758 (the peak) at n = 6.2e4 (check --full), up to the peak 7654 at n = 1e5; at most 1.4 for the other lobes (flog-normalized at n = 1e5)",
};

pub const INFO_BLINN: ModelInfo = ModelInfo {
    id: "blinn-phong",
    kind: Kind::Brdf,
    params: &[LOBE, params::N, NORM],
    formula: "coef(n) lobe(n . h) / (4 wi . h) (energy) or lobe(n . h) (none)",
    source: "Blinn 1977; Torrance & Sparrow 1967 (microfacet form); seed 001 (coef by Int(n))",
    ops: Ops::new(1, 0, 1, 0, 0),
    bounds: &[],
    f32_bound: 2e3,
    note: "ops are the wrapper's, add the lobe's; albedo <= 1 with norm = energy; f32: cos_h rounded once to f32 moves flog-normalized-clamped near its zero by up to 0.3 at n = 1e4 and by its whole height 1 above n ~ 2e4, times coef(n) / (4 wi.h): 265 at n = 1e4 (check --full), up to the peak 1914 at n = 1e5; 2 for flog-normalized",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, models| {
    Ok(Plan::Brdf(LobeBrdf::from_params(p, models, false)?.into()))
});
pub const ENTRY_BLINN: Entry = Entry::new(INFO_BLINN, |p, models| {
    Ok(Plan::Brdf(LobeBrdf::from_params(p, models, true)?.into()))
});

/// `Int(n) = integral_0^1 lobe(c) c dc` in f64 (`1 / (n + 2)` for `pow`): the normalisation
/// integral, by adaptive Gauss-Kronrod split at the lobe's cut and kinks.
pub fn lobe_integral(lobe: &LobePlan) -> f64 {
    if let LobePlan::Pow(p) = lobe {
        return 1.0 / (p.n() + 2.0);
    }
    let mut breaks = lobe.kinks();
    breaks.push(lobe.zero_below());
    let lo = lobe.zero_below();
    let f = |c: f64| lobe.at::<f64, Exact>(c.clamp(0.0, 1.0)) * c;
    quad::integrate(f, lo, 1.0, &breaks, 1e-12).0
}

/// A lobe used as a BRDF: Phong (`lobe(reflect(wi) . wo)`) or Blinn-Phong (`lobe(n . h)`),
/// normalised or not. Generic over the lobe: the plan holds a `LobePlan`, the batch kernels
/// one family each.
#[derive(Clone, Copy, Debug)]
pub struct LobeBrdf<L = LobePlan> {
    pub lobe: L,
    /// The lobe's cut, decided on the f64 cosine.
    zero: f64,
    /// `1 / (2 pi Int(n))` when normalised, else 1.
    coef: K,
    blinn: bool,
    normalized: bool,
    /// The exponent (the twin `pow`'s, for sampling).
    n: f64,
}

impl LobeBrdf {
    /// The plan from resolved parameters (`lobe`, `n`, `norm`); the lobe is built by the
    /// registry (`models`).
    pub fn from_params(p: &Params, models: &dyn Models, blinn: bool) -> Result<Self> {
        let id = if blinn { "blinn-phong" } else { "phong" };
        let n = params::check(id, &params::N, p.num("n"))?;
        let lobe_id = p.choice("lobe");
        // Every value this model holds goes to the lobe where it declares it (`n` today; a
        // lobe parameter this model does not declare is added by the registry).
        let lobe = models
            .plan(lobe_id, &|name| {
                if name == "n" {
                    Some(Value::Num(n))
                } else {
                    p.get(name).cloned()
                }
            })?
            .lobe(lobe_id)?;
        let normalized = p.choice("norm") == "energy";
        let coef = if normalized {
            1.0 / (2.0 * std::f64::consts::PI * lobe_integral(&lobe))
        } else {
            1.0
        };
        Ok(Self {
            zero: lobe.zero_below(),
            lobe,
            coef: K::new(coef),
            blinn,
            normalized,
            n,
        })
    }

    /// The same BRDF with the lobe as a concrete family (for the batch kernels).
    pub(crate) fn with_lobe<L: LobeForm>(&self, lobe: L) -> LobeBrdf<L> {
        LobeBrdf {
            lobe,
            zero: self.zero,
            coef: self.coef,
            blinn: self.blinn,
            normalized: self.normalized,
            n: self.n,
        }
    }
}

impl<L: LobeForm> LobeBrdf<L> {
    fn breaks(&self, blinn: bool) -> Vec<f64> {
        if self.blinn != blinn {
            return Vec::new();
        }
        let mut b = self.lobe.kinks();
        b.push(self.lobe.zero_below());
        b
    }

    /// The cosine density strategy `s` draws from.
    fn dist(&self, s: Strategy) -> Option<CosDist> {
        match s {
            Strategy::Lobe => self.lobe.cos_dist(),
            Strategy::Twin => Some(CosDist::Pow { m: self.n }),
            _ => None,
        }
    }

    /// Phong with a lobe that is not 0 at `c = 0` is `lobe(0)` on the whole back half
    /// (`c < 0`: the lobe's argument is clamped), which a density on [0, 1] never reaches:
    /// strategy `s` then draws `c` uniform on [-1, 0) with this probability (`lobe`: the exact
    /// share `pdf_c(0) / (1 + pdf_c(0))`; `twin`: the share it would have next to `c^n`).
    fn back(&self, d: &CosDist, s: Strategy) -> f64 {
        let l0 = self.lobe.at::<f64, Exact>(0.0);
        if self.blinn || !(l0 > 0.0) {
            return 0.0;
        }
        match s {
            Strategy::Lobe => {
                let p0: f64 = d.pdf(0.0);
                p0 / (1.0 + p0)
            }
            _ => l0 / (l0 + 1.0 / (self.n + 1.0)),
        }
    }
}

impl<L: LobeForm> BrdfForm for LobeBrdf<L> {
    // No .wgsl file: the body is assembled per instance around its lobe's function.
    const WGSL: &'static str = "";
    #[inline(always)]
    fn at_pair<T: Real, M: Math<T>>(&self, p: &Pair<T>) -> T {
        let cut = p.lobe_cut(self.zero, self.blinn);
        // The lobe's argument is clamped as `Lobe::eval` does (pair cosines lie in [-1, 1]).
        let arg = |c: T| min1(pos(c));
        let v = if self.blinn {
            let l = self.lobe.at::<T, M>(arg(p.cos_h));
            if self.normalized {
                self.coef.t::<T>() * l / (T::c(4.0) * p.cos_ih)
            } else {
                l
            }
        } else {
            self.coef.t::<T>() * self.lobe.at::<T, M>(arg(p.cos_r))
        };
        if cut { T::zero() } else { v }
    }
    fn wgsl_body(&self, e: &Emit) -> String {
        let coef = if !self.normalized {
            e.constant(self.coef)
        } else if e.is_runtime() {
            self.lobe.wgsl_norm(e)
        } else {
            e.constant(self.coef)
        };
        let (r, v) = if self.blinn {
            let l = self.lobe.wgsl("p.h.z", e);
            let v = if self.normalized {
                format!("{coef} * {l} / (4.0 * p.cos_ih)")
            } else {
                l
            };
            ("", v)
        } else {
            (
                "    let r_dot_wo = -p.wi.x * p.wo.x - p.wi.y * p.wo.y + p.wi.z * p.wo.z;\n",
                format!("{coef} * {}", self.lobe.wgsl("r_dot_wo", e)),
            )
        };
        format!("{PAIR}{r}    let v = {v};\n    return select(0.0, v, p.valid);\n")
    }
    fn mirror_breaks(&self) -> Vec<f64> {
        self.breaks(false)
    }
    fn half_breaks(&self) -> Vec<f64> {
        self.breaks(true)
    }
    fn claims_energy(&self) -> bool {
        self.normalized || self.lobe.normalised()
    }
    fn strategies(&self) -> &'static [Strategy] {
        if self.lobe.cos_dist().is_some() {
            &[Strategy::Lobe, Strategy::Twin, Strategy::Cosine]
        } else {
            &[Strategy::Twin, Strategy::Cosine]
        }
    }
    fn sample_wi<T: Real>(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<V3<T>> {
        if s == Strategy::Cosine {
            return Some(sample::cosine(u));
        }
        let d = self.dist(s)?;
        if self.blinn {
            let z = [T::zero(), T::zero(), T::one()];
            sample::reflect_about(wo, d.sample_dir(z, u))
        } else {
            let w0 = T::c(self.back(&d, s));
            let u0 = sample::unit_interval(u[0]);
            let c = if u0 < w0 {
                -(u0 / w0)
            } else {
                d.sample((u0 - w0) / (T::one() - w0))
            };
            Some(sample::about(reflect(wo), c, sample::unit_interval(u[1])))
        }
    }
    fn pdf_wi<T: Real>(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T {
        if s == Strategy::Cosine {
            return sample::cosine_pdf(wi);
        }
        let Some(d) = self.dist(s) else {
            return T::zero();
        };
        if self.blinn {
            let z = [T::zero(), T::zero(), T::one()];
            match sample::half(wo, wi) {
                Some((h, c)) => d.pdf_dir(z, h) / (T::c(4.0) * c),
                None => T::zero(),
            }
        } else {
            let w0 = T::c(self.back(&d, s));
            let c = crate::vec3::dot(reflect(wo), wi);
            let pc = if c < T::zero() {
                w0
            } else {
                (T::one() - w0) * d.pdf(c)
            };
            pc / T::c(std::f64::consts::TAU)
        }
    }
}
