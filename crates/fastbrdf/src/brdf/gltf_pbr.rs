//! `gltf-pbr`: glTF 2.0's metallic-roughness material (the specification's Appendix B) with
//! the extensions `KHR_materials_ior`, `_specular`, `_clearcoat`, `_sheen` and `_anisotropy`,
//! as one BRDF whose every term is a choice from the ledger (issue 33).
//!
//! Parameters:
//!
//! | name | range | default | meaning |
//! |---|---|---|---|
//! | `base_color` | [0, 1] | 1 | `baseColorFactor` (R,G,B for a colour) |
//! | `metallic` | [0, 1] | 1 | `metallicFactor` |
//! | `roughness` | [0, 1] | 1 | `roughnessFactor`; `alpha = max(roughness^2, 0.005)` |
//! | `ior` | [1, 5] | 1.5 | `KHR_materials_ior` |
//! | `specular` | [0, 1] | 1 | `KHR_materials_specular`'s `specularFactor` |
//! | `specular_color` | [0, 10] | 1 | its `specularColorFactor` |
//! | `clearcoat`, `clearcoat_roughness` | [0, 1] | 0, 0 | `KHR_materials_clearcoat` (coat ior 1.5) |
//! | `sheen_color`, `sheen_roughness` | [0, 1] | 0, 0 | `KHR_materials_sheen` |
//! | `sheen_max` | [0, 1] | `sheen_color` | the largest channel of `sheen_color` (the colour rule sets it when `sheen_color` is R,G,B) |
//! | `anisotropy`, `anisotropy_rotation` | [0, 1], [-2 pi, 2 pi] | 0, 0 | `KHR_materials_anisotropy` (radians, from the frame's x axis, the tangent) |
//! | `d` | `ggx`, `beckmann` | `ggx` | the microfacet distribution of the base and the coat |
//! | `g` | `smith-ggx-correlated`, `-fast`, `-fast-tuned`, `smith-ggx-joint-approx`, `smith-ggx`, `schlick-ggx`, `smith` | `smith-ggx-correlated` | their shadowing-masking term |
//! | `f` | `schlick`, `schlick-sg`, `schlick-sg-tuned` | `schlick` | the Fresnel curve of every Schlick term |
//! | `diffuse` | `lambert`, `burley` | `lambert` | the base's diffuse lobe |
//! | `sheen_v` | `charlie`, `neubelt` | `charlie` | the sheen visibility (`microfacet::sheen`) |
//! | `sheen_albedo` | `table`, `fit`, `none` | `table` | the sheen's directional albedo `E` that scales the layers below |
//! | `spec_albedo` | `fresnel`, `table`, `materialx`, `karis` | `fresnel` | what weights the dielectric's diffuse: glTF's `1 - F_d(v . h)`, or the specular layer's albedo from a DFG ledger row (`env-brdf-table`: Filament's 32 x 32 half-float table; `env-brdf-materialx`; `env-brdf-approx`, Karis's mobile fit); only with `d = ggx`, `g = smith-ggx-correlated` |
//! | `ms` | `none`, `kulla-conty`, `filament` | `none` | energy compensation of the base's specular lobe (`microfacet::ms`, as `cook-torrance`'s): only with `d = ggx`, `g = smith-ggx-correlated`; with anisotropy, the isotropic table at `sqrt(alpha_t alpha)` (an approximation, as engines make it) |
//!
//! The value, per channel (`spec = D G / (4 cos_i cos_o)`, `c = wi . h`):
//! - `f0_d = min(((ior - 1) / (ior + 1))^2 specular_color, 1) specular`, `f90_d = specular`;
//!   `F_d = schlick(f0_d, f90_d, c)` (`KHR_materials_specular`'s implementation section);
//!   `F_m = schlick(base_color, 1, c)`;
//! - `base = (1 - metallic) ((1 - F_d) diffuse + F_d spec) + metallic F_m spec`, `diffuse =
//!   base_color / pi` (Lambert) or Burley's `base_color / pi (1 + (F_D90 - 1)(1 - cos_i)^5)
//!   (1 + (F_D90 - 1)(1 - cos_o)^5)`, `F_D90 = 0.5 + 2 roughness c^2`;
//! - sheen: `sheen_color D_s V_s + base S`, `S = max(0, min(1 - sheen_max E(cos_o), 1 -
//!   sheen_max E(cos_i)))` (`none`: `S = 1`), the sheen D at `max(sheen_roughness, 0.07)`;
//! - clearcoat: `mix(that, D_c G_c / (4 cos_i cos_o), clearcoat F_c(cos_o))`, `F_c =
//!   schlick(0.04, 1, cos_o)`, the coat's D and G at `max(clearcoat_roughness^2, 0.005)`
//!   (`fresnel_coat` of `KHR_materials_clearcoat`: the Fresnel of `N . V`, so a coated
//!   material is not reciprocal).
//! - Specular albedo scaling (`spec_albedo` other than `fresnel`): the diffuse weight `1 - F_d`
//!   becomes `S_d = max(0, min(1 - E_d(cos_o), 1 - E_d(cos_i)))`, `E_d(mu) = F_d(1) A(mu,
//!   alpha) + F_d(0) B(mu, alpha)` with the split-sum scale `A` and bias `B` of the chosen row
//!   (the rule the sheen's albedo scaling uses; reciprocal, and with a white base and the
//!   exact `E` at most 1 from either side).
//! - Energy compensation (`ms`): the dielectric's `F_d spec` and the metal's `F_m spec` each
//!   go through `microfacet::ms::apply` with their own Fresnel ends (`F(1)`, `F(0)`): Kulla
//!   and Conty's lobe added, or Filament's factor; the coat is not compensated.
//! - Anisotropy: `alpha_t = alpha + (1 - alpha) anisotropy^2` along the direction
//!   `(cos r, sin r)` of the frame, `alpha` across it; D and G as `cook-torrance`'s anisotropic
//!   forms (the parts at `sqrt(alpha_t alpha)` on stretched arguments); needs an anisotropic
//!   `d` and `g`.
//!
//! Colour: three grey channels, like every model. Two terms of the extensions couple the
//! channels: the sheen's `max3(sheenColor)` (here `sheen_max`, which the colour rule fills
//! from an R,G,B `sheen_color`) and nothing else (the sample viewer's per-channel Fresnel
//! mix is used for `specular_color`).
//!
//! Sampling: `vndf` (default, an exact `d`): a mixture of the base's and the coat's visible
//! normals and the cosine lobe, weighted by rough albedos (the pdf is the mixture's, so every
//! weight is `f cos / pdf` exactly); `cosine`.
//!
//! Source: glTF 2.0 specification, Appendix B; the `KHR_materials_*` extensions'
//! implementation notes; Estevez and Kulla 2017 (sheen); Burley 2012 (diffuse). Cost: two D,
//! two G, three Fresnel terms, the sheen lobe (a `pow`, four `exp` and two table reads), about
//! 40 mul/add and 4 div. Reciprocal without a clearcoat.

use crate::brdf::cook_torrance::Aniso;
use crate::entry::Entry;
use crate::error::{Error, Result};
use crate::forms::{BrdfForm, DistForm, EnvForm, FresnelForm, ShadowForm};
use crate::math::Math;
use crate::microfacet::ms::{self, Ms};
use crate::microfacet::sheen::{self, Charlie, Vis};
use crate::model::{Kind, ModelInfo, Ops};
use crate::params::{self, Options, ParamKind, ParamSpec, Params, Value};
use crate::plan::{DistPlan, EnvPlan, FresnelPlan, Models, Plan, ShadowPlan};
use crate::real::{K, Real, pos};
use crate::sample::{self, Micro, Strategy};
use crate::vec3::{COS_MIN, Pair, V3};
use crate::wgsl::Emit;

const fn num(name: &'static str, min: f64, max: f64, default: f64, doc: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        kind: ParamKind::Number {
            min,
            max,
            default: Some(default),
            requires: &[],
        },
        doc,
    }
}

const fn list(
    name: &'static str,
    options: &'static [&'static str],
    doc: &'static str,
) -> ParamSpec {
    ParamSpec {
        name,
        kind: ParamKind::Choice {
            options: Options::List(options),
            default: options[0],
        },
        doc,
    }
}

/// The distributions (both have anisotropic forms and exact sampling).
pub const D_IDS: [&str; 2] = ["ggx", "beckmann"];
/// The shadowing terms: the Smith terms, exact and approximated, all with anisotropic forms
/// (`schlick-ggx` at its default `remap = alpha-half`).
pub const G_IDS: [&str; 7] = [
    "smith-ggx-correlated",
    "smith-ggx-correlated-fast",
    "smith-ggx-correlated-fast-tuned",
    "smith-ggx-joint-approx",
    "smith-ggx",
    "schlick-ggx",
    "smith",
];

pub const PARAMS: &[ParamSpec] = &[
    num(
        "base_color",
        0.0,
        1.0,
        1.0,
        "baseColorFactor (R,G,B for a colour)",
    ),
    num("metallic", 0.0, 1.0, 1.0, "metallicFactor"),
    num(
        "roughness",
        0.0,
        1.0,
        1.0,
        "roughnessFactor; alpha = max(roughness^2, 0.005)",
    ),
    num(
        "ior",
        1.0,
        5.0,
        1.5,
        "KHR_materials_ior: the dielectric's index of refraction",
    ),
    num(
        "specular",
        0.0,
        1.0,
        1.0,
        "KHR_materials_specular: specularFactor",
    ),
    num(
        "specular_color",
        0.0,
        10.0,
        1.0,
        "KHR_materials_specular: specularColorFactor (F0 colour)",
    ),
    num(
        "clearcoat",
        0.0,
        1.0,
        0.0,
        "KHR_materials_clearcoat: clearcoatFactor",
    ),
    num(
        "clearcoat_roughness",
        0.0,
        1.0,
        0.0,
        "KHR_materials_clearcoat: clearcoatRoughnessFactor",
    ),
    num(
        "sheen_color",
        0.0,
        1.0,
        0.0,
        "KHR_materials_sheen: sheenColorFactor",
    ),
    num(
        "sheen_roughness",
        0.0,
        1.0,
        0.0,
        "KHR_materials_sheen: sheenRoughnessFactor (at least 0.07 in the lobe)",
    ),
    ParamSpec {
        name: "sheen_max",
        kind: ParamKind::Number {
            min: 0.0,
            max: 1.0,
            default: None,
            requires: &[],
        },
        doc: "max3(sheenColor), which the sheen's albedo scaling uses (set from an R,G,B sheen_color; else sheen_color)",
    },
    num(
        "anisotropy",
        0.0,
        1.0,
        0.0,
        "KHR_materials_anisotropy: anisotropyStrength",
    ),
    num(
        "anisotropy_rotation",
        -std::f64::consts::TAU,
        std::f64::consts::TAU,
        0.0,
        "KHR_materials_anisotropy: anisotropyRotation (radians from the tangent, the frame's x axis)",
    ),
    list(
        "d",
        &D_IDS,
        "microfacet distribution of the base and the coat",
    ),
    list(
        "g",
        &G_IDS,
        "shadowing-masking term of the base and the coat (the exact height-correlated Smith term first, then the shortcuts engines use)",
    ),
    list(
        "f",
        &["schlick", "schlick-sg", "schlick-sg-tuned"],
        "the curve of every Schlick Fresnel term",
    ),
    list("diffuse", &["lambert", "burley"], "the base's diffuse lobe"),
    list(
        "sheen_v",
        &sheen::Vis::NAMES,
        "sheen visibility: Charlie's fit (Estevez and Kulla 2017) or Neubelt and Pettineo's",
    ),
    ParamSpec {
        name: "spec_albedo",
        kind: ParamKind::Choice {
            options: Options::Gated {
                list: &SPEC_ALBEDO_NAMES,
                requires: &[("d", &["ggx"]), ("g", &["smith-ggx-correlated"])],
            },
            default: "fresnel",
        },
        doc: "what weights the dielectric's diffuse: fresnel (glTF's 1 - F(v.h)), or the specular albedo scaling 1 - E(cos) with E from a DFG ledger row: table (env-brdf-table, 32 x 32 half float), materialx (env-brdf-materialx), karis (env-brdf-approx); needs d = ggx, g = smith-ggx-correlated",
    },
    crate::brdf::cook_torrance::MS,
    list(
        "sheen_albedo",
        &["table", "fit", "none"],
        "the sheen's directional albedo E: 32 x 32 table of the quadrature, the analytic fit, or no scaling",
    ),
];

/// The choices of `spec_albedo` (a public contract) and the env rows they read.
pub const SPEC_ALBEDO_NAMES: [&str; 4] = ["fresnel", "table", "materialx", "karis"];
const SPEC_ALBEDO_ROWS: [Option<&str>; 4] = [
    None,
    Some("env-brdf-table"),
    Some("env-brdf-materialx"),
    Some("env-brdf-approx"),
];

pub const INFO: ModelInfo = ModelInfo {
    id: "gltf-pbr",
    kind: Kind::Brdf,
    params: PARAMS,
    formula: "mix(sheen_color D_s V_s + S [(1 - m)((1 - F_d) diffuse + F_d D G / 4 cos_i cos_o) + m F_m D G / 4 cos_i cos_o], D_c G_c / 4 cos_i cos_o, clearcoat F_c(cos_o))",
    source: "glTF 2.0 Appendix B; KHR_materials_ior, _specular, _clearcoat, _sheen, _anisotropy; Estevez & Kulla 2017; Burley 2012",
    ops: Ops::new(30, 12, 4, 0, 5),
    bounds: &[],
    f32_bound: 5e-2,
    note: "ops exclude D, G and F; the whole material (diffuse included): a renderer gives it kd = 0, ks = 1; f32: 3.5e-2 found by the adversarial search (tests/precision.rs) at cos 1e-6 with anisotropy, where the stretch of directions rounded to f32 dominates",
};

pub const ENTRY: Entry = Entry::new(INFO, |p, models| {
    Ok(Plan::Brdf(GltfPbr::from_params(p, models)?.into()))
});

/// The smallest slope of the base and the coat.
const A_MIN: f64 = params::ALPHA_MIN;

/// The anisotropic stretch, rotated by `anisotropy_rotation`.
#[derive(Clone, Copy, Debug)]
pub struct Rotated {
    pub s: Aniso,
    pub cos: K,
    pub sin: K,
}

impl Rotated {
    /// `v` in the frame whose x axis is `(cos r, sin r, 0)`.
    #[inline(always)]
    fn to<T: Real>(&self, v: V3<T>) -> V3<T> {
        let (c, s) = (self.cos.t::<T>(), self.sin.t::<T>());
        [c * v[0] + s * v[1], c * v[1] - s * v[0], v[2]]
    }
    /// The inverse of [`Self::to`].
    #[inline(always)]
    fn from<T: Real>(&self, v: V3<T>) -> V3<T> {
        let (c, s) = (self.cos.t::<T>(), self.sin.t::<T>());
        [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
    }
}

/// The sheen layer (its coefficients always built, so the runtime form can turn it on).
#[derive(Clone, Copy, Debug)]
pub struct Sheen {
    pub on: bool,
    pub color: K,
    pub max: K,
    /// Whether `sheen_max` was given (else the runtime form reads `sheen_color`).
    pub max_given: bool,
    pub c: Charlie,
    pub vis: Vis,
    pub albedo: Albedo,
    /// The fit's constant at this slope.
    pub fit_k: K,
    /// The table row position of this slope.
    pub row: (usize, K),
}

/// How the sheen's albedo `E` is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Albedo {
    Table,
    Fit,
    None,
}

/// The clearcoat layer.
#[derive(Clone, Copy, Debug)]
pub struct Coat {
    pub on: bool,
    pub weight: K,
    pub d: DistPlan,
    pub g: ShadowPlan,
    /// `schlick(0.04, 1, .)` in the chosen curve.
    pub f: FresnelPlan,
}

/// The plan: every part's coefficients computed once.
#[derive(Clone, Copy, Debug)]
pub struct GltfPbr {
    pub d: DistPlan,
    pub g: ShadowPlan,
    pub aniso: Option<Rotated>,
    /// The dielectric's Fresnel (`f0_d`, `f90_d`).
    pub fd: FresnelPlan,
    /// The metal's Fresnel (`base_color`, 1).
    pub fm: FresnelPlan,
    pub base: K,
    pub metallic: K,
    /// Burley's diffuse at this roughness; `None` for Lambert.
    pub burley: Option<K>,
    pub sheen: Sheen,
    pub coat: Coat,
    /// Sampling weights: the base's specular, the coat's, the cosine lobe (sum 1).
    pub weights: [f64; 3],
    /// The base's energy compensation (`microfacet::ms`).
    pub ms: Ms,
    /// The specular albedo scaling of the dielectric's diffuse; `None`: `1 - F_d(v . h)`.
    pub spec_albedo: Option<SpecAlbedo>,
}

/// The split-sum terms of the DFG ledger row that `spec_albedo` names, at the base's slope.
#[derive(Clone, Copy, Debug)]
pub struct SpecAlbedo {
    pub scale: EnvPlan,
    pub bias: EnvPlan,
    pub alpha: K,
}

fn invalid(param: &str, value: String, expected: String) -> Error {
    Error::InvalidParam {
        model: "gltf-pbr".into(),
        param: param.into(),
        value,
        expected,
    }
}

impl GltfPbr {
    pub fn from_params(p: &Params, models: &dyn Models) -> Result<Self> {
        let r = p.num("roughness");
        let alpha = (r * r).max(A_MIN);
        let strength = p.num("anisotropy");
        let at = alpha + (1.0 - alpha) * strength * strength;
        let aniso = strength > 0.0;
        let parts_alpha = if aniso { (at * alpha).sqrt() } else { alpha };
        let with_alpha = |a: f64| {
            move |name: &str| {
                if name == "alpha" {
                    Some(Value::Num(a))
                } else {
                    p.get(name).cloned()
                }
            }
        };
        let (d_id, g_id) = (p.choice("d"), p.choice("g"));
        let base_nums = with_alpha(parts_alpha);
        let d = models.plan(d_id, &base_nums)?.distribution(d_id)?;
        let g = models.plan(g_id, &base_nums)?.shadowing(g_id)?;
        if aniso && !(d.aniso() && g.aniso()) {
            return Err(invalid(
                "anisotropy",
                strength.to_string(),
                format!(
                    "0 unless d and g have anisotropic forms (d in {{{}}}, g in {{{}}}; given d = {d_id}, g = {g_id})",
                    crate::brdf::cook_torrance::ANISO_D.join(", "),
                    crate::brdf::cook_torrance::ANISO_G.join(", ")
                ),
            ));
        }
        let ms_id = p.choice("ms");
        // With anisotropy, the isotropic table at the parts' slope (as engines do).
        let ms = Ms::new(ms_id, parts_alpha)
            .ok_or_else(|| invalid("ms", ms_id.into(), ms::NAMES.join(", ")))?;
        let sa_id = p.choice("spec_albedo");
        let row = SPEC_ALBEDO_NAMES
            .iter()
            .position(|n| *n == sa_id)
            .map(|i| SPEC_ALBEDO_ROWS[i])
            .ok_or_else(|| invalid("spec_albedo", sa_id.into(), SPEC_ALBEDO_NAMES.join(", ")))?;
        let spec_albedo = match row {
            None => None,
            Some(id) => {
                let term = |t: &'static str| -> Result<EnvPlan> {
                    let nums = move |name: &str| (name == "term").then(|| Value::Text(t.into()));
                    match models.plan(id, &nums)? {
                        Plan::Env(e) => Ok(e),
                        _ => Err(invalid(
                            "spec_albedo",
                            sa_id.into(),
                            "a split-sum row".into(),
                        )),
                    }
                };
                Some(SpecAlbedo {
                    scale: term("scale")?,
                    bias: term("bias")?,
                    alpha: K::new(parts_alpha),
                })
            }
        };
        let rot = p.num("anisotropy_rotation");
        let f_id = format!("fresnel-{}", p.choice("f"));
        let fresnel = |f0: f64, f90: f64| -> Result<FresnelPlan> {
            let nums = move |name: &str| match name {
                "f0" => Some(Value::Num(f0)),
                "f90" => Some(Value::Num(f90)),
                _ => None,
            };
            models.plan(&f_id, &nums)?.fresnel(&f_id)
        };
        let ior = p.num("ior");
        let specular = p.num("specular");
        let f0d =
            (((ior - 1.0) / (ior + 1.0)).powi(2) * p.num("specular_color")).min(1.0) * specular;
        let base = p.num("base_color");
        let metallic = p.num("metallic");
        let fd = fresnel(f0d, specular)?;
        let fm = fresnel(base, 1.0)?;
        let burley = match p.choice("diffuse") {
            "lambert" => None,
            "burley" => Some(K::new(r)),
            other => return Err(invalid("diffuse", other.into(), "lambert or burley".into())),
        };
        let sheen_color = p.num("sheen_color");
        let sheen_alpha = p.num("sheen_roughness").max(sheen::ALPHA_MIN);
        let vis = Vis::parse(p.choice("sheen_v"))
            .ok_or_else(|| invalid("sheen_v", p.choice("sheen_v").into(), Vis::NAMES.join(", ")))?;
        let albedo = match p.choice("sheen_albedo") {
            "table" => Albedo::Table,
            "fit" => Albedo::Fit,
            "none" => Albedo::None,
            other => {
                return Err(invalid(
                    "sheen_albedo",
                    other.into(),
                    "table, fit or none".into(),
                ));
            }
        };
        let max_given = p.opt_num("sheen_max").is_some();
        let (row_i, row_t) = sheen::row(sheen_alpha);
        let sheen = Sheen {
            on: sheen_color > 0.0,
            color: K::new(sheen_color),
            max: K::new(p.opt_num("sheen_max").unwrap_or(sheen_color)),
            max_given,
            c: Charlie::new(sheen_alpha),
            vis,
            albedo,
            fit_k: K::new(sheen::fit_constant(sheen_alpha)),
            row: (row_i, row_t),
        };
        if albedo == Albedo::Table {
            // Built here, once per process, rather than on the first evaluation.
            sheen::table(vis);
        }
        let rc = p.num("clearcoat_roughness");
        let coat_nums = with_alpha((rc * rc).max(A_MIN));
        let weight = p.num("clearcoat");
        let coat = Coat {
            on: weight > 0.0,
            weight: K::new(weight),
            d: models.plan(d_id, &coat_nums)?.distribution(d_id)?,
            g: models.plan(g_id, &coat_nums)?.shadowing(g_id)?,
            f: fresnel(0.04, 1.0)?,
        };
        // Rough albedos of the lobes: the base's specular (F's average), the coat's, the rest.
        let favg = (20.0 * f0d + specular) / 21.0;
        let ws = metallic + (1.0 - metallic) * favg;
        let wc = if coat.on { 0.5 * weight } else { 0.0 };
        let wd = ((1.0 - metallic) * base * (1.0 - favg) + sheen_color).max(0.1);
        let sum = ws + wc + wd;
        Ok(Self {
            d,
            g,
            aniso: aniso.then(|| Rotated {
                s: Aniso {
                    x_over_y: K::new(at / alpha),
                    y_over_x: K::new(alpha / at),
                },
                cos: K::new(rot.cos()),
                sin: K::new(rot.sin()),
            }),
            fd,
            fm,
            base: K::new(base),
            metallic: K::new(metallic),
            burley,
            sheen,
            coat,
            weights: [ws / sum, wc / sum, wd / sum],
            ms,
            spec_albedo,
        })
    }

    /// The sheen's albedo at `mu`.
    #[inline(always)]
    fn sheen_e<T: Real>(&self, mu: T) -> T {
        let s = &self.sheen;
        match s.albedo {
            Albedo::Table => {
                sheen::table_albedo(sheen::table(s.vis), s.row.0, s.row.1.t::<T>(), mu)
            }
            Albedo::Fit => sheen::fit_albedo(mu, s.fit_k.t::<T>()),
            Albedo::None => T::zero(),
        }
    }

    /// The exact distribution the base's half vectors are drawn from, in the rotated frame.
    fn micro(&self, d: &DistPlan) -> Micro {
        let m = d.sampler().micro;
        match &self.aniso {
            None => m,
            Some(a) => Micro {
                ax: m.ax * a.s.x_over_y.x.sqrt(),
                ay: m.ay * a.s.y_over_x.x.sqrt(),
                ..m
            },
        }
    }
}

impl BrdfForm for GltfPbr {
    const WGSL: &'static str = include_str!("gltf_pbr.wgsl");
    fn simd(&self) -> bool {
        // The sheen table's reads are gathers.
        // The sheen's and the compensation's table reads are gathers.
        !(self.sheen.on && self.sheen.albedo == Albedo::Table)
            && self.ms == Ms::None
            && self.spec_albedo.is_none()
    }
    fn reciprocal(&self) -> bool {
        !self.coat.on && !matches!(self.ms, Ms::Filament { .. })
    }
    fn strategies(&self) -> &'static [Strategy] {
        if self.d.sampler().exact && self.coat.d.sampler().exact {
            &[Strategy::Vndf, Strategy::Cosine]
        } else {
            &[Strategy::Cosine]
        }
    }
    fn sample_wi<T: Real>(&self, wo: V3<T>, u: [T; 2], s: Strategy) -> Option<V3<T>> {
        match s {
            Strategy::Cosine => Some(sample::cosine(u)),
            Strategy::Vndf => {
                let [ws, wc, _] = self.weights.map(T::c);
                if u[0] < ws {
                    let u = [(u[0] / ws).min(T::c(0.999_999)), u[1]];
                    let h = match &self.aniso {
                        None => self.micro(&self.d).sample_vndf(wo, u),
                        Some(r) => r.from(self.micro(&self.d).sample_vndf(r.to(wo), u)),
                    };
                    sample::reflect_about(wo, h)
                } else if u[0] < ws + wc {
                    let u = [((u[0] - ws) / wc).min(T::c(0.999_999)), u[1]];
                    sample::reflect_about(wo, self.coat.d.sampler().micro.sample_vndf(wo, u))
                } else {
                    let u = [
                        ((u[0] - ws - wc) / (T::one() - ws - wc)).min(T::c(0.999_999)),
                        u[1],
                    ];
                    Some(sample::cosine(u))
                }
            }
            _ => None,
        }
    }
    fn pdf_wi<T: Real>(&self, wo: V3<T>, wi: V3<T>, s: Strategy) -> T {
        match s {
            Strategy::Cosine => sample::cosine_pdf(wi),
            Strategy::Vndf => {
                let [ws, wc, wd] = self.weights.map(T::c);
                let mut p = wd * sample::cosine_pdf(wi);
                if let Some((h, c)) = sample::half(wo, wi) {
                    let base = match &self.aniso {
                        None => self.micro(&self.d).pdf_vndf(wo, h),
                        Some(r) => self.micro(&self.d).pdf_vndf(r.to(wo), r.to(h)),
                    };
                    p = p + ws * base / (T::c(4.0) * c);
                    if wc > T::zero() {
                        let coat = self.coat.d.sampler().micro.pdf_vndf(wo, h);
                        p = p + wc * coat / (T::c(4.0) * c);
                    }
                }
                p
            }
            _ => T::zero(),
        }
    }
    #[inline(always)]
    fn at_pair<T: Real, M: Math<T>>(&self, p: &Pair<T>) -> T {
        let one = T::one();
        let (sin2, co, ci) = match &self.aniso {
            None => (p.sin2_h, p.cos_o, p.cos_i),
            Some(r) => (
                r.s.sin2_h::<T, M>(r.to(p.h)),
                r.s.cos::<T, M>(r.to(p.wo)),
                r.s.cos::<T, M>(r.to(p.wi)),
            ),
        };
        let above = p.cos_h >= T::c(COS_MIN);
        let d = if above {
            self.d.d::<T, M>(p.cos_h, sin2)
        } else {
            T::zero()
        };
        let g = self.g.g_pair::<T, M>(co, ci, p.cos_h, p.cos_ih);
        let denom = T::c(4.0) * (p.cos_i * p.cos_o);
        let spec = d * g / denom;
        let fd = self.fd.f::<T, M>(p.cos_ih);
        let fm = self.fm.f::<T, M>(p.cos_ih);
        let mut diff = self.base.t::<T>() * T::FRAC_1_PI();
        if let Some(r) = self.burley {
            let f90 = T::c(0.5) + T::c(2.0) * r.t::<T>() * p.cos_ih * p.cos_ih;
            let w = |c: T| {
                let m = one - c;
                let m2 = m * m;
                one + (f90 - one) * m2 * m2 * m
            };
            diff = diff * (w(p.cos_i) * w(p.cos_o));
        }
        let m = self.metallic.t::<T>();
        // The diffuse's weight: glTF's 1 - F_d(v . h), or the specular albedo scaling.
        let wd = match &self.spec_albedo {
            None => one - fd,
            Some(sa) => {
                let a = sa.alpha.t::<T>();
                let (f1, f0) = (self.fd.f::<T, M>(one), self.fd.f::<T, M>(T::zero()));
                let e = |mu: T| f1 * sa.scale.e::<T, M>(mu, a) + f0 * sa.bias.e::<T, M>(mu, a);
                pos((one - e(p.cos_o)).min(one - e(p.cos_i)))
            }
        };
        let mut v = match self.ms {
            Ms::None => (one - m) * (wd * diff + fd * spec) + m * fm * spec,
            _ => {
                let z = T::zero();
                let (ci, co) = (p.cos_i, p.cos_o);
                let (fd1, fd0) = (self.fd.f::<T, M>(one), self.fd.f::<T, M>(z));
                let (fm1, fm0) = (self.fm.f::<T, M>(one), self.fm.f::<T, M>(z));
                let sd = ms::apply::<T, M>(&self.ms, fd * spec, ci, co, fd1, fd0);
                let sm = ms::apply::<T, M>(&self.ms, fm * spec, ci, co, fm1, fm0);
                (one - m) * (wd * diff + sd) + m * sm
            }
        };
        let s = &self.sheen;
        if s.on {
            let ds = s.c.d::<T, M>(p.sin2_h);
            let vs = match s.vis {
                Vis::Charlie => s.c.v::<T, M>(p.cos_o, p.cos_i),
                Vis::Neubelt => sheen::neubelt_v(p.cos_o, p.cos_i),
            };
            let mx = s.max.t::<T>();
            let scale = if s.albedo == Albedo::None {
                one
            } else {
                let eo = self.sheen_e(p.cos_o);
                let ei = self.sheen_e(p.cos_i);
                pos((one - mx * eo).min(one - mx * ei))
            };
            v = s.color.t::<T>() * ds * vs + v * scale;
        }
        let c = &self.coat;
        if c.on {
            let dc = if above {
                c.d.d::<T, M>(p.cos_h, p.sin2_h)
            } else {
                T::zero()
            };
            let gc = c.g.g_pair::<T, M>(p.cos_o, p.cos_i, p.cos_h, p.cos_ih);
            let w = c.weight.t::<T>() * c.f.f::<T, M>(p.cos_o);
            v = v * (one - w) + w * dc * gc / denom;
        }
        v
    }
    fn wgsl_body(&self, e: &Emit) -> String {
        // Written per instance from its parts (`brdf/gltf_pbr_wgsl.rs`).
        self.wgsl_parts(e)
    }
}
