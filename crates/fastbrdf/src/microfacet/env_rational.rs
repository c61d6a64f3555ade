//! Rational fits of the split-sum terms (`Kind::Env`): `env-brdf-materialx` (MaterialX's
//! rational quadratic fit of the GGX directional albedo) and `env-brdf-materialx-tuned` (the
//! same form, its constants refitted minimax against `env-brdf`).
//!
//! Formula, with `x = cos_v`, `y = alpha` (MaterialX passes the average alpha, not the
//! perceptual roughness: `mx_ggx_dir_albedo(NdotV, avgAlpha, ...)`):
//! `P_c(x, y) = c0 + c1 x + c2 y + c3 x y + c4 x^2 + c5 y^2 + c6 x^2 y + c7 x y^2 + c8 x^2 y^2`,
//! `scale = P_a / P_b`, `bias = P_c / P_d` (each term its own numerator and denominator; the
//! denominators' constant coefficient is 1), clamped at 0 (every model is non-negative).
//! Evaluated by Horner in `y` inside Horner in `x`: per term two polynomials of 8 mul and 8
//! add each and one division: 16 mul, 16 add, 1 div (the `ops` of both ids).
//!
//! - `env-brdf-materialx`: MaterialX, `libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl`,
//!   `mx_ggx_dir_albedo_analytic` ("Rational quadratic fit to Monte Carlo data for GGX
//!   directional albedo"), the five-significant-digit constants of MaterialX main at commit
//!   0aa65a15abbe281f1648bb86ac6d52c649c63ba3 (MaterialX 1.39; 1.38 printed the same fit to
//!   four digits). Its data: GGX with the height-correlated Smith term (`mx_ggx_smith_G2`),
//!   the reference of `env-brdf` here.
//! - `env-brdf-materialx-tuned`: the 17 free constants of each term refitted against
//!   `env-brdf` over `cos_v` in (0, 1] and `alpha` in [0.005, 1], minimising the larger of its
//!   max and its mean absolute error each relative to MaterialX's, so that both fall (scale:
//!   max 0.0797 from 0.0863, mean 4.59e-3 from 4.94e-3; bias: 0.0373 from 0.0426, 4.98e-4 from
//!   5.66e-4; `cargo run --release -p fastbrdf-analysis --example fit_env_rational`); same cost.
//!
//! Error bounds (max abs over `cos_v` in (0, 1], `alpha` in [0.005, 1], both terms): see the
//! `INFO_*` constants (and `fastbrdf models`); the mean errors and the furnace consequence are
//! in `fastbrdf errors --model ID` and the book's DFG ledger (`docs/book/src/dfg-ledger.md`).

use crate::entry::Entry;
use crate::forms::EnvForm;
use crate::math::Math;
use crate::microfacet::env_brdf::TERM;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::Params;
use crate::plan::Plan;
use crate::real::{K, Real, pos};
use crate::wgsl::Emit;

const fn vs_dfg(bound: f64) -> [ErrorBound; 1] {
    [ErrorBound {
        reference: "env-brdf",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound,
    }]
}

pub const INFO_MATERIALX: ModelInfo = ModelInfo {
    id: "env-brdf-materialx",
    kind: Kind::Env,
    params: &[TERM],
    formula: "x = cos_v, y = alpha, P(x, y) = biquadratic (9 terms); scale = P_a / P_b, bias = P_c / P_d, clamped at 0",
    source: "MaterialX mx_ggx_dir_albedo_analytic (libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl, main at 0aa65a1)",
    ops: Ops::new(16, 16, 1, 0, 0),
    bounds: &vs_dfg(0.0864),
    f32_bound: 1e-6,
    note: "fitted by MaterialX to Monte Carlo data of GGX with height-correlated Smith (alpha, not perceptual roughness, is its second input)",
};

pub const INFO_MATERIALX_TUNED: ModelInfo = ModelInfo {
    id: "env-brdf-materialx-tuned",
    kind: Kind::Env,
    params: &[TERM],
    formula: "env-brdf-materialx's form, its 2 x 17 free constants refitted against env-brdf (max and mean both below MaterialX's)",
    source: "this project (fit_env_rational example)",
    ops: Ops::new(16, 16, 1, 0, 0),
    bounds: &vs_dfg(0.0797),
    f32_bound: 1e-6,
    note: "",
};

fn bias(p: &Params) -> bool {
    p.choice("term") == "bias"
}

pub const ENTRY_MATERIALX: Entry = Entry::new(INFO_MATERIALX, |p, _| {
    Ok(Plan::Env(Rational::new(bias(p), &MATERIALX).into()))
});
pub const ENTRY_MATERIALX_TUNED: Entry = Entry::new(INFO_MATERIALX_TUNED, |p, _| {
    Ok(Plan::Env(Rational::new(bias(p), &TUNED).into()))
});

/// The four polynomials' coefficients, in the order of the monomials `1, x, y, x y, x^2, y^2,
/// x^2 y, x y^2, x^2 y^2`: scale numerator, bias numerator, scale denominator, bias
/// denominator (MaterialX's `r.x`, `r.y`, `r.z`, `r.w`).
pub type Coeffs = [[f64; 9]; 4];

/// MaterialX's constants (`mx_ggx_dir_albedo_analytic`), transposed from its `vec4` rows.
pub const MATERIALX: Coeffs = [
    [
        0.10031, -0.63301, 9.74995, -2.02075, 29.38247, -8.24713, -26.51510, 19.98406, -5.41717,
    ],
    [
        0.93450, -2.32352, 2.22823, -3.74584, 1.42450, -0.76829, 1.43366, 0.29060, 0.62933,
    ],
    [
        1.0, -1.76427, 8.26501, 11.54840, 28.99991, -7.50867, -36.16186, 15.85408, 33.41550,
    ],
    [
        1.0, 0.22797, 15.93688, -55.82466, 13.07919, 41.25882, 54.86775, 300.10923, -284.73288,
    ],
];

/// The refit (`fit_env_rational` example).
pub const TUNED: Coeffs = [
    [
        0.085452, -0.191066, 10.218748, 0.907510, 28.483358, -8.181671, -24.737931, 17.283280,
        -6.033422,
    ],
    [
        0.928778, -2.271133, 2.281598, -3.585109, 1.347032, -0.865758, 1.307620, 0.280952, 0.708361,
    ],
    [
        1.000000, -1.180156, 8.803780, 14.385899, 27.735349, -7.465713, -33.963556, 14.708145,
        34.397942,
    ],
    [
        1.000000,
        -0.020249,
        16.308169,
        -56.675835,
        14.286259,
        41.799783,
        54.884053,
        285.368313,
        -200.145018,
    ],
];

/// One term of a rational fit: numerator and denominator coefficients.
#[derive(Clone, Copy, Debug)]
pub struct Rational {
    pub bias: bool,
    pub num: [K; 9],
    pub den: [K; 9],
}

impl Rational {
    pub fn new(bias: bool, c: &Coeffs) -> Self {
        let (n, d) = if bias { (1, 3) } else { (0, 2) };
        Self {
            bias,
            num: c[n].map(K::new),
            den: c[d].map(K::new),
        }
    }
}

/// `P_c(x, y)` by Horner in `y` for each power of `x`, then in `x`.
#[inline(always)]
pub fn poly<T: Real, M: Math<T>>(c: &[K; 9], x: T, y: T) -> T {
    let k = |i: usize| c[i].t::<T>();
    let p0 = M::madd(y, M::madd(y, k(5), k(2)), k(0));
    let p1 = M::madd(y, M::madd(y, k(7), k(3)), k(1));
    let p2 = M::madd(y, M::madd(y, k(8), k(6)), k(4));
    M::madd(x, M::madd(x, p2, p1), p0)
}

impl EnvForm for Rational {
    const WGSL: &'static str = include_str!("env_rational.wgsl");
    #[inline(always)]
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T {
        pos(poly::<T, M>(&self.num, cos_v, alpha) / poly::<T, M>(&self.den, cos_v, alpha))
    }
    fn wgsl(&self, v: &str, a: &str, e: &Emit) -> String {
        let list = |c: &[K; 9]| -> String {
            c.iter()
                .map(|&x| e.constant(x))
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "fb_env_rational({v}, {a}, array<f32, 9>({}), array<f32, 9>({}))",
            list(&self.num),
            list(&self.den)
        )
    }
}
