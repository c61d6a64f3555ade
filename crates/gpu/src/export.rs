//! Shader export: one model instance as a self-contained function, ready to paste.
//!
//! - `wgsl`: the library items the function needs (with their comments) and the function.
//! - `glsl` (4.50 core functions, no `#version`), `hlsl` (SM 5.1), `msl` (2.0): the same WGSL
//!   translated by naga's back ends. naga keeps no comments, so each export starts with our
//!   header: the model's formula, source, parameters, documented error bounds and the exact
//!   command that made it. The WGSL module is validated by naga before any translation.
//! - `brdf-explorer`: a `.brdf` file for Disney's BRDF Explorer: the GLSL functions and
//!   `vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)`, which moves L and V into the local
//!   frame (X, Y, N) and calls the model. Lobes are shaded as `blinn-phong` (lobe of n.h,
//!   norm = none) and distributions as `cook-torrance` with that D, as `fastbrdf render` does;
//!   shadowing and Fresnel terms are plotted as the factor itself (not a BRDF).
//!
//! Coefficients are literals computed in f64 from the parameters (`Form::Literals`), or, with
//! `Form::Runtime` (`--runtime-params`), computed in the shader in f32 from the parameters
//! passed as arguments (`Instance::runtime`). BRDF Explorer files always take the second form,
//! the parameters being its sliders. Its sliders are
//! linear (it has no other kind), so parameters spanning two decades or more (n, alpha, eta)
//! get a `log10_<name>` slider mapped in the shader; every grid passes through the export's
//! value exactly (`slider`).
//!
//! GLSL back end detail: naga writes GLSL only for an entry point, so the module gets a
//! one-line compute entry point that calls the function, and its text (with `#version` and
//! the `layout(local_size...)` line) is cut from the output. Tests parse every GLSL export
//! back with naga's GLSL front end.

use crate::context::GpuError;
use crate::spec::{Instance, shown};
use fastbrdf::model::{Kind, Metric, Zone};
use fastbrdf::params::ParamKind;
use std::fmt::Write as _;

/// An output language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lang {
    Wgsl,
    Glsl,
    Hlsl,
    Msl,
    BrdfExplorer,
}

impl Lang {
    /// Every language, in the order of `--lang`'s help.
    pub const ALL: [Lang; 5] = [
        Lang::Wgsl,
        Lang::Glsl,
        Lang::Hlsl,
        Lang::Msl,
        Lang::BrdfExplorer,
    ];

    /// The `--lang` name.
    pub fn name(self) -> &'static str {
        match self {
            Lang::Wgsl => "wgsl",
            Lang::Glsl => "glsl",
            Lang::Hlsl => "hlsl",
            Lang::Msl => "msl",
            Lang::BrdfExplorer => "brdf-explorer",
        }
    }

    /// The usual file extension.
    pub fn extension(self) -> &'static str {
        match self {
            Lang::Wgsl => "wgsl",
            Lang::Glsl => "glsl",
            Lang::Hlsl => "hlsl",
            Lang::Msl => "metal",
            Lang::BrdfExplorer => "brdf",
        }
    }

    /// Parses a `--lang` name.
    pub fn parse(s: &str) -> Option<Lang> {
        Lang::ALL.into_iter().find(|l| l.name() == s)
    }
}

/// The name `function` has in `lang`: naga's back ends append `_` to names that end in a
/// digit (`fb_cubic3` becomes `fb_cubic3_`), so that they cannot collide with its numbered
/// renamings.
pub fn exported_name(function: &str, lang: Lang) -> String {
    let digit = function.ends_with(|c: char| c.is_ascii_digit());
    if digit && !matches!(lang, Lang::Wgsl) {
        format!("{function}_")
    } else {
        function.to_string()
    }
}

/// The name of the compute entry point added for naga's GLSL writer.
const ENTRY: &str = "fb_export_entry";

/// How an export takes the model's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Form {
    /// Coefficients computed in f64 for the given parameters, written as literals.
    #[default]
    Literals,
    /// The model's numeric parameters as trailing arguments `p_<name>` (f32), coefficients
    /// computed in the shader (`--runtime-params`): parameters may vary per pixel.
    Runtime,
}

/// Exports model `id` with parameters `given` in `lang`, coefficients as literals.
pub fn export(id: &str, given: &[(&str, &str)], lang: Lang) -> Result<String, GpuError> {
    export_form(id, given, lang, Form::Literals)
}

/// Exports model `id` with parameters `given` in `lang`, in `form` (BRDF Explorer files always
/// take their parameters from sliders, so both forms are the same file there).
pub fn export_form(
    id: &str,
    given: &[(&str, &str)],
    lang: Lang,
    form: Form,
) -> Result<String, GpuError> {
    if let Some(text) = export_coloured(id, given, lang, form)? {
        return Ok(text);
    }
    let (inst, shaded) = match lang {
        Lang::BrdfExplorer => {
            let inst = Instance::new(id, given)?;
            let kind = inst.info.kind;
            // What BRDF Explorer evaluates: the BRDF fastbrdf render shades with, with its
            // coefficients as expressions of sliders where it has them.
            let given: Vec<(String, String)> = given
                .iter()
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .collect();
            let (target, p) = match kind {
                Kind::Lobe | Kind::Distribution => {
                    let (b, p) = fastbrdf::registry::shading_brdf(id, &given)?;
                    (b.to_string(), p)
                }
                _ => (id.to_string(), given),
            };
            let p: Vec<(&str, &str)> = p.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
            let shaded = Instance::runtime(&target, &p)?;
            (inst, Some(shaded))
        }
        _ => (
            match form {
                Form::Literals => Instance::new(id, given)?,
                Form::Runtime => Instance::runtime(id, given)?,
            },
            None,
        ),
    };
    let form = if lang == Lang::BrdfExplorer {
        Form::Literals
    } else {
        form
    };
    let header = header(&inst, id, given, lang, form, shaded.as_ref());
    let body = match lang {
        Lang::Wgsl => {
            let src = inst.module_source();
            validate(&src, id)?;
            src
        }
        Lang::Glsl => glsl_functions(&inst.module_source(), &call_of(&inst), id)?,
        Lang::Hlsl => hlsl(&inst.module_source(), id)?,
        Lang::Msl => msl(&inst.module_source(), id)?,
        Lang::BrdfExplorer => {
            let target = shaded
                .as_ref()
                .expect("BRDF Explorer exports have a shaded BRDF");
            return brdf_explorer(target, &header);
        }
    };
    Ok(format!("{header}\n{body}"))
}

/// The export of a coloured model (a parameter given as `R,G,B`: `fastbrdf::colour::channels`),
/// or `None` for a grey one. Three channel instances `fb_<id>_r`, `_g`, `_b` (each an ordinary
/// grey instance, coefficients as literals) and `fb_<id>_rgb` returning `vec3<f32>` (GLSL
/// `vec3`, HLSL `float3`, MSL `metal::float3`); BRDF Explorer's `BRDF` returns the three
/// channels of the BRDF `fastbrdf render` shades with, with no sliders (the parameters are
/// per channel; a slider per channel and parameter is not offered yet). The runtime form is
/// refused: its parameters are arguments, so one grey function called per channel with that
/// channel's values is the coloured form already.
fn export_coloured(
    id: &str,
    given: &[(&str, &str)],
    lang: Lang,
    form: Form,
) -> Result<Option<String>, GpuError> {
    let owned: Vec<(String, String)> = given
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    if !owned.iter().any(|(_, v)| v.contains(',')) {
        return Ok(None);
    }
    // What is exported: the model itself, or for BRDF Explorer the BRDF it shades with.
    let (target, params) = match lang {
        Lang::BrdfExplorer => {
            let e = fastbrdf::registry::find(id)?;
            match e.info.kind {
                Kind::Lobe | Kind::Distribution => {
                    let (b, p) = fastbrdf::registry::shading_brdf(id, &owned)?;
                    (b.to_string(), p)
                }
                _ => (e.info.id.to_string(), owned.clone()),
            }
        }
        _ => (id.to_string(), owned.clone()),
    };
    let Some(lists) = fastbrdf::colour::channels(&target, &params)? else {
        return Ok(None);
    };
    if form == Form::Runtime && lang != Lang::BrdfExplorer {
        return Err(GpuError::Input(format!(
            "--runtime-params with per-channel (R,G,B) parameters of {id}: the runtime form takes \
             the parameters as arguments, so call the grey export once per channel with that \
             channel's values; or drop --runtime-params for fb_<id>_rgb with literals"
        )));
    }
    let mut insts = vec![];
    for (c, list) in ["r", "g", "b"].iter().zip(&lists) {
        let l: Vec<(&str, &str)> = list.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        let mut inst = Instance::new(&target, &l)?;
        let named = format!("{}_{c}", inst.function);
        inst.wrapper = inst.wrapper.replacen(
            &format!("fn {}(", inst.function),
            &format!("fn {named}("),
            1,
        );
        inst.function = named;
        insts.push(inst);
    }
    let kind = insts[0].info.kind;
    let base = crate::spec::function_name(insts[0].info.id);
    let rgb = format!("{base}_rgb");
    let args = crate::spec::arguments(kind);
    let wrappers: String = insts
        .iter()
        .map(|i| i.wrapper.as_str())
        .collect::<Vec<_>>()
        .join("\n");
    let calls: Vec<String> = insts
        .iter()
        .map(|i| format!("{}({args})", i.function))
        .collect();
    let src = format!(
        "{}\n{wrappers}\n/// {target} in colour: the R, G, B channels (650, 550, 450 nm), each one grey instance above.\nfn {rgb}({}) -> vec3<f32> {{\n    return vec3<f32>({});\n}}\n",
        crate::library::closure_source(&wrappers),
        crate::spec::signature(kind),
        calls.join(", ")
    );
    let call = call_of(&insts[0]).replacen(&insts[0].function, &rgb, 1);
    let text = header_text(&insts[0], id, given, lang, Form::Literals, None);
    // The entry is the vector function.
    let mut text: String = text
        .lines()
        .map(|l| match l.strip_prefix("Entry: ") {
            Some(rest) => format!(
                "Entry: {}{}\n",
                exported_name(&rgb, lang),
                rest.trim_start_matches(&exported_name(&insts[0].function, lang))
                    .replace("returns f32.", "returns a 3-vector (R, G, B).")
            ),
            None => format!("{l}\n"),
        })
        .collect();
    let _ = writeln!(
        text,
        "Colour: per-channel parameters make three grey instances, {0}_r, {0}_g, {0}_b \
         (channels R, G, B at 650, 550, 450 nm; the parameters above are the R channel's), and \
         {1} with the same inputs, returning the three as a vector.",
        exported_name(&base, lang),
        exported_name(&rgb, lang)
    );
    for (c, i) in CHANNEL_NAMES.iter().zip(&insts) {
        let _ = writeln!(text, "  {c}: {}", shown(&i.params));
    }
    let mut header = String::new();
    comment_lines(
        &mut header,
        if lang == Lang::BrdfExplorer {
            "# "
        } else {
            "// "
        },
        &text,
    );
    let body = match lang {
        Lang::Wgsl => {
            validate(&src, id)?;
            src
        }
        Lang::Glsl => glsl_functions(&src, &call, id)?,
        Lang::Hlsl => hlsl(&src, id)?,
        Lang::Msl => msl(&src, id)?,
        Lang::BrdfExplorer => {
            let functions = glsl_functions(&src, &call, id)?;
            let f = exported_name(&rgb, Lang::Glsl);
            let body = match kind {
                Kind::Brdf => format!(
                    "    vec3 wi = vec3(dot(L, X), dot(L, Y), dot(L, N));\n    vec3 wo = vec3(dot(V, X), dot(V, Y), dot(V, N));\n    return {f}(wi, wo);"
                ),
                Kind::Fresnel => {
                    format!("    vec3 H = normalize(L + V);\n    return {f}(dot(V, H));")
                }
                Kind::Shadowing => format!(
                    "    vec3 H = normalize(L + V);\n    return {f}(dot(N, V), dot(N, L), dot(N, H), dot(V, H));"
                ),
                Kind::Env => format!("    return {f}(dot(N, V), 0.3);"),
                _ => unreachable!("lobes and distributions are shaded through a BRDF"),
            };
            return Ok(Some(format!(
                "analytic\n\n{header}\n::begin parameters\n::end parameters\n\n::begin shader\n\n{functions}\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{{\n{body}\n}}\n\n::end shader\n"
            )));
        }
    };
    Ok(Some(format!("{header}\n{body}")))
}

const CHANNEL_NAMES: [&str; 3] = ["R (650 nm)", "G (550 nm)", "B (450 nm)"];

/// A call of the instance's function on fixed arguments (for entry points).
pub fn call_of(inst: &Instance) -> String {
    let f = &inst.function;
    let extra: String = inst
        .sliders
        .iter()
        .map(|(_, v)| format!(", {}", crate::spec::lit(*v)))
        .collect();
    match inst.info.kind {
        Kind::Brdf => {
            format!("{f}(vec3<f32>(0.0, 0.6, 0.8), vec3<f32>(0.0, -0.6, 0.8){extra})")
        }
        Kind::Shadowing => format!("{f}(0.8, 0.8, 0.9, 0.9{extra})"),
        Kind::Env => format!("{f}(0.9, 0.3{extra})"),
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => format!("{f}(0.9{extra})"),
    }
}

fn comment_lines(out: &mut String, prefix: &str, text: &str) {
    for line in text.lines() {
        if line.is_empty() {
            out.push_str(prefix.trim_end());
        } else {
            out.push_str(prefix);
            out.push_str(line);
        }
        out.push('\n');
    }
}

fn metric_name(m: Metric) -> &'static str {
    match m {
        Metric::MaxAbs => "max abs error (relative to the peak)",
        Metric::MaxRel => "max rel error",
    }
}

fn zone_name(z: Zone) -> String {
    match z {
        Zone::All => "whole domain".into(),
        Zone::Epicentre => "epicentre (reference >= half its peak)".into(),
        Zone::Band { lo, hi } => format!("where {lo} < reference / peak < {hi}"),
    }
}

/// The comment header (without comment markers).
fn header_text(
    inst: &Instance,
    id: &str,
    given: &[(&str, &str)],
    lang: Lang,
    form: Form,
    shaded: Option<&Instance>,
) -> String {
    let info = inst.info;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "fastbrdf {} ({}): {id}",
        env!("CARGO_PKG_VERSION"),
        info.kind.name()
    );
    let args: String = given
        .iter()
        .map(|(k, v)| format!(" --param {k}={v}"))
        .collect();
    let flag = if form == Form::Runtime {
        " --runtime-params"
    } else {
        ""
    };
    let _ = writeln!(
        s,
        "Made by: fastbrdf shader --model {id}{args} --lang {}{flag}",
        lang.name()
    );
    let _ = writeln!(s);
    let _ = writeln!(s, "Formula: {}", info.formula);
    let _ = writeln!(s, "Source: {}", info.source);
    if !info.note.is_empty() {
        let _ = writeln!(s, "Note: {}", info.note);
    }
    let _ = writeln!(s, "Parameters (this export: {}):", shown(&inst.params));
    for p in info.params {
        let range = match p.kind {
            ParamKind::Number { .. } => format!("range {}", p.range_text()),
            ParamKind::Choice { options, .. } => format!("one of {}", options.names().join(", ")),
        };
        let _ = writeln!(
            s,
            "  {}: {} ({range}, default {})",
            p.name,
            p.doc,
            p.default_text()
        );
    }
    if info.bounds.is_empty() {
        let _ = writeln!(
            s,
            "Error bounds: none documented (an exact model or a reference)."
        );
    } else {
        let _ = writeln!(s, "Documented error bounds (measured by `fastbrdf check`):");
        for b in info.bounds {
            let _ = writeln!(
                s,
                "  {} vs {}: {} <= {} over {} in [{}, {}], {}",
                info.id,
                b.reference,
                metric_name(b.metric),
                b.bound,
                b.param.0,
                b.param.1,
                b.param.2,
                zone_name(b.zone)
            );
        }
    }
    let _ = writeln!(
        s,
        "Precision: f32 on the CPU within {:e} of f64 (mixed error); on GPUs see fastbrdf's \
         tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).",
        info.f32_bound
    );
    if form == Form::Runtime {
        let names: Vec<String> = inst.sliders.iter().map(|(n, _)| format!("p_{n}")).collect();
        let _ = writeln!(
            s,
            "Runtime parameters: {} (f32, after the inputs; the parameters above are only the \
             defaults of this export). Coefficients are computed in the shader in f32: closed \
             forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, \
             normalisation integrals), whose added f32 error fastbrdf measures per model \
             (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are \
             not checked in the shader.",
            if names.is_empty() {
                "none (the model has no numeric parameter)".to_string()
            } else {
                names.join(", ")
            }
        );
    } else if lang != Lang::BrdfExplorer {
        let _ = writeln!(
            s,
            "Coefficients are literals computed in f64 for these parameters; for other values \
             re-export, or use --runtime-params (parameters as arguments, coefficients computed \
             in the shader in f32)."
        );
    }
    let sig = match info.kind {
        Kind::Lobe => "(c) with c the cosine to the lobe's axis, clamped to [0, 1]",
        Kind::Distribution => "(cos_h) with cos_h = n.h",
        Kind::Shadowing => "(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided",
        Kind::Fresnel => "(cos_vh) with cos_vh = v.h",
        Kind::Env => {
            "(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); \
             specular albedo = f0 scale + bias"
        }
        Kind::Brdf => {
            "(wi, wo): directions in the local frame (normal +z, need not be unit), \
             value without the cosine factor"
        }
    };
    let extra: String = if form == Form::Runtime {
        inst.sliders
            .iter()
            .map(|(n, _)| format!(", then p_{n}"))
            .collect()
    } else {
        String::new()
    };
    let _ = writeln!(
        s,
        "Entry: {}{sig}{extra}; returns f32.",
        exported_name(&inst.function, lang)
    );
    if info.kind == Kind::Shadowing && lang != Lang::BrdfExplorer {
        let _ = writeln!(
            s,
            "V form: {}, the same arguments, returns V = G / (4 cos_v cos_l), the visibility \
             term engines multiply by D and F with no further denominator (Filament's \
             V_SmithGGXCorrelated, Unreal's Vis_*).",
            exported_name(&crate::spec::v_function_name(&inst.function), lang)
        );
    }
    if let Some(b) = shaded {
        if b.info.id != info.id {
            let _ = writeln!(
                s,
                "BRDF Explorer shades this {} through {} ({}).",
                info.kind.name(),
                b.info.id,
                shown(&b.params)
            );
        }
        // Every coefficient has a runtime form now, so the sliders are the numeric
        // parameters the instance uses: none only for models without one.
        if info.kind == Kind::Env {
            let _ = writeln!(
                s,
                "Slider: alpha, the roughness input (BRDF Explorer plots the term against the view angle at that alpha; the model has no numeric parameters)."
            );
        } else if b.sliders.is_empty() {
            let _ = writeln!(s, "No sliders: the model has no numeric parameters.");
        } else {
            let names: Vec<&str> = b.sliders.iter().map(|(n, _)| n.as_str()).collect();
            let _ = writeln!(
                s,
                "Sliders: {} (the coefficients are computed from them in the shader, in f32).",
                names.join(", ")
            );
            let _ = writeln!(
                s,
                "A parameter spanning two decades or more has the slider log10_<name> (BRDF \
                 Explorer's sliders are linear); every slider's grid passes through this \
                 export's value, and the shader clamps to the documented range."
            );
        }
    }
    s
}

fn header(
    inst: &Instance,
    id: &str,
    given: &[(&str, &str)],
    lang: Lang,
    form: Form,
    shaded: Option<&Instance>,
) -> String {
    let text = header_text(inst, id, given, lang, form, shaded);
    let mut out = String::new();
    let prefix = if lang == Lang::BrdfExplorer {
        "# "
    } else {
        "// "
    };
    comment_lines(&mut out, prefix, &text);
    out
}

/// Parses and validates WGSL with naga.
pub fn validate(
    src: &str,
    what: &str,
) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
    let module = naga::front::wgsl::parse_str(src).map_err(|e| GpuError::Shader {
        what: format!("WGSL of {what}"),
        message: e.emit_to_string(src),
    })?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| GpuError::Shader {
        what: format!("WGSL of {what}"),
        message: e.emit_to_string(src),
    })?;
    Ok((module, info))
}

fn backend_error(lang: &str, what: &str, e: impl std::fmt::Display) -> GpuError {
    GpuError::Shader {
        what: format!("{lang} export of {what}"),
        message: e.to_string(),
    }
}

/// GLSL 4.50 functions (no `#version`, no entry point) for a WGSL module; `call` is a WGSL
/// expression using the module, for the temporary entry point.
pub fn glsl_functions(wgsl: &str, call: &str, what: &str) -> Result<String, GpuError> {
    let src =
        format!("{wgsl}\n@compute @workgroup_size(1)\nfn {ENTRY}() {{\n    _ = {call};\n}}\n");
    let (module, info) = validate(&src, what)?;
    let mut out = String::new();
    let options = naga::back::glsl::Options {
        version: naga::back::glsl::Version::Desktop(450),
        writer_flags: naga::back::glsl::WriterFlags::empty(),
        ..Default::default()
    };
    let pipeline = naga::back::glsl::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: ENTRY.into(),
        multiview: None,
    };
    let mut w = naga::back::glsl::Writer::new(
        &mut out,
        &module,
        &info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .map_err(|e| backend_error("GLSL", what, e))?;
    w.write().map_err(|e| backend_error("GLSL", what, e))?;
    // Cut the version line, the workgroup layout and the entry point (`void main()` to the end).
    let end = out.rfind("void main()").unwrap_or(out.len());
    let kept: Vec<&str> = out[..end]
        .lines()
        .filter(|l| {
            !l.starts_with("#version")
                && !l.starts_with("#extension GL_ARB_compute_shader")
                && !l.starts_with("layout(local_size")
        })
        .collect();
    Ok(format!("{}\n", kept.join("\n").trim()))
}

fn hlsl(wgsl: &str, what: &str) -> Result<String, GpuError> {
    let (module, info) = validate(wgsl, what)?;
    let mut out = String::new();
    let options = naga::back::hlsl::Options {
        shader_model: naga::back::hlsl::ShaderModel::V5_1,
        ..Default::default()
    };
    let pipeline = naga::back::hlsl::PipelineOptions::default();
    let mut w = naga::back::hlsl::Writer::new(&mut out, &options, &pipeline);
    w.write(&module, &info, None)
        .map_err(|e| backend_error("HLSL", what, e))?;
    Ok(format!("{}\n", initialiser_lists(&out).trim()))
}

/// naga writes a constant array (`const FB_MS_LOSS = array<f32, 1024>(...)`) as
/// `static const float FB_MS_LOSS[1024] = Constructarray1024_float_(...);`, a call of a helper
/// function that returns the array. glslang's HLSL front end (the usual HLSL-to-SPIR-V path
/// besides DXC) rejects a function call in a static initialiser ("Recursion detected:
/// Constructarray12_float_", glslang issue 1216), so such declarations become initialiser
/// lists (`= { ... };`, valid HLSL for every compiler), and a helper no longer called is
/// removed (its `typedef` and definition). Calls inside function bodies are left as they are.
pub fn initialiser_lists(hlsl: &str) -> String {
    let mut lines: Vec<String> = hlsl
        .lines()
        .map(|line| {
            let Some(decl) = line.strip_prefix("static const ") else {
                return line.to_string();
            };
            let Some((lhs, rhs)) = decl.split_once(" = ") else {
                return line.to_string();
            };
            let call = rhs.strip_suffix(';').unwrap_or(rhs);
            let helper = call.split('(').next().unwrap_or("");
            if !helper.starts_with("Constructarray") || !lhs.ends_with(']') {
                return line.to_string();
            }
            match call[helper.len()..]
                .strip_prefix('(')
                .and_then(|a| a.strip_suffix(')'))
            {
                // Only a flat list of scalars (no nested array constructor).
                Some(args) if !args.contains("Construct") => {
                    format!("static const {lhs} = {{ {args} }};")
                }
                _ => line.to_string(),
            }
        })
        .collect();
    // Drop helpers nobody calls any more: `typedef T ret_H[N];`, then `ret_H H(...) {` to `}`.
    let helpers: Vec<String> = lines
        .iter()
        .filter_map(|l| l.strip_prefix("typedef "))
        .filter_map(|l| l.split_whitespace().nth(1))
        .filter_map(|l| l.split('[').next())
        .filter_map(|l| l.strip_prefix("ret_"))
        .filter(|h| h.starts_with("Constructarray"))
        .map(str::to_string)
        .collect();
    for h in helpers {
        let call = format!("{h}(");
        let definition = format!("ret_{h} {h}(");
        let used = lines
            .iter()
            .any(|l| l.contains(&call) && !l.starts_with(&definition));
        if used {
            continue;
        }
        let typedef = format!("ret_{h}[");
        lines.retain(|l| !(l.starts_with("typedef ") && l.contains(&typedef)));
        if let Some(start) = lines.iter().position(|l| l.starts_with(&definition)) {
            let end = lines[start..]
                .iter()
                .position(|l| l == "}")
                .map_or(lines.len(), |e| start + e + 1);
            // The blank line after the definition goes with it.
            let end = if lines.get(end).is_some_and(|l| l.is_empty()) {
                end + 1
            } else {
                end
            };
            lines.drain(start..end);
        }
    }
    let mut out = lines.join("\n");
    out.push('\n');
    out
}

fn msl(wgsl: &str, what: &str) -> Result<String, GpuError> {
    let (module, info) = validate(wgsl, what)?;
    let options = naga::back::msl::Options {
        lang_version: (2, 0),
        ..Default::default()
    };
    let pipeline = naga::back::msl::PipelineOptions::default();
    let (out, _) = naga::back::msl::write_string(&module, &info, &options, &pipeline)
        .map_err(|e| backend_error("MSL", what, e))?;
    Ok(format!("{}\n", out.trim()))
}

/// One BRDF Explorer slider: the `::begin parameters` line and the GLSL that turns the
/// slider's value into the model parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Slider {
    /// The uniform BRDF Explorer declares: the parameter's name, or `log10_<name>`.
    pub uniform: String,
    /// The slider's ends as written (f32 values, printed so that they parse back exactly).
    pub lo: f32,
    pub hi: f32,
    /// The default as written: already what BRDF Explorer's text field shows (6 significant
    /// digits), so the value it starts with is the value of one slider position exactly.
    pub default_text: String,
    /// The GLSL expression of the parameter (a name, or a clamped mapping of the uniform).
    pub param: String,
    /// Whether the slider is logarithmic.
    pub log: bool,
}

/// How far a lobe's argument (its cosine) may lie from the CPU's in a shader, in units of
/// 2^-24 (the f32 spacing just below 1): the parity rule of `tests/parity.rs` for Phong and
/// Blinn-Phong, whose lobe argument goes through three normalisations in f32. Near its peak a
/// lobe of exponent n moves by about n times this, so BRDF Explorer's `n` slider stops where
/// that stays within the lobe's documented error ([`lobe_n_max`]).
pub const LOBE_ARG_ULPS: f64 = 32.0;

/// The largest change of lobe `lobe`'s value at exponent `n`, relative to its peak, when its
/// cosine moves by [`LOBE_ARG_ULPS`] units of 2^-24 (on cosines 1 - 2^-24 .. 0, log-spaced,
/// away from its cuts and kinks, where a jump is a jump whatever the precision).
pub fn lobe_argument_error(lobe: &str, n: f64) -> Result<f64, GpuError> {
    let l = fastbrdf::registry::lobe::<f64>(lobe, n)?;
    let peak = l.eval(1.0).abs().max(f64::MIN_POSITIVE);
    let u = LOBE_ARG_ULPS * 2f64.powi(-24);
    let mut marks = l.kinks();
    marks.push(l.zero_below());
    let mut worst = 0.0f64;
    for i in 0..=1200 {
        let c = 1.0 - 2f64.powf(-24.0 + 24.0 * i as f64 / 1200.0);
        if marks.iter().any(|&m| m > 0.0 && (c - m).abs() <= 2.0 * u) {
            continue;
        }
        let v = l.eval(c);
        for d in [(c + u).min(1.0), (c - u).max(0.0)] {
            worst = worst.max((l.eval(d) - v).abs() / peak);
        }
    }
    Ok(worst)
}

/// The error lobe `lobe` documents at exponent `n`: the tightest of its max-abs bounds against
/// its reference on the whole lobe whose `n` range holds `n`; for a lobe that documents none
/// (the reference `pow` itself) the tightest such bound any lobe documents at `n`.
pub fn lobe_tolerance(lobe: &str, n: f64) -> Result<f64, GpuError> {
    let documented = |info: &fastbrdf::ModelInfo| {
        info.bounds
            .iter()
            .filter(|b| b.metric == Metric::MaxAbs && b.zone == Zone::All)
            .filter(|b| b.param.0 == "n" && b.param.1 <= n && n <= b.param.2)
            .map(|b| b.bound)
            .reduce(f64::min)
    };
    let info = &fastbrdf::registry::find(lobe)?.info;
    Ok(documented(info).unwrap_or_else(|| {
        fastbrdf::registry::all()
            .iter()
            .filter(|e| e.info.kind == Kind::Lobe)
            .filter_map(|e| documented(&e.info))
            .fold(f64::INFINITY, f64::min)
    }))
}

/// Where BRDF Explorer's `n` slider of lobe `lobe` stops, in `[min, max]`: the largest n
/// (two significant digits, rounded down) at which [`lobe_argument_error`] stays within
/// [`lobe_tolerance`], so that the f32 shader's lobe stays within the lobe's documented error
/// on the whole slider. Issue 27: `power4-tuned` at n = 1e5 was off by 0.82 of its peak in
/// BRDF Explorer.
pub fn lobe_n_max(lobe: &str, min: f64, max: f64) -> Result<f64, GpuError> {
    let holds =
        |n: f64| Ok::<_, GpuError>(lobe_argument_error(lobe, n)? <= lobe_tolerance(lobe, n)?);
    if holds(max)? {
        return Ok(max);
    }
    // The error grows with n: bisect on log n.
    let (mut lo, mut hi) = (min.ln(), max.ln());
    if !holds(min)? {
        return Ok(min);
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if holds(mid.exp())? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let n = lo.exp();
    let scale = 10f64.powf(n.log10().floor() - 1.0);
    Ok(((n / scale).floor() * scale).max(min))
}

/// The largest value BRDF Explorer's slider of parameter `name` reaches in the export of
/// `target` (the shaded instance) at `value`: the documented maximum, or for the exponent of a
/// lobe [`lobe_n_max`] (at least `value`, so that the export's own value stays reachable).
pub fn slider_max(target: &Instance, name: &str, max: f64, value: f64) -> Result<f64, GpuError> {
    let lobe = target
        .params
        .iter()
        .find(|(k, _)| k == "lobe")
        .map(|(_, v)| v.as_str());
    let min = match target
        .info
        .params
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.kind)
    {
        Some(ParamKind::Number { min, .. }) => min,
        _ => return Ok(max),
    };
    match lobe {
        Some(lobe) if name == "n" => Ok(lobe_n_max(lobe, min, max)?.max(value).min(max)),
        _ => Ok(max),
    }
}

/// Parameters spanning at least this ratio (two decades) get a logarithmic slider.
pub const LOG_SLIDER_RATIO: f64 = 100.0;

/// BRDF Explorer's slider positions (`FloatVarWidget`: an integer 0..=1000).
pub const SLIDER_STEPS: u32 = 1000;

/// What BRDF Explorer's text field shows for `x` (`QString::setNum(float)`: 6 significant
/// digits), as text.
pub fn g6(x: f64) -> String {
    let r: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    if r == 0.0 { "0".into() } else { format!("{r}") }
}

/// The value BRDF Explorer uses at slider position `x` of a slider `lo..hi`:
/// `FloatVarWidget::sliderToFloat` (f32: lo + (x / 1000) (hi - lo)), shown in the text field
/// with 6 significant digits and read back from it (`getValue` parses the text).
pub fn slider_value(lo: f32, hi: f32, x: u32) -> f32 {
    let raw = lo + (x as f32 / SLIDER_STEPS as f32) * (hi - lo);
    g6(raw as f64).parse().unwrap_or(raw)
}

/// The f32 nearest to `x` on its side: rounded down (`up` false) or up.
fn f32_toward(x: f64, up: bool) -> f32 {
    let f = x as f32;
    let (fx, bits) = (f as f64, f.to_bits());
    let step = |b: u32| f32::from_bits(b);
    match (up, fx > x, fx < x) {
        (false, true, _) => step(if f > 0.0 { bits - 1 } else { bits + 1 }),
        (true, _, true) => step(if f >= 0.0 { bits + 1 } else { bits - 1 }),
        _ => f,
    }
}

/// A shortest decimal that parses back to `x` (f32).
fn f32_text(x: f32) -> String {
    let t = format!("{x:?}");
    t.strip_suffix(".0").map(str::to_string).unwrap_or(t)
}

/// The slider of parameter `name` in `[min, max]` at this export's `value`.
///
/// BRDF Explorer's sliders are linear with 1001 positions and no other option (its parser
/// reads `float name min max default`; `FloatVarWidget` maps position x to
/// `min + x / 1000 (max - min)`). So a parameter spanning two decades or more gets the slider
/// `log10_<name>` and the shader computes the parameter from it. Every slider's grid is
/// anchored at the export's value: the grid steps by span / 998, with position k at the value,
/// so the ends lie half a step to a step and a half beyond the documented range (the shader
/// clamps to it), and the
/// default text is the value BRDF Explorer computes at position k, so that the default is a
/// slider position and, at that position, the parameter is exactly `value`.
pub fn slider(name: &str, min: f64, max: f64, value: f64) -> Slider {
    let log = min > 0.0 && max / min >= LOG_SLIDER_RATIO;
    let (t, tmin, tmax) = if log {
        (value.log10(), min.log10(), max.log10())
    } else {
        (value, min, max)
    };
    let k_of =
        |step: f64| -> u32 { (((t - tmin) / step + 0.5).ceil().max(0.0) as u32).min(SLIDER_STEPS) };
    // A linear parameter whose value is a position of the plain slider keeps it.
    if !log {
        let (lo, hi) = (min as f32, max as f32);
        let k = ((t - tmin) / (tmax - tmin) * SLIDER_STEPS as f64).round();
        if (0.0..=SLIDER_STEPS as f64).contains(&k)
            && lo as f64 == min
            && hi as f64 == max
            && slider_value(lo, hi, k as u32) as f64 == value
        {
            return Slider {
                uniform: name.into(),
                lo,
                hi,
                default_text: g6(value),
                param: name.into(),
                log,
            };
        }
    }
    // 998 steps span the range: with position k half a step or more above the low end,
    // both ends of the slider lie half a step or more beyond the range, so that the clamp, not
    // the rounding of the mapping, decides that the ends reach min and max.
    let step = (tmax - tmin) / (SLIDER_STEPS - 2) as f64;
    let k = k_of(step);
    let lo = f32_toward(t - k as f64 * step, false);
    let hi = f32_toward(lo as f64 + SLIDER_STEPS as f64 * step, true);
    let anchor = slider_value(lo, hi, k);
    let s0 = g6(anchor as f64);
    // GLSL float literals (`{:?}` keeps the `.0`), parsing to the same f32.
    let v = format!("{:?}", value as f32);
    let (a, b) = (format!("{:?}", min as f32), format!("{:?}", max as f32));
    // `u - s0`, written `u + 0.86` for s0 = -0.86: exactly 0 at the default either way.
    let minus_s0 = match s0.strip_prefix('-') {
        Some(pos) => format!("+ {pos}"),
        None => format!("- {s0}"),
    };
    let uniform = if log {
        format!("log10_{name}")
    } else {
        format!("{name}_slider")
    };
    let param = if log {
        format!("clamp({v} * exp2(({uniform} {minus_s0}) * 3.321928), {a}, {b})")
    } else {
        format!("clamp({v} + ({uniform} {minus_s0}), {a}, {b})")
    };
    Slider {
        uniform,
        lo,
        hi,
        default_text: s0,
        param,
        log,
    }
}

impl Slider {
    /// Its line in BRDF Explorer's parameter block: `float <uniform> <lo> <hi> <default>`.
    fn declaration(&self) -> String {
        format!(
            "float {} {} {} {}",
            self.uniform,
            f32_text(self.lo),
            f32_text(self.hi),
            self.default_text
        )
    }
}

/// The `.brdf` file of `target` (the BRDF, Fresnel or shadowing instance BRDF Explorer
/// evaluates): `header`, a slider per parameter its coefficients are computed from (see
/// `slider`), the GLSL functions and `BRDF(L, V, N, X, Y)`.
fn brdf_explorer(target: &Instance, header: &str) -> Result<String, GpuError> {
    let f = &exported_name(&target.function, Lang::Glsl);
    let mut sliders = String::new();
    let mut params = String::new();
    let mut extra = String::new();
    let mut capped = String::new();
    for (name, value) in &target.sliders {
        let spec = target
            .info
            .params
            .iter()
            .find(|p| p.name == name)
            .expect("sliders are parameters");
        if let ParamKind::Number { min, max, .. } = spec.kind {
            let top = slider_max(target, name, max, *value)?;
            if top < max {
                let _ = writeln!(
                    capped,
                    "# The {name} slider stops at {top} (the model allows {max}): beyond it a few \
                     f32 roundings of the lobe's cosine move the lobe by more than its documented \
                     error (fastbrdf_gpu::export::lobe_n_max)."
                );
            }
            let s = slider(name, min, top, *value);
            let _ = writeln!(sliders, "{}", s.declaration());
            if s.param == *name {
                let _ = write!(extra, ", {name}");
            } else {
                let _ = writeln!(params, "    float p_{name} = {};", s.param);
                let _ = write!(extra, ", p_{name}");
            }
        }
    }
    // A split-sum term's roughness is an input, not a parameter: one more slider for it.
    if target.info.kind == Kind::Env {
        let (lo, hi) = fastbrdf::params::ALPHA.range();
        let s = slider("alpha", lo, hi, 0.3);
        let _ = writeln!(sliders, "{}", s.declaration());
        let _ = writeln!(params, "    float p_alpha = {};", s.param);
    }
    let body = match target.info.kind {
        Kind::Brdf => format!(
            "{params}    vec3 wi = vec3(dot(L, X), dot(L, Y), dot(L, N));\n    vec3 wo = vec3(dot(V, X), dot(V, Y), dot(V, N));\n    return vec3({f}(wi, wo{extra}));"
        ),
        Kind::Fresnel => {
            format!(
                "{params}    vec3 H = normalize(L + V);\n    return vec3({f}(dot(V, H){extra}));"
            )
        }
        Kind::Shadowing => format!(
            "{params}    vec3 H = normalize(L + V);\n    return vec3({f}(dot(N, V), dot(N, L), dot(N, H), dot(V, H){extra}));"
        ),
        // A split-sum term is a function of the view and the roughness: plotted against the
        // view angle at the `alpha` slider's value.
        Kind::Env => format!("{params}    return vec3({f}(dot(N, V), p_alpha{extra}));"),
        _ => unreachable!("lobes and distributions are shaded through a BRDF"),
    };
    let functions = glsl_functions(&target.module_source(), &call_of(target), target.info.id)?;
    let mut s = String::new();
    s.push_str("analytic\n\n");
    s.push_str(header);
    s.push_str(&capped);
    let _ = write!(
        s,
        "\n::begin parameters\n{sliders}::end parameters\n\n::begin shader\n\n{functions}"
    );
    let _ = write!(
        s,
        "\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{{\n{body}\n}}\n\n::end shader\n"
    );
    Ok(s)
}
