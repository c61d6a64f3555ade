//! Fresnel terms: `fresnel-none`, `fresnel-schlick`, `fresnel-dielectric`, `fresnel-conductor`
//! (the `f` choices of `cook-torrance`: `none`, `schlick`, `dielectric`, `conductor`).
//!
//! - none: `F = 1`.
//! - schlick: `F = f0 + (1 - f0)(1 - cos)^5` (Schlick 1994). Cost: 4 mul, 2 add.
//! - dielectric: the exact unpolarised Fresnel reflectance of a dielectric interface with
//!   relative index `eta` (`eta < 1` gives total internal reflection beyond the critical
//!   angle), as pbrt's `FrDielectric`. Cost: ~10 mul, 6 add, 3 div, 1 sqrt.
//! - conductor: the exact unpolarised reflectance for a complex index `eta + i k`, in the
//!   real-arithmetic form of pbrt-v3's `FrConductor` (tested against complex arithmetic).
//!   Cost: ~16 mul, 8 add, 2 div, 3 sqrt.
//!
//! Parameters: `f0` in [0, 1] (default 0.04), `eta` in [0.01, 10] (default 1.5), `k` in [0, 20]
//! (default 0). The cosine is that between the view and the microfacet normal.

use crate::error::Result;
use crate::model::{Fresnel, Kind, Model, ModelInfo, Ops};
use crate::params::{ParamKind, ParamSpec, Params};
use crate::real::{Real, sqr};
use crate::registry::Entry;

pub const F0: ParamSpec = ParamSpec {
    name: "f0",
    kind: ParamKind::Number {
        min: 0.0,
        max: 1.0,
        default: Some(0.04),
    },
    doc: "reflectance at normal incidence (Schlick)",
};
pub const ETA: ParamSpec = ParamSpec {
    name: "eta",
    kind: ParamKind::Number {
        min: 0.01,
        max: 10.0,
        default: Some(1.5),
    },
    doc: "relative index of refraction (real part)",
};
pub const K: ParamSpec = ParamSpec {
    name: "k",
    kind: ParamKind::Number {
        min: 0.0,
        max: 20.0,
        default: Some(0.0),
    },
    doc: "extinction coefficient (imaginary part of the index, conductors)",
};

/// The Fresnel choices of `cook-torrance`.
pub const CHOICES: &[&str] = &["none", "schlick", "dielectric", "conductor"];

macro_rules! info {
    ($id:literal, $params:expr, $formula:literal, $source:literal, $ops:expr) => {
        ModelInfo {
            id: $id,
            kind: Kind::Fresnel,
            params: $params,
            formula: $formula,
            source: $source,
            ops: $ops,
            bounds: &[],
            f32_bound: 1e-6,
            note: "",
        }
    };
}

pub const INFO_NONE: ModelInfo = info!("fresnel-none", &[], "1", "-", Ops::new(0, 0, 0, 0, 0));
pub const INFO_SCHLICK: ModelInfo = info!(
    "fresnel-schlick",
    &[F0],
    "f0 + (1 - f0)(1 - cos)^5",
    "Schlick 1994",
    Ops::new(4, 2, 0, 0, 0)
);
pub const INFO_DIELECTRIC: ModelInfo = info!(
    "fresnel-dielectric",
    &[ETA],
    "(r_par^2 + r_perp^2) / 2, exact, with total internal reflection",
    "Fresnel equations; pbrt-v3 FrDielectric",
    Ops::new(10, 6, 3, 1, 0)
);
pub const INFO_CONDUCTOR: ModelInfo = info!(
    "fresnel-conductor",
    &[ETA, K],
    "(R_s + R_p) / 2 for complex index eta + i k, exact",
    "Fresnel equations; pbrt-v3 FrConductor",
    Ops::new(16, 8, 2, 3, 0)
);

pub const ENTRY_NONE: Entry = Entry {
    info: INFO_NONE,
    build32: build::<f32, 0>,
    build64: build::<f64, 0>,
};
pub const ENTRY_SCHLICK: Entry = Entry {
    info: INFO_SCHLICK,
    build32: build::<f32, 1>,
    build64: build::<f64, 1>,
};
pub const ENTRY_DIELECTRIC: Entry = Entry {
    info: INFO_DIELECTRIC,
    build32: build::<f32, 2>,
    build64: build::<f64, 2>,
};
pub const ENTRY_CONDUCTOR: Entry = Entry {
    info: INFO_CONDUCTOR,
    build32: build::<f32, 3>,
    build64: build::<f64, 3>,
};

/// A Fresnel term, chosen by name.
#[derive(Clone, Debug)]
pub enum FresnelTerm<T> {
    None,
    Schlick { f0: T },
    Dielectric { eta: T },
    Conductor { eta: T, k: T },
}

impl<T: Real> FresnelTerm<T> {
    /// Builds the term named `choice` (`none`, `schlick`, `dielectric`, `conductor`) from
    /// already validated `f0`, `eta`, `k`.
    pub fn from_choice(choice: &str, f0: f64, eta: f64, k: f64) -> Self {
        match choice {
            "schlick" => Self::Schlick { f0: T::c(f0) },
            "dielectric" => Self::Dielectric { eta: T::c(eta) },
            "conductor" => Self::Conductor {
                eta: T::c(eta),
                k: T::c(k),
            },
            _ => Self::None,
        }
    }
}

impl<T: Real> Fresnel<T> for FresnelTerm<T> {
    #[inline]
    fn f(&self, cos: T) -> T {
        let one = T::one();
        let c = if cos >= T::zero() {
            cos.min(one)
        } else {
            T::zero()
        };
        match *self {
            Self::None => one,
            Self::Schlick { f0 } => {
                let m = one - c;
                let m2 = m * m;
                f0 + (one - f0) * (m2 * m2 * m)
            }
            Self::Dielectric { eta } => {
                let sin2_t = (one - c * c) / (eta * eta);
                if sin2_t >= one {
                    return one;
                }
                let cos_t = (one - sin2_t).sqrt();
                let r_par = (eta * c - cos_t) / (eta * c + cos_t);
                let r_perp = (c - eta * cos_t) / (c + eta * cos_t);
                (r_par * r_par + r_perp * r_perp) * T::c(0.5)
            }
            Self::Conductor { eta, k } => {
                let cos2 = c * c;
                let sin2 = one - cos2;
                let eta2 = eta * eta;
                let k2 = k * k;
                let t0 = eta2 - k2 - sin2;
                let a2b2 = (sqr(t0) + T::c(4.0) * eta2 * k2).sqrt();
                let t1 = a2b2 + cos2;
                let a = (T::c(0.5) * (a2b2 + t0)).max(T::zero()).sqrt();
                let t2 = T::c(2.0) * c * a;
                let rs = (t1 - t2) / (t1 + t2);
                let t3 = cos2 * a2b2 + sin2 * sin2;
                let t4 = t2 * sin2;
                let rp = rs * (t3 - t4) / (t3 + t4);
                let f = (rp + rs) * T::c(0.5);
                if f.is_finite() {
                    f.max(T::zero()).min(one)
                } else {
                    one
                }
            }
        }
    }
}

fn build<T: Real, const W: u8>(p: &Params) -> Result<Model<T>> {
    let term = match W {
        0 => FresnelTerm::None,
        1 => FresnelTerm::Schlick {
            f0: T::c(p.num("f0")),
        },
        2 => FresnelTerm::Dielectric {
            eta: T::c(p.num("eta")),
        },
        _ => FresnelTerm::Conductor {
            eta: T::c(p.num("eta")),
            k: T::c(p.num("k")),
        },
    };
    Ok(Model::Fresnel(Box::new(term)))
}
