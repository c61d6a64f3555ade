//! `sg` and `ue4-phong-approx`: one-`exp2` stand-ins for `c^n` used by production engines.
//!
//! - `sg`: `exp2((n / ln 2)(c - 1)) = exp(n (c - 1))`, the spherical-Gaussian form
//!   (Lagarde 2012). Cost: 1 mul, 1 add, 1 exp2.
//! - `ue4-phong-approx`: `exp2(1.4427 (n + 0.775)(c - 1))`, Unreal Engine 4's mobile
//!   approximation (`PhongApprox`). Cost: 1 mul, 1 add, 1 exp2.
//!
//! Parameters: `n` in [1, 100000] (default 20). Error bounds against `pow`: see `INFO`.
//! Sampling (`lobe`): `c = 1 + ln(e^-r + u (1 - e^-r)) / r` with `r = k ln 2` (`sample::CosDist::Exp`), every rate here.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K, Real};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "sg",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "exp2((n / ln 2)(c - 1))",
    source: "Lagarde 2012, 'Spherical Gaussian approximation for Blinn-Phong, Phong and Fresnel'",
    ops: Ops::new(1, 1, 0, 0, 1),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 100000.0),
            bound: 0.368,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 16.0, 100000.0),
            bound: 0.0173,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 100000.0),
            bound: 0.214,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

pub const INFO_UE4: ModelInfo = ModelInfo {
    id: "ue4-phong-approx",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "exp2(1.4427 (n + 0.775)(c - 1))",
    source: "Unreal Engine 4 mobile shading (PhongApprox), Karis 2014",
    ops: Ops::new(1, 1, 0, 0, 1),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 100000.0),
            bound: 0.17,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 16.0, 100000.0),
            bound: 0.0097,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 100000.0),
            bound: 0.183,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

/// `2^(k (c - 1))`, the spherical Gaussian with rate `k`.
#[derive(Clone, Copy, Debug)]
pub struct Exp2Lobe {
    k: K,
    form: Exp2Form,
}

/// Which rate an `Exp2Lobe` uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exp2Form {
    /// `n / ln 2`.
    Sg,
    /// `1.4427 (n + 0.775)` (Karis 2013).
    Ue4,
    /// `(n / ln 2) Re(1/n)` (`lobes::tuned`).
    Tuned,
}

impl Exp2Lobe {
    /// The spherical Gaussian matched to `c^n` at the peak; `n` in [1, 100000].
    pub fn sg(n: f64) -> Result<Self> {
        let n = params::check("sg", &params::N, n)?;
        Ok(Self {
            k: K::new(n / std::f64::consts::LN_2),
            form: Exp2Form::Sg,
        })
    }
    /// Unreal Engine 4's rate; `n` in [1, 100000].
    #[allow(clippy::approx_constant)]
    pub fn ue4(n: f64) -> Result<Self> {
        let n = params::check("ue4-phong-approx", &params::N, n)?;
        Ok(Self {
            k: K::new(1.4427 * (n + 0.775)),
            form: Exp2Form::Ue4,
        })
    }
    /// The tuned rate; `n` in [1, 100000].
    pub fn tuned(n: f64) -> Result<Self> {
        let n = params::check("sg-tuned", &params::N, n)?;
        Ok(Self {
            k: K::new(super::fits::exp2_rate(n)),
            form: Exp2Form::Tuned,
        })
    }
}

impl LobeForm for Exp2Lobe {
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("sg.wgsl");
    fn id(&self) -> &'static str {
        match self.form {
            Exp2Form::Sg => "sg",
            Exp2Form::Ue4 => "ue4-phong-approx",
            Exp2Form::Tuned => "sg-tuned",
        }
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        M::exp2_nonpos_tail(self.k.t::<T>() * (c - T::one()))
    }
    /// Where the rate `k >= 127` (n >= 88 for `sg`) the value at c = 0 is already below
    /// 2^-126, 0 from `exp2_nonpos_tail`, so c < 0 needs no clamp: on the FMA instruction sets the
    /// exponent is one fused `k c - k` (elsewhere the product would round alone), clamped at
    /// 0 for c > 1 (`0 < x ? 0 : x` keeps NaN, which the exponential maps to 0), and no final
    /// `max(0, v)`: three of the kernel's twenty operations (issue 13). The exponential is
    /// `exp2_nonpos_tail`: the degree-6 minimax polynomial by Horner (six fused
    /// multiply-adds where `exp2_nonpos` spends nine multiply-pipe operations on degree 7;
    /// about 1 f32 epsilon) and no final select (NaN and x <= -127 give exactly 0 by
    /// construction; below 2^-125.5 the value may be off by 2^-126): 9.1 -> 11.3 G/s in
    /// `fastbrdf bench`.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let k = self.k.t::<f32>();
        if M::FMA && k >= 127.0 {
            let x = M::madd(k, c, -k);
            M::exp2_nonpos_tail(if 0.0 < x { 0.0 } else { x })
        } else {
            crate::forms::clamped_batch::<Self, M>(self, c)
        }
    }
    /// The FMA kernels: `k c - k` (one fused multiply-add) at rates >= 127, `k (c - 1)` (one
    /// multiply) below, and `exp2_nonpos_tail`'s six. No division.
    fn batch_pipe_ops(&self) -> Option<crate::model::PipeOps> {
        Some(crate::model::PipeOps {
            mul: 1 + crate::math::fast::EXP2_NONPOS_TIMES_MULS,
            div: 0,
        })
    }
    /// `exp2_nonpos_tail` builds its result from the bits of 2^k: no subnormal arithmetic.
    fn batch_ftz(&self) -> bool {
        false
    }
    fn cos_dist(&self) -> Option<crate::sample::CosDist> {
        Some(crate::sample::CosDist::Exp {
            r: self.k.x * std::f64::consts::LN_2,
        })
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        let expr = match self.form {
            Exp2Form::Sg => "p_n * 1.4426950408889634".to_string(),
            Exp2Form::Ue4 => "1.4427 * (p_n + 0.775)".to_string(),
            Exp2Form::Tuned => format!(
                "p_n * 1.4426950408889634 * ({})",
                super::fits::poly_expr(&super::fits::R_EXP2)
            ),
        };
        format!("fb_lobe_exp2({c}, {})", e.kx(self.k, &expr, &["n"]))
    }
}

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Lobe(Exp2Lobe::sg(p.num("n"))?.into()))
});
pub const ENTRY_UE4: Entry = Entry::new(INFO_UE4, |p, _| {
    Ok(Plan::Lobe(Exp2Lobe::ue4(p.num("n"))?.into()))
});
