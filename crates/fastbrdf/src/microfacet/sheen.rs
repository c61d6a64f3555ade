//! The sheen lobe of glTF's `KHR_materials_sheen` (issue 33), a part of `gltf-pbr`: the
//! "Charlie" distribution and visibility of Estevez and Kulla 2017 ("Production Friendly
//! Microfacet Sheen BRDF", SIGGRAPH course), Neubelt and Pettineo's visibility (2013, "Crafting
//! a Next-Gen Material Pipeline for The Order: 1886"; the extension's "Ashikhmin" form), and the
//! lobe's directional albedo `E(mu, alpha)` that scales the layers below it.
//!
//! As the extension's implementation notes write them (`alpha = sheenRoughness`, here at least
//! [`ALPHA_MIN`] = 0.07, the floor of Khronos' and Enterprise PBR's implementations; the
//! extension itself divides by it):
//! - `D(h) = (2 + 1 / alpha) sin^(1 / alpha)(theta_h) / (2 pi)`;
//! - Charlie's visibility `V = 1 / ((1 + Lambda(cos_o) + Lambda(cos_i)) 4 cos_o cos_i)` with the
//!   fitted `Lambda(mu) = exp(l(mu))` for `mu < 0.5`, `exp(2 l(0.5) - l(1 - mu))` above,
//!   `l(x) = a / (1 + b x^c) + d x + e`, each of `a..e` linear in `(1 - alpha)^2`;
//! - Neubelt's `V = 1 / (4 (cos_i + cos_o - cos_i cos_o))` (cheaper; the extension warns the
//!   albedo scaling then no longer conserves energy: our tables follow the chosen `V`).
//!
//! `E(mu, alpha)`, the albedo of `D V` (sheen colour 1) seen from `mu = cos theta`:
//! - `table`: [`N`] x [`N`] values of the quadrature ([`albedo_quadrature`]: product
//!   Gauss-Legendre, 48 x 48 in `(cos theta_i, phi)`), nodes uniform in `mu` on [0, 1] (the
//!   `mu = 0` node evaluated at `mu = 0.001`: the albedo grows without bound as `1 / mu` for
//!   `mu` below `1 / Lambda(0)`, ~1e-8) and in `alpha` on [0.07, 1], stored as f32 (both
//!   precisions read the same numbers), bilinear, built once per process per visibility;
//! - `fit`: the analytic fit the Khronos reference renderer and Enterprise PBR use,
//!   `0.65584461 (1 - mu)^3 + 1 / (4.16526551 + exp(-7.97291361 sqrt(alpha) + 6.33516894))`
//!   (fitted to Charlie's visibility).
//!
//! Measured error (`cargo test -p fastbrdf --lib sheen`): see the tests below.

use crate::math::Math;
use crate::real::{K, Real};
use std::sync::OnceLock;

/// The smallest sheen slope (0.07: Khronos' reference renderer and Enterprise PBR).
pub const ALPHA_MIN: f64 = 0.07;
/// Table nodes per axis.
pub const N: usize = 32;
/// Gauss-Legendre nodes per axis of the albedo quadrature.
const QUAD_N: usize = 48;

/// Which visibility term.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vis {
    Charlie,
    Neubelt,
}

impl Vis {
    pub const NAMES: [&'static str; 2] = ["charlie", "neubelt"];
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "charlie" => Some(Self::Charlie),
            "neubelt" => Some(Self::Neubelt),
            _ => None,
        }
    }
}

/// Charlie's coefficients at one slope, computed once.
#[derive(Clone, Copy, Debug)]
pub struct Charlie {
    /// The slope (at least [`ALPHA_MIN`]).
    pub alpha: K,
    /// `(2 + 1 / alpha) / (2 pi)`.
    pub norm: K,
    /// `1 / (2 alpha)`: the exponent of `sin^2 theta_h`.
    pub expo: K,
    /// `a, b, c, d, e` of `l(x)`.
    pub l: [K; 5],
    /// `l(0.5)`.
    pub l_half: K,
}

/// The fit's `l(x)` in f64 from its coefficients.
fn l64(l: &[f64; 5], x: f64) -> f64 {
    l[0] / (1.0 + l[1] * x.powf(l[2])) + l[3] * x + l[4]
}

impl Charlie {
    /// `alpha` is clamped to [[`ALPHA_MIN`], 1].
    pub fn new(alpha: f64) -> Self {
        let a = alpha.clamp(ALPHA_MIN, 1.0);
        let t = (1.0 - a) * (1.0 - a);
        let mix = |x: f64, y: f64| x + (y - x) * t;
        let l = [
            mix(21.5473, 25.3245),
            mix(3.82987, 3.32435),
            mix(0.19823, 0.16801),
            mix(-1.97760, -1.27393),
            mix(-4.32054, -4.85967),
        ];
        Self {
            alpha: K::new(a),
            norm: K::new((2.0 + 1.0 / a) / (2.0 * std::f64::consts::PI)),
            expo: K::new(0.5 / a),
            l: l.map(K::new),
            l_half: K::new(l64(&l, 0.5)),
        }
    }

    /// `D` from `sin^2 theta_h`.
    #[inline(always)]
    pub fn d<T: Real, M: Math<T>>(&self, sin2_h: T) -> T {
        self.norm.t::<T>() * M::pow(crate::real::pos(sin2_h), self.expo.t::<T>())
    }

    #[inline(always)]
    fn l<T: Real, M: Math<T>>(&self, x: T) -> T {
        let [a, b, c, d, e] = self.l.map(|k| k.t::<T>());
        a / (T::one() + b * M::pow(crate::real::pos(x), c)) + d * x + e
    }

    /// The fitted `Lambda(mu)`.
    #[inline(always)]
    pub fn lambda<T: Real, M: Math<T>>(&self, mu: T) -> T {
        if mu < T::c(0.5) {
            M::exp(self.l::<T, M>(mu))
        } else {
            M::exp(T::c(2.0) * self.l_half.t::<T>() - self.l::<T, M>(T::one() - mu))
        }
    }

    /// Charlie's visibility `1 / ((1 + Lambda(cos_o) + Lambda(cos_i)) 4 cos_o cos_i)`.
    #[inline(always)]
    pub fn v<T: Real, M: Math<T>>(&self, cos_o: T, cos_i: T) -> T {
        // Grouped so that swapping the directions gives the same bits (reciprocity).
        let s = T::one() + (self.lambda::<T, M>(cos_o) + self.lambda::<T, M>(cos_i));
        T::one() / (s * (T::c(4.0) * (cos_o * cos_i)))
    }
}

/// Neubelt and Pettineo's visibility `1 / (4 (cos_i + cos_o - cos_i cos_o))`.
#[inline(always)]
pub fn neubelt_v<T: Real>(cos_o: T, cos_i: T) -> T {
    T::one() / (T::c(4.0) * (cos_i + cos_o - cos_i * cos_o))
}

/// The constant term of the albedo fit at `alpha`: `1 / (4.16526551 + exp(-7.97291361
/// sqrt(alpha) + 6.33516894))`.
pub fn fit_constant(alpha: f64) -> f64 {
    1.0 / (4.16526551 + (-7.97291361 * alpha.sqrt() + 6.33516894).exp())
}

/// The albedo fit: `0.65584461 (1 - mu)^3 + k`, `k` = [`fit_constant`].
#[inline(always)]
pub fn fit_albedo<T: Real>(mu: T, k: T) -> T {
    let c = T::one() - crate::real::min1(crate::real::pos(mu));
    T::c(0.65584461) * c * c * c + k
}

/// Gauss-Legendre nodes and weights on [0, 1] (Newton on the Legendre recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((0.5 * (1.0 - x), 1.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// The albedo quadrature's Gauss-Legendre rule on [0, 1], `(node, weight)`, computed once
/// (`sheen_albedo`'s WGSL twin holds it as constants).
pub(crate) fn quadrature_nodes() -> &'static [(f64, f64)] {
    static NODES: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    NODES.get_or_init(|| gauss_legendre(QUAD_N))
}

/// `E(mu, alpha)` of `D V` with visibility `vis` (sheen colour 1) by product Gauss-Legendre
/// in `(cos theta_i, phi)`, f64.
pub fn albedo_quadrature(mu: f64, alpha: f64, vis: Vis) -> f64 {
    let nodes = quadrature_nodes();
    let c = Charlie::new(alpha);
    let wo = [(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu];
    let mut sum = 0.0;
    for &(t, wt) in nodes {
        let st = (1.0 - t * t).max(0.0).sqrt();
        let v = match vis {
            Vis::Charlie => c.v::<f64, crate::math::Exact>(mu, t),
            Vis::Neubelt => neubelt_v(mu, t),
        };
        for &(u, wp) in nodes {
            // phi in [0, pi], doubled (the integrand is even in phi).
            let phi = std::f64::consts::PI * u;
            let wi = [st * phi.cos(), st * phi.sin(), t];
            let h = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
            let len2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
            let sin2 = (h[0] * h[0] + h[1] * h[1]) / len2;
            let d = c.d::<f64, crate::math::Exact>(sin2);
            sum += wt * wp * d * v * t;
        }
    }
    sum * 2.0 * std::f64::consts::PI
}

/// Node `j` of the `mu` axis (node 0 evaluated at 0.001: see the module header).
pub fn mu_node(j: usize) -> f64 {
    (j as f64 / (N - 1) as f64).max(0.001)
}

/// Node `i` of the `alpha` axis.
pub fn alpha_node(i: usize) -> f64 {
    ALPHA_MIN + (1.0 - ALPHA_MIN) * i as f64 / (N - 1) as f64
}

/// The table of visibility `vis`: row `i` (alpha node), column `j` (mu node), f32.
pub fn table(vis: Vis) -> &'static [f32] {
    static CHARLIE: OnceLock<Vec<f32>> = OnceLock::new();
    static NEUBELT: OnceLock<Vec<f32>> = OnceLock::new();
    let cell = match vis {
        Vis::Charlie => &CHARLIE,
        Vis::Neubelt => &NEUBELT,
    };
    cell.get_or_init(|| {
        let mut v = vec![0f32; N * N];
        for i in 0..N {
            for j in 0..N {
                v[i * N + j] = albedo_quadrature(mu_node(j), alpha_node(i), vis) as f32;
            }
        }
        v
    })
}

/// The table's row position of `alpha` (a plan constant): `(i, t)`, `alpha` clamped.
pub fn row(alpha: f64) -> (usize, K) {
    let u = ((alpha.clamp(ALPHA_MIN, 1.0) - ALPHA_MIN) / (1.0 - ALPHA_MIN) * (N - 1) as f64)
        .clamp(0.0, (N - 1) as f64);
    let i = (u.floor() as usize).min(N - 2);
    (i, K::new(u - i as f64))
}

/// `E(mu)` from the table at row position `(i, t)` ([`row`]), bilinear, `mu` clamped.
#[inline(always)]
pub fn table_albedo<T: Real>(tab: &[f32], i: usize, t: T, mu: T) -> T {
    let u = crate::real::min1(crate::real::pos(mu)) * T::c((N - 1) as f64);
    let j = u.floor().to_usize().unwrap_or(0).min(N - 2);
    let tm = u - T::c(j as f64);
    let at = |k: usize| T::c(tab[k] as f64);
    let r0 = at(i * N + j) + (at(i * N + j + 1) - at(i * N + j)) * tm;
    let r1 = at((i + 1) * N + j) + (at((i + 1) * N + j + 1) - at((i + 1) * N + j)) * tm;
    r0 + (r1 - r0) * t
}

/// The items [`wgsl_source`] defines, in its order (known without generating it:
/// `plan::GeneratedSource`).
pub const WGSL_ITEMS: &[&str] = &[
    "FB_SHEEN_E_CHARLIE",
    "FB_SHEEN_E_NEUBELT",
    "fb_sheen_d",
    "fb_sheen_l",
    "fb_sheen_lambda",
    "fb_sheen_v_charlie",
    "fb_sheen_v_neubelt",
    "fb_sheen_fit",
    "fb_sheen_table",
    "fb_sheen_row",
];

/// The WGSL twin: both tables as constant arrays and the lobe's functions, generated once.
pub fn wgsl_source() -> &'static str {
    static SRC: OnceLock<String> = OnceLock::new();
    SRC.get_or_init(|| {
        let list = |v: &[f32]| -> String {
            v.iter()
                .map(|x| format!("{x:?}f"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "// WGSL twin of microfacet/sheen.rs: the Charlie sheen lobe and its albedo tables\n\
             // (32 x 32 in (alpha, mu)), generated from them.\n\n\
             const FB_SHEEN_E_CHARLIE = array<f32, {n}>({c});\n\
             const FB_SHEEN_E_NEUBELT = array<f32, {n}>({nb});\n\n\
             fn fb_sheen_d(sin2_h: f32, norm: f32, expo: f32) -> f32 {{\n\
             \x20   return norm * pow(max(sin2_h, 0.0), expo);\n\
             }}\n\n\
             fn fb_sheen_l(x: f32, l: array<f32, 5>) -> f32 {{\n\
             \x20   return l[0] / (1.0 + l[1] * pow(max(x, 0.0), l[2])) + l[3] * x + l[4];\n\
             }}\n\n\
             fn fb_sheen_lambda(mu: f32, l: array<f32, 5>, l_half: f32) -> f32 {{\n\
             \x20   if mu < 0.5 {{\n\
             \x20       return exp(fb_sheen_l(mu, l));\n\
             \x20   }}\n\
             \x20   return exp(2.0 * l_half - fb_sheen_l(1.0 - mu, l));\n\
             }}\n\n\
             fn fb_sheen_v_charlie(cos_o: f32, cos_i: f32, l: array<f32, 5>, l_half: f32) -> f32 {{\n\
             \x20   let s = 1.0 + (fb_sheen_lambda(cos_o, l, l_half) + fb_sheen_lambda(cos_i, l, l_half));\n\
             \x20   return 1.0 / (s * (4.0 * (cos_o * cos_i)));\n\
             }}\n\n\
             fn fb_sheen_v_neubelt(cos_o: f32, cos_i: f32) -> f32 {{\n\
             \x20   return 1.0 / (4.0 * (cos_i + cos_o - cos_i * cos_o));\n\
             }}\n\n\
             fn fb_sheen_fit(mu: f32, k: f32) -> f32 {{\n\
             \x20   let c = 1.0 - min(max(mu, 0.0), 1.0);\n\
             \x20   return 0.65584461 * c * c * c + k;\n\
             }}\n\n\
             /// E(mu) from a table at row i, row fraction t (as sheen::table_albedo).\n\
             fn fb_sheen_table(charlie: bool, i: i32, t: f32, mu: f32) -> f32 {{\n\
             \x20   var tab = FB_SHEEN_E_NEUBELT;\n\
             \x20   if charlie {{\n\
             \x20       tab = FB_SHEEN_E_CHARLIE;\n\
             \x20   }}\n\
             \x20   let u = min(max(mu, 0.0), 1.0) * {nm1};\n\
             \x20   let j = min(i32(floor(u)), {nm2});\n\
             \x20   let tm = u - f32(j);\n\
             \x20   let r0 = tab[i * {nn} + j] + (tab[i * {nn} + j + 1] - tab[i * {nn} + j]) * tm;\n\
             \x20   let r1 = tab[(i + 1) * {nn} + j] + (tab[(i + 1) * {nn} + j + 1] - tab[(i + 1) * {nn} + j]) * tm;\n\
             \x20   return r0 + (r1 - r0) * t;\n\
             }}\n\n\
             /// The row position of alpha, clamped (as sheen::row).\n\
             fn fb_sheen_row(alpha: f32) -> vec2<f32> {{\n\
             \x20   let u = clamp((clamp(alpha, {amin}, 1.0) - {amin}) / {arange} * {nm1}, 0.0, {nm1});\n\
             \x20   let i = min(floor(u), {nm2}.0);\n\
             \x20   return vec2<f32>(i, u - i);\n\
             }}\n",
            n = N * N,
            c = list(table(Vis::Charlie)),
            nb = list(table(Vis::Neubelt)),
            nm1 = crate::wgsl::lit((N - 1) as f64),
            nm2 = N - 2,
            nn = N,
            amin = crate::wgsl::lit(ALPHA_MIN),
            arange = crate::wgsl::lit(1.0 - ALPHA_MIN),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The product rule agrees with the crate's adaptive hemisphere integrator (an
    /// independent method: nested Gauss-Kronrod around the normal) within 1e-4.
    #[test]
    fn quadrature_matches_the_adaptive_integrator() {
        for &(mu, alpha) in &[(0.9f64, 0.3), (0.5, 0.07), (0.2, 1.0), (0.05, 0.5)] {
            for vis in [Vis::Charlie, Vis::Neubelt] {
                let c = Charlie::new(alpha);
                let f = |wi: [f64; 3]| {
                    if wi[2] <= 0.0 {
                        return 0.0;
                    }
                    let wo = [(1.0 - mu * mu).sqrt(), 0.0, mu];
                    let h = [wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]];
                    let len2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
                    let d = c.d::<f64, crate::math::Exact>((h[0] * h[0] + h[1] * h[1]) / len2);
                    let v = match vis {
                        Vis::Charlie => c.v::<f64, crate::math::Exact>(mu, wi[2]),
                        Vis::Neubelt => neubelt_v(mu, wi[2]),
                    };
                    // quad::albedo multiplies by the cosine itself.
                    d * v
                };
                let (want, _) = crate::quad::albedo(f, [0.0, 0.0, 1.0], &[], 1e-7);
                let got = albedo_quadrature(mu, alpha, vis);
                assert!(
                    (got - want).abs() < 1e-4,
                    "{vis:?} mu {mu} alpha {alpha}: {got} vs {want}"
                );
            }
        }
    }

    /// The table reads its own nodes exactly (to f32) and interpolates between them within
    /// 2e-2 of the quadrature (measured on the mid-points of the grid for mu >= 0.05).
    #[test]
    fn table_is_close_to_the_quadrature() {
        let tab = table(Vis::Charlie);
        let mut worst: f64 = 0.0;
        for i in 0..N - 1 {
            for j in 1..N - 1 {
                let (a, m) = (
                    0.5 * (alpha_node(i) + alpha_node(i + 1)),
                    0.5 * (mu_node(j) + mu_node(j + 1)),
                );
                let (ri, rt) = row(a);
                let got = table_albedo::<f64>(tab, ri, rt.x, m);
                worst = worst.max((got - albedo_quadrature(m, a, Vis::Charlie)).abs());
            }
        }
        assert!(worst < 2e-2, "worst {worst}");
    }
}
