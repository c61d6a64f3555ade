//! The comment header of an export: the model, the command that made it, its formula,
//! parameters, documented error bounds and entry point.

use super::{Form, Lang, exported_name};
use crate::spec::{Instance, shown};
use fastbrdf::ModelSpec;
use fastbrdf::model::{Kind, Metric, Zone};
use fastbrdf::params::ParamKind;
use std::fmt::Write as _;

pub(super) fn comment_lines(out: &mut String, prefix: &str, text: &str) {
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

/// The comment header (without comment markers) of the export of `spec` (as given: the
/// command that made it repeats the given values) through `inst`.
pub(super) fn header_text(
    inst: &Instance,
    spec: &ModelSpec,
    lang: Lang,
    form: Form,
    shaded: Option<&Instance>,
) -> String {
    let info = inst.info;
    let id = spec.id();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "fastbrdf {} ({}): {id}",
        env!("CARGO_PKG_VERSION"),
        info.kind.name()
    );
    let args: String = spec
        .pairs()
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
    let _ = writeln!(s, "Parameters (this export: {}):", shown(&inst.spec));
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
                shown(&b.spec)
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

pub(super) fn header(
    inst: &Instance,
    spec: &ModelSpec,
    lang: Lang,
    form: Form,
    shaded: Option<&Instance>,
) -> String {
    let text = header_text(inst, spec, lang, form, shaded);
    let mut out = String::new();
    let prefix = if lang == Lang::BrdfExplorer {
        "# "
    } else {
        "// "
    };
    comment_lines(&mut out, prefix, &text);
    out
}
