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
//! Coefficients are literals, computed in f64 from the parameters; a shader compiler may fold
//! literals into reassociated expressions (Mesa does, see `spec::Emit`), so a header line says
//! that passing them as uniforms keeps more precision. BRDF Explorer files instead compute
//! the coefficients in f32 from sliders (`Instance::symbolic`) where every coefficient has an
//! expression in the parameters, and keep literals (no sliders) where not.
//!
//! GLSL back end detail: naga writes GLSL only for an entry point, so the module gets a
//! one-line compute entry point that calls the function, and its text (with `#version` and
//! the `layout(local_size...)` line) is cut from the output. Tests parse every GLSL export
//! back with naga's GLSL front end.

use crate::context::GpuError;
use crate::spec::{Emit, Instance, shown};
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

/// Exports model `id` with parameters `given` in `lang`.
pub fn export(id: &str, given: &[(&str, &str)], lang: Lang) -> Result<String, GpuError> {
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
                Kind::Lobe | Kind::Distribution => fastbrdf_render::scene::shading_brdf(id, &given)
                    .map_err(|e| GpuError::Input(e.to_string()))?,
                _ => (id.to_string(), given),
            };
            let p: Vec<(&str, &str)> = p.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
            let shaded = match Instance::symbolic(&target, &p)? {
                Some(sym) => sym,
                None => Instance::with(&target, &p, Emit::literals())?,
            };
            (inst, Some(shaded))
        }
        _ => (Instance::new(id, given)?, None),
    };
    let header = header(&inst, id, given, lang, shaded.as_ref());
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
        _ => format!("{f}(0.9{extra})"),
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
    let _ = writeln!(
        s,
        "Made by: fastbrdf shader --model {id}{args} --lang {}",
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
            ParamKind::Choice { options, .. } => format!("one of {}", options.join(", ")),
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
    if lang != Lang::BrdfExplorer {
        let _ = writeln!(
            s,
            "Coefficients are literals computed in f64 for these parameters; for other values \
             re-export, or pass them as uniforms (a compiler cannot fold those into \
             reassociated, less accurate expressions)."
        );
    }
    let sig = match info.kind {
        Kind::Lobe => "(c) with c the cosine to the lobe's axis, clamped to [0, 1]",
        Kind::Distribution => "(cos_h) with cos_h = n.h",
        Kind::Shadowing => "(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided",
        Kind::Fresnel => "(cos_vh) with cos_vh = v.h",
        Kind::Brdf => {
            "(wi, wo): directions in the local frame (normal +z, need not be unit), \
             value without the cosine factor"
        }
    };
    let _ = writeln!(
        s,
        "Entry: {}{sig}; returns f32.",
        exported_name(&inst.function, lang)
    );
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
        let numeric = b
            .info
            .params
            .iter()
            .any(|p| matches!(p.kind, ParamKind::Number { .. }));
        if b.sliders.is_empty() && !numeric {
            let _ = writeln!(s, "No sliders: the model has no numeric parameters.");
        } else if b.sliders.is_empty() {
            let _ = writeln!(
                s,
                "No sliders: this model's coefficients need f64 on the CPU; re-export for other values."
            );
        } else {
            let names: Vec<&str> = b.sliders.iter().map(|(n, _)| n.as_str()).collect();
            let _ = writeln!(
                s,
                "Sliders: {} (the coefficients are computed from them in the shader, in f32).",
                names.join(", ")
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
    shaded: Option<&Instance>,
) -> String {
    let text = header_text(inst, id, given, lang, shaded);
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
    Ok(format!("{}\n", out.trim()))
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

/// The `.brdf` file of `target` (the BRDF, Fresnel or shadowing instance BRDF Explorer
/// evaluates): `header`, a slider per parameter its coefficients are computed from, the GLSL
/// functions and `BRDF(L, V, N, X, Y)`.
fn brdf_explorer(target: &Instance, header: &str) -> Result<String, GpuError> {
    let f = &exported_name(&target.function, Lang::Glsl);
    let extra: String = target
        .sliders
        .iter()
        .map(|(n, _)| format!(", {n}"))
        .collect();
    let body = match target.info.kind {
        Kind::Brdf => format!(
            "    vec3 wi = vec3(dot(L, X), dot(L, Y), dot(L, N));\n    vec3 wo = vec3(dot(V, X), dot(V, Y), dot(V, N));\n    return vec3({f}(wi, wo{extra}));"
        ),
        Kind::Fresnel => {
            format!("    vec3 H = normalize(L + V);\n    return vec3({f}(dot(V, H){extra}));")
        }
        Kind::Shadowing => format!(
            "    vec3 H = normalize(L + V);\n    return vec3({f}(dot(N, V), dot(N, L), dot(N, H), dot(V, H){extra}));"
        ),
        _ => unreachable!("lobes and distributions are shaded through a BRDF"),
    };
    // One slider per numeric parameter the coefficients are computed from, over its
    // documented range, starting at this export's value.
    let mut sliders = String::new();
    for (name, value) in &target.sliders {
        let spec = target
            .info
            .params
            .iter()
            .find(|p| p.name == name)
            .expect("sliders are parameters");
        if let ParamKind::Number { min, max, .. } = spec.kind {
            let _ = writeln!(sliders, "float {name} {min} {max} {value}");
        }
    }
    let functions = glsl_functions(&target.module_source(), &call_of(target), target.info.id)?;
    let mut s = String::new();
    s.push_str("analytic\n\n");
    s.push_str(header);
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
