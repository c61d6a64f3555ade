//! `beckmann` and `beckmann-ct`: the exact Beckmann distribution in two normalisations.
//!
//! - `beckmann`: `D = exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)`, normalised so
//!   that the integral of `D cos theta_h` over the hemisphere is 1 (Walter et al. 2007,
//!   Mitsuba 3's `MicrofacetDistribution`, pbrt). Cost: 3 mul, 1 div, 1 exp.
//! - `beckmann-ct`: `exp(-tan^2 theta_h / m^2) / (4 m^2 cos^4 theta_h)`, the Cook-Torrance form
//!   seed 000 uses (`= beckmann * pi / 4`). Cost: 3 mul, 1 div, 1 exp.
//!
//! `tan^2 = sin^2 / cos^2` with `sin^2` from the half vector (BRDFs) or `(1 - c)(1 + c)`
//! (standalone), avoiding `1 - c^2` cancellation near the peak.
//! Parameters: `alpha` in [0.005, 1] (default 0.3). Below `cos_h = COS_MIN` the value is 0 (the
//! exact value there is below 1e-300). Exact models: no error bound; `beckmann`'s
//! normalisation is tested to 1e-6 for alpha in [0.005, 1]. At alpha = 0.005 (issue 14: the
//! smallest MERL fit) `1/alpha^2 = 4e4` and the peak `1/(pi alpha^2) = 1.3e4` are well inside
//! f32; in f32 the exponential underflows to 0 about 2.7 degrees off the peak, where the exact
//! value is below 2e-38 of the peak (mixed error 1e-6, relative error 1).
//!
//! Anisotropic Beckmann (`alpha_x`, `alpha_y`) needs the half vector's azimuth, which the
//! distribution kind (inputs `cos_h`, `sin^2 h`) does not have: it is `cook-torrance`'s
//! `alpha_x`, `alpha_y` with `d = beckmann` (or `beckmann-ct`), this formula at
//! `alpha = sqrt(alpha_x alpha_y)` on a stretched `sin^2` (`brdf::cook_torrance`,
//! `DistForm::ANISO`).
//! Sampling (in `cook-torrance`): `D cos` (`tan^2 = -alpha^2 ln(1 - u)`) and visible normals (Heitz & d'Eon 2014), `sample::Micro`.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::{DistForm, DistSampler};
use crate::math::Math;
use crate::model::{Kind, ModelInfo, Ops};
use crate::params;
use crate::plan::Plan;
use crate::real::{K, Real};
use crate::sample::{Micro, MicroKind};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "beckmann",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)",
    source: "Beckmann & Spizzichino 1963; Walter et al. 2007 (normalisation of Mitsuba 3, pbrt)",
    ops: Ops::new(4, 0, 2, 0, 1),
    bounds: &[],
    f32_bound: 3e-6,
    note: "integral of D cos theta_h over the hemisphere = 1; f32: 1.4e-6 at alpha = 0.01; anisotropic: cook-torrance's alpha_x, alpha_y",
};

pub const INFO_CT: ModelInfo = ModelInfo {
    id: "beckmann-ct",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "exp(-tan^2 theta_h / m^2) / (4 m^2 cos^4 theta_h)",
    source: "Cook & Torrance 1982; seed 000",
    ops: Ops::new(4, 0, 2, 0, 1),
    bounds: &[],
    f32_bound: 3e-6,
    note: "= beckmann * pi / 4 (integral of D cos theta_h = pi / 4); f32: 1.4e-6 at alpha = 0.01",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Distribution(Beckmann::new(p.num("alpha"))?.into()))
});
pub const ENTRY_CT: Entry = Entry::new(INFO_CT, |p, _| {
    Ok(Plan::Distribution(
        Beckmann::cook_torrance(p.num("alpha"))?.into(),
    ))
});

/// The Beckmann distribution with a given normalisation.
#[derive(Clone, Copy, Debug)]
pub struct Beckmann {
    alpha: f64,
    inv_alpha2: K,
    /// `-log2(e) / alpha^2`: the batch form's exponent in base 2.
    log2_k: K,
    /// `1 / (pi alpha^2)` (normalised) or `1 / (4 alpha^2)` (Cook-Torrance's).
    scale: K,
    ct: bool,
}

impl Beckmann {
    /// The normalised distribution; `alpha` in [0.005, 1].
    pub fn new(alpha: f64) -> Result<Self> {
        let a = params::check("beckmann", &params::ALPHA, alpha)?;
        Ok(Self {
            alpha: a,
            inv_alpha2: K::new(1.0 / (a * a)),
            log2_k: K::new(-std::f64::consts::LOG2_E / (a * a)),
            scale: K::new(1.0 / (std::f64::consts::PI * a * a)),
            ct: false,
        })
    }

    /// Cook and Torrance's normalisation `1 / (4 m^2)`; `alpha` in [0.005, 1].
    pub fn cook_torrance(alpha: f64) -> Result<Self> {
        let a = params::check("beckmann-ct", &params::ALPHA, alpha)?;
        Ok(Self {
            alpha: a,
            inv_alpha2: K::new(1.0 / (a * a)),
            log2_k: K::new(-std::f64::consts::LOG2_E / (a * a)),
            scale: K::new(ct_scale(a)),
            ct: true,
        })
    }
}

/// Cook and Torrance's (and seed 000's) scale `1 / (4 m^2)`, shared by the power forms.
pub fn ct_scale(alpha: f64) -> f64 {
    1.0 / (4.0 * alpha * alpha)
}

/// `ct_scale` as a WGSL coefficient of `p_alpha`.
pub(crate) fn ct_scale_wgsl(alpha: f64, e: &Emit) -> String {
    e.kx(ct_scale(alpha), "0.25 / (p_alpha * p_alpha)", &["alpha"])
}

impl DistForm for Beckmann {
    const ANISO: bool = true;
    /// Beckmann's own Smith term (Walter et al. 2007, eq. 25-27), also for `beckmann-ct`.
    fn smith(&self) -> &'static str {
        "smith"
    }
    fn sampler(&self) -> DistSampler {
        DistSampler {
            micro: Micro {
                kind: MicroKind::Beckmann,
                ax: self.alpha,
                ay: self.alpha,
            },
            exact: true,
            closed: None,
        }
    }
    const WGSL: &'static str = include_str!("beckmann.wgsl");
    #[inline(always)]
    fn d<T: Real, M: Math<T>>(&self, cos_h: T, sin2_h: T) -> T {
        let c2 = cos_h * cos_h;
        // One division: exp(-tan^2 / alpha^2) / cos^4 as e * (1/c2)^2.
        let inv_c2 = T::one() / c2;
        self.scale.t::<T>()
            * M::exp_nonpos(-(sin2_h * inv_c2) * self.inv_alpha2.t::<T>())
            * (inv_c2 * inv_c2)
    }
    /// The batch kernels' form (issue 13), the formula rearranged for the vector units:
    /// `q = tan^2 = (1 - c^2) / c^2` by the one division (`1 - c^2` one fused multiply-add on
    /// the FMA instruction sets: exact product, one rounding; `(1 - c)(1 + c)` on SSE2), then
    /// `1 / c^2 = 1 + q` (an addition, off the multiply pipes), and `scale e^(-q / alpha^2)`
    /// as `exp2_nonpos_times(q log2_k, scale)` with `log2_k = -log2(e) / alpha^2` rounded once
    /// (so the exponent has as many roundings as `d`'s): the scale rides in the polynomial and
    /// `2^k` in the exponent bits. 11 multiply-pipe operations and a division
    /// (`batch_pipe_ops`) where `d` with `exp_nonpos` takes 21. Same f32 bound, tested
    /// against the scalar model on every ISA.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let (cc, s2) = crate::forms::clamp_sin2::<M>(c);
        let q = s2 / (cc * cc);
        let ic = 1.0 + q;
        let v = M::exp2_nonpos_times(q * self.log2_k.t::<f32>(), self.scale.t::<f32>()) * (ic * ic);
        // NaN, c = 0 (q = inf: 0 * inf) and c < COS_MIN give 0.
        crate::forms::above_cos_min(c, v)
    }
    /// `batch` on the FMA instruction sets: `c^2`, `1 - c^2` (fused), `q log2_k`, the
    /// polynomial of `exp2_nonpos_times`, `(1 + q)^2` and the product: 5 + 6 multiply-pipe
    /// operations, and the one division.
    fn batch_pipe_ops(&self) -> Option<crate::model::PipeOps> {
        Some(crate::model::PipeOps {
            mul: 5 + crate::math::fast::EXP2_NONPOS_TIMES_MULS,
            div: 1,
        })
    }
    fn wgsl(&self, c: &str, s2: &str, e: &Emit) -> String {
        let a = self.alpha;
        let scale = if self.ct {
            ct_scale_wgsl(a, e)
        } else {
            e.kx(
                self.scale,
                "0.3183098861837907 / (p_alpha * p_alpha)",
                &["alpha"],
            )
        };
        format!(
            "fb_d_beckmann({c}, {s2}, {}, {scale})",
            e.kx(self.inv_alpha2, "1.0 / (p_alpha * p_alpha)", &["alpha"])
        )
    }
}
