//! naga's back ends: WGSL validated, then written as GLSL functions, HLSL or MSL.

use super::ENTRY;
use crate::context::GpuError;

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

pub(super) fn hlsl(wgsl: &str, what: &str) -> Result<String, GpuError> {
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

pub(super) fn msl(wgsl: &str, what: &str) -> Result<String, GpuError> {
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
