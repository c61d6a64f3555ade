//! `pow`: the Phong / Blinn-Phong lobe, the reference of every lobe.
//!
//! Formula: `c^n`. Parameters: `n` in [1, 100000] (default 20).
//! Source: Phong 1975, Blinn 1977; all three seeds.
//! Cost: one `pow` (exp2 and log2 inside). Error: exact (it is the reference).
//! Energy: `Int(n) = integral_0^1 c^n c dc = 1 / (n + 2)`, so `coef(n) = (n + 2) / (2 pi)`.
//! Sampling (`phong`/`blinn-phong`'s `lobe`): `c = u^(1/(n+1))`, density `(n+1) c^n` (`sample::CosDist::Pow`); the twin every other lobe samples.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{Kind, ModelInfo, Ops};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K, Real};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "pow",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "c^n",
    source: "Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003)",
    ops: Ops::new(0, 0, 0, 0, 1),
    bounds: &[],
    f32_bound: 2e-7,
    note: "",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| Ok(Plan::Lobe(Pow::new(p.num("n"))?.into())));

/// `c^n`.
#[derive(Clone, Copy, Debug)]
pub struct Pow {
    n: K,
}

impl Pow {
    /// A `c^n` lobe; `n` must be in [1, 100000].
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: K::new(params::check("pow", &params::N, n)?),
        })
    }
}

impl Pow {
    /// The exponent.
    pub fn n(&self) -> f64 {
        self.n.x
    }
}

impl LobeForm for Pow {
    const WGSL: &'static str = include_str!("pow.wgsl");
    fn id(&self) -> &'static str {
        "pow"
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        M::pow(c, self.n.t())
    }
    /// The kernel sends NaN to 0 in the clamp itself (`c > 0 ? c : 0`), so the FMA
    /// instruction sets' `pow_unit` needs one select instead of `pow`'s three (issue 13: 13%
    /// of the kernel); results below 2^-126 are 0.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let x = if c > 0.0 { c } else { 0.0 };
        let x = if x < 1.0 { x } else { 1.0 };
        M::pow_unit(x, self.n.t())
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        format!("fb_lobe_pow({c}, {})", e.kx(self.n, "p_n", &["n"]))
    }
    fn cos_dist(&self) -> Option<crate::sample::CosDist> {
        Some(crate::sample::CosDist::Pow { m: self.n.x })
    }
    fn wgsl_norm(&self, e: &Emit) -> String {
        // Int(n) = 1 / (n + 2): coef(n) = (n + 2) / (2 pi).
        format!("({} + 2.0) * 0.15915494309189535", e.param("n"))
    }
}
