//! `beckmann-pow` and `beckmann-power4/8/16`: seed 000's one-function Beckmann forms.
//!
//! Seed 000 replaces `exp(-tan^2 theta / m^2)` by `cos^(2/m^2) theta` (equal to second order
//! in theta), so that with the `1 / cos^4` factor
//! - `beckmann-pow`: `D = cos^(2/m^2 - 4) theta_h / (4 m^2)` (one `pow`), and then replaces the
//!   power by `(1 + x/g)^g` (Lyon 1993):
//! - `beckmann-power{g}`: `D = max(0, 1 + ((2/m^2 - 4)/g)(cos theta_h - 1))^g / (4 m^2)`,
//!   `g = 4, 8, 16` (k = 2, 3, 4 squarings).
//!
//! All approximate `beckmann-ct` (the same `1 / (4 m^2)` normalisation).
//! Warning, by construction: for `m > 1/sqrt(2)` the exponent `2/m^2 - 4` is negative, so
//! `beckmann-pow` grows without bound as `cos theta_h -> 0` while the exact D goes to 0; the
//! power forms stay bounded (their base exceeds 1) but are also far from the exact value
//! there. Below `cos_h = COS_MIN` every form returns 0. `cos theta_h - 1` is computed as
//! `-sin^2 / (1 + cos)`, exact in f32 near the peak.
//! Parameters: `alpha` (= m) in [0.005, 1] (default 0.3). Source: seed 000 (Romanyuk et al.).
//! Cost: `beckmann-pow` 1 mul and 1 pow; power forms 2 mul, 2 add and k squarings in the batch
//! kernels (`DistForm::batch`: `cos - 1` straight from the f32 cosine), one division more in
//! the BRDFs (`d`: `-sin^2 / (1 + cos)` from the half vector's `sin^2`).
//! Error bounds against `beckmann-ct`: see the `INFO` constants.
//! Sampling (in `cook-torrance`): `beckmann-pow` inverts `D cos ~ cos^(2/m^2 - 3)` in closed form (m < 1); the power forms (and `twin`) sample Beckmann's `D cos` at the same alpha and weight by f/pdf.

use super::beckmann::{ct_scale, ct_scale_wgsl};
use crate::entry::Entry;
use crate::error::Result;
use crate::forms::{DistForm, DistSampler};
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params;
use crate::plan::Plan;
use crate::real::{K as Coef, Real, pos, pow2k};
use crate::sample::{CosDist, Micro, MicroKind};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "beckmann-pow",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "cos^(2/m^2 - 4) theta_h / (4 m^2)",
    source: "seed 000 ('one function' D)",
    ops: Ops::new(1, 0, 0, 0, 1),
    bounds: &[
        ErrorBound {
            reference: "beckmann-ct",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 0.6),
            bound: 0.403,
        },
        ErrorBound {
            reference: "beckmann-ct",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 1.0),
            bound: 4.65,
        },
        ErrorBound {
            reference: "beckmann-ct",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.005, 0.6),
            bound: 0.403,
        },
        ErrorBound {
            reference: "beckmann-ct",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.005, 1.0),
            bound: 4.65,
        },
    ],
    f32_bound: 1e-6,
    note: "unbounded as cos theta_h -> 0 for m > 1/sqrt(2) (negative exponent), by the seed's construction",
};

macro_rules! power_info {
    ($id:literal, $k:literal, $formula:literal, $b06:expr, $b1:expr, $w06:expr, $w1:expr) => {
        ModelInfo {
            id: $id,
            kind: Kind::Distribution,
            params: &[params::ALPHA],
            formula: $formula,
            source: "seed 000 (D4, D8, D16); Lyon 1993",
            // The batch kernel's count (`batch`: no division); `d` adds one for the BRDFs.
            ops: Ops::new(2 + $k, 2, 0, 0, 0),
            bounds: &[
                ErrorBound {
                    reference: "beckmann-ct",
                    metric: Metric::MaxRel,
                    zone: Zone::Epicentre,
                    param: ("alpha", 0.05, 0.6),
                    bound: $b06,
                },
                ErrorBound {
                    reference: "beckmann-ct",
                    metric: Metric::MaxRel,
                    zone: Zone::Epicentre,
                    param: ("alpha", 0.05, 1.0),
                    bound: $b1,
                },
                ErrorBound {
                    reference: "beckmann-ct",
                    metric: Metric::MaxRel,
                    zone: Zone::Epicentre,
                    param: ("alpha", 0.005, 0.6),
                    bound: $w06,
                },
                ErrorBound {
                    reference: "beckmann-ct",
                    metric: Metric::MaxRel,
                    zone: Zone::Epicentre,
                    param: ("alpha", 0.005, 1.0),
                    bound: $w1,
                },
            ],
            f32_bound: 8e-6,
            note: "f32: 4.6e-6 (power4; check --full, alpha down to 0.005)",
        }
    };
}

pub const INFO4: ModelInfo = power_info!(
    "beckmann-power4",
    2,
    "max(0, 1 + ((2/m^2 - 4)/4)(cos theta_h - 1))^4 / (4 m^2)",
    0.438,
    2.37,
    0.438,
    2.37
);
pub const INFO8: ModelInfo = power_info!(
    "beckmann-power8",
    3,
    "max(0, 1 + ((2/m^2 - 4)/8)(cos theta_h - 1))^8 / (4 m^2)",
    0.447,
    2.55,
    0.447,
    2.55
);
pub const INFO16: ModelInfo = power_info!(
    "beckmann-power16",
    4,
    "max(0, 1 + ((2/m^2 - 4)/16)(cos theta_h - 1))^16 / (4 m^2)",
    0.452,
    2.65,
    0.452,
    2.65
);

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Distribution(BeckmannPow::new(p.num("alpha"))?.into()))
});
pub const ENTRY4: Entry = Entry::new(INFO4, |p, _| {
    Ok(Plan::Distribution(
        BeckmannPower::<2>::new(p.num("alpha"))?.into(),
    ))
});
pub const ENTRY8: Entry = Entry::new(INFO8, |p, _| {
    Ok(Plan::Distribution(
        BeckmannPower::<3>::new(p.num("alpha"))?.into(),
    ))
});
pub const ENTRY16: Entry = Entry::new(INFO16, |p, _| {
    Ok(Plan::Distribution(
        BeckmannPower::<4>::new(p.num("alpha"))?.into(),
    ))
});

/// Seed 000's exponent `2 / m^2 - 4`.
pub fn exponent(alpha: f64) -> f64 {
    2.0 / (alpha * alpha) - 4.0
}

/// `exponent` as a WGSL expression of `p_alpha`.
const EXPONENT_WGSL: &str = "2.0 / (p_alpha * p_alpha) - 4.0";

/// `cos^(2/m^2 - 4) / (4 m^2)`.
#[derive(Clone, Copy, Debug)]
pub struct BeckmannPow {
    alpha: f64,
    e: Coef,
    scale: Coef,
}

impl BeckmannPow {
    /// `alpha` in [0.005, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        let alpha = params::check("beckmann-pow", &params::ALPHA, alpha)?;
        Ok(Self {
            alpha,
            e: Coef::new(exponent(alpha)),
            scale: Coef::new(ct_scale(alpha)),
        })
    }
}

/// The exact twin of the seed's forms: Beckmann at the same `alpha`, sampled by `D cos`.
fn twin(alpha: f64, closed: Option<CosDist>) -> DistSampler {
    DistSampler {
        micro: Micro {
            kind: MicroKind::Beckmann,
            ax: alpha,
            ay: alpha,
        },
        exact: false,
        closed,
    }
}

impl DistForm for BeckmannPow {
    /// An approximation of `beckmann-ct` at the same alpha: Beckmann's Smith term.
    fn smith(&self) -> &'static str {
        "smith"
    }
    /// `D cos = cos^(2/m^2 - 3) / (4 m^2)` inverts in closed form where it is integrable
    /// (`2/m^2 - 3 > -1`: m < 1); at m = 1 only the twin.
    fn sampler(&self) -> DistSampler {
        let m = exponent(self.alpha) + 1.0;
        twin(self.alpha, (m > -1.0 + 1e-9).then_some(CosDist::Pow { m }))
    }
    const WGSL: &'static str = include_str!("beckmann_pow.wgsl");
    #[inline(always)]
    fn d<T: Real, M: Math<T>>(&self, cos_h: T, _sin2_h: T) -> T {
        self.scale.t::<T>() * M::pow(cos_h, self.e.t::<T>())
    }
    fn wgsl(&self, c: &str, _s2: &str, e: &Emit) -> String {
        let a = self.alpha;
        format!(
            "fb_d_beckmann_pow({c}, {}, {})",
            e.kx(self.e, EXPONENT_WGSL, &["alpha"]),
            ct_scale_wgsl(a, e)
        )
    }
}

/// `max(0, 1 + s (cos - 1))^(2^K) / (4 m^2)` with `s = (2/m^2 - 4) / 2^K`.
#[derive(Clone, Copy, Debug)]
pub struct BeckmannPower<const K: u32> {
    alpha: f64,
    s: Coef,
    scale: Coef,
}

impl<const K: u32> BeckmannPower<K> {
    /// `g = 2^K`.
    pub const G: u32 = 1 << K;

    /// `alpha` in [0.005, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        let alpha = params::check("beckmann-power", &params::ALPHA, alpha)?;
        Ok(Self {
            alpha,
            s: Coef::new(exponent(alpha) / f64::from(Self::G)),
            scale: Coef::new(ct_scale(alpha)),
        })
    }
}

impl<const K: u32> DistForm for BeckmannPower<K> {
    /// An approximation of `beckmann-ct` at the same alpha: Beckmann's Smith term.
    fn smith(&self) -> &'static str {
        "smith"
    }
    /// `D cos` (a power-g form times `cos`) has no closed-form inverse: the twin.
    fn sampler(&self) -> DistSampler {
        twin(self.alpha, None)
    }
    const WGSL: &'static str = include_str!("beckmann_pow.wgsl");
    #[inline(always)]
    fn d<T: Real, M: Math<T>>(&self, cos_h: T, sin2_h: T) -> T {
        let cos_minus_1 = -sin2_h / (T::one() + cos_h);
        self.scale.t::<T>() * pow2k(pos(M::madd(self.s.t::<T>(), cos_minus_1, T::one())), K)
    }
    /// The batch kernels' form (issue 13): their input is the f32 cosine itself, so `cos - 1`
    /// is computed directly (exact for `cos >= 1/2`; below, where `1 + s (cos - 1)` is clamped
    /// to 0 unless `s <= 2`, relative to 6e-8) instead of `-sin^2 / (1 + cos)`, whose division
    /// only adds a rounding when `sin^2` is itself `(1 - c)(1 + c)`. `d` keeps that form for
    /// the BRDFs, whose `sin^2` comes from the half vector. One multiply and the division
    /// fewer than the default form.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let t = M::madd(self.s.t::<f32>(), crate::real::min1(c) - 1.0, 1.0);
        let v = self.scale.t::<f32>() * pow2k(pos(t), K);
        crate::forms::above_cos_min(c, v)
    }
    fn wgsl(&self, c: &str, s2: &str, e: &Emit) -> String {
        let g = Self::G;
        format!(
            "fb_d_beckmann_power{g}({c}, {s2}, {}, {})",
            e.kx(self.s, &format!("({EXPONENT_WGSL}) / {g}.0"), &["alpha"]),
            ct_scale_wgsl(self.alpha, e)
        )
    }
}
