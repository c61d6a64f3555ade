//! `gauss`: the Gaussian lobe of seed 001, `exp(-n theta^2 / 2)` with `theta = acos(c)`.
//!
//! Parameters: `n` in [1, 100000] (default 20). Source: seed 001 (its reference \[10\]).
//! Cost: 2 mul, 1 acos, 1 exp. For small angles `cos^n theta ~ exp(-n theta^2 / 2)`, so it
//! matches `pow` near the peak and has a lighter tail. Error bounds against `pow`: see `INFO`.
//! Sampling: no closed-form inverse used; `phong`/`blinn-phong` sample the twin `pow` at the same n (`twin`) and weight by f/pdf.

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
    id: "gauss",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "exp(-n theta^2 / 2), theta = acos(c)",
    source: "seed 001 (Gauss BRDF, its reference [10])",
    ops: Ops::new(2, 0, 0, 0, 2),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 1.0, 100000.0),
            bound: 0.292,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxRel,
            zone: Zone::Epicentre,
            param: ("n", 1.0, 100000.0),
            bound: 0.156,
        },
    ],
    f32_bound: 2e-7,
    note: "",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| Ok(Plan::Lobe(Gauss::new(p.num("n"))?.into())));

/// The Gaussian lobe.
#[derive(Clone, Copy, Debug)]
pub struct Gauss {
    half_n: K,
}

impl Gauss {
    /// `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            half_n: K::new(0.5 * params::check("gauss", &params::N, n)?),
        })
    }
}

impl LobeForm for Gauss {
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("gauss.wgsl");
    fn id(&self) -> &'static str {
        "gauss"
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        let t = M::acos(c);
        M::exp_nonpos(-self.half_n.t::<T>() * (t * t))
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        format!(
            "fb_lobe_gauss({c}, {})",
            e.kx(self.half_n, "0.5 * p_n", &["n"])
        )
    }
}
