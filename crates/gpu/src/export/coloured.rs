//! Coloured exports: a model with a parameter given per colour channel.

use super::backends::{glsl_functions, hlsl, msl, validate};
use super::header::{comment_lines, header_text};
use super::{Form, Lang, call_of, exported_name};
use crate::context::GpuError;
use crate::spec::{Instance, shown};
use fastbrdf::ModelSpec;
use fastbrdf::model::Kind;
use std::fmt::Write as _;

/// The export of a coloured model (a parameter given as `R,G,B`): `target`, the model `spec` or
/// for BRDF Explorer the BRDF it shades with, split by `ModelSpec::channel_specs`. Three channel instances `fb_<id>_r`, `_g`, `_b` (each an ordinary
/// grey instance, coefficients as literals) and `fb_<id>_rgb` returning `vec3<f32>` (GLSL
/// `vec3`, HLSL `float3`, MSL `metal::float3`); BRDF Explorer's `BRDF` returns the three
/// channels of the BRDF `fastbrdf render` shades with, with no sliders (the parameters are
/// per channel; a slider per channel and parameter is not offered yet). The runtime form is
/// refused: its parameters are arguments, so one grey function called per channel with that
/// channel's values is the coloured form already.
pub(super) fn export_coloured(
    spec: &ModelSpec,
    target: &ModelSpec,
    lang: Lang,
    form: Form,
) -> Result<String, GpuError> {
    let id = spec.id();
    if form == Form::Runtime && lang != Lang::BrdfExplorer {
        return Err(GpuError::Input(format!(
            "--runtime-params with per-channel (R,G,B) parameters of {id}: the runtime form takes \
             the parameters as arguments, so call the grey export once per channel with that \
             channel's values; or drop --runtime-params for fb_<id>_rgb with literals"
        )));
    }
    let mut insts = vec![];
    for (c, channel) in ["r", "g", "b"].iter().zip(target.channel_specs()) {
        let mut inst = Instance::new(&channel)?;
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
        calls.join(", "),
        target = target.id(),
    );
    let call = call_of(&insts[0]).replacen(&insts[0].function, &rgb, 1);
    let text = header_text(&insts[0], spec, lang, Form::Literals, None);
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
        let _ = writeln!(text, "  {c}: {}", shown(&i.spec));
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
            return Ok(format!(
                "analytic\n\n{header}\n::begin parameters\n::end parameters\n\n::begin shader\n\n{functions}\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{{\n{body}\n}}\n\n::end shader\n"
            ));
        }
    };
    Ok(format!("{header}\n{body}"))
}

const CHANNEL_NAMES: [&str; 3] = ["R (650 nm)", "G (550 nm)", "B (450 nm)"];
