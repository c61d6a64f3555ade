//! `ggx`: the GGX (Trowbridge-Reitz) microfacet distribution, isotropic (anisotropic inside
//! `cook-torrance`, see below).
//!
//! `D = alpha^2 / (pi cos^4 theta_h (alpha^2 + tan^2 theta_h)^2)`, normalised so that the
//! integral of `D cos theta_h` over the hemisphere is 1 (Trowbridge & Reitz 1975; Walter et al.
//! 2007, eq. 33; Mitsuba 3, pbrt, Filament, Unreal).
//!
//! Arranged for f32: `cos^4 (alpha^2 + tan^2)^2 = (alpha^2 cos^2 + sin^2)^2`, with `sin^2` from
//! the half vector (BRDFs) or `(1 - c)(1 + c)` (standalone). Both terms are non-negative, so
//! there is no cancellation at any alpha: the common form `cos^2 (alpha^2 - 1) + 1` cancels
//! near `cos = 1` for small alpha (evaluated in f32 it errs by 3.4e-4 relative at
//! alpha = 0.01 and 1.2e-5 at alpha = 0.1, near the peak). Computed as
//! `(alpha^2 / pi) / (t t)`, `t = alpha^2 cos^2 + sin^2`; f32 against f64 measured 3.3e-7
//! (`tests/precision.rs`; near the peak at small alpha) and 4.5e-7 (`fastbrdf check --full`),
//! documented 1e-6; no term degrades as alpha shrinks below 0.01.
//!
//! Parameters: `alpha` (params::ALPHA, default 0.3). Below `cos_h = COS_MIN` the value is 0.
//! Cost: 3 mul, 1 add, 1 div. Exact model: no error bound; the normalisation is tested to 1e-6
//! (tests/energy.rs). Anisotropic GGX (`alpha_x`, `alpha_y`) needs the half vector's azimuth,
//! which the distribution kind (inputs `cos_h`, `sin^2 h`) does not have: it is
//! `cook-torrance`'s `alpha_x`, `alpha_y` with `d = ggx`, this formula at
//! `alpha = sqrt(alpha_x alpha_y)` on a stretched `sin^2` (`brdf::cook_torrance`,
//! `DistForm::ANISO`).
//! Sampling (in `cook-torrance`): `D cos` (`tan^2 = alpha^2 u / (1 - u)`) and visible normals (Heitz 2018), `sample::Micro`.

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
    id: "ggx",
    kind: Kind::Distribution,
    params: &[params::ALPHA],
    formula: "alpha^2 / (pi cos^4 theta_h (alpha^2 + tan^2 theta_h)^2) = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2)",
    source: "Trowbridge & Reitz 1975; Walter et al. 2007, eq. 33 (GGX)",
    ops: Ops::new(3, 1, 1, 0, 0),
    bounds: &[],
    f32_bound: F32_BOUND,
    note: "integral of D cos theta_h over the hemisphere = 1; no cancellation at small alpha (alpha^2 cos^2 + sin^2); anisotropic: cook-torrance's alpha_x, alpha_y",
};

/// Measured by `tests/precision.rs`; see the module header.
const F32_BOUND: f64 = 1e-6;

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Distribution(Ggx::new(p.num("alpha"))?.into()))
});

/// The GGX distribution.
#[derive(Clone, Copy, Debug)]
pub struct Ggx {
    /// `alpha^2`.
    alpha2: K,
    /// `1 - alpha^2` (the batch form).
    one_minus_alpha2: K,
    /// `alpha^2 / pi`.
    scale: K,
}

impl Ggx {
    /// `alpha` in `params::ALPHA`'s range.
    pub fn new(alpha: f64) -> Result<Self> {
        let a = params::check("ggx", &params::ALPHA, alpha)?;
        Ok(Self {
            alpha2: K::new(a * a),
            one_minus_alpha2: K::new(1.0 - a * a),
            scale: K::new(a * a / std::f64::consts::PI),
        })
    }

    /// `alpha^2` (`batch`'s closed form of Cook-Torrance with GGX).
    pub fn alpha2(&self) -> f64 {
        self.alpha2.x
    }
}

impl DistForm for Ggx {
    const ANISO: bool = true;
    /// GGX's own Smith term (Walter et al. 2007, eq. 34).
    fn smith(&self) -> &'static str {
        "smith-ggx"
    }
    fn sampler(&self) -> DistSampler {
        let a = self.alpha2.x.sqrt();
        DistSampler {
            micro: Micro {
                kind: MicroKind::Ggx,
                ax: a,
                ay: a,
            },
            exact: true,
            closed: None,
        }
    }
    const WGSL: &'static str = include_str!("ggx.wgsl");
    #[inline(always)]
    fn d<T: Real, M: Math<T>>(&self, cos_h: T, sin2_h: T) -> T {
        let t = self.alpha2.t::<T>() * (cos_h * cos_h) + sin2_h;
        self.scale.t::<T>() / (t * t)
    }
    /// The batch kernels' form (issue 13): with `c^2 = 1 - sin^2`, `t = alpha^2 c^2 + sin^2
    /// = alpha^2 + (1 - alpha^2) sin^2`, a sum of two non-negative terms (alpha <= 1), so it
    /// keeps `d`'s freedom from cancellation at one multiply fewer: `sin^2` is one fused
    /// multiply-add (exact product, one rounding; `(1 - c)(1 + c)` on SSE2) and `t` another,
    /// three multiply-pipe operations and the division, the count of the engines' cancelling
    /// `(alpha^2 - 1) c^2 + 1`.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let (_, s2) = crate::forms::clamp_sin2::<M>(c);
        let t = M::madd(self.one_minus_alpha2.t::<f32>(), s2, self.alpha2.t::<f32>());
        crate::forms::above_cos_min(c, self.scale.t::<f32>() / (t * t))
    }
    /// No flush-to-zero switch (its ~8 ns a call is 4% of a 4096-cosine batch): no step of
    /// the batch form is subnormal (`1 - c^2` is one fused multiply-add or `(1 - c)(1 + c)`,
    /// `alpha^2 <= t <= 1`, so `t t >= 6e-10` and the value is at least `alpha^2 / pi`);
    /// tested (`tests/batch/`: every output 0 or normal).
    fn batch_ftz(&self) -> bool {
        false
    }
    fn wgsl(&self, c: &str, s2: &str, e: &Emit) -> String {
        format!(
            "fb_d_ggx({c}, {s2}, {}, {})",
            e.kx(self.alpha2, "p_alpha * p_alpha", &["alpha"]),
            e.kx(
                self.scale,
                "p_alpha * p_alpha * 0.3183098861837907",
                &["alpha"]
            )
        )
    }
}
