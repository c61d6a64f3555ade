//! `cubic` and `cubic3`: seed 003's cubic polynomials in `c`, clipped to be non-negative.
//!
//! - `cubic`: `a c^3 + b c^2 + (1 - a - b) c`: value 0 at `c = 0`, 1 at `c = 1`, and value 0.5
//!   with the slope of `c^n` at `q = 0.5^(1/n)` (Hermite conditions). Seed 003 gives the closed
//!   forms `a = ((q-1)(2q+n)+1) / (2 (q-1)^2 q^2)`, `b = -(q^2(4q-3) + n(q^2-1) + 1) / (2 (q-1)^2 q^2)`.
//!   Decision: we use `q = 0.5^(1/n)` exactly; the seed's `q = e^(-0.6931471/n)` rounds ln 2,
//!   which at n = 1000 moves the cubic by 1.4e-3.
//! - `cubic3`: through `(0, 0)`, `(1, 1)`, `(r, Q)` and `(l, G)` with `r = Q^(1/n)`,
//!   `l = G^(1/n)`, `Q = 0.5`, `G = 1/18` (the seed's chosen values).
//!
//! Both are zero below the cubic's local minimum (where one lies in (0, q)) and wherever the
//! cubic is negative, as seed 003 prescribes ("the function must be clipped").
//!
//! Conditioning (the reason for this file's form): the monomial coefficients grow like `n^2`
//! (`a ~ 3e5` at n = 1000), so `a c^3 + b c^2 + ...` cancels catastrophically in f32. We
//! construct instead the Newton form of the same interpolating cubic in `x = c - 1` (exact in
//! floating point for `c >= 0.5`), around the nodes near the peak,
//! `p(x) = 1 + x (d1 + (x - x1)(d2 + (x - x2) d3))` (divided differences `d1..d3` and nodes
//! `x1 = q - 1` computed in f64, `expm1`), and evaluate it by Horner in `x`,
//! `p(x) = 1 + x (a + x (b + x d3))`, with `a` and `b` expanded from the Newton form in f64:
//! above the cut `|x|` is a few `1/n`, where every term is of order 1 (no cancellation), and
//! Horner is 3 fused multiply-adds in the batch kernels (issue 13: 1.10x over the Newton form).
//! `tests/precision.rs` proves the f32 bound over the whole domain. The WGSL twin keeps the
//! Newton form in `y = 1 - c` (fold-proof, see `lobes/mod.wgsl`).
//!
//! Parameters: `n` in [1, 100000] (default 20). Cost: 3 mul, 4 add (constants precomputed); the
//! seed's monomial form is 5 mul, 2 add. Error bounds: see `INFO`.
//! Sampling: no closed-form inverse used; `phong`/`blinn-phong` sample the twin `pow` at the same n (`twin`) and weight by f/pdf.

use crate::entry::Entry;
use crate::error::Result;
use crate::forms::LobeForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self};
use crate::plan::Plan;
use crate::real::{K, Real, pos};
use crate::wgsl::Emit;

pub const INFO: ModelInfo = ModelInfo {
    id: "cubic",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "a c^3 + b c^2 + (1 - a - b) c, Hermite fit of c^n at q = 0.5^(1/n); 0 below its local minimum and where negative",
    source: "seed 003 (Romanyuk, Chan et al., cubic approximation of Phong)",
    ops: Ops::new(3, 4, 0, 0, 0),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::Epicentre,
            param: ("n", 4.0, 1000.0),
            bound: 0.00552,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::Epicentre,
            param: ("n", 4.0, 100000.0),
            bound: 0.00555,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 4.0, 1000.0),
            bound: 0.228,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 4.0, 100000.0),
            bound: 0.23,
        },
    ],
    f32_bound: 1e-6,
    note: "q = 0.5^(1/n) exactly (the seed rounds ln 2); for f32 accuracy, evaluated on the CPU by Horner in (c - 1) with coefficients from the Newton form, on the GPU in the Newton form in 1 - c (fold-proof)",
};

pub const INFO3: ModelInfo = ModelInfo {
    id: "cubic3",
    kind: Kind::Lobe,
    params: &[params::N],
    formula: "a c^3 + b c^2 + c' c through (1, 1), (0.5^(1/n), 0.5), ((1/18)^(1/n), 1/18); 0 below its local minimum and where negative",
    source: "seed 003 (three-point variant, Q = 0.5, G = 1/18)",
    ops: Ops::new(3, 4, 0, 0, 0),
    bounds: &[
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::Epicentre,
            param: ("n", 4.0, 1000.0),
            bound: 0.0215,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::Epicentre,
            param: ("n", 4.0, 100000.0),
            bound: 0.0217,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 4.0, 1000.0),
            bound: 0.108,
        },
        ErrorBound {
            reference: "pow",
            metric: Metric::MaxAbs,
            zone: Zone::All,
            param: ("n", 4.0, 100000.0),
            bound: 0.109,
        },
    ],
    f32_bound: 1e-6,
    note: "for f32 accuracy, evaluated on the CPU by Horner in (c - 1) with coefficients from the Newton form, on the GPU in the Newton form in 1 - c (fold-proof)",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, _| {
    Ok(Plan::Lobe(Cubic::hermite(p.num("n"))?.into()))
});
pub const ENTRY3: Entry = Entry::new(INFO3, |p, _| {
    Ok(Plan::Lobe(Cubic::three_point(p.num("n"))?.into()))
});

/// A cubic through `(c=0, 0)` and `(c=1, 1)`, by Horner in `x = c - 1`, clipped: zero
/// below its shape's `cut` (the local minimum) and where negative.
#[derive(Clone, Copy, Debug)]
pub struct Cubic {
    shape: CubicShape,
    /// `a, b, d3, cut`: the shape's coefficients in monomials of `c - 1`, and its cut.
    k: [K; 4],
    three: bool,
}

/// The precomputed f64 shape of a clipped cubic: Newton coefficients, nodes and cut.
#[derive(Clone, Copy, Debug)]
pub struct CubicShape {
    pub d1: f64,
    pub d2: f64,
    pub d3: f64,
    pub x1: f64,
    pub x2: f64,
    pub cut: f64,
}

impl CubicShape {
    /// Seed 003's Hermite cubic: nodes `x = 0` (value 1), `x = q - 1` twice (value 0.5, slope
    /// `n 0.5 / q`), `x = -1` (value 0).
    pub fn hermite(n: f64) -> Self {
        Self::hermite_at(n, 0.5)
    }

    /// The Hermite cubic matched to `c^n` at the level `c^n = level` (seed 003: 0.5).
    pub fn hermite_at(n: f64, level: f64) -> Self {
        let xq = (level.ln() / n).exp_m1(); // q - 1, accurately
        let q = 1.0 + xq;
        let s = n * level / q; // slope of c^n at q
        let f0q = (level - 1.0) / xq;
        let fqm = level / q; // f[xq, -1]
        let f0qq = (s - f0q) / xq;
        let fqqm = (fqm - s) / (-1.0 - xq);
        let d3 = (fqqm - f0qq) / -1.0;
        Self::finish(f0q, f0qq, d3, xq, xq)
    }

    /// Seed 003's three-point cubic through `(r, Q)` and `(l, G)`.
    pub fn three_point(n: f64, big_q: f64, big_g: f64) -> Self {
        let xr = (big_q.ln() / n).exp_m1();
        let xl = (big_g.ln() / n).exp_m1();
        let f0r = (big_q - 1.0) / xr;
        let frl = (big_g - big_q) / (xl - xr);
        let flm = big_g / (1.0 + xl); // f[xl, -1]
        let f0rl = (frl - f0r) / xl;
        let frlm = (flm - frl) / (-1.0 - xr);
        let d3 = (frlm - f0rl) / -1.0;
        Self::finish(f0r, f0rl, d3, xr, xl)
    }

    fn finish(d1: f64, d2: f64, d3: f64, x1: f64, x2: f64) -> Self {
        // Monomial coefficients in x: p = 1 + al x + be x^2 + ga x^3.
        let al = d1 - d2 * x1 + d3 * x1 * x2;
        let be = d2 - d3 * (x1 + x2);
        let ga = d3;
        // Critical points: 3 ga x^2 + 2 be x + al = 0; keep the local minimum in (-1, x1).
        let mut cut = 0.0;
        for x in quadratic_roots(3.0 * ga, 2.0 * be, al) {
            let curvature = 2.0 * be + 6.0 * ga * x;
            if x > -1.0 && x < x1 && curvature > 0.0 {
                cut = f64::max(cut, 1.0 + x);
            }
        }
        // The cut is a jump (from the local minimum to 0): it is rounded to an f32 number so
        // that both precisions cut at the same input, as COS_MIN does (otherwise a cosine
        // between the two roundings is the whole jump apart in f32 and f64; issue 11).
        Self {
            d1,
            d2,
            d3,
            x1,
            x2,
            cut: cut as f32 as f64,
        }
    }

    /// The unclipped cubic at `c`, in f64 (for analysis).
    pub fn raw(&self, c: f64) -> f64 {
        let x = c - 1.0;
        1.0 + x * (self.d1 + (x - self.x1) * (self.d2 + (x - self.x2) * self.d3))
    }
}

/// Real roots of `a x^2 + b x + c` (a linear equation when `a` is negligible).
fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    let scale = a.abs().max(b.abs()).max(c.abs());
    if scale == 0.0 {
        return vec![];
    }
    if a.abs() <= 1e-14 * scale {
        return if b != 0.0 { vec![-c / b] } else { vec![] };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let mut r = vec![q / a];
    if q != 0.0 {
        r.push(c / q);
    }
    r
}

impl Cubic {
    /// Seed 003's Hermite cubic; `n` must be in [1, 100000].
    pub fn hermite(n: f64) -> Result<Self> {
        Ok(Self::from_shape(CubicShape::hermite(params::check(
            "cubic",
            &params::N,
            n,
        )?)))
    }

    /// Seed 003's three-point cubic; `n` must be in [1, 100000].
    pub fn three_point(n: f64) -> Result<Self> {
        Ok(Self {
            three: true,
            ..Self::from_shape(CubicShape::three_point(
                params::check("cubic3", &params::N, n)?,
                0.5,
                1.0 / 18.0,
            ))
        })
    }

    /// The cubic of a given shape (the Hermite family; `cubic-rational` uses it).
    pub fn from_shape(shape: CubicShape) -> Self {
        let s = &shape;
        // The Newton form expanded into monomials of x = c - 1 (in f64): p = 1 + x (a + x (b +
        // x d3)). Above the cut |x| is a few 1/n, where every term is O(1): no cancellation,
        // and Horner needs 3 fused multiply-adds and no node subtractions.
        let a = s.d1 - s.x1 * s.d2 + s.x1 * s.x2 * s.d3;
        let b = s.d2 - (s.x1 + s.x2) * s.d3;
        Self {
            k: [a, b, s.d3, s.cut].map(K::new),
            shape,
            three: false,
        }
    }

    /// The literal/storage arguments of `fb_lobe_cubic` after `c`.
    pub(crate) fn wgsl_args(&self, e: &Emit) -> String {
        let s = &self.shape;
        [s.d1, s.d2, s.d3, s.x1, s.x2, s.cut]
            .iter()
            .map(|x| e.constant(*x))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl LobeForm for Cubic {
    // NaN: `pos` (power, cubic) or the `c > 0` select (flog) gives 0.
    const NAN_TO_ZERO: bool = true;
    fn wgsl_norm(&self, e: &Emit) -> String {
        crate::forms::norm_by_integral(self.id(), e)
    }
    const WGSL: &'static str = include_str!("cubic.wgsl");
    fn id(&self) -> &'static str {
        if self.three { "cubic3" } else { "cubic" }
    }
    #[inline(always)]
    fn at<T: Real, M: Math<T>>(&self, c: T) -> T {
        let [a, b, d3, cut] = self.k.map(|k| k.t::<T>());
        let x = c - T::one();
        let p = M::madd(x, M::madd(x, M::madd(x, d3, b), a), T::one());
        // The cut is an f32 number, so both precisions cut at the same input.
        if c < cut { T::zero() } else { pos(p) }
    }
    /// The kernel clamps once: the cut is >= 0, so `c >= cut` already fails for c < 0 and
    /// NaN (0, the rule's value); only c > 1 is clamped (`c < 1 ? c : 1`, one minps; NaN
    /// becomes 1 there, and the cut test still gives 0). Issue 13.
    #[inline(always)]
    fn batch<M: Math<f32>>(&self, c: f32) -> f32 {
        let [a, b, d3, cut] = self.k.map(|k| k.t::<f32>());
        let x = c - 1.0;
        let x = if x < 0.0 { x } else { 0.0 };
        let p = M::madd(x, M::madd(x, M::madd(x, d3, b), a), 1.0);
        pos(if c >= cut { p } else { 0.0 })
    }
    /// Horner's terms are of order 1 above the cut; p is tiny only next to its root.
    fn batch_ftz(&self) -> bool {
        false
    }
    fn zero_below(&self) -> f64 {
        self.shape.cut
    }
    fn wgsl(&self, c: &str, e: &Emit) -> String {
        if e.is_runtime() {
            let f = if self.three {
                "fb_rt_cubic3"
            } else {
                "fb_rt_cubic"
            };
            format!("{f}({c}, {})", e.param("n"))
        } else {
            format!("fb_lobe_cubic({c}, {})", self.wgsl_args(e))
        }
    }
}
