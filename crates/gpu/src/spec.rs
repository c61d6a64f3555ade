//! Model instances on the GPU: a model id and its parameters become one WGSL function,
//! `fb_<id>` (dashes as underscores), that calls the library's core functions with the
//! instance's coefficients, placed as `Emit` says: f32 literals, the storage array `fb_k`, or
//! expressions of the parameters.
//!
//! The coefficients are computed here in f64 exactly as the CPU batch kernels compute them
//! (`fastbrdf::batch`, `build` and friends): cubic shapes, rational nodes, tuned slopes and
//! normalisation integrals need f64 and `expm1`, which a shader does not have. The CPU-GPU
//! parity tests (`tests/parity.rs`) compare every model through these instances, so a
//! difference between the two mappings fails a test.
//!
//! Signatures of the generated function, by kind:
//! - lobe: `fn fb_<id>(c: f32) -> f32`
//! - distribution: `fn fb_<id>(cos_h: f32) -> f32`
//! - shadowing: `fn fb_<id>(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32` (two-sided)
//! - Fresnel: `fn fb_<id>(cos_vh: f32) -> f32`
//! - BRDF: `fn fb_<id>(wi: vec3<f32>, wo: vec3<f32>) -> f32` (local frame, normal +z, no cosine)

use crate::library;
use fastbrdf::brdf::phong::lobe_integral;
use fastbrdf::lobes::cubic::CubicShape;
use fastbrdf::lobes::flog::seed_coef;
use fastbrdf::lobes::tuned;
use fastbrdf::microfacet::beckmann_pow::exponent;
use fastbrdf::model::{Kind, ModelInfo};
use fastbrdf::params::{Params, Value};
use fastbrdf::{Error, Result, registry};
use std::f64::consts::{LN_2, PI};

/// One model with fixed parameters, as WGSL.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The registry entry.
    pub info: &'static ModelInfo,
    /// Every resolved parameter (given or default), as text.
    pub params: Vec<(String, String)>,
    /// The generated function's name, `fb_<id>`.
    pub function: String,
    /// The generated function (WGSL, with a doc comment).
    pub wrapper: String,
    /// The coefficients the function reads from `fb_k` (empty with literals).
    pub coefs: Vec<f32>,
    /// Symbolic instances: the parameters passed as arguments `p_<name>` (in order), with
    /// this instance's values.
    pub sliders: Vec<(String, f64)>,
    /// Symbolic mode only: some coefficient had no expression (so literals were used).
    opaque: bool,
}

impl Instance {
    /// Builds the instance of `id` with parameters given as text, validated like
    /// `fastbrdf::registry::build`, with its coefficients as literals (for exported code).
    pub fn new(id: &str, given: &[(&str, &str)]) -> Result<Self> {
        Self::with(id, given, Emit::literals())
    }

    /// As `new`, with the coefficients in the storage array
    /// `fb_k: array<f32>` (for the compute and render paths).
    pub fn with_storage(id: &str, given: &[(&str, &str)]) -> Result<Self> {
        Self::with(id, given, Emit::storage())
    }

    /// Builds the instance with coefficients placed as `emit` says.
    pub fn with(id: &str, given: &[(&str, &str)], emit: Emit) -> Result<Self> {
        let e = registry::find(id)?;
        let p = Params::resolve(e.info.id, e.info.params, given)?;
        let function = function_name(e.info.id);
        let body = body(&emit, e.info.id, e.info.kind, &p)?;
        let mut signature = signature(e.info.kind).to_string();
        // Symbolic coefficients: the parameters they use become arguments, in registry order.
        let used = emit.used.borrow().clone();
        let sliders: Vec<(String, f64)> = e
            .info
            .params
            .iter()
            .filter(|spec| used.contains(spec.name))
            .map(|spec| (spec.name.to_string(), p.num(spec.name)))
            .collect();
        for (name, _) in &sliders {
            signature.push_str(&format!(", p_{name}: f32"));
        }
        let params: Vec<(String, String)> = p
            .iter()
            .map(|(k, v)| {
                let v = match v {
                    Value::Num(x) => format!("{x}"),
                    Value::Text(t) => t.clone(),
                };
                (k.to_string(), v)
            })
            .collect();
        let shown = shown(&params);
        let wrapper = format!(
            "/// {id}: {formula}\n/// Source: {source}. Instance: {shown}.\nfn {function}({signature}) -> f32 {{\n{body}}}\n",
            id = e.info.id,
            formula = e.info.formula,
            source = e.info.source,
        );
        Ok(Self {
            info: &e.info,
            params,
            function,
            wrapper,
            coefs: emit.values.into_inner(),
            sliders,
            opaque: emit.opaque.get(),
        })
    }

    /// The instance with coefficients as expressions of its numeric parameters, which become
    /// arguments `p_<name>` after the model's inputs; `None` when a coefficient has no such
    /// expression (cubic shapes, rational nodes, numerical normalisation).
    pub fn symbolic(id: &str, given: &[(&str, &str)]) -> Result<Option<Self>> {
        let inst = Self::with(id, given, Emit::symbolic())?;
        Ok(if inst.opaque { None } else { Some(inst) })
    }

    /// A self-contained WGSL module: the library items the function needs, then the function.
    pub fn module_source(&self) -> String {
        let mut s = library::closure_source(&self.wrapper);
        s.push('\n');
        s.push_str(&self.wrapper);
        s
    }
}

/// The inputs of a kind's `fb_<id>`, as WGSL parameters (see the module header).
pub fn signature(kind: Kind) -> &'static str {
    match kind {
        Kind::Lobe => "c: f32",
        Kind::Distribution => "cos_h: f32",
        Kind::Shadowing => "cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32",
        Kind::Fresnel => "cos_vh: f32",
        Kind::Brdf => "wi: vec3<f32>, wo: vec3<f32>",
    }
}

/// The names in `signature(kind)`, as a call's argument list.
pub fn arguments(kind: Kind) -> String {
    signature(kind)
        .split(", ")
        .map(|a| a.split(':').next().unwrap_or(a))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `a = 1, b = x`, or `no parameters`.
pub fn shown(params: &[(String, String)]) -> String {
    if params.is_empty() {
        "no parameters".into()
    } else {
        params
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `fb_` and the id with dashes as underscores.
pub fn function_name(id: &str) -> String {
    format!("fb_{}", id.replace('-', "_"))
}

/// An f32 literal that parses back to the same f32.
pub fn lit(x: f64) -> String {
    let f = x as f32;
    assert!(f.is_finite(), "non-finite coefficient {x}");
    format!("{f:?}f")
}

/// Where the coefficients of an instance go: inline as literals (exported code), into the
/// storage array `fb_k` (the compute and render paths), or as expressions of the model's
/// numeric parameters passed as arguments `p_<name>` (BRDF Explorer's sliders).
///
/// Why literals and storage: a shader compiler folds literal constants into reassociated
/// expressions (Mesa turns the cubic's Newton form `(x - x2) d3` into `x d3 - x2 d3`, which
/// cancels catastrophically when `d3 ~ 1e8`). Coefficients it cannot see keep the arrangement
/// the CPU uses; `tests/parity.rs` measures both forms. Symbolic coefficients are computed in
/// f32 in the shader, so only models whose coefficients are simple expressions offer them
/// (not the cubics, rationals or numerically normalised lobes, which need f64 and `expm1`).
#[derive(Debug, Default)]
pub struct Emit {
    mode: Mode,
    values: std::cell::RefCell<Vec<f32>>,
    /// Symbolic mode: the parameters the expressions use.
    used: std::cell::RefCell<std::collections::BTreeSet<String>>,
    /// Symbolic mode: a coefficient had no expression.
    opaque: std::cell::Cell<bool>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Mode {
    #[default]
    Literals,
    Storage,
    Symbolic,
}

impl Emit {
    /// Coefficients as literals.
    pub fn literals() -> Self {
        Self::default()
    }
    /// Coefficients as `fb_k[i]`.
    pub fn storage() -> Self {
        Self {
            mode: Mode::Storage,
            ..Default::default()
        }
    }
    /// Coefficients as expressions of `p_<param>` arguments, where every coefficient has one.
    pub fn symbolic() -> Self {
        Self {
            mode: Mode::Symbolic,
            ..Default::default()
        }
    }
    /// One coefficient with no expression in the parameters.
    pub fn k(&self, x: f64) -> String {
        match self.mode {
            Mode::Literals => lit(x),
            Mode::Symbolic => {
                self.opaque.set(true);
                lit(x)
            }
            Mode::Storage => {
                let mut v = self.values.borrow_mut();
                v.push(x as f32);
                format!("fb_k[{}]", v.len() - 1)
            }
        }
    }
    /// One coefficient, value `x`, which is the WGSL expression `expr` of the parameters
    /// `params` (written `p_<name>` in `expr`).
    pub fn kx(&self, x: f64, expr: &str, params: &[&str]) -> String {
        if self.mode != Mode::Symbolic {
            return self.k(x);
        }
        let mut used = self.used.borrow_mut();
        for p in params {
            used.insert(p.to_string());
        }
        format!("({expr})")
    }
    /// A constant that does not depend on the parameters.
    pub fn constant(&self, x: f64) -> String {
        if self.mode == Mode::Storage {
            self.k(x)
        } else {
            lit(x)
        }
    }
    fn args(&self, xs: &[f64]) -> String {
        xs.iter().map(|x| self.k(*x)).collect::<Vec<_>>().join(", ")
    }
    fn cubic(&self, s: CubicShape) -> String {
        self.args(&[s.d1, s.d2, s.d3, s.x1, s.x2, s.cut])
    }
    /// `(peak, g)` of seed 003's rational at `level` in its fold-proof form
    /// `peak c / (1 + g (1 - c))` (see `fb_lobe_rational`): d0 = 1 + n xq with
    /// xq = level^(1/n) - 1 (expm1), peak = level / d0, g = (n - 1) / d0.
    fn rational(&self, n: f64, level: f64) -> String {
        let d0 = 1.0 + n * (level.ln() / n).exp_m1();
        self.args(&[level / d0, (n - 1.0) / d0])
    }
}

/// `R(1/n)` of a tuned family as a WGSL expression of `p_n`.
fn poly_expr(r: &[f64; 5]) -> String {
    let x = "(1.0 / p_n)";
    format!(
        "{} + {x} * ({} + {x} * ({} + {x} * ({} + {x} * {})))",
        r[0], r[1], r[2], r[3], r[4]
    )
}

/// seed 001's energy coefficient of flog, as an expression of `p_n`.
const FLOG_COEF: &str = "0.197 * (p_n + 1.24) + 0.068 / (0.64 + p_n)";

/// The call of lobe `id` at exponent `n` on the expression `c` (twin: batch `lobe_op`).
pub fn lobe_call(e: &Emit, id: &str, n: f64, c: &str) -> Option<String> {
    let power =
        |g: u32, s: f64, expr: String| format!("fb_lobe_power{g}({c}, {})", e.kx(s, &expr, &["n"]));
    let nn = |x: f64| e.kx(x, "p_n", &["n"]);
    let cubic_rational = |level: f64| {
        format!(
            "fb_lobe_cubic_rational({c}, {}, {}, {})",
            e.cubic(CubicShape::hermite_at(n, level)),
            e.rational(n, level),
            e.k(level.powf(1.0 / n))
        )
    };
    Some(match id {
        "pow" => format!("fb_lobe_pow({c}, {})", nn(n)),
        "schlick" => format!("fb_lobe_schlick({c}, {})", nn(n)),
        "schlick-modified" => format!("fb_lobe_schlick_modified({c}, {})", nn(n)),
        "gauss" => format!("fb_lobe_gauss({c}, {})", e.kx(0.5 * n, "0.5 * p_n", &["n"])),
        "flog" => format!("fb_lobe_flog({c}, {}, 1.0f, false)", nn(n)),
        "flog-normalized" => {
            format!(
                "fb_lobe_flog({c}, {}, {}, false)",
                nn(n),
                e.kx(seed_coef(n), FLOG_COEF, &["n"])
            )
        }
        "flog-normalized-clamped" => {
            format!(
                "fb_lobe_flog({c}, {}, {}, true)",
                nn(n),
                e.kx(seed_coef(n), FLOG_COEF, &["n"])
            )
        }
        "cubic" => format!("fb_lobe_cubic({c}, {})", e.cubic(CubicShape::hermite(n))),
        "cubic3" => format!(
            "fb_lobe_cubic({c}, {})",
            e.cubic(CubicShape::three_point(n, 0.5, 1.0 / 18.0))
        ),
        "rational" => format!("fb_lobe_rational({c}, {})", e.rational(n, 0.5)),
        "cubic-rational" => cubic_rational(0.5),
        "cubic-rational-tuned" => cubic_rational(tuned::cubic_rational_level(n)),
        "power4" => power(4, n / 4.0, "p_n / 4.0".into()),
        "power8" => power(8, n / 8.0, "p_n / 8.0".into()),
        "power16" => power(16, n / 16.0, "p_n / 16.0".into()),
        "power4-tuned" => power(
            4,
            tuned::power_slope(4, n),
            format!(
                "select(p_n / 4.0 * ({}), 1.0, p_n == 4.0)",
                poly_expr(&tuned::R_POWER4)
            ),
        ),
        "power8-tuned" => power(
            8,
            tuned::power_slope(8, n),
            format!(
                "select(p_n / 8.0 * ({}), 1.0, p_n == 8.0)",
                poly_expr(&tuned::R_POWER8)
            ),
        ),
        "power16-tuned" => power(
            16,
            tuned::power_slope(16, n),
            format!(
                "select(p_n / 16.0 * ({}), 1.0, p_n == 16.0)",
                poly_expr(&tuned::R_POWER16)
            ),
        ),
        "sg" => format!(
            "fb_lobe_exp2({c}, {})",
            e.kx(n / LN_2, "p_n * 1.4426950408889634", &["n"])
        ),
        "sg-tuned" => format!(
            "fb_lobe_exp2({c}, {})",
            e.kx(
                tuned::exp2_rate(n),
                &format!("p_n * 1.4426950408889634 * ({})", poly_expr(&tuned::R_EXP2)),
                &["n"]
            )
        ),
        #[allow(clippy::approx_constant)]
        "ue4-phong-approx" => format!(
            "fb_lobe_exp2({c}, {})",
            e.kx(1.4427 * (n + 0.775), "1.4427 * (p_n + 0.775)", &["n"])
        ),
        _ => return None,
    })
}

/// The call of distribution `id` at slope `alpha` on `c` (cos theta_h, <= 1) and `s2`
/// (sin^2 theta_h) (twin: batch `dist_op`).
pub fn dist_call(e: &Emit, id: &str, alpha: f64, c: &str, s2: &str) -> Option<String> {
    let a2 = alpha * alpha;
    let ct = 1.0 / (4.0 * a2);
    let ex = exponent(alpha);
    const A: &[&str] = &["alpha"];
    let inv_a2 = || e.kx(1.0 / a2, "1.0 / (p_alpha * p_alpha)", A);
    let ct_k = || e.kx(ct, "0.25 / (p_alpha * p_alpha)", A);
    let power = |g: u32| {
        format!(
            "fb_d_beckmann_power{g}({c}, {s2}, {}, {})",
            e.kx(
                ex / g as f64,
                &format!("(2.0 / (p_alpha * p_alpha) - 4.0) / {g}.0"),
                A
            ),
            ct_k()
        )
    };
    Some(match id {
        "beckmann" => format!(
            "fb_d_beckmann({c}, {s2}, {}, {})",
            inv_a2(),
            e.kx(
                1.0 / (PI * a2),
                "0.3183098861837907 / (p_alpha * p_alpha)",
                A
            )
        ),
        "beckmann-ct" => format!("fb_d_beckmann({c}, {s2}, {}, {})", inv_a2(), ct_k()),
        "beckmann-pow" => format!(
            "fb_d_beckmann_pow({c}, {}, {})",
            e.kx(ex, "2.0 / (p_alpha * p_alpha) - 4.0", A),
            ct_k()
        ),
        "beckmann-power4" => power(4),
        "beckmann-power8" => power(8),
        "beckmann-power16" => power(16),
        _ => return None,
    })
}

fn fresnel_call(e: &Emit, id: &str, p: &Params, c: &str) -> String {
    match id {
        "none" => "1.0f".into(),
        "schlick" => format!("fb_f_schlick({c}, {})", e.kx(p.num("f0"), "p_f0", &["f0"])),
        "dielectric" => format!(
            "fb_f_dielectric({c}, {})",
            e.kx(p.num("eta"), "p_eta", &["eta"])
        ),
        _ => format!(
            "fb_f_conductor({c}, {}, {})",
            e.kx(p.num("eta"), "p_eta", &["eta"]),
            e.kx(p.num("k"), "p_k", &["k"])
        ),
    }
}

fn shadow_call(e: &Emit, id: &str, p: &Params, v: &str, l: &str, h: &str, vh: &str) -> String {
    match id {
        "v-cavity" => format!("fb_g_v_cavity({v}, {l}, {h}, {vh})"),
        "smith" => {
            let a = e.kx(p.num("alpha"), "p_alpha", &["alpha"]);
            format!("fb_g1_smith({v}, {a}) * fb_g1_smith({l}, {a})")
        }
        _ => {
            let a = e.kx(p.num("alpha"), "p_alpha", &["alpha"]);
            format!("fb_g1_smith_rational({v}, {a}) * fb_g1_smith_rational({l}, {a})")
        }
    }
}

const PAIR: &str = "    let p = fb_pair(wi, wo);\n";

fn body(e: &Emit, id: &str, kind: Kind, p: &Params) -> Result<String> {
    let missing = || Error::MissingParam {
        model: id.into(),
        param: "a GPU twin".into(),
    };
    Ok(match kind {
        Kind::Lobe => format!(
            "    return {};\n",
            lobe_call(e, id, p.num("n"), "c").ok_or_else(missing)?
        ),
        Kind::Distribution => format!(
            "    let cc = min(cos_h, 1.0);\n    let d = {};\n    return select(0.0, d, cos_h >= FB_COS_MIN);\n",
            dist_call(e, id, p.num("alpha"), "cc", "(1.0 - cc) * (1.0 + cc)")
                .ok_or_else(missing)?
        ),
        Kind::Fresnel => format!(
            "    let c = max(cos_vh, 0.0);\n    return {};\n",
            fresnel_call(e, id.trim_start_matches("fresnel-"), p, "c")
        ),
        Kind::Shadowing => {
            // The scalar model's rule: any non-positive cosine gives 0.
            let guard = if id == "v-cavity" {
                "(cos_v > 0.0) & (cos_l > 0.0) & (cos_h > 0.0) & (cos_vh > 0.0)"
            } else {
                "(cos_v > 0.0) & (cos_l > 0.0)"
            };
            format!(
                "    let g = {};\n    return select(0.0, g, {guard});\n",
                shadow_call(e, id, p, "cos_v", "cos_l", "cos_h", "cos_vh")
            )
        }
        Kind::Brdf => brdf_body(e, id, p)?,
    })
}

fn brdf_body(e: &Emit, id: &str, p: &Params) -> Result<String> {
    Ok(match id {
        "cook-torrance" => {
            let k = match p.choice("denominator") {
                "4" => 0.25,
                "seed-000" => 1.0,
                _ => 1.0 / PI,
            };
            let d = dist_call(e, p.choice("d"), p.num("alpha"), "p.h.z", "p.sin2_h").ok_or_else(
                || Error::MissingParam {
                    model: id.into(),
                    param: "d".into(),
                },
            )?;
            format!(
                "{PAIR}    let d = select(0.0, {d}, p.h.z >= FB_COS_MIN);\n    let g = {g};\n    let f = {f};\n    let v = f * d * g * {k} / (p.cos_i * p.cos_o);\n    return select(0.0, v, p.valid);\n",
                g = shadow_call(
                    e,
                    p.choice("g"),
                    p,
                    "p.cos_o",
                    "p.cos_i",
                    "p.h.z",
                    "p.cos_ih"
                ),
                f = fresnel_call(e, p.choice("f"), p, "p.cos_ih"),
                k = e.constant(k),
            )
        }
        "ward" | "ward-pow" | "ward-power16" => {
            let (nx, ny) = fastbrdf::brdf::ward::slope_params(p)?;
            let (ax, ay) = (p.num(nx), p.num(ny));
            let ps = &[nx, ny];
            let scale = e.kx(
                1.0 / (4.0 * PI * ax * ay),
                &format!("0.07957747154594767 / (p_{nx} * p_{ny})"),
                ps,
            );
            let ex = 2.0 / (ax * ax);
            let px = &[nx];
            match id {
                "ward" => format!(
                    "    return fb_brdf_ward(wi, wo, {}, {}, {scale});\n",
                    e.kx(1.0 / (ax * ax), &format!("1.0 / (p_{nx} * p_{nx})"), px),
                    e.kx(1.0 / (ay * ay), &format!("1.0 / (p_{ny} * p_{ny})"), &[ny])
                ),
                "ward-pow" => format!(
                    "    return fb_brdf_ward_pow(wi, wo, {}, {scale});\n",
                    e.kx(ex, &format!("2.0 / (p_{nx} * p_{nx})"), px)
                ),
                _ => format!(
                    "    return fb_brdf_ward_power16(wi, wo, {}, {scale});\n",
                    e.kx(ex / 16.0, &format!("0.125 / (p_{nx} * p_{nx})"), px)
                ),
            }
        }
        "lambert" => format!(
            "{PAIR}    return select(0.0, {}, p.valid);\n",
            e.kx(
                p.num("albedo") / PI,
                "p_albedo * 0.3183098861837907",
                &["albedo"]
            )
        ),
        "phong" | "blinn-phong" => {
            let normalized = p.choice("norm") == "energy";
            let n = p.num("n");
            let lobe = p.choice("lobe");
            let coef = if normalized {
                1.0 / (2.0 * PI * lobe_integral(lobe, n)?)
            } else {
                1.0
            };
            // pow's integral has a closed form, 1 / (n + 2); the others are numerical.
            let coef_k = || {
                if !normalized {
                    e.constant(coef)
                } else if lobe == "pow" {
                    e.kx(coef, "(p_n + 2.0) * 0.15915494309189535", &["n"])
                } else {
                    e.k(coef)
                }
            };
            let v = if id == "blinn-phong" {
                let l = lobe_call(e, lobe, n, "p.h.z").unwrap_or_default();
                if normalized {
                    format!("{} * {l} / (4.0 * p.cos_ih)", coef_k())
                } else {
                    l
                }
            } else {
                format!(
                    "{} * {}",
                    coef_k(),
                    lobe_call(e, lobe, n, "r_dot_wo").unwrap_or_default()
                )
            };
            let r = if id == "phong" {
                "    let r_dot_wo = -p.wi.x * p.wo.x - p.wi.y * p.wo.y + p.wi.z * p.wo.z;\n"
            } else {
                ""
            };
            format!("{PAIR}{r}    let v = {v};\n    return select(0.0, v, p.valid);\n")
        }
        _ => {
            return Err(Error::MissingParam {
                model: id.into(),
                param: "a GPU twin".into(),
            });
        }
    })
}
