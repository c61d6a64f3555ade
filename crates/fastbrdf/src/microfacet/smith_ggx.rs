//! Smith shadowing-masking for GGX, exact and approximated: `smith-ggx`,
//! `smith-ggx-correlated`, `smith-ggx-correlated-fast`, `smith-ggx-joint-approx`,
//! `schlick-ggx`.
//!
//! GGX's Smith `Lambda(c) = (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2` (Walter et al. 2007,
//! eq. 34; Heitz 2014, eq. 72), so `1 + Lambda = (1 + S) / 2` with
//! `S(c) = sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c`: no `S - 1`
//! appears anywhere (no cancellation), and a cosine small enough to make `S` infinite gives
//! `G = 0`, never NaN.
//!
//! - `smith-ggx`: separable, `G1 = 1 / (1 + Lambda) = 2 / (1 + S)`, `G = G1(v) G1(l)`
//!   (Walter et al. 2007, eq. 34). Cost per G1: 3 mul, 4 add, 2 div, 1 sqrt (two-sided 7 mul,
//!   8 add, 4 div, 2 sqrt).
//! - `smith-ggx-correlated`: height-correlated, `G = 1 / (1 + Lambda(v) + Lambda(l)) =
//!   2 / (S(v) + S(l))` (Heitz 2014, eq. 99); one-sided (no `cos_l`): `G1`, the same formula at
//!   `cos_l = 1` (`Lambda = 0` there). Cost: 6 mul, 7 add, 3 div, 2 sqrt.
//! - `smith-ggx-correlated-fast`: Hammon 2017 as in Filament (`V_SmithGGXCorrelated_Fast`):
//!   `V = 0.5 / mix(2 NL NV, NL + NV, alpha)`, `G = 4 NL NV V = 2 NL NV / (2 NL NV (1 - alpha)
//!   + alpha (NL + NV))`. Cost: 4 mul, 2 add, 1 div.
//! - `smith-ggx-joint-approx`: Unreal Engine 4's `Vis_SmithJointApprox` (Karis 2014):
//!   `V = 0.5 / (NL (NV (1 - a) + a) + NV (NL (1 - a) + a))`, `a = alpha`, `G = 4 NL NV V`.
//!   Expanded, its denominator is `2 NL NV (1 - a) + a (NL + NV)`: it is **the same function
//!   as Hammon's** (Filament's `mix` form); both ids are kept, each in its published
//!   arrangement, so they differ only by rounding. Cost: 6 mul, 3 add, 1 div.
//! - `smith-ggx-correlated-fast-tuned`: Hammon's form with `alpha` replaced by
//!   `k = alpha (c0 + c1 alpha + c2 alpha^2)` ([`FAST_TUNED`]), the per-alpha minimax `k`
//!   against the exact correlated term fitted by a quadratic (`cargo run --release -p
//!   fastbrdf-analysis --example fit_smith_fast`): `k` is a plan constant, so the cost is
//!   Hammon's; the two-sided error falls from 0.231 to 0.104 (55% less; both worst at small
//!   alpha near grazing, and both exact at alpha = 1).
//! - `schlick-ggx`: Schlick's `G1 = NV / (NV (1 - k) + k)`, separable; parameter `remap`:
//!   `alpha-half` (default, `k = alpha / 2`, Karis 2013 after Walter's GGX fit) or `ue4`
//!   (`k = (r + 1)^2 / 8`, `r = sqrt(alpha)` the perceptual roughness: Unreal's remapping
//!   "for analytic light sources", Karis 2013). Named `remap`, not `k`: `cook-torrance`
//!   passes its numeric parameters to its parts by name, and its Fresnel `k` would land here.
//!   Cost per G1: 1 mul, 1 add, 1 div (two-sided 3 mul, 2 add, 2 div).
//!
//! In both fast forms a denominator that underflows (both cosines below about 1e-36 in f32)
//! is replaced by the smallest normal number, so the value is 0, never NaN. One-sided terms
//! are the two-sided ones at `cos_l = 1` (for the separable ones, `G1(v)`).
//!
//! Error bounds against the exact twins, max abs over alpha in [0.005, 1] (all worst at
//! alpha = 0.005, near grazing). One-sided (`ErrorBound`s, `tests/bounds.rs`, measured by
//! `accuracy::worst` on `G1(v)`): Hammon's and Unreal's forms at `cos_l = 1` are exactly
//! Schlick's `G1` with `k = alpha / 2` (`2 NV / (2 NV (1 - a) + a (1 + NV))`), and the exact
//! correlated `G1` is `smith-ggx`'s, so all three share one number, 0.1620 at `NV = 0.0057`
//! (documented 0.162). Two-sided ([`TWO_SIDED_BOUNDS`], enforced by
//! `tests/bounds.rs::two_sided_shadowing_bounds_hold` on a grid of both cosines):
//! `smith-ggx-correlated-fast` and `-joint-approx` vs `smith-ggx-correlated` 0.2307
//! (documented 0.231); `schlick-ggx` (`alpha-half`) vs `smith-ggx` 0.2605
//! (0.261); `schlick-ggx` (`ue4`, a deliberately hotter `k`) vs `smith-ggx` 0.8819 one-sided
//! (0.882) and 0.9575 two-sided (0.958). Relative errors are no better: 0.198 one-sided.
//! f32 against f64: at most 2.7e-7 for every id here in `tests/precision.rs`, 3.3e-7 with
//! `fastbrdf check --full` (`smith-ggx`; documented 1e-6 for all).
//!
//! Parameters: `alpha` (params::ALPHA, default 0.3). Cosines that are NaN or `<= 0` give 0.

use crate::entry::Entry;
use crate::error::{Error, Result};
use crate::forms::ShadowForm;
use crate::math::Math;
use crate::microfacet::shadowing::separable;
use crate::model::{ErrorBound, Kind, Metric, ModelInfo, Ops, Zone};
use crate::params::{self, Options, ParamKind, ParamSpec};
use crate::plan::Plan;
use crate::real::{K, Real, min1};
use crate::wgsl::Emit;

pub const INFO_SMITH_GGX: ModelInfo = ModelInfo {
    id: "smith-ggx",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G1 = 1 / (1 + Lambda), Lambda = (-1 + sqrt(1 + alpha^2 tan^2)) / 2, i.e. G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); G = G1(v) G1(l)",
    source: "Smith 1967; Walter et al. 2007, eq. 34 (GGX Lambda)",
    ops: Ops::new(7, 8, 4, 2, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "two-sided form is separable G1(v) G1(l)",
};

pub const INFO_CORRELATED: ModelInfo = ModelInfo {
    id: "smith-ggx-correlated",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G = 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (sqrt(1 + alpha^2 tan^2 v) + sqrt(1 + alpha^2 tan^2 l))",
    source: "Heitz 2014, eq. 99 (height-correlated Smith); GGX Lambda of Walter et al. 2007",
    ops: Ops::new(6, 7, 3, 2, 0),
    bounds: &[],
    f32_bound: 1e-6,
    note: "one-sided (no cos_l): G1",
};

pub const INFO_FAST: ModelInfo = ModelInfo {
    id: "smith-ggx-correlated-fast",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G = 4 NL NV V, V = 0.5 / mix(2 NL NV, NL + NV, alpha)",
    source: "Hammon 2017 (GDC, \"PBR Diffuse Lighting for GGX+Smith Microsurfaces\"), as Filament's V_SmithGGXCorrelated_Fast",
    ops: Ops::new(4, 2, 1, 0, 0),
    bounds: &[ErrorBound {
        reference: "smith-ggx-correlated",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound: BOUND_FAST,
    }],
    f32_bound: 1e-6,
    note: "the same function as smith-ggx-joint-approx (Unreal); one-sided it is schlick-ggx (alpha-half); two-sided max abs error against smith-ggx-correlated 0.231",
};

pub const INFO_JOINT: ModelInfo = ModelInfo {
    id: "smith-ggx-joint-approx",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "G = 4 NL NV V, V = 0.5 / (NL (NV (1 - a) + a) + NV (NL (1 - a) + a)), a = alpha",
    source: "Karis 2014, Unreal Engine 4's Vis_SmithJointApprox",
    ops: Ops::new(6, 3, 1, 0, 0),
    bounds: &[ErrorBound {
        reference: "smith-ggx-correlated",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound: BOUND_FAST,
    }],
    f32_bound: 1e-6,
    note: "algebraically identical to smith-ggx-correlated-fast (Hammon/Filament), differs by rounding only; two-sided max abs error against smith-ggx-correlated 0.231",
};

/// `k(alpha) / alpha = c0 + c1 alpha + c2 alpha^2` of `smith-ggx-correlated-fast-tuned`
/// (`fit_smith_fast` example).
pub const FAST_TUNED: [f64; 3] = [0.529334, 0.505461, -0.035766];

pub const INFO_FAST_TUNED: ModelInfo = ModelInfo {
    id: "smith-ggx-correlated-fast-tuned",
    kind: Kind::Shadowing,
    params: &[params::ALPHA],
    formula: "Hammon's G with alpha replaced by k = alpha (0.529334 + 0.505461 alpha - 0.035766 alpha^2): G = 2 NL NV / (2 NL NV (1 - k) + k (NL + NV))",
    source: "this project: Hammon 2017's form, k refitted minimax against Heitz 2014's exact term (fit_smith_fast example)",
    ops: Ops::new(4, 2, 1, 0, 0),
    bounds: &[ErrorBound {
        reference: "smith-ggx-correlated",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound: 0.104,
    }],
    f32_bound: 1e-6,
    note: "same cost as smith-ggx-correlated-fast (k is a plan constant); two-sided max abs error against smith-ggx-correlated 0.104",
};

/// The one-sided max abs error of the Hammon/Unreal forms against the exact correlated term.
const BOUND_FAST: f64 = 0.162;

/// Documented max abs errors the `ErrorBound`s cannot express (they measure the one-sided term
/// at a choice parameter's default): `(id, remap, reference, two_sided, bound)`, alpha in
/// [0.005, 1]; enforced by `tests/bounds.rs::two_sided_shadowing_bounds_hold`.
pub const TWO_SIDED_BOUNDS: &[(&str, &str, &str, bool, f64)] = &[
    (
        "smith-ggx-correlated-fast",
        "",
        "smith-ggx-correlated",
        true,
        0.231,
    ),
    (
        "smith-ggx-joint-approx",
        "",
        "smith-ggx-correlated",
        true,
        0.231,
    ),
    (
        "smith-ggx-correlated-fast-tuned",
        "",
        "smith-ggx-correlated",
        true,
        0.104,
    ),
    ("schlick-ggx", "alpha-half", "smith-ggx", true, 0.261),
    ("schlick-ggx", "ue4", "smith-ggx", false, 0.882),
    ("schlick-ggx", "ue4", "smith-ggx", true, 0.958),
];

/// `schlick-ggx`'s choice of `k`.
pub const REMAP: ParamSpec = ParamSpec {
    name: "remap",
    kind: ParamKind::Choice {
        options: Options::List(&["alpha-half", "ue4"]),
        default: "alpha-half",
    },
    doc: "Schlick's k: alpha / 2, or Unreal's (sqrt(alpha) + 1)^2 / 8",
};

pub const INFO_SCHLICK: ModelInfo = ModelInfo {
    id: "schlick-ggx",
    kind: Kind::Shadowing,
    params: &[params::ALPHA, REMAP],
    formula: "G1 = NV / (NV (1 - k) + k), k = alpha / 2 (alpha-half) or (sqrt(alpha) + 1)^2 / 8 (ue4); G = G1(v) G1(l)",
    source: "Schlick 1994; Karis 2013 (k = alpha / 2 for GGX, and Unreal's remapping)",
    ops: Ops::new(3, 2, 2, 0, 0),
    bounds: &[ErrorBound {
        reference: "smith-ggx",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("alpha", 0.005, 1.0),
        bound: 0.162,
    }],
    f32_bound: 1e-6,
    note: "bound for remap = alpha-half (two-sided 0.261); ue4 (a hotter k, by design) errs against smith-ggx by up to 0.882 one-sided, 0.958 two-sided",
};

pub const ENTRY_SMITH_GGX: Entry = Entry::new(INFO_SMITH_GGX, |p, _| {
    Ok(Plan::Shadowing(
        SmithGgx::new("smith-ggx", p.num("alpha"))?.into(),
    ))
});
pub const ENTRY_CORRELATED: Entry = Entry::new(INFO_CORRELATED, |p, _| {
    Ok(Plan::Shadowing(
        SmithGgxCorrelated(SmithGgx::new("smith-ggx-correlated", p.num("alpha"))?).into(),
    ))
});
pub const ENTRY_FAST: Entry = Entry::new(INFO_FAST, |p, _| {
    Ok(Plan::Shadowing(
        HammonFast::new("smith-ggx-correlated-fast", p.num("alpha"))?.into(),
    ))
});
pub const ENTRY_FAST_TUNED: Entry = Entry::new(INFO_FAST_TUNED, |p, _| {
    Ok(Plan::Shadowing(
        HammonFast::tuned("smith-ggx-correlated-fast-tuned", p.num("alpha"))?.into(),
    ))
});
pub const ENTRY_JOINT: Entry = Entry::new(INFO_JOINT, |p, _| {
    Ok(Plan::Shadowing(
        JointApprox(HammonFast::new("smith-ggx-joint-approx", p.num("alpha"))?).into(),
    ))
});
pub const ENTRY_SCHLICK: Entry = Entry::new(INFO_SCHLICK, |p, _| {
    Ok(Plan::Shadowing(
        SchlickGgx::new(p.num("alpha"), p.choice("remap"))?.into(),
    ))
});

/// `S(c) = sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c`, `c` in (0, 1].
#[inline(always)]
fn ggx_s<T: Real>(alpha2: T, c: T) -> T {
    let s2 = (T::one() - c) * (T::one() + c);
    (c * c + alpha2 * s2).sqrt() / c
}

/// The exact separable Smith term for GGX.
#[derive(Clone, Copy, Debug)]
pub struct SmithGgx {
    alpha2: K,
}

impl SmithGgx {
    /// `alpha` in `params::ALPHA`'s range; `id` names the model in errors.
    pub fn new(id: &'static str, alpha: f64) -> Result<Self> {
        let a = params::check(id, &params::ALPHA, alpha)?;
        Ok(Self {
            alpha2: K::new(a * a),
        })
    }

    /// `alpha^2` (`batch`'s closed form of Cook-Torrance with GGX).
    pub fn alpha2(&self) -> f64 {
        self.alpha2.x
    }
}

impl SmithGgxCorrelated {
    /// `alpha^2` (`batch`'s closed form of Cook-Torrance with GGX).
    pub fn alpha2(&self) -> f64 {
        self.0.alpha2.x
    }
}

impl ShadowForm for SmithGgx {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("smith_ggx.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        let a2 = self.alpha2.t::<T>();
        separable(cos_v, cos_l, |c| T::c(2.0) / (T::one() + ggx_s(a2, c)))
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let a2 = e.kx(self.alpha2, "p_alpha * p_alpha", &["alpha"]);
        format!("fb_g1_smith_ggx({v}, {a2}) * fb_g1_smith_ggx({l}, {a2})")
    }
}

/// The exact height-correlated Smith term for GGX.
#[derive(Clone, Copy, Debug)]
pub struct SmithGgxCorrelated(SmithGgx);

impl ShadowForm for SmithGgxCorrelated {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("smith_ggx.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        let a2 = self.0.alpha2.t::<T>();
        let (v, l) = (min1(cos_v), min1(cos_l));
        T::c(2.0) / (ggx_s(a2, v) + ggx_s(a2, l))
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let a2 = e.kx(self.0.alpha2, "p_alpha * p_alpha", &["alpha"]);
        format!("fb_g_smith_ggx_correlated({v}, {l}, {a2})")
    }
}

/// Hammon's approximation of the height-correlated GGX term (Filament's arrangement).
#[derive(Clone, Copy, Debug)]
pub struct HammonFast {
    /// `alpha`, or the tuned `k(alpha)`.
    alpha: K,
    one_minus_alpha: K,
    tuned: bool,
}

impl HammonFast {
    /// `alpha` in `params::ALPHA`'s range; `id` names the model in errors.
    pub fn new(id: &'static str, alpha: f64) -> Result<Self> {
        let a = params::check(id, &params::ALPHA, alpha)?;
        Ok(Self {
            alpha: K::new(a),
            one_minus_alpha: K::new(1.0 - a),
            tuned: false,
        })
    }
    /// The tuned form: `k = alpha (c0 + c1 alpha + c2 alpha^2)` ([`FAST_TUNED`]).
    pub fn tuned(id: &'static str, alpha: f64) -> Result<Self> {
        let a = params::check(id, &params::ALPHA, alpha)?;
        let [c0, c1, c2] = FAST_TUNED;
        let k = a * (c0 + a * (c1 + a * c2));
        Ok(Self {
            alpha: K::new(k),
            one_minus_alpha: K::new(1.0 - k),
            tuned: true,
        })
    }
    fn wgsl_ks(&self, e: &Emit) -> (String, String) {
        let k = if self.tuned {
            let [c0, c1, c2] = FAST_TUNED.map(crate::wgsl::lit);
            format!("p_alpha * ({c0} + p_alpha * ({c1} + p_alpha * {c2}))")
        } else {
            "p_alpha".to_string()
        };
        (
            e.kx(self.alpha, &k, &["alpha"]),
            e.kx(self.one_minus_alpha, &format!("1.0 - {k}"), &["alpha"]),
        )
    }
}

/// `num / den` with a denominator that underflowed to 0 (then `num` is 0 too) made the
/// smallest normal f32 number: 0, not NaN.
#[inline(always)]
fn ratio_safe<T: Real>(num: T, den: T) -> T {
    let tiny = T::c(f32::MIN_POSITIVE as f64);
    num / (if den > tiny { den } else { tiny })
}

impl ShadowForm for HammonFast {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("smith_ggx.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        let (v, l) = (min1(cos_v), min1(cos_l));
        let two_vl = T::c(2.0) * (v * l);
        // mix(x, y, a) = x (1 - a) + y a, as GLSL.
        let den = two_vl * self.one_minus_alpha.t::<T>() + (v + l) * self.alpha.t::<T>();
        ratio_safe(two_vl, den)
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let (a, b) = self.wgsl_ks(e);
        format!("fb_g_smith_ggx_correlated_fast({v}, {l}, {a}, {b})")
    }
}

/// Unreal's `Vis_SmithJointApprox` (the same function as [`HammonFast`], Unreal's arrangement).
#[derive(Clone, Copy, Debug)]
pub struct JointApprox(HammonFast);

impl ShadowForm for JointApprox {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("smith_ggx.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        let (v, l) = (min1(cos_v), min1(cos_l));
        let (a, b) = (self.0.alpha.t::<T>(), self.0.one_minus_alpha.t::<T>());
        let vis_v = l * (v * b + a);
        let vis_l = v * (l * b + a);
        ratio_safe(T::c(2.0) * (v * l), vis_v + vis_l)
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let (a, b) = self.0.wgsl_ks(e);
        format!("fb_g_smith_ggx_joint_approx({v}, {l}, {a}, {b})")
    }
}

/// Schlick's separable approximation of the Smith term, with GGX's `k`.
#[derive(Clone, Copy, Debug)]
pub struct SchlickGgx {
    k: K,
    one_minus_k: K,
    ue4: bool,
}

impl SchlickGgx {
    /// `alpha` in `params::ALPHA`'s range; `remap` `alpha-half` or `ue4`.
    pub fn new(alpha: f64, remap: &str) -> Result<Self> {
        let a = params::check("schlick-ggx", &params::ALPHA, alpha)?;
        let (k, ue4) = match remap {
            "alpha-half" => (a / 2.0, false),
            "ue4" => ((a.sqrt() + 1.0).powi(2) / 8.0, true),
            other => {
                return Err(Error::InvalidParam {
                    model: "schlick-ggx".into(),
                    param: "remap".into(),
                    value: other.into(),
                    expected: REMAP.range_text(),
                });
            }
        };
        Ok(Self {
            k: K::new(k),
            one_minus_k: K::new(1.0 - k),
            ue4,
        })
    }
}

impl ShadowForm for SchlickGgx {
    const ANISO: bool = true;
    const WGSL: &'static str = include_str!("smith_ggx.wgsl");
    #[inline(always)]
    fn g_pair<T: Real, M: Math<T>>(&self, cos_v: T, cos_l: T, _cos_h: T, _cos_vh: T) -> T {
        let (k, b) = (self.k.t::<T>(), self.one_minus_k.t::<T>());
        separable(cos_v, cos_l, |c| c / (c * b + k))
    }
    fn wgsl(&self, v: &str, l: &str, _h: &str, _vh: &str, e: &Emit) -> String {
        let (k, b) = if self.ue4 {
            (
                e.kx(
                    self.k,
                    "0.125 * (sqrt(p_alpha) + 1.0) * (sqrt(p_alpha) + 1.0)",
                    &["alpha"],
                ),
                e.kx(
                    self.one_minus_k,
                    "1.0 - 0.125 * (sqrt(p_alpha) + 1.0) * (sqrt(p_alpha) + 1.0)",
                    &["alpha"],
                ),
            )
        } else {
            (
                e.kx(self.k, "0.5 * p_alpha", &["alpha"]),
                e.kx(self.one_minus_k, "1.0 - 0.5 * p_alpha", &["alpha"]),
            )
        };
        format!("fb_g1_schlick_ggx({v}, {k}, {b}) * fb_g1_schlick_ggx({l}, {k}, {b})")
    }
}
