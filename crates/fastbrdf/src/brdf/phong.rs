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
//! Parameters: `lobe` (a lobe id, default `pow`), `n` in [1, 10000] (default 20), `norm`
//! (`energy` or `none`, default `energy`). Cost: the lobe's, plus 3 mul, 2 add (phong) or
//! 1 mul, 1 div (blinn-phong, energy). Reciprocal.

use crate::error::Result;
use crate::lobes;
use crate::model::{Brdf, Kind, Lobe, Model, ModelInfo, Ops};
use crate::params::{self, ParamKind, ParamSpec, Params};
use crate::quad;
use crate::real::Real;
use crate::registry::{self, Entry};
use crate::vec3::Pair;

pub const LOBE: ParamSpec = ParamSpec {
    name: "lobe",
    kind: ParamKind::Choice {
        options: lobes::IDS,
        default: "pow",
    },
    doc: "lobe id",
};
pub const NORM: ParamSpec = ParamSpec {
    name: "norm",
    kind: ParamKind::Choice {
        options: &["energy", "none"],
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
    f32_bound: 200.0,
    note: "ops are the wrapper's, add the lobe's; albedo at normal incidence = 1 with norm = energy; f32: reflect(wi).wo rounded once to f32 moves flog-normalized-clamped near its zero (slope ~3e6 at n = 10000) by up to 0.3, times coef(n): 85 at n = 10000 (check --full); below 0.2 for the other lobes",
};

pub const INFO_BLINN: ModelInfo = ModelInfo {
    id: "blinn-phong",
    kind: Kind::Brdf,
    params: &[LOBE, params::N, NORM],
    formula: "coef(n) lobe(n . h) / (4 wi . h) (energy) or lobe(n . h) (none)",
    source: "Blinn 1977; Torrance & Sparrow 1967 (microfacet form); seed 001 (coef by Int(n))",
    ops: Ops::new(1, 0, 1, 0, 0),
    bounds: &[],
    f32_bound: 600.0,
    note: "ops are the wrapper's, add the lobe's; albedo <= 1 with norm = energy; f32: cos_h rounded once to f32 moves flog-normalized-clamped near its zero by up to 0.3, times coef(n) / (4 wi.h): 265 at n = 10000 (check --full); 2 for flog-normalized",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32, 0>,
    build64: build::<f64, 0>,
};
pub const ENTRY_BLINN: Entry = Entry {
    info: INFO_BLINN,
    build32: build::<f32, 1>,
    build64: build::<f64, 1>,
};

/// `Int(n) = integral_0^1 lobe(c) c dc` of a lobe, by adaptive quadrature (exact for `pow`).
pub fn lobe_integral(lobe_id: &str, n: f64) -> Result<f64> {
    if lobe_id == "pow" {
        return Ok(1.0 / (n + 2.0));
    }
    let lobe = build_lobe::<f64>(lobe_id, n)?;
    let mut breaks = lobe.kinks();
    breaks.push(lobe.zero_below());
    let lo = lobe.zero_below();
    Ok(quad::integrate(|c| lobe.eval(c) * c, lo, 1.0, &breaks, 1e-12).0)
}

/// Builds a lobe by id with exponent `n`.
pub fn build_lobe<T: Real>(id: &str, n: f64) -> Result<Box<dyn Lobe<T>>> {
    match registry::build::<T>(id, &[("n", &n.to_string())])? {
        Model::Lobe(l) => Ok(l),
        other => Err(crate::Error::WrongKind {
            model: id.into(),
            expected: "lobe".into(),
            found: other.kind().name().into(),
        }),
    }
}

/// A Phong or Blinn-Phong BRDF built from a lobe.
pub struct LobeBrdf<T: Real> {
    lobe: Box<dyn Lobe<T>>,
    /// The lobe's cut (`Lobe::zero_below`), decided on the f64 cosine of the pair.
    zero: f64,
    coef: T,
    blinn: bool,
    normalized: bool,
}

impl<T: Real> LobeBrdf<T> {
    /// `blinn`: lobe of `n . h` (else of `reflect(wi) . wo`); `normalized`: apply `coef(n)`.
    pub fn new(lobe_id: &str, n: f64, blinn: bool, normalized: bool) -> Result<Self> {
        let n = params::check(if blinn { "blinn-phong" } else { "phong" }, &params::N, n)?;
        let lobe = build_lobe::<T>(lobe_id, n)?;
        let coef = if normalized {
            1.0 / (2.0 * std::f64::consts::PI * lobe_integral(lobe_id, n)?)
        } else {
            1.0
        };
        Ok(Self {
            zero: lobe.zero_below(),
            lobe,
            coef: T::c(coef),
            blinn,
            normalized,
        })
    }
}

impl<T: Real> Brdf<T> for LobeBrdf<T> {
    #[inline]
    fn eval_pair(&self, p: &Pair<T>) -> T {
        // A lobe without a cut (zero = 0) takes negative cosines as 0 (clamped, not cut).
        if p.lobe_cut(self.zero, self.blinn) {
            return T::zero();
        }
        if self.blinn {
            let l = self.lobe.eval(p.cos_h);
            if self.normalized {
                self.coef * l / (T::c(4.0) * p.cos_ih)
            } else {
                l
            }
        } else {
            self.coef * self.lobe.eval(p.cos_r)
        }
    }
    fn mirror_breaks(&self) -> Vec<f64> {
        self.breaks(false)
    }
    fn half_breaks(&self) -> Vec<f64> {
        self.breaks(true)
    }
}

impl<T: Real> LobeBrdf<T> {
    /// The lobe's kinks and cut, for the cosine it is a lobe of: that of the half vector
    /// (`blinn`) or of the mirror direction; none for the other.
    fn breaks(&self, blinn: bool) -> Vec<f64> {
        if self.blinn != blinn {
            return Vec::new();
        }
        let mut b = self.lobe.kinks();
        b.push(self.lobe.zero_below());
        b
    }
}

fn build<T: Real, const BLINN: u8>(p: &Params) -> Result<Model<T>> {
    let b = LobeBrdf::<T>::new(
        p.choice("lobe"),
        p.num("n"),
        BLINN == 1,
        p.choice("norm") == "energy",
    )?;
    Ok(Model::Brdf(Box::new(b)))
}
