//! `ward`, `ward-pow`, `ward-power16`: Ward's 1992 BRDF and seed 000's one-function forms.
//!
//! - `ward` (isotropic, `alpha`; anisotropic with `alpha_x`, `alpha_y`):
//!   `f = exp(-(h_x^2/alpha_x^2 + h_y^2/alpha_y^2) / h_z^2) / (4 pi alpha_x alpha_y sqrt(cos_i cos_o))`;
//!   isotropic: `exp(-tan^2 theta_h / alpha^2) / (4 pi alpha^2 sqrt(cos_i cos_o))`.
//!   Cost: 6 mul, 1 add, 2 div, 1 sqrt, 1 exp (plus the pair set-up).
//! - `ward-pow`: the exponential replaced by `cos^(2/alpha^2) theta_h` (seed 000).
//!   Cost: 2 mul, 1 div, 1 sqrt, 1 pow.
//! - `ward-power16`: by `max(0, 1 + (2/alpha^2/16)(cos theta_h - 1))^16` (seed 000, g = 16).
//!   Cost: 6 mul, 2 add, 2 div, 1 sqrt.
//!
//! Parameters: `alpha` in [0.005, 1] (default 0.3); `ward` also `alpha_x`, `alpha_y` (both or
//! neither; when given they replace `alpha`). Source: Ward 1992; seed 000. Reciprocal.
//! Ward's normalisation is approximate: the albedo is below 1 up to 85 degrees of incidence
//! for every alpha, but the `1 / sqrt(cos_i)` factor makes it exceed 1 very near grazing
//! (alpha = 1: 0.49 at 89 degrees, 1.50 at 89.9; measured in `tests/energy.rs`). The approximations' error is that of their
//! exponential factor (the rest is identical): see the `INFO` bounds.
//! Sampling: `ward` by Walter 2005's half-vector sampling (`d-cos`: exactly Beckmann's
//! `D cos`, anisotropic); `ward-pow` by `cos^(2/alpha^2 - 3) theta_h` inverted in closed form
//! (`lobe`, alpha < 1) or Ward's (`twin`); `ward-power16` by Ward's (`twin`); all `cosine`.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::BrdfForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params;
use crate::plan::Plan;
use crate::real::{K, Real, pos, pow2k, sqr};
use crate::sample::{self, CosDist, Micro, MicroKind, Strategy};
use crate::vec3::{Pair, V3};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "ward",
    kind: Kind::Brdf,
    params: &[params::ALPHA, params::ALPHA_X, params::ALPHA_Y],
    formula: "exp(-(h_x^2/ax^2 + h_y^2/ay^2)/h_z^2) / (4 pi ax ay sqrt(cos_i cos_o))",
    source: "Ward 1992, 'Measuring and modeling anisotropic reflection'",
    ops: Ops::new(6, 1, 2, 1, 1),
    bounds: &[],
    f32_bound: 1e-5,
    note: "albedo <= 1 up to 85 degrees; exceeds 1 within ~0.5 degree of grazing (1.50 at 89.9 degrees, alpha = 1)",
};

pub const INFO_POW: ModelInfo = ModelInfo {
    id: "ward-pow",
    kind: Kind::Brdf,
    params: &[params::ALPHA],
    formula: "cos^(2/alpha^2) theta_h / (4 pi alpha^2 sqrt(cos_i cos_o))",
    source: "seed 000 (exp replaced by one power)",
    ops: Ops::new(2, 0, 1, 1, 1),
    bounds: &[
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 0.6),
            bound: 0.108,
        },
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 1.0),
            bound: 0.396,
        },
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.005, 0.6),
            bound: 0.108,
        },
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.005, 1.0),
            bound: 0.396,
        },
    ],
    f32_bound: 2.5e-3,
    note: "isotropic only; f32: cos_h^(2/alpha^2) of a cosine rounded to f32 has a relative error up to (2/alpha^2) 2^-25 (6e-4 at alpha = 0.01, 2.4e-3 at alpha = 0.005)",
};

pub const INFO_POWER16: ModelInfo = ModelInfo {
    id: "ward-power16",
    kind: Kind::Brdf,
    params: &[params::ALPHA],
    formula: "max(0, 1 + (2/alpha^2/16)(cos theta_h - 1))^16 / (4 pi alpha^2 sqrt(cos_i cos_o))",
    source: "seed 000 (g = 16 form of the exponential)",
    ops: Ops::new(6, 2, 2, 1, 0),
    bounds: &[
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 0.6),
            bound: 0.142,
        },
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.05, 1.0),
            bound: 0.549,
        },
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.005, 0.6),
            bound: 0.142,
        },
        ErrorBound {
            reference: "ward",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("alpha", 0.005, 1.0),
            bound: 0.549,
        },
    ],
    f32_bound: 1e-5,
    note: "isotropic only",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Brdf(
        match params::slope_params(p)? {
            ("alpha", _) => Ward::<0>::isotropic(p.num("alpha"))?,
            (x, y) => Ward::<0>::anisotropic(p.num(x), p.num(y))?,
        }
        .into(),
    ))
});
pub const ENTRY_POW: Entry = Entry::new(INFO_POW, |p, _| {
    Ok(Plan::Brdf(Ward::<1>::isotropic(p.num("alpha"))?.into()))
});
pub const ENTRY_POWER16: Entry = Entry::new(INFO_POWER16, |p, _| {
    Ok(Plan::Brdf(Ward::<2>::isotropic(p.num("alpha"))?.into()))
});

/// Ward's BRDF (`FORM` 0, anisotropic or isotropic) and seed 000's variants of its
/// exponential factor: `FORM` 1 `cos_h^(2/alpha^2)`, 2 its `(1 + x/16)^16` form.
#[derive(Clone, Copy, Debug)]
pub struct Ward<const FORM: u8> {
    /// `alpha_x`/`alpha_y` given (the WGSL parameters' names).
    aniso: bool,
    inv_ax2: K,
    inv_ay2: K,
    /// `2 / alpha^2` (pow) or `2 / alpha^2 / 16` (power16).
    e: K,
    /// `1 / (4 pi alpha_x alpha_y)`.
    scale: K,
}

impl<const FORM: u8> Ward<FORM> {
    /// Isotropic Ward of this form; `alpha` in [0.005, 1].
    pub fn isotropic(alpha: f64) -> Result<Self> {
        let a = params::check("ward", &params::ALPHA, alpha)?;
        Ok(Self::with(a, a, false))
    }

    fn with(ax: f64, ay: f64, aniso: bool) -> Self {
        let e = 2.0 / (ax * ax);
        Self {
            aniso,
            inv_ax2: K::new(1.0 / (ax * ax)),
            inv_ay2: K::new(1.0 / (ay * ay)),
            e: K::new(if FORM == 2 { e / 16.0 } else { e }),
            scale: K::new(1.0 / (4.0 * std::f64::consts::PI * ax * ay)),
        }
    }
}

impl Ward<0> {
    /// Anisotropic exact Ward; both slopes in [0.005, 1].
    pub fn anisotropic(alpha_x: f64, alpha_y: f64) -> Result<Self> {
        Ok(Self::with(
            params::check("ward", &params::ALPHA_X, alpha_x)?,
            params::check("ward", &params::ALPHA_Y, alpha_y)?,
            true,
        ))
    }
}

impl<const FORM: u8> Ward<FORM> {
    /// Ward's half-vector density (Walter 2005): Beckmann's `D cos` at the slopes.
    fn micro(&self) -> Micro {
        Micro {
            kind: MicroKind::Beckmann,
            ax: 1.0 / self.inv_ax2.x.sqrt(),
            ay: 1.0 / self.inv_ay2.x.sqrt(),
        }
    }
    /// `ward-pow`'s closed form: `cos^(2/alpha^2 - 3)`, integrable for alpha < 1.
    fn closed(&self) -> Option<CosDist> {
        let m = 2.0 * self.inv_ax2.x - 3.0;
        (FORM == 1 && m > -1.0 + 1e-9).then_some(CosDist::Pow { m })
    }
}

impl<const FORM: u8> BrdfForm for Ward<FORM> {
    const WGSL: &'static str = include_str!("ward.wgsl");
    fn strategies(&self) -> &'static [Strategy] {
        match FORM {
            0 => &[Strategy::DCos, Strategy::Cosine],
            _ if self.closed().is_some() => &[Strategy::Lobe, Strategy::Twin, Strategy::Cosine],
            _ => &[Strategy::Twin, Strategy::Cosine],
        }
    }
    fn sample_wi<T: Real>(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<V3<T>> {
        let h = match s {
            Strategy::Cosine => return Some(sample::cosine(u)),
            Strategy::Lobe => self
                .closed()?
                .sample_dir([T::zero(), T::zero(), T::one()], u),
            _ => self.micro().sample_dcos(u),
        };
        sample::reflect_about(wo, h)
    }
    fn pdf_wi<T: Real>(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T {
        if s == Strategy::Cosine {
            return sample::cosine_pdf(wi);
        }
        let Some((h, c)) = sample::half(wo, wi) else {
            return T::zero();
        };
        let ph = match s {
            Strategy::Lobe => match self.closed() {
                Some(d) => d.pdf_dir([T::zero(), T::zero(), T::one()], h),
                None => T::zero(),
            },
            _ => self.micro().pdf_dcos(h),
        };
        ph / (T::c(4.0) * c)
    }
    fn claims_energy(&self) -> bool {
        true
    }
    #[inline(always)]
    fn at_pair<T: Real, M: Math<T>>(&self, p: &Pair<T>) -> T {
        let lobe = match FORM {
            0 => {
                let q = M::madd(
                    sqr(p.h[0]),
                    self.inv_ax2.t::<T>(),
                    sqr(p.h[1]) * self.inv_ay2.t::<T>(),
                );
                M::exp_nonpos(-q / sqr(p.cos_h))
            }
            1 => M::pow(p.cos_h, self.e.t::<T>()),
            _ => {
                let cos_minus_1 = -p.sin2_h / (T::one() + p.cos_h);
                pow2k(pos(M::madd(self.e.t::<T>(), cos_minus_1, T::one())), 4)
            }
        };
        self.scale.t::<T>() * lobe / (p.cos_i * p.cos_o).sqrt()
    }
    fn wgsl_body(&self, e: &Emit) -> String {
        let (nx, ny) = if self.aniso {
            ("alpha_x", "alpha_y")
        } else {
            ("alpha", "alpha")
        };
        let scale = e.kx(
            self.scale,
            &format!("0.07957747154594767 / (p_{nx} * p_{ny})"),
            &[nx, ny],
        );
        match FORM {
            0 => format!(
                "    return fb_brdf_ward(wi, wo, {}, {}, {scale});\n",
                e.kx(self.inv_ax2, &format!("1.0 / (p_{nx} * p_{nx})"), &[nx]),
                e.kx(self.inv_ay2, &format!("1.0 / (p_{ny} * p_{ny})"), &[ny])
            ),
            1 => format!(
                "    return fb_brdf_ward_pow(wi, wo, {}, {scale});\n",
                e.kx(self.e, &format!("2.0 / (p_{nx} * p_{nx})"), &[nx])
            ),
            _ => format!(
                "    return fb_brdf_ward_power16(wi, wo, {}, {scale});\n",
                e.kx(self.e, &format!("0.125 / (p_{nx} * p_{nx})"), &[nx])
            ),
        }
    }
}
