//! Model instances on the GPU: a model spec (`fastbrdf::ModelSpec`: a model and its parameters,
//! validated once where they arrived) becomes one WGSL function,
//! `fb_<id>` (dashes as underscores), that calls the library's core functions with the
//! instance's coefficients, placed as `Emit` says: f32 literals, the storage array `fb_k`, or
//! expressions of the parameters.
//!
//! The body comes from the spec's plan (`ModelSpec::plan`, built once): each family writes the
//! call of its WGSL twin with the plan's coefficients (computed once, in f64, the same numbers
//! the CPU's scalar models and batch kernels read), or, in the runtime form, with expressions
//! of the parameters. This module adds only the kind's domain rules and the signature; it
//! matches no model id. The CPU-GPU parity tests (`tests/parity.rs`) compare every model in
//! every form through these instances.
//!
//! Signatures of the generated function, by kind:
//! - lobe: `fn fb_<id>(c: f32) -> f32`
//! - distribution: `fn fb_<id>(cos_h: f32) -> f32`
//! - shadowing: `fn fb_<id>(cos_v: f32, cos_l: f32, cos_h: f32, cos_vh: f32) -> f32` (two-sided
//!   `G`), and beside it `fn fb_<id>_v(...)`, the same arguments, the engines' `V = G / (4 cos_v
//!   cos_l)` ([`v_form`])
//! - Fresnel: `fn fb_<id>(cos_vh: f32) -> f32`
//! - BRDF: `fn fb_<id>(wi: vec3<f32>, wo: vec3<f32>) -> f32` (local frame, normal +z, no cosine)

use crate::library;
use fastbrdf::model::{Kind, ModelInfo};
use fastbrdf::params::{Params, Value};
use fastbrdf::plan::{BrdfForm, DistForm, EnvForm, FresnelForm, LobeForm, Plan, ShadowForm};
use fastbrdf::{ModelSpec, Result};

pub use fastbrdf::wgsl::{Emit, lit};

/// One model with fixed parameters, as WGSL.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The registry entry.
    pub info: &'static ModelInfo,
    /// The spec it was built from.
    pub spec: ModelSpec,
    /// Every resolved parameter (given or default), as text (for display).
    pub params: Vec<(String, String)>,
    /// The generated function's name, `fb_<id>`.
    pub function: String,
    /// The generated function (WGSL, with a doc comment).
    pub wrapper: String,
    /// The coefficients the function reads from `fb_k` (empty with literals).
    pub coefs: Vec<f32>,
    /// Runtime-parameter instances: the parameters passed as arguments `p_<name>` (in
    /// registry order), with this instance's values.
    pub sliders: Vec<(String, f64)>,
}

impl Instance {
    /// The instance of `spec` (a grey model: one plan) with its coefficients as literals (for
    /// exported code).
    pub fn new(spec: &ModelSpec) -> Result<Self> {
        Self::with(spec, Emit::literals())
    }

    /// As `new`, with the coefficients in the storage array
    /// `fb_k: array<f32>` (for the compute and render paths).
    pub fn with_storage(spec: &ModelSpec) -> Result<Self> {
        Self::with(spec, Emit::storage())
    }

    /// Builds the instance with coefficients placed as `emit` says: the spec's plan writes
    /// the body (each family its own WGSL call; no model id is matched here). A coloured spec
    /// is an error naming its `R,G,B` parameters (export its `channel_specs` one by one).
    pub fn with(spec: &ModelSpec, emit: Emit) -> Result<Self> {
        let (plan, p) = (spec.plan()?, spec.params()?);
        let info = spec.info();
        let function = function_name(info.id);
        let body = body(&emit, plan);
        let mut signature = info.kind.wgsl_signature().to_string();
        // Runtime parameters: the ones the expressions use become arguments, in registry order.
        let used = emit.used();
        let sliders: Vec<(String, f64)> = info
            .params
            .iter()
            .filter(|s| used.contains(s.name))
            .map(|s| (s.name.to_string(), p.num(s.name)))
            .collect();
        for (name, _) in &sliders {
            signature.push_str(&format!(", p_{name}: f32"));
        }
        let params = resolved_text(p);
        let shown = if emit.is_runtime() {
            let names: Vec<String> = sliders.iter().map(|(n, _)| format!("p_{n}")).collect();
            let fixed: Vec<(String, String)> = params
                .iter()
                .filter(|(k, _)| !sliders.iter().any(|(n, _)| n == k))
                .cloned()
                .collect();
            format!(
                "runtime parameters {}; fixed: {}",
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                },
                shown_pairs(&fixed)
            )
        } else {
            shown_pairs(&params)
        };
        let mut wrapper = format!(
            "/// {id}: {formula}\n/// Source: {source}. Instance: {shown}.\nfn {function}({signature}) -> f32 {{\n{body}}}\n",
            id = info.id,
            formula = info.formula,
            source = info.source,
        );
        if info.kind == Kind::Shadowing {
            wrapper.push_str(&v_form(&function, &signature));
        }
        Ok(Self {
            info,
            spec: spec.clone(),
            params,
            function,
            wrapper,
            coefs: emit.into_values(),
            sliders,
        })
    }

    /// The instance with runtime parameters: coefficients computed in the shader (in f32)
    /// from the model's numeric parameters, which become arguments `p_<name>` after the
    /// model's inputs. Every model has this form; a call of a `fb_rt_*` function that the
    /// library lacks (a new lobe without its normalisation integral) is an error, so no test
    /// skips a model silently.
    pub fn runtime(spec: &ModelSpec) -> Result<Self> {
        let inst = Self::with(spec, Emit::runtime())?;
        let missing: Vec<&str> = inst
            .wrapper
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .filter(|w| w.starts_with("fb_rt_"))
            .filter(|w| !library::defines(w))
            .collect();
        if let Some(w) = missing.first() {
            return Err(fastbrdf::Error::MissingParam {
                model: spec.id().into(),
                param: format!("the WGSL function {w} (runtime form)"),
            });
        }
        Ok(inst)
    }

    /// A runtime-parameter instance behind an entry with the model's plain signature
    /// (`fb_runtime_entry`), its parameters read from the storage array `fb_k`: as in a
    /// shader whose parameters vary per pixel (uniforms, textures), the compiler cannot fold
    /// them into the in-shader coefficient computations. For the compute path and the tests.
    pub fn runtime_entry(mut self) -> Self {
        let args: String = (0..self.sliders.len())
            .map(|i| format!(", fb_k[{i}]"))
            .collect();
        let kind = self.info.kind;
        self.wrapper = format!(
            "{}\nfn fb_runtime_entry({}) -> f32 {{\n    return {}({}{args});\n}}\n",
            self.wrapper,
            signature(kind),
            self.function,
            arguments(kind)
        );
        self.function = "fb_runtime_entry".into();
        self.coefs = self.sliders.iter().map(|(_, v)| *v as f32).collect();
        self
    }

    /// A self-contained WGSL module: the library items the function needs, then the function.
    pub fn module_source(&self) -> String {
        let mut s = library::closure_source(&self.wrapper);
        s.push('\n');
        s.push_str(&self.wrapper);
        s
    }
}

/// The name of a shadowing instance's V-form companion of `function` (see [`v_form`]).
pub fn v_function_name(function: &str) -> String {
    format!("{function}_v")
}

/// The V form of a shadowing instance `function` (the engines' convention: Filament's
/// `V_SmithGGXCorrelated`, Unreal's `Vis_*`): `V = G / (4 cos_v cos_l)`, to be multiplied by
/// `D` and `F` with no further denominator. fastbrdf's terms return `G` so that they compose
/// with `cook-torrance`'s denominator; this is the conversion, emitted beside `G` in every
/// export. The denominator is kept at or above the smallest normal f32: with `G <= 1` the
/// result stays finite (at most 8.5e37) for every input, and is 0 wherever `G` is.
fn v_form(function: &str, signature: &str) -> String {
    let args = signature
        .split(", ")
        .map(|a| a.split(':').next().unwrap_or(a))
        .collect::<Vec<_>>()
        .join(", ");
    let v = v_function_name(function);
    format!(
        "\n/// V form of {function}: V = G / (4 cos_v cos_l), as engines write the visibility term\n/// (multiply by D and F only; 0 wherever G is 0).\nfn {v}({signature}) -> f32 {{\n    let g = {function}({args});\n    return select(0.0, g / max(4.0 * cos_v * cos_l, 1.1754943508222875e-38), g > 0.0);\n}}\n"
    )
}

/// The inputs of a kind's `fb_<id>`, as WGSL parameters (`Kind::wgsl_signature`).
pub fn signature(kind: Kind) -> &'static str {
    kind.wgsl_signature()
}

/// The names in `signature(kind)`, as a call's argument list.
pub fn arguments(kind: Kind) -> String {
    signature(kind)
        .split(", ")
        .map(|a| a.split(':').next().unwrap_or(a))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The resolved parameters (given or default) of `spec`, `a = 1, b = x` (a value that differs
/// between colour channels as `r,g,b`), or `no parameters`.
pub fn shown(spec: &ModelSpec) -> String {
    let channels: Vec<Vec<(String, String)>> = spec.channels().iter().map(resolved_text).collect();
    let pairs: Vec<(String, String)> = channels[0]
        .iter()
        .enumerate()
        .map(|(i, (k, v))| {
            if channels.iter().all(|c| c[i].1 == *v) {
                (k.clone(), v.clone())
            } else {
                let rgb: Vec<&str> = channels.iter().map(|c| c[i].1.as_str()).collect();
                (k.clone(), rgb.join(","))
            }
        })
        .collect();
    shown_pairs(&pairs)
}

/// Resolved parameters as `(name, text)` pairs, in `Params`' order.
fn resolved_text(p: &Params) -> Vec<(String, String)> {
    p.iter()
        .map(|(k, v)| {
            let v = match v {
                Value::Num(x) => format!("{x}"),
                Value::Text(t) => t.clone(),
            };
            (k.to_string(), v)
        })
        .collect()
}

/// `a = 1, b = x`, or `no parameters`.
fn shown_pairs(params: &[(String, String)]) -> String {
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

/// The body of `fb_<id>` for a plan: the kind's domain rules around the family's call.
fn body(e: &Emit, plan: &Plan) -> String {
    match plan {
        Plan::Lobe(l) => format!("    return {};\n", l.wgsl("c", e)),
        Plan::Distribution(d) => format!(
            "    let cc = min(cos_h, 1.0);\n    let d = {};\n    return select(0.0, d, cos_h >= FB_COS_MIN);\n",
            d.wgsl("cc", "(1.0 - cc) * (1.0 + cc)", e)
        ),
        Plan::Fresnel(f) => format!(
            "    let c = max(cos_vh, 0.0);\n    return {};\n",
            f.wgsl("c", e)
        ),
        Plan::Shadowing(g) => {
            // The scalar model's rule: any non-positive cosine gives 0.
            let guard = if g.needs_half_vector() {
                "(cos_v > 0.0) & (cos_l > 0.0) & (cos_h > 0.0) & (cos_vh > 0.0)"
            } else {
                "(cos_v > 0.0) & (cos_l > 0.0)"
            };
            format!(
                "    let g = {};\n    return select(0.0, g, {guard});\n",
                g.wgsl("cos_v", "cos_l", "cos_h", "cos_vh", e)
            )
        }
        Plan::Brdf(b) => b.wgsl_body(e),
        Plan::Env(x) => {
            // The scalar model's rule (plan::env_args): cos_v into [0, 1], alpha into its
            // documented range, NaN to the lower end (WGSL's max/min may pass NaN through).
            let (lo, hi) = fastbrdf::params::ALPHA.range();
            format!(
                "    let v = select(0.0, min(cos_v, 1.0), cos_v > 0.0);\n    let a = select({lo}, min(alpha, {hi}), alpha > {lo});\n    return {};\n",
                x.wgsl("v", "a", e),
                lo = fastbrdf::wgsl::lit(lo),
                hi = fastbrdf::wgsl::lit(hi),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An instance is one grey model: a coloured spec is an error naming its `R,G,B`
    /// parameters, and each of its channels is an instance; `shown` lists resolved values.
    #[test]
    fn instances_are_built_from_grey_specs() {
        let s =
            ModelSpec::parse("cook-torrance", &[("f0", "0.9,0.6,0.5"), ("alpha", "0.2")]).unwrap();
        let e = Instance::new(&s).unwrap_err().to_string();
        assert!(e.contains("f0") && e.contains("R,G,B"), "{e}");
        let all = shown(&s);
        assert!(
            all.contains("f0 = 0.9,0.6,0.5") && all.contains("alpha = 0.2"),
            "{all}"
        );
        let g = Instance::new(&s.channel_specs()[1]).unwrap();
        assert!(shown(&g.spec).contains("f0 = 0.6"), "{}", shown(&g.spec));
        assert!(g.wrapper.contains(&shown(&g.spec)), "{}", g.wrapper);
        assert_eq!(g.spec, s.channel_specs()[1]);
        assert_eq!(
            shown(&ModelSpec::parse("lambert", &[]).unwrap()),
            "albedo = 1"
        );
    }
}
