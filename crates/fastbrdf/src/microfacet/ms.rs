//! Energy compensation for multiple scattering (issue 14): `cook-torrance`'s parameter `ms`.
//!
//! Single-scattering microfacet BRDFs lose the energy of light that bounces more than once
//! between microfacets: the white-furnace albedo of GGX with the height-correlated Smith term
//! (F = 1) is `E(mu, alpha)` < 1 (0.86, 0.66, 0.45, 0.31 at the three.js anchors). Two
//! published compensations, both built on `E`:
//!
//! - `kulla-conty` (Kulla and Conty 2017, "Revisiting Physically Based Shading at
//!   Imageworks"): adds the lobe
//!   `f_ms(wi, wo) = (1 - E(mu_i)) (1 - E(mu_o)) / (pi (1 - E_avg)) * F_ms`,
//!   `E_avg = 2 integral_0^1 E(mu) mu dmu`, `F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg))`.
//!   With F = 1, `F_ms = 1` and the albedo is `E(mu) + (1 - E(mu)) = 1` for every direction;
//!   reciprocal. `F_avg = 2 integral F(mu) mu dmu`: for Schlick's term (f0, f90) that is
//!   `(20 f0 + f90) / 21` exactly (Kulla and Conty's `(20 f0 + 1) / 21` at f90 = 1); every
//!   Fresnel term here uses `F_avg = (20 F(1) + F(0)) / 21`, its values at normal and grazing
//!   incidence: exact for `none` (1) and `schlick`, the Schlick curve through the exact end
//!   points for `dielectric`, `conductor` and `schlick-sg` (an approximation of their average
//!   that costs two Fresnel evaluations, in every form alike, with no quadrature).
//! - `filament` (Filament's documentation, "Energy compensation"): multiplies the
//!   single-scattering BRDF by `1 + f0 (1 / E(mu_o) - 1)`, `E` Filament's `dfg.y` of the view
//!   direction `wo`, `f0 = F(1)` (the Fresnel term at normal incidence: `f0` for Schlick, 1 for
//!   `none`). With F = 1 the albedo seen from `wo` (integrated over `wi`) is exactly 1; seen
//!   from `wi` (integrated over `wo`) it is not, and the BRDF is not reciprocal.
//!
//! `E(mu, alpha) = scale + bias` of `env-brdf` (its quadrature: GGX with the height-correlated
//! Smith term), so the compensation is exact only for `d = ggx`, `g = smith-ggx-correlated`;
//! `ms` other than `none` with any other `d` or `g` is refused at construction
//! (`params::Options::Gated`).
//!
//! Design: a table, built once per process (`OnceLock`, about 1.2 million integrand
//! evaluations of `env_brdf::albedo`, tens of milliseconds) and shared by every target: the
//! loss `1 - E` on a 32 x 32 grid, uniform in `x = ln(1 + mu / c) / ln(1 + 1 / c)` with
//! `c = 0.005` (`params::ALPHA`'s minimum) and in `u = ln(alpha / 0.005) / ln(1 / 0.005)`,
//! stored as f32 numbers (so f32 and f64 read the same table), bilinear in `(x, u)`. Why these
//! axes (issue 27): at small alpha the loss is a step in `mu / alpha` (it falls from 1 to 0
//! between `mu ~ alpha / 3` and `mu ~ 10 alpha`), which moves with alpha; the former axes
//! (uniform in `sqrt(mu)` and `sqrt(alpha)`) put 4 nodes on that step at alpha = 0.005 and
//! doubled alpha from one row to the next there, so bilinear interpolation missed the
//! promise (1.04e-2 at alpha = 0.0078, cos = 0.011). Logarithmic in both (`x` is linear in
//! `mu` below `c`, so `mu = 0` is a node) the step is a function of `x - u` sampled with the
//! same step (0.17 in `ln`) on both axes at every alpha, and the interpolation error is
//! 1.9e-3 (Kulla-Conty) and 3.4e-3 (Filament) at worst over the promise's range, the worst
//! now at large alpha and normal incidence (`tests/corners.rs` sweeps it; 32 x 32 uniform in
//! the square roots read 1.04e-2, 48 x 48 6.1e-3, 64 x 64 3.1e-3).
//! `1 - E_avg` per row is the integral of the row's piecewise-linear interpolant
//! (`2 integral loss(mu) mu dmu`, by 10-point Gauss-Legendre on each interval in `x`, where
//! the integrand is smooth: exact to rounding), interpolated in `u` like the rows, so `E_avg`
//! is the average of the interpolated `E` at every alpha and Kulla-Conty's lobe integrates to
//! `1 - E_table(mu_o)`. The furnace error is therefore the table's interpolation error
//! `E(mu) - E_table(mu)` alone. The WGSL twin (`fb_ms_loss`, `fb_ms_avg`) holds the same f32
//! numbers as a constant array (`wgsl_source`, generated from the same table), so the literal,
//! storage and runtime-parameter forms all read it, alpha being a literal, a storage value or
//! `p_alpha`; CPU and GPU run the same arithmetic. Why not a fitted closed form: a fit needs a
//! generator and its own error analysis; a table of the quadrature is what engines ship
//! (Filament's DFG texture, Kulla-Conty's E and E_avg tables), and its error is measured by a
//! test against the quadrature itself.
//!
//! Error: the table is within 2.5e-3 of the quadrature for `cos >= 0.01` (a unit test below,
//! on and between the nodes; `tests/corners.rs` on a 91 x 91 sweep of the promise's range,
//! logarithmic in alpha and cos), and the white furnace with F = 1 reads 1 within 0.4%
//! (`tests/energy.rs` and `tests/corners.rs`, 1% asserted: `FURNACE_TOL`) for `alpha` in
//! [0.005, 1] and `cos >= 0.01`, for both methods (Filament: the albedo seen from `wo`, which
//! is `E / E_table`). Below cos = 0.01 (extreme grazing) nothing is promised: the quadrature's
//! own error (`env_brdf::QUADRATURE_ERROR`, promised for cos >= 0.001) grows.
//! Cost: `kulla-conty`: two table look-ups (4 reads and 3 lerps each, 2 ln), one `E_avg`
//! look-up, 2 Fresnel evaluations, about 12 mul, 3 div; `filament`: one look-up, one Fresnel
//! evaluation, 1 div. Table reads are gathers: the SIMD kernels of a compensated Cook-Torrance
//! do not vectorise (`Kernel::simd()` says so).

use crate::math::Math;
use crate::microfacet::env_brdf;
use crate::params::ALPHA;
use crate::real::{K, Real};
use std::sync::OnceLock;

/// Nodes in `mu` (uniform in `x = ln(1 + mu / MU_SCALE) / ln(1 + 1 / MU_SCALE)` on [0, 1]:
/// node `j` is `mu_node(j)`).
pub const N_MU: usize = 32;
/// Nodes in `alpha` (uniform in `ln(alpha)` on `params::ALPHA`'s range: node `i` is
/// `alpha_node(i)`).
pub const N_R: usize = 32;
/// The scale `c` of the `mu` axis: `params::ALPHA`'s minimum, below which the axis is nearly
/// linear in `mu` and above which logarithmic.
pub const MU_SCALE: f64 = 0.005;

/// The white furnace's promise with F = 1 (`alpha` in [0.005, 1], `cos >= 0.01`; Filament's
/// seen from `wo`): `|albedo - 1| <= FURNACE_TOL` (3.4e-3 at worst: `tests/corners.rs` on a
/// sweep of the whole range, `tests/energy.rs` by quadrature of the BRDFs).
pub const FURNACE_TOL: f64 = 0.01;

/// The choice names of `cook-torrance`'s `ms` (a public contract).
pub const NAMES: [&str; 3] = ["none", "kulla-conty", "filament"];

/// The compensation chosen, with what it needs from the plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ms {
    None,
    KullaConty { alpha: K },
    Filament { alpha: K },
}

impl Ms {
    /// From the choice name and the plan's alpha.
    pub fn new(name: &str, alpha: f64) -> Option<Self> {
        let alpha = K::new(alpha);
        Some(match name {
            "none" => Ms::None,
            "kulla-conty" => Ms::KullaConty { alpha },
            "filament" => Ms::Filament { alpha },
            _ => return None,
        })
    }
}

/// The table: `loss[i * N_MU + j] = 1 - E(mu_node(j), alpha_node(i))` and
/// `avg[i] = 1 - E_avg(alpha_node(i))`. Row-major, `N_R` rows of `N_MU` (the layout the WGSL
/// twin and the shader exports copy).
pub struct Table {
    pub loss: Vec<f32>,
    pub avg: Vec<f32>,
    /// [`scales`], computed once.
    scales: (f64, f64, f64, f64),
}

fn a_min() -> f64 {
    ALPHA.range().0
}

/// `ln(1 + 1 / MU_SCALE)`: the `mu` axis' length in its variable.
fn mu_len() -> f64 {
    (1.0 / MU_SCALE).ln_1p()
}

/// `mu` at the fractional position `x` in [0, 1] of its axis.
fn mu_at(x: f64) -> f64 {
    if x >= 1.0 {
        1.0
    } else {
        MU_SCALE * (x * mu_len()).exp_m1()
    }
}

/// `alpha` at the fractional position `u` in [0, 1] of its axis.
fn alpha_at(u: f64) -> f64 {
    if u >= 1.0 {
        1.0
    } else {
        a_min() * (u * (1.0 / a_min()).ln()).exp()
    }
}

/// The `mu` of column `j`.
pub fn mu_node(j: usize) -> f64 {
    mu_at(j as f64 / (N_MU - 1) as f64)
}

/// The `alpha` of row `i`.
pub fn alpha_node(i: usize) -> f64 {
    alpha_at(i as f64 / (N_R - 1) as f64)
}

/// The look-ups' scales (f64; both precisions and the WGSL twin round them once):
/// `(1 / MU_SCALE, (N_MU - 1) / ln(1 + 1 / MU_SCALE), 1 / alpha_min, (N_R - 1) / ln(1 / alpha_min))`.
fn scales() -> (f64, f64, f64, f64) {
    (
        1.0 / MU_SCALE,
        (N_MU - 1) as f64 / mu_len(),
        1.0 / a_min(),
        (N_R - 1) as f64 / (1.0 / a_min()).ln(),
    )
}

/// 10-point Gauss-Legendre nodes and weights on [-1, 1] (positive half).
const GL10: [(f64, f64); 5] = [
    (0.148_874_338_981_631_2, 0.295_524_224_714_752_9),
    (0.433_395_394_129_247_2, 0.269_266_719_309_996_4),
    (0.679_409_568_299_024_4, 0.219_086_362_515_982_04),
    (0.865_063_366_688_984_5, 0.149_451_349_150_580_6),
    (0.973_906_528_517_171_7, 0.066_671_344_308_688_14),
];

/// `E(mu, alpha) = scale + bias` by `env-brdf`'s quadrature (f64), in one pass.
pub fn e_quadrature(mu: f64, alpha: f64) -> f64 {
    env_brdf::albedo::<f64, crate::math::Exact>(mu, alpha)
}

/// The shared table (built on first use).
pub fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut loss = vec![0f32; N_R * N_MU];
        let mut avg = vec![0f32; N_R];
        let h = 1.0 / (N_MU - 1) as f64;
        // d mu / dx.
        let dmu = |x: f64| MU_SCALE * mu_len() * (x * mu_len()).exp();
        for i in 0..N_R {
            let alpha = alpha_node(i);
            for j in 0..N_MU {
                loss[i * N_MU + j] = (1.0 - e_quadrature(mu_node(j), alpha)).max(0.0) as f32;
            }
            // 2 integral_0^1 loss(mu) mu dmu of the row's interpolant (linear in x between
            // its f32 values): on each interval the integrand in x is smooth.
            let mut s = 0.0;
            for j in 0..N_MU - 1 {
                let (la, lb) = (loss[i * N_MU + j] as f64, loss[i * N_MU + j + 1] as f64);
                let (a, mid) = (j as f64 * h, (j as f64 + 0.5) * h);
                for (z, w) in GL10 {
                    for x in [mid - 0.5 * h * z, mid + 0.5 * h * z] {
                        let t = (x - a) / h;
                        s += 0.5 * h * w * (la + (lb - la) * t) * mu_at(x) * dmu(x);
                    }
                }
            }
            avg[i] = (2.0 * s) as f32;
        }
        Table {
            loss,
            avg,
            scales: scales(),
        }
    })
}

/// The fractional index of `alpha` on the table's axis, clamped: `(i, t)`.
#[inline(always)]
fn r_index<T: Real>(tab: &Table, alpha: T) -> (usize, T) {
    let (_, _, inv_amin, rscale) = tab.scales;
    split((alpha * T::c(inv_amin)).ln() * T::c(rscale), N_R)
}

/// The fractional index of `mu` on the table's axis, clamped: `(j, t)`.
#[inline(always)]
fn mu_index<T: Real>(tab: &Table, mu: T) -> (usize, T) {
    let (inv_c, mscale, _, _) = tab.scales;
    let mu = crate::real::min1(crate::real::pos(mu));
    split((T::one() + mu * T::c(inv_c)).ln() * T::c(mscale), N_MU)
}

#[inline(always)]
fn split<T: Real>(u: T, n: usize) -> (usize, T) {
    let u = crate::real::pos(u).min(T::c((n - 1) as f64));
    let i = u.floor().to_usize().unwrap_or(0).min(n - 2);
    (i, u - T::c(i as f64))
}

#[inline(always)]
fn lerp<T: Real>(a: f32, b: f32, t: T) -> T {
    let a = T::c(a as f64);
    a + (T::c(b as f64) - a) * t
}

/// `1 - E(mu, alpha)` from the table (mu in [0, 1]).
#[inline(always)]
pub fn loss<T: Real>(mu: T, alpha: T) -> T {
    let tab = table();
    let (i, tr) = r_index(tab, alpha);
    let (j, tm) = mu_index(tab, mu);
    let row = |i: usize| lerp(tab.loss[i * N_MU + j], tab.loss[i * N_MU + j + 1], tm);
    let (l0, l1) = (row(i), row(i + 1));
    l0 + (l1 - l0) * tr
}

/// `1 - E_avg(alpha)` from the table.
#[inline(always)]
pub fn avg_loss<T: Real>(alpha: T) -> T {
    let tab = table();
    let (i, tr) = r_index(tab, alpha);
    lerp(tab.avg[i], tab.avg[i + 1], tr)
}

/// The smallest `1 - E_avg` divided by (a guard: the table's rows are all positive).
const AVG_MIN: f64 = 1e-12;

/// The compensation applied to the single-scattering value `ss` of a valid pair; `f1`, `f0g`
/// the Fresnel term at normal and grazing incidence (`F(1)`, `F(0)`).
#[inline(always)]
pub fn apply<T: Real, M: Math<T>>(ms: &Ms, ss: T, cos_i: T, cos_o: T, f1: T, f0g: T) -> T {
    match *ms {
        Ms::None => ss,
        Ms::KullaConty { alpha } => {
            let a = alpha.t::<T>();
            let avg = avg_loss(a).max(T::c(AVG_MIN));
            let favg = (T::c(20.0) * f1 + f0g) * T::c(1.0 / 21.0);
            // F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)).
            let fms = favg * favg * (T::one() - avg) / (T::one() - favg * avg);
            let lobe = loss(cos_i, a) * loss(cos_o, a) / (T::PI() * avg);
            ss + lobe * fms
        }
        Ms::Filament { alpha } => {
            let l = loss(cos_o, alpha.t::<T>());
            // 1 + f0 (1 / E - 1) = 1 + f0 (1 - E) / E.
            ss * (T::one() + f1 * l / (T::one() - l))
        }
    }
}

/// The items [`wgsl_source`] defines, in its order (known without generating it:
/// `plan::GeneratedSource`).
pub const WGSL_ITEMS: &[&str] = &[
    "FB_MS_LOSS",
    "FB_MS_AVG",
    "fb_ms_split",
    "fb_ms_r",
    "fb_ms_loss",
    "fb_ms_avg",
    "fb_ms_kulla_conty",
    "fb_ms_filament",
];

/// The WGSL twin: the table as constant arrays and its look-ups (`fb_ms_loss`, `fb_ms_avg`,
/// `fb_ms_kulla_conty`, `fb_ms_filament`), generated once from [`table`].
pub fn wgsl_source() -> &'static str {
    static SRC: OnceLock<String> = OnceLock::new();
    SRC.get_or_init(|| {
        let tab = table();
        let list = |v: &[f32]| -> String {
            v.iter()
                .map(|x| format!("{x:?}f"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let (inv_c, mscale, inv_amin, rscale) = tab.scales;
        format!(
            "// WGSL twin of microfacet/ms.rs: the energy-compensation table (1 - E of GGX with the\n\
             // height-correlated Smith term, 32 x 32 in (ln(1 + mu / 0.005), ln(alpha))), generated from it.\n\n\
             /// 1 - E: row i (alpha node), column j (mu node).\n\
             const FB_MS_LOSS = array<f32, {n}>({loss});\n\
             /// 1 - E_avg per row.\n\
             const FB_MS_AVG = array<f32, {nr}>({avg});\n\n\
             /// The fractional index of u on a table axis of n nodes, clamped (as ms::split).\n\
             fn fb_ms_split(u0: f32, n: i32) -> vec2<f32> {{\n\
             \x20   let u = min(max(u0, 0.0), f32(n - 1));\n\
             \x20   let i = min(floor(u), f32(n - 2));\n\
             \x20   return vec2<f32>(i, u - i);\n\
             }}\n\n\
             /// The row index of alpha (as ms::r_index).\n\
             fn fb_ms_r(alpha: f32) -> vec2<f32> {{\n\
             \x20   return fb_ms_split(log(alpha * {inv_amin}) * {rscale}, {nr});\n\
             }}\n\n\
             /// 1 - E(mu, alpha), bilinear in (ln(1 + mu / 0.005), ln(alpha)) (as ms::loss).\n\
             fn fb_ms_loss(mu: f32, alpha: f32) -> f32 {{\n\
             \x20   let ri = fb_ms_r(alpha);\n\
             \x20   let mj = fb_ms_split(log(1.0 + min(max(mu, 0.0), 1.0) * {inv_c}) * {mscale}, {nm});\n\
             \x20   let i = i32(ri.x);\n\
             \x20   let j = i32(mj.x);\n\
             \x20   // One local copy: a compiler may spill a constant array once per dynamic access.\n\
             \x20   var tab = FB_MS_LOSS;\n\
             \x20   let a0 = tab[i * {nm} + j];\n\
             \x20   let l0 = a0 + (tab[i * {nm} + j + 1] - a0) * mj.y;\n\
             \x20   let a1 = tab[(i + 1) * {nm} + j];\n\
             \x20   let l1 = a1 + (tab[(i + 1) * {nm} + j + 1] - a1) * mj.y;\n\
             \x20   return l0 + (l1 - l0) * ri.y;\n\
             }}\n\n\
             /// 1 - E_avg(alpha) (as ms::avg_loss).\n\
             fn fb_ms_avg(alpha: f32) -> f32 {{\n\
             \x20   let ri = fb_ms_r(alpha);\n\
             \x20   let i = i32(ri.x);\n\
             \x20   let a0 = FB_MS_AVG[i];\n\
             \x20   return a0 + (FB_MS_AVG[i + 1] - a0) * ri.y;\n\
             }}\n\n\
             /// Kulla-Conty: ss + f_ms F_ms (as ms::apply); f1, f0g: F at normal and grazing incidence.\n\
             fn fb_ms_kulla_conty(ss: f32, cos_i: f32, cos_o: f32, alpha: f32, f1: f32, f0g: f32) -> f32 {{\n\
             \x20   let avg = max(fb_ms_avg(alpha), {avg_min});\n\
             \x20   let favg = (20.0 * f1 + f0g) * {r21};\n\
             \x20   let fms = favg * favg * (1.0 - avg) / (1.0 - favg * avg);\n\
             \x20   let lobe = fb_ms_loss(cos_i, alpha) * fb_ms_loss(cos_o, alpha) / ({pi} * avg);\n\
             \x20   return ss + lobe * fms;\n\
             }}\n\n\
             /// Filament: ss (1 + f0 (1 / E(cos_o) - 1)) (as ms::apply).\n\
             fn fb_ms_filament(ss: f32, cos_o: f32, alpha: f32, f1: f32) -> f32 {{\n\
             \x20   let l = fb_ms_loss(cos_o, alpha);\n\
             \x20   return ss * (1.0 + f1 * l / (1.0 - l));\n\
             }}\n",
            n = N_R * N_MU,
            nr = N_R,
            nm = N_MU,
            loss = list(&tab.loss),
            avg = list(&tab.avg),
            inv_amin = crate::wgsl::lit(inv_amin),
            rscale = crate::wgsl::lit(rscale),
            inv_c = crate::wgsl::lit(inv_c),
            mscale = crate::wgsl::lit(mscale),
            avg_min = crate::wgsl::lit(AVG_MIN),
            r21 = crate::wgsl::lit(1.0 / 21.0),
            pi = crate::wgsl::lit(std::f64::consts::PI),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table's error against the quadrature it tabulates, at the cell centres and on the
    /// nodes (where it is the f32 rounding only), over the promise's range (cos >= 0.01):
    /// this is the white furnace's error (see the module header).
    #[test]
    fn table_is_within_its_bound_of_the_quadrature() {
        let mut worst: f64 = 0.0;
        for i in 0..2 * (N_R - 1) + 1 {
            let alpha = alpha_at(i as f64 / (2 * (N_R - 1)) as f64);
            for j in 0..2 * (N_MU - 1) + 1 {
                let mu = mu_at(j as f64 / (2 * (N_MU - 1)) as f64);
                if mu < 0.01 {
                    continue;
                }
                let e = e_quadrature(mu, alpha);
                let d = (1.0 - loss::<f64>(mu, alpha) - e).abs();
                worst = worst.max(d);
            }
        }
        eprintln!("table vs quadrature, cos >= 0.01: max abs error {worst:.2e}");
        assert!(worst < 2.5e-3, "table error {worst}");
    }

    /// `1 - E_avg` of each row is the integral of its interpolant: checked by Simpson's rule on
    /// the interpolated row, and `E_avg` at alpha = 1 against the known 0.6 neighbourhood.
    #[test]
    fn average_is_the_integral_of_the_interpolant() {
        for alpha in [0.005, 0.05, 0.3, 0.77, 1.0] {
            let n = 20000;
            let mut s = 0.0;
            for k in 0..=n {
                let mu = k as f64 / n as f64;
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                s += w * loss::<f64>(mu, alpha) * mu;
            }
            let avg = 2.0 * s / (3.0 * n as f64);
            assert!(
                (avg - avg_loss::<f64>(alpha)).abs() < 2e-5,
                "alpha={alpha}: {avg} vs {}",
                avg_loss::<f64>(alpha)
            );
        }
    }

    /// The WGSL twin holds the table's numbers.
    #[test]
    fn wgsl_holds_the_table() {
        let src = wgsl_source();
        let list = |name: &str| -> Vec<f32> {
            let start = src.find(&format!("const {name}")).unwrap();
            let body = &src[start..];
            let open = body.find(">(").unwrap() + 1;
            let close = body.find(");").unwrap();
            body[open + 1..close]
                .split(',')
                .map(|s| s.trim().trim_end_matches('f').parse().unwrap())
                .collect()
        };
        assert_eq!(list("FB_MS_LOSS"), table().loss);
        assert_eq!(list("FB_MS_AVG"), table().avg);
    }
}
