//! `cook-torrance`: the microfacet BRDF `F D G / (4 cos theta_i cos theta_o)`.
//!
//! Parameters:
//!
//! | name | range | default | meaning |
//! |---|---|---|---|
//! | `alpha` | [0.01, 1] | 0.3 | RMS slope of D and of the Smith terms |
//! | `d` | a distribution id | `beckmann` | `beckmann`, `beckmann-ct`, `beckmann-pow`, `beckmann-power4/8/16` |
//! | `g` | `v-cavity`, `smith`, `smith-rational` | `smith` | shadowing-masking |
//! | `f` | `none`, `schlick`, `dielectric`, `conductor` | `none` | Fresnel at `wi . h` |
//! | `f0`, `eta`, `k` | see `microfacet::fresnel` | 0.04, 1.5, 0 | Fresnel parameters |
//! | `denominator` | `4`, `seed-000`, `seed-001` | `4` | `4 cos_i cos_o`, `cos_i cos_o` (seed 000), `pi cos_i cos_o` (seed 001) |
//!
//! With the defaults and `f = none` this is exactly Mitsuba 3's `roughconductor` (Beckmann,
//! no visible-normal sampling involved in `eval`) divided by `cos theta_o`: microfacet theory
//! (Walter et al. 2007). The seeds' denominators exist as named variants; they are not energy
//! conserving with the normalised `beckmann`.
//! Source: Cook & Torrance 1982; Walter et al. 2007. Cost: D + G + F + 3 mul, 1 div (plus the
//! pair set-up: 2 normalisations of wi, wo and one of h). Reciprocal.

use crate::error::{Error, Result};
use crate::microfacet::{DISTRIBUTION_IDS, fresnel};
use crate::model::{
    Brdf, Distribution, Fresnel, Kind, Model, ModelInfo, Ops, ShadowInput, Shadowing,
};
use crate::params::{self, ParamKind, ParamSpec, Params};
use crate::real::Real;
use crate::registry::{self, Entry};
use crate::vec3::Pair;

pub const D: ParamSpec = ParamSpec {
    name: "d",
    kind: ParamKind::Choice {
        options: DISTRIBUTION_IDS,
        default: "beckmann",
    },
    doc: "microfacet distribution id",
};
pub const G: ParamSpec = ParamSpec {
    name: "g",
    kind: ParamKind::Choice {
        options: &["v-cavity", "smith", "smith-rational"],
        default: "smith",
    },
    doc: "shadowing-masking term",
};
pub const F: ParamSpec = ParamSpec {
    name: "f",
    kind: ParamKind::Choice {
        options: fresnel::CHOICES,
        default: "none",
    },
    doc: "Fresnel term",
};
pub const DENOMINATOR: ParamSpec = ParamSpec {
    name: "denominator",
    kind: ParamKind::Choice {
        options: &["4", "seed-000", "seed-001"],
        default: "4",
    },
    doc: "4 cos_i cos_o (microfacet theory), cos_i cos_o (seed 000), pi cos_i cos_o (seed 001)",
};

pub const INFO: ModelInfo = ModelInfo {
    id: "cook-torrance",
    kind: Kind::Brdf,
    params: &[
        params::ALPHA,
        D,
        G,
        F,
        fresnel::F0,
        fresnel::ETA,
        fresnel::K,
        DENOMINATOR,
    ],
    formula: "F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o)",
    source: "Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators)",
    ops: Ops::new(3, 0, 1, 0, 0),
    bounds: &[],
    f32_bound: 3.0,
    note: "ops exclude D, G, F and the pair set-up; equals Mitsuba 3 roughconductor eval / cos_o; f32: 1e-5 except with f = dielectric/conductor at eta << 1, where F is a near-step at the critical angle and wi.h rounded once to f32 can double it (1.0 at eta = 0.01)",
};

pub const ENTRY: Entry = Entry {
    info: INFO,
    build32: build::<f32>,
    build64: build::<f64>,
};

/// Cook-Torrance with D, G and F chosen by name.
pub struct CookTorrance<T: Real> {
    d: Box<dyn Distribution<T>>,
    g: Box<dyn Shadowing<T>>,
    f: fresnel::FresnelTerm<T>,
    k: T,
}

impl<T: Real> CookTorrance<T> {
    /// Builds from validated parameters (see the table in the module header).
    pub fn from_params(p: &Params) -> Result<Self> {
        let alpha = p.num("alpha").to_string();
        let d = match registry::build::<T>(p.choice("d"), &[("alpha", &alpha)])? {
            Model::Distribution(d) => d,
            _ => unreachable!("d choices are distributions"),
        };
        let g_id = p.choice("g");
        let g_params: &[(&str, &str)] = if g_id == "v-cavity" {
            &[]
        } else {
            &[("alpha", &alpha)]
        };
        let g = match registry::build::<T>(g_id, g_params)? {
            Model::Shadowing(g) => g,
            _ => unreachable!("g choices are shadowing terms"),
        };
        let f =
            fresnel::FresnelTerm::from_choice(p.choice("f"), p.num("f0"), p.num("eta"), p.num("k"));
        let k = match p.choice("denominator") {
            "4" => 0.25,
            "seed-000" => 1.0,
            "seed-001" => std::f64::consts::FRAC_1_PI,
            other => {
                return Err(Error::InvalidParam {
                    model: "cook-torrance".into(),
                    param: "denominator".into(),
                    value: other.into(),
                    expected: "4, seed-000 or seed-001".into(),
                });
            }
        };
        Ok(Self {
            d,
            g,
            f,
            k: T::c(k),
        })
    }
}

impl<T: Real> Brdf<T> for CookTorrance<T> {
    #[inline]
    fn eval_pair(&self, p: &Pair<T>) -> T {
        let d = self.d.d(p.cos_h, p.sin2_h);
        let g = self.g.g(&ShadowInput {
            cos_v: p.cos_o,
            cos_l: Some(p.cos_i),
            cos_h: p.cos_h,
            cos_vh: p.cos_ih,
        });
        let f = self.f.f(p.cos_ih);
        f * d * g * self.k / (p.cos_i * p.cos_o)
    }
}

fn build<T: Real>(p: &Params) -> Result<Model<T>> {
    Ok(Model::Brdf(Box::new(CookTorrance::<T>::from_params(p)?)))
}
