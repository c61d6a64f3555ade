//! The sheen rows of the albedo ledger (`Kind::Env`, issue 33): the directional albedo
//! `E(mu, alpha)` of the Charlie sheen lobe `D V` (sheen colour 1; `microfacet::sheen`), which
//! `gltf-pbr` uses to scale the layers below its sheen (`1 - sheen_max E`), exactly, from
//! `gltf-pbr`'s table and from fits. Inputs as every env model's: `cos_v` = `mu` and `alpha`
//! (the sheen slope), clamped to `mu` in [0.001, 1] (the albedo grows as `1 / mu` below
//! `1 / Lambda(0)`, ~1e-8: `gltf-pbr`'s table node 0 is evaluated at 0.001 too) and `alpha`
//! in [0.07, 1] (`sheen::ALPHA_MIN`, the floor of Khronos' and Enterprise PBR's
//! implementations).
//!
//! - `sheen-albedo`: the reference, `sheen::albedo_quadrature` (product Gauss-Legendre, 48 x 48
//!   in `(cos theta_i, phi)`, f64), parameter `v` the visibility (`charlie`, Estevez and Kulla's
//!   fitted Lambda; `neubelt`, Neubelt and Pettineo's). Within 1e-4 of adaptive quadrature
//!   (`sheen`'s tests; `tests/sheen_albedo.rs` checks it independently on the whole domain).
//! - `sheen-albedo-table`: `gltf-pbr`'s `sheen_albedo = table`: the 32 x 32 table of the
//!   quadrature (nodes uniform in `mu` on [0, 1] and in `alpha` on [0.07, 1]), bilinear,
//!   parameter `bits` the storage as read back (32: `gltf-pbr`'s f32; 16: half float; 8:
//!   unorm8, the storage of the Khronos sample viewer's `lut_sheen_E.png`), rounded as
//!   `env_table::quantise`.
//! - `sheen-albedo-khronos`: the analytic fit of Dassault's Enterprise PBR and the Khronos
//!   reference renderers (`gltf-pbr`'s `sheen_albedo = fit`), fitted to Charlie's visibility:
//!   `0.65584461 (1 - mu)^3 + 1 / (4.16526551 + exp(-7.97291361 sqrt(alpha) + 6.33516894))`
//!   (Enterprise PBR passes `alpha = roughness^2`, so `sqrt(alpha)` is its roughness).
//! - `sheen-albedo-tuned`: this project's form at the Khronos fit's cost (4 mul, 4 add, 1 div,
//!   1 sqrt, 1 exp): `exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha`, clamped at 0
//!   (an exponential fall from grazing whose rate and amplitude follow `1 / sqrt(alpha)`),
//!   its 5 constants fitted against `sheen-albedo` once per visibility (`v`; [`TUNED`],
//!   printed by `cargo run --release -p fastbrdf-analysis --example fit_sheen_albedo`, which
//!   also shows that refitting the Khronos form's 4 constants gains little).
//!
//! Error bounds (max abs against `sheen-albedo` at the same `v`, over `mu` in [0.001, 1] and
//! `alpha` in [0.07, 1]): [`LEDGER`], one per configuration (each `INFO`'s note gives the
//! default's), held against an independent adaptive quadrature by `tests/sheen_albedo.rs`;
//! every row with its mean, where, and the furnace consequence for `gltf-pbr`: `fastbrdf errors
//! --model ID` and `fastbrdf pareto --sheen` (the book's DFG ledger,
//! `docs/book/src/dfg-ledger.md`). They are not the registry's `bounds`: the registry-wide
//! search (`accuracy::worst`, `worst_search`, run by `tests/bounds.rs` for every bound) would
//! evaluate the 2304-point reference some 10^5 times per bound, several minutes of the test
//! suite for three rows (measured: 35 to 50 s each in a release build).

use crate::entry::Entry;
use crate::forms::EnvForm;
use crate::math::Math;
use crate::microfacet::env_table::quantise;
use crate::microfacet::sheen::{self, ALPHA_MIN, N, Vis};
use crate::model::{Kind, ModelInfo, Ops};
use crate::params::{Options, ParamKind, ParamSpec, Params};
use crate::plan::Plan;
use crate::real::{K, Real};
use crate::wgsl::Emit;

/// The smallest `mu` evaluated (below, the value at it).
pub const MU_MIN: f64 = 0.001;

pub const V: ParamSpec = ParamSpec {
    name: "v",
    kind: ParamKind::Choice {
        options: Options::List(&Vis::NAMES),
        default: "charlie",
    },
    doc: "the sheen visibility whose albedo: charlie (Estevez and Kulla's fitted Lambda) or neubelt (Neubelt and Pettineo)",
};

pub const BITS: ParamSpec = ParamSpec {
    name: "bits",
    kind: ParamKind::Choice {
        options: Options::List(&["8", "16", "32"]),
        default: "32",
    },
    doc: "storage per value: 32 (float32, gltf-pbr's table), 16 (half float) or 8 (unorm8, the Khronos sample viewer's lut_sheen_E.png)",
};

/// The reference of every bound below.
pub const REFERENCE: &str = "sheen-albedo";

pub const INFO_EXACT: ModelInfo = ModelInfo {
    id: "sheen-albedo",
    kind: Kind::Env,
    params: &[V],
    formula: "E(mu, alpha) = integral of D_charlie V cos_i over the hemisphere (sheen colour 1), product Gauss-Legendre 48 x 48 in (cos_i, phi); mu in [0.001, 1], alpha in [0.07, 1]",
    source: "Estevez and Kulla 2017 (Charlie D and V); Neubelt and Pettineo 2013 (V); KHR_materials_sheen (albedo scaling)",
    ops: Ops::new(12, 9, 1, 1, 1),
    bounds: &[],
    f32_bound: 1e-6,
    note: "ops are per quadrature point (2304 points, plus 48 visibility terms); within 1e-4 of adaptive quadrature; the reference of the sheen rows of the DFG ledger",
};

pub const INFO_TABLE: ModelInfo = ModelInfo {
    id: "sheen-albedo-table",
    kind: Kind::Env,
    params: &[V, BITS],
    formula: "bilinear in gltf-pbr's 32 x 32 table of sheen-albedo (nodes mu = j / 31, alpha = 0.07 + 0.93 i / 31), each value stored at 32, 16 or 8 bits",
    source: "gltf-pbr's sheen albedo table (microfacet::sheen); the Khronos sample viewer's sheen LUT (8-bit storage)",
    ops: Ops::new(8, 9, 0, 0, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "max abs 0.0757 against sheen-albedo (charlie, float32; mean 1.7e-3), at mu 0.008 between the first two mu nodes; every visibility and storage: sheen_albedo::LEDGER, fastbrdf errors --model sheen-albedo-table --param v=V --param bits=B",
};

pub const INFO_KHRONOS: ModelInfo = ModelInfo {
    id: "sheen-albedo-khronos",
    kind: Kind::Env,
    params: &[],
    formula: "0.65584461 (1 - mu)^3 + 1 / (4.16526551 + exp(-7.97291361 sqrt(alpha) + 6.33516894))",
    source: "Enterprise PBR 2022x (directional_albedo_sheen); the Khronos reference renderers",
    ops: Ops::new(4, 4, 1, 1, 1),
    bounds: &[],
    f32_bound: 1e-6,
    note: "max abs 0.329 against sheen-albedo (charlie; mean 0.031) at grazing, alpha 0.07; 0.894 against neubelt's (gltf-pbr's sheen_albedo = fit reads it with either visibility); fastbrdf errors --model sheen-albedo-khronos",
};

pub const INFO_TUNED: ModelInfo = ModelInfo {
    id: "sheen-albedo-tuned",
    kind: Kind::Env,
    params: &[V],
    formula: "max(0, exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha), 5 constants fitted against sheen-albedo per visibility",
    source: "this project (fit_sheen_albedo example)",
    ops: Ops::new(4, 4, 1, 1, 1),
    bounds: &[],
    f32_bound: 1e-6,
    note: "max abs 0.124 against sheen-albedo (charlie; mean 0.0114), 0.103 (neubelt; mean 0.0072); fastbrdf errors --model sheen-albedo-tuned --param v=V",
};

/// The sheen rows' ids (the ledger measures them against [`REFERENCE`], not `env-brdf`).
pub const IDS: [&str; 4] = [INFO_EXACT.id, INFO_TABLE.id, INFO_KHRONOS.id, INFO_TUNED.id];

fn vis(p: &Params) -> Vis {
    Vis::parse(p.choice("v")).expect("a listed visibility")
}

pub const ENTRY_EXACT: Entry = Entry::new(INFO_EXACT, |p, _| {
    Ok(Plan::Env(
        SheenAlbedo {
            vis: vis(p),
            form: Form::Exact,
        }
        .into(),
    ))
});
pub const ENTRY_TABLE: Entry = Entry::new(INFO_TABLE, |p, _| {
    let bits = p.choice("bits").parse().expect("a listed storage");
    Ok(Plan::Env(
        SheenAlbedo {
            vis: vis(p),
            form: Form::Table { bits },
        }
        .into(),
    ))
});
pub const ENTRY_KHRONOS: Entry = Entry::new(INFO_KHRONOS, |_, _| {
    Ok(Plan::Env(
        SheenAlbedo {
            vis: Vis::Charlie,
            form: Form::Fit(KHRONOS.map(K::new)),
        }
        .into(),
    ))
});
pub const ENTRY_TUNED: Entry = Entry::new(INFO_TUNED, |p, _| {
    let v = vis(p);
    let c = match v {
        Vis::Charlie => TUNED[0],
        Vis::Neubelt => TUNED[1],
    };
    Ok(Plan::Env(
        SheenAlbedo {
            vis: v,
            form: Form::Own(c.map(K::new)),
        }
        .into(),
    ))
});

/// The Khronos fit's constants `a, b, c, d` of `a (1 - mu)^3 + 1 / (b + exp(c sqrt(alpha) + d))`.
pub type FitCoeffs = [f64; 4];

/// Enterprise PBR's and Khronos' constants.
pub const KHRONOS: FitCoeffs = [0.65584461, 4.16526551, -7.97291361, 6.33516894];

/// This project's constants `k0..k4` of `exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4
/// alpha`.
pub type OwnCoeffs = [f64; 5];

/// Its fits (`fit_sheen_albedo` example): Charlie's, Neubelt's.
pub const TUNED: [OwnCoeffs; 2] = [
    [
        -0.26377832,
        -0.50874621,
        0.03881789,
        -1.31301892,
        0.04970510,
    ],
    [
        -0.83888869,
        0.41529529,
        0.33970263,
        -1.48697685,
        -0.06823929,
    ],
];

/// One ledger bound: `(id, choices, v of the reference, max abs error)`.
pub type LedgerBound = (
    &'static str,
    &'static [(&'static str, &'static str)],
    &'static str,
    f64,
);

/// The ledger's maximum absolute error of every configuration against `sheen-albedo` (at its
/// `v`; the Khronos fit, which has none, at both) over the whole domain, rounded up at the third
/// significant digit: `(id, choices, v of the reference, bound)`. Measured by `fastbrdf pareto
/// --sheen` (and `fastbrdf errors --model ID --param ...`); `tests/sheen_albedo.rs` holds every
/// row to its bound against an independent adaptive quadrature of the lobe.
pub const LEDGER: &[LedgerBound] = &[
    (
        "sheen-albedo-table",
        &[("v", "charlie"), ("bits", "32")],
        "charlie",
        0.0757,
    ),
    (
        "sheen-albedo-table",
        &[("v", "charlie"), ("bits", "16")],
        "charlie",
        0.0758,
    ),
    (
        "sheen-albedo-table",
        &[("v", "charlie"), ("bits", "8")],
        "charlie",
        0.0764,
    ),
    (
        "sheen-albedo-table",
        &[("v", "neubelt"), ("bits", "32")],
        "neubelt",
        0.0378,
    ),
    (
        "sheen-albedo-table",
        &[("v", "neubelt"), ("bits", "16")],
        "neubelt",
        0.0379,
    ),
    (
        "sheen-albedo-table",
        &[("v", "neubelt"), ("bits", "8")],
        "neubelt",
        0.561,
    ),
    ("sheen-albedo-khronos", &[], "charlie", 0.329),
    ("sheen-albedo-khronos", &[], "neubelt", 0.894),
    ("sheen-albedo-tuned", &[("v", "charlie")], "charlie", 0.124),
    ("sheen-albedo-tuned", &[("v", "neubelt")], "neubelt", 0.103),
];

/// How `E` is computed.
#[derive(Clone, Copy, Debug)]
pub enum Form {
    /// `sheen::albedo_quadrature`.
    Exact,
    /// `gltf-pbr`'s table of the visibility, stored at `bits`.
    Table { bits: u8 },
    /// `a (1 - mu)^3 + 1 / (b + exp(c sqrt(alpha) + d))`.
    Fit([K; 4]),
    /// `max(0, exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha)`.
    Own([K; 5]),
}

/// One sheen albedo row: the visibility and the form.
#[derive(Clone, Copy, Debug)]
pub struct SheenAlbedo {
    pub vis: Vis,
    pub form: Form,
}

/// `mu` and `alpha` clamped to the sheen's domain (NaN to the minimum).
#[inline(always)]
fn clamp<T: Real>(mu: T, alpha: T) -> (T, T) {
    let lo = |x: T, m: f64| if x > T::c(m) { x } else { T::c(m) };
    let hi = |x: T| if x < T::one() { x } else { T::one() };
    (hi(lo(mu, MU_MIN)), hi(lo(alpha, ALPHA_MIN)))
}

/// The fit at `(mu, alpha)` (already clamped).
#[inline(always)]
pub fn fit<T: Real, M: Math<T>>(c: &[K; 4], mu: T, alpha: T) -> T {
    let [a, b, cc, d] = c.map(|k| k.t::<T>());
    let m = T::one() - mu;
    a * (m * m * m) + T::one() / (b + M::exp(M::madd(cc, alpha.sqrt(), d)))
}

/// This project's form at `(mu, alpha)` (already clamped).
#[inline(always)]
pub fn own<T: Real, M: Math<T>>(k: &[K; 5], mu: T, alpha: T) -> T {
    let [k0, k1, k2, k3, k4] = k.map(|k| k.t::<T>());
    let inv = T::one() / alpha.sqrt();
    let x = M::madd(inv, M::madd(mu, k3, k2), M::madd(mu, k1, k0));
    crate::real::pos(M::madd(k4, alpha, M::exp(x)))
}

/// The table of `vis` at `(mu, alpha)` (already clamped), each node stored at `bits`: the
/// arithmetic of `sheen::row` and `sheen::table_albedo` (bits 32: the same numbers).
#[inline(always)]
pub fn table<T: Real>(vis: Vis, bits: u8, mu: T, alpha: T) -> T {
    let tab = sheen::table(vis);
    let top = T::c((N - 1) as f64);
    let u = (alpha - T::c(ALPHA_MIN)) / T::c(1.0 - ALPHA_MIN) * top;
    let u = if u > T::zero() { u } else { T::zero() };
    let u = if u < top { u } else { top };
    let i = u.floor().to_usize().unwrap_or(0).min(N - 2);
    let t = u - T::c(i as f64);
    let x = mu * top;
    let j = x.floor().to_usize().unwrap_or(0).min(N - 2);
    let tm = x - T::c(j as f64);
    let at = |k: usize| T::c(quantise(tab[k], bits) as f64);
    let r0 = at(i * N + j) + (at(i * N + j + 1) - at(i * N + j)) * tm;
    let r1 = at((i + 1) * N + j) + (at((i + 1) * N + j + 1) - at((i + 1) * N + j)) * tm;
    r0 + (r1 - r0) * t
}

impl EnvForm for SheenAlbedo {
    const WGSL: &'static str = include_str!("sheen_albedo.wgsl");
    // The quadrature and the table (gathers) do not vectorise; the fits lose a little.
    const SIMD: bool = false;
    #[inline(always)]
    fn e<T: Real, M: Math<T>>(&self, cos_v: T, alpha: T) -> T {
        let (mu, a) = clamp(cos_v, alpha);
        match self.form {
            Form::Exact => T::c(sheen::albedo_quadrature(mu.f64(), a.f64(), self.vis)),
            Form::Table { bits } => table(self.vis, bits, mu, a),
            Form::Fit(c) => fit::<T, M>(&c, mu, a),
            Form::Own(k) => own::<T, M>(&k, mu, a),
        }
    }
    fn wgsl(&self, v: &str, a: &str, e: &Emit) -> String {
        let charlie = self.vis == Vis::Charlie;
        match self.form {
            Form::Exact => format!("fb_sheen_e_quadrature({v}, {a}, {charlie})"),
            Form::Table { bits } => format!("fb_sheen_e_table({v}, {a}, {charlie}, {bits}u)"),
            Form::Fit(c) => {
                let k: Vec<String> = c.iter().map(|&x| e.constant(x)).collect();
                format!("fb_sheen_e_fit({v}, {a}, {})", k.join(", "))
            }
            Form::Own(c) => {
                let k: Vec<String> = c.iter().map(|&x| e.constant(x)).collect();
                format!("fb_sheen_e_own({v}, {a}, {})", k.join(", "))
            }
        }
    }
}

/// The Gauss-Legendre rule of the quadrature as the WGSL twin holds it (`FB_SHEEN_GL48` in
/// `sheen_albedo.wgsl`): `(node, weight)` on [0, 1].
pub fn wgsl_nodes() -> Vec<(f32, f32)> {
    sheen::quadrature_nodes()
        .iter()
        .map(|&(x, w)| (x as f32, w as f32))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Exact;

    /// The WGSL twin's rule is the quadrature's, to f32.
    #[test]
    fn wgsl_nodes_are_the_quadrature_nodes() {
        let src = include_str!("sheen_albedo.wgsl");
        let start = src.find("FB_SHEEN_GL48").expect("the rule");
        let body = &src[start..];
        let body = &body[body.find('(').unwrap() + 1..body.find(");").unwrap()];
        let nums: Vec<f32> = body
            .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
            .filter(|s| s.contains('.'))
            .map(|s| s.parse().unwrap())
            .collect();
        let want = wgsl_nodes();
        assert_eq!(nums.len(), 2 * want.len());
        for (k, &(x, w)) in want.iter().enumerate() {
            assert_eq!((nums[2 * k], nums[2 * k + 1]), (x, w), "node {k}");
        }
    }

    /// At 32 bits the table reads `gltf-pbr`'s numbers: `sheen::table_albedo` at `sheen::row`.
    #[test]
    fn table_at_32_bits_is_gltf_pbr_s() {
        for vis in [Vis::Charlie, Vis::Neubelt] {
            for &(mu, alpha) in &[(0.3f64, 0.5f64), (0.001, 0.07), (1.0, 1.0), (0.77, 0.123)] {
                let (i, t) = sheen::row(alpha);
                let want = sheen::table_albedo::<f64>(sheen::table(vis), i, t.x, mu);
                let got = table::<f64>(vis, 32, mu, alpha);
                assert!((got - want).abs() < 1e-12, "{vis:?} {mu} {alpha}");
            }
        }
    }

    /// The Khronos row is `sheen::fit_albedo` (what `gltf-pbr` reads with `sheen_albedo = fit`).
    #[test]
    fn khronos_row_is_gltf_pbr_s_fit() {
        for &(mu, alpha) in &[(0.3f64, 0.5f64), (0.001, 0.07), (1.0, 1.0), (0.77, 0.123)] {
            let want = sheen::fit_albedo::<f64>(mu, sheen::fit_constant(alpha));
            let got = fit::<f64, Exact>(&KHRONOS.map(K::new), mu, alpha);
            assert!((got - want).abs() < 1e-12, "{mu} {alpha}: {got} vs {want}");
        }
    }
}
