//! Split-sum image-based lighting terms (`Kind::Env`): `env-brdf` (the reference, by
//! quadrature), `env-brdf-approx` (Karis's mobile polynomial) and `env-brdf-approx-tuned`
//! (its constants refitted).
//!
//! With Schlick's Fresnel `F = f0 + (1 - f0)(1 - v.h)^5`, the directional albedo of the GGX
//! specular BRDF `F D G2 / (4 cos_v cos_l)` is `f0 scale + bias` (Karis 2013, "Real Shading in
//! Unreal Engine 4"; the "DFG" terms of Filament):
//!
//! - `scale(cos_v, alpha) = integral of (1 - (1 - v.h)^5) D G2 / (4 cos_v cos_l) cos_l dl`
//! - `bias(cos_v, alpha)  = integral of (1 - v.h)^5 D G2 / (4 cos_v cos_l) cos_l dl`
//!
//! with `D` the isotropic GGX distribution of roughness `alpha` and `G2` the height-correlated
//! Smith term `1 / (1 + Lambda(v) + Lambda(l))`, `Lambda(c) = (sqrt(1 + alpha^2 tan^2) - 1) / 2`
//! (Heitz 2014; Filament's choice. Unreal's own table used the separable Schlick-Smith term,
//! so Karis's fit carries that difference in its measured error here). `scale + bias` is the
//! white-furnace albedo of single scattering (F = 1): 0.857, 0.663, 0.451 and 0.307 at
//! perceptual roughness `r = sqrt(alpha)` and `cos_v` of (0.5, 0.5), (0.75, 0.5), (1, 0.5),
//! (1, 1), the values a three.js issue published (0.86, 0.66, 0.45, 0.31; tested).
//!
//! Inputs: `cos_v` in [0, 1] and `alpha` in the range of `params::ALPHA` (both input
//! columns, as an engine's look-up table's axes; outside, clamped). Parameter `term`:
//! `scale` (default) or `bias`.
//!
//! - `env-brdf`: the integral by a product Gauss-Legendre rule in the half-vector variables
//!   `(u, phi)`, `u` the GGX cumulative `tan^2 theta_h = alpha^2 u / (1 - u)` (so `D cos theta_h
//!   dh = du dphi / 2 pi` and a narrow lobe needs no more nodes than a wide one). The horizon
//!   `cos_l > 0` bounds `phi` by `acos(q(u))` and ends at two half-vector angles
//!   `theta_h = (pi/2 -/+ theta_v) / 2` (closed forms): the `u` range is split there (24
//!   nodes each, the second piece in `u = u2 - (u2 - u1) t^2`, which removes the square root at
//!   its end) and `phi` integrated over its live range (24 nodes), so no node straddles the
//!   horizon. 1152 integrand evaluations. Quadrature error against adaptive Gauss-Kronrod (the
//!   independent reference in `tests/reference/`): see `QUADRATURE_ERROR`. Cost per
//!   evaluation: 1152 x (27 mul, 18 add, 4 div, 1 sqrt; the cosine of each phi node is a
//!   polynomial), plus 48 acos; not vectorised.
//! - `env-brdf-approx`: Karis 2014, "Physically Based Shading on Mobile" (Unreal's
//!   `EnvBRDFApprox`): with `r = sqrt(alpha)`, `c0 = (-1, -0.0275, -0.572, 0.022)`,
//!   `c1 = (1, 0.0425, 1.04, -0.04)`, `p = r c0 + c1`,
//!   `a004 = min(p.x^2, 2^(-9.28 cos_v)) p.x + p.y`, `scale = -1.04 a004 + p.z`,
//!   `bias = 1.04 a004 + p.w`. Its bias goes slightly negative near `r = 1` (-0.0024): here it is
//!   clamped at 0 (every model is non-negative). Cost: 6 mul, 6 add, 1 sqrt, 1 exp2.
//! - `env-brdf-approx-tuned`: the same form with its 11 constants refitted to minimise the
//!   maximum error of both terms against `env-brdf` (`cargo run --release -p
//!   fastbrdf-analysis --example fit_env_brdf`); same cost.
//!
//! Error bounds (max abs over `cos_v` in (0, 1], `alpha` in [0.005, 1], both terms): see the
//! `INFO_*` constants (and `fastbrdf models`).

use crate::entry::Entry;
use crate::forms::EnvForm;
use crate::math::Math;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{Options, ParamKind, ParamSpec, Params};
use crate::plan::Plan;
use crate::real::{K, Real, min1, pos};
use crate::wgsl::Emit;

pub const TERM: ParamSpec = ParamSpec {
    name: "term",
    kind: ParamKind::Choice {
        options: Options::List(&["scale", "bias"]),
        default: "scale",
    },
    doc: "which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias)",
};

/// The largest difference between `env-brdf`'s fixed rule and adaptive Gauss-Kronrod to
/// 1e-9 over the documented domain, `cos_v >= 0.001` (measured and enforced by
/// `tests/reference/`); below `cos_v = 0.001` the rule degrades gracefully (the albedo's
/// limit at grazing is finite).
pub const QUADRATURE_ERROR: f64 = 2e-3;

const fn vs_dfg(bound: f64) -> [ErrorBound; 1] {
    [ErrorBound {
        reference: "env-brdf",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound,
    }]
}

pub const INFO_DFG: ModelInfo = ModelInfo {
    id: "env-brdf",
    kind: Kind::Env,
    params: &[TERM],
    formula: "scale/bias = integral of (1 - (1 - v.h)^5) or (1 - v.h)^5 times D_ggx G2_correlated / (4 cos_v cos_l) cos_l dl",
    source: "Karis 2013 (split sum); Heitz 2014 (height-correlated Smith); Filament's DFG",
    ops: Ops::new(27, 18, 4, 1, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "ops are per quadrature point (1152 points, plus 48 acos); product Gauss-Legendre rule, within 2e-3 of adaptive quadrature for cos_v >= 0.001",
};

pub const INFO_APPROX: ModelInfo = ModelInfo {
    id: "env-brdf-approx",
    kind: Kind::Env,
    params: &[TERM],
    formula: "p = sqrt(alpha) c0 + c1, a004 = min(p.x^2, 2^(-9.28 cos_v)) p.x + p.y, scale = -1.04 a004 + p.z, bias = max(0, 1.04 a004 + p.w)",
    source: "Karis 2014, Physically Based Shading on Mobile (Unreal's EnvBRDFApprox)",
    ops: Ops::new(6, 6, 0, 1, 1),
    bounds: &vs_dfg(0.525),
    f32_bound: 1e-6,
    note: "fitted to Unreal's table (separable Schlick-Smith G, k = alpha/2, which is darker than the height-correlated term at grazing: the error is largest there); the bias is clamped at 0",
};

pub const INFO_APPROX_TUNED: ModelInfo = ModelInfo {
    id: "env-brdf-approx-tuned",
    kind: Kind::Env,
    params: &[TERM],
    formula: "env-brdf-approx's form, its 11 constants refitted minimax against env-brdf",
    source: "this project (fit_env_brdf example)",
    ops: Ops::new(6, 6, 0, 1, 1),
    bounds: &vs_dfg(0.339),
    f32_bound: 1e-6,
    note: "",
};

fn bias(p: &Params) -> bool {
    p.choice("term") == "bias"
}

pub const ENTRY_DFG: Entry =
    Entry::new(INFO_DFG, |p, _| Ok(Plan::Env(Dfg { bias: bias(p) }.into())));
pub const ENTRY_APPROX: Entry = Entry::new(INFO_APPROX, |p, _| {
    Ok(Plan::Env(Approx::new(bias(p), &KARIS).into()))
});
pub const ENTRY_APPROX_TUNED: Entry = Entry::new(INFO_APPROX_TUNED, |p, _| {
    Ok(Plan::Env(Approx::new(bias(p), &TUNED).into()))
});

/// Gauss-Legendre nodes and weights on [-1, 1], 24 points, the positive half (the rule is
/// symmetric). Twin: `FB_GL24_X`, `FB_GL24_W` in `env_brdf.wgsl`; both checked against
/// Newton's method on the Legendre recurrence by a test.
pub const GL24: [(f64, f64); 12] = [
    (0.995_187_219_997_021_3, 0.012_341_229_799_987_334),
    (0.974_728_555_971_309_5, 0.028_531_388_628_933_813),
    (0.938_274_552_002_732_8, 0.044_277_438_817_419_676),
    (0.886_415_527_004_401_1, 0.059_298_584_915_436_66),
    (0.820_001_985_973_903, 0.073_346_481_411_080_27),
    (0.740_124_191_578_554_4, 0.086_190_161_531_953_22),
    (0.648_093_651_936_975_5, 0.097_618_652_104_113_9),
    (0.545_421_471_388_839_6, 0.107_444_270_115_965_62),
    (0.433_793_507_626_045_1, 0.115_505_668_053_725_61),
    (0.315_042_679_696_163_4, 0.121_670_472_927_803_35),
    (0.191_118_867_473_616_3, 0.125_837_456_346_828_39),
    (0.064_056_892_862_605_63, 0.127_938_195_346_752_24),
];

/// The smallest `cos_v` evaluated (`2^-20`, `vec3::COS_MIN`): the albedo has a finite limit
/// at grazing, and every term below stays finite from there.
const MU_MIN: f64 = 9.5367431640625e-7;
/// The smallest `cos_l` in the integrand (`2^-40`): `G2` is 0 to f32 precision there, and
/// `Lambda`'s `tan^2` stays finite in f32.
const CL_MIN: f64 = 9.094947017729282e-13;

/// The reference: the split-sum term by quadrature.
#[derive(Clone, Copy, Debug)]
pub struct Dfg {
    pub bias: bool,
}

/// `cos(x)` for `x` in [0, pi] with the backend's functions (`cos(x) = -sin(x - pi/2)`, an
/// odd Taylor polynomial to degree 13 on [-pi/2, pi/2]: truncation 6e-10). Exact backends
/// would call `cos`; one polynomial keeps the three targets (f64, f32, SIMD) on one formula.
#[inline(always)]
fn cos_0_pi<T: Real, M: Math<T>>(x: T) -> T {
    let y = x - T::c(std::f64::consts::FRAC_PI_2);
    let y2 = y * y;
    let mut p = T::c(-1.0 / 6_227_020_800.0);
    for k in [39_916_800.0, -362_880.0, 5_040.0, -120.0, 6.0, -1.0] {
        p = M::madd(p, y2, T::c(1.0 / k));
    }
    // -sin y = y (-1 + y^2/6 - y^4/120 + ... - y^12/13!), by Horner in y^2.
    y * p
}

/// The directional albedo of GGX with the height-correlated Smith term and F = 1: `scale +
/// bias` in one pass of the rule (the energy-compensation table's `E`), `cos_v` in [0, 1],
/// `alpha` in the documented range.
pub fn albedo<T: Real, M: Math<T>>(cos_v: T, alpha: T) -> T {
    integral::<T, M>(cos_v, alpha, |_| T::one())
}

/// The rule of `env-brdf` with the Fresnel weight `weight((1 - v.h)^5)`: `1 - f5` for the scale,
/// `f5` for the bias, 1 for the F = 1 albedo.
fn integral<T: Real, M: Math<T>>(cos_v: T, alpha: T, weight: impl Fn(T) -> T) -> T {
    let one = T::one();
    let mu = if cos_v > T::c(MU_MIN) {
        cos_v
    } else {
        T::c(MU_MIN)
    };
    let a2 = alpha * alpha;
    let sv = pos((one - mu) * (one + mu)).sqrt();
    // mu Lambda(v) without the 0 * inf of grazing: a^2 sv^2 / (2 (sqrt(mu^2 + a^2 sv^2) + mu)).
    let mlv = a2 * sv * sv / (T::c(2.0) * ((mu * mu + a2 * sv * sv).sqrt() + mu));
    // The horizon's ends in u: tan theta_h1 = mu / (1 + sv), tan theta_h2 = (1 + sv) / mu.
    // u and w = 1 - u are both carried, each computed without cancellation (u reaches
    // 1 - 1e-7 at small alpha and grazing, where 1 - u in f32 would keep no bits).
    let t1 = mu / (one + sv);
    let t12 = t1 * t1;
    let (u1, w1) = (t12 / (a2 + t12), a2 / (a2 + t12));
    let (u2, w2) = (one / (one + a2 * t12), a2 * t12 / (one + a2 * t12));
    let mut sum = T::zero();
    // One u node of weight wu: the phi integral over its live range.
    let ring = |u: T, w: T, wu: T, full: bool| -> T {
        let d = w + a2 * u;
        let ch = (w / d).sqrt();
        let sh = alpha * (u / d).sqrt();
        let pm = if full {
            T::PI()
        } else {
            // cos(phi_max) = mu (1 - 2 ch^2) / (2 ch sh sv), 1 - 2 ch^2 = (a^2 u - w) / d.
            let qd = T::c(2.0) * ch * sh * sv;
            let q = mu * ((a2 * u - w) / d);
            let q = if qd > T::zero() { q / qd } else { one };
            let q = min1(q.max(-one));
            let ac = M::acos(q.abs());
            if q >= T::zero() { ac } else { T::PI() - ac }
        };
        let mut acc = T::zero();
        for &(x, w) in &GL24 {
            for s in [-x, x] {
                let phi = pm * T::c(0.5 * (s + 1.0));
                let vh = sv * sh * cos_0_pi::<T, M>(phi) + mu * ch;
                let cl = T::c(2.0) * vh * ch - mu;
                let cl = if cl > T::c(CL_MIN) { cl } else { T::c(CL_MIN) };
                let tl2 = (one - cl) * (one + cl) / (cl * cl);
                let ll = a2 * tl2 / (T::c(2.0) * ((one + a2 * tl2).sqrt() + one));
                let g_over_mu = one / (mu * (one + ll) + mlv);
                let f5 = {
                    let m = pos(one - vh);
                    let m2 = m * m;
                    m2 * m2 * m
                };
                acc = acc + T::c(w) * weight(f5) * vh * g_over_mu / ch;
            }
        }
        acc * pm * T::c(0.5) * wu
    };
    // u2 - u1 = w1 - w2, computed from the w's (both small where the u's are near 1).
    let du = w1 - w2;
    for &(x, w) in &GL24 {
        for s in [-x, x] {
            let (t, t_c) = (T::c(0.5 * (s + 1.0)), T::c(0.5 * (1.0 - s)));
            let wt = T::c(0.5 * w);
            // Piece 1: u = u1 t, w = 1 - u1 t = w1 + u1 (1 - t).
            sum = sum + ring(u1 * t, w1 + u1 * t_c, u1 * wt, true);
            // Piece 2: u = u2 - (u2 - u1) t^2, w = w2 + (u2 - u1) t^2.
            let tt = du * t * t;
            sum = sum + ring(u2 - tt, w2 + tt, du * T::c(2.0) * t * wt, false);
        }
    }
    pos(sum * T::c(std::f64::consts::FRAC_1_PI))
}

impl EnvForm for Dfg {
    const WGSL: &'static str = include_str!("env_brdf.wgsl");
    const SIMD: bool = false;
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T {
        let bias = self.bias;
        integral::<T, M>(
            cos_v,
            alpha,
            move |f5| if bias { f5 } else { T::one() - f5 },
        )
    }
    fn wgsl(&self, v: &str, a: &str, _e: &Emit) -> String {
        format!(
            "fb_env_dfg({v}, {a}, {})",
            if self.bias { "true" } else { "false" }
        )
    }
}

/// Karis's constants: `c0` (4), `c1` (4), the exp2 rate, the two output slopes.
pub const KARIS: [f64; 11] = [
    -1.0, -0.0275, -0.572, 0.022, 1.0, 0.0425, 1.04, -0.04, -9.28, -1.04, 1.04,
];
/// The refit (`fit_env_brdf` example).
pub const TUNED: [f64; 11] = [
    -1.072325, -0.028393, -0.488609, 0.023184, 1.040579, 0.040344, 1.129695, -0.038556, -9.478977,
    -0.965804, 1.019101,
];

/// Karis's mobile polynomial (or its refit).
#[derive(Clone, Copy, Debug)]
pub struct Approx {
    pub bias: bool,
    pub c: [K; 11],
}

impl Approx {
    pub fn new(bias: bool, c: &[f64; 11]) -> Self {
        Self {
            bias,
            c: c.map(K::new),
        }
    }
}

impl EnvForm for Approx {
    const WGSL: &'static str = include_str!("env_brdf.wgsl");
    #[inline(always)]
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T {
        let k = |i: usize| self.c[i].t::<T>();
        let r = alpha.sqrt();
        let px = M::madd(r, k(0), k(4));
        let py = M::madd(r, k(1), k(5));
        let a004 = M::madd((px * px).min(M::exp2_nonpos_tail(k(8) * cos_v)), px, py);
        let v = if self.bias {
            M::madd(k(10), a004, M::madd(r, k(3), k(7)))
        } else {
            M::madd(k(9), a004, M::madd(r, k(2), k(6)))
        };
        pos(v)
    }
    fn wgsl(&self, v: &str, a: &str, e: &Emit) -> String {
        let c: Vec<String> = self.c.iter().map(|&x| e.constant(x)).collect();
        format!(
            "fb_env_approx({v}, {a}, array<f32, 11>({}), {})",
            c.join(", "),
            if self.bias { "true" } else { "false" }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hard-coded Gauss-Legendre rule is the one Newton's method finds on the Legendre
    /// recurrence, and its WGSL twin holds the same numbers (as f32).
    #[test]
    fn gauss_legendre_nodes_are_right_in_rust_and_wgsl() {
        let n = 24;
        for (i, &(x0, w0)) in GL24.iter().enumerate() {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..50 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                x -= p1 / dp;
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            assert!((x - x0).abs() < 1e-15 && (w - w0).abs() < 1e-15, "node {i}");
        }
        let total: f64 = GL24.iter().map(|&(_, w)| 2.0 * w).sum();
        assert!((total - 2.0).abs() < 1e-14);
        let src = include_str!("env_brdf.wgsl");
        let list = |name: &str| -> Vec<f32> {
            let start = src.find(name).unwrap();
            let body = &src[start..];
            let open = body.find('(').unwrap();
            let close = body.find(");").unwrap();
            body[open + 1..close]
                .split(',')
                .map(|s| s.trim().trim_end_matches('f').parse().unwrap())
                .collect()
        };
        let (xs, ws) = (list("FB_GL24_X"), list("FB_GL24_W"));
        assert_eq!(xs.len(), 12);
        for (i, &(x, w)) in GL24.iter().enumerate() {
            assert_eq!((xs[i], ws[i]), (x as f32, w as f32), "WGSL node {i}");
        }
    }
}
