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

mod backends;
mod coloured;
mod explorer;
mod header;

pub use backends::{glsl_functions, initialiser_lists, validate};
pub use explorer::{
    LOBE_ARG_ULPS, LOG_SLIDER_RATIO, SLIDER_STEPS, Slider, g6, lobe_argument_error, lobe_n_max,
    lobe_tolerance, slider, slider_max, slider_value,
};

use crate::context::GpuError;
use crate::spec::Instance;
use backends::{hlsl, msl};
use fastbrdf::ModelSpec;
use fastbrdf::model::Kind;

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

/// Exports the model of `spec` in `lang`, coefficients as literals.
pub fn export(spec: &ModelSpec, lang: Lang) -> Result<String, GpuError> {
    export_form(spec, lang, Form::Literals)
}

/// Exports the model of `spec` in `lang`, in `form` (BRDF Explorer files always take their
/// parameters from sliders, so both forms are the same file there).
pub fn export_form(spec: &ModelSpec, lang: Lang, form: Form) -> Result<String, GpuError> {
    // What is exported: the model itself, or for BRDF Explorer the BRDF fastbrdf render
    // shades with (`ModelSpec::shaded`: lobes and distributions; other kinds as they are).
    let target = match (lang, spec.kind()) {
        (Lang::BrdfExplorer, Kind::Lobe | Kind::Distribution) => spec.shaded()?,
        _ => spec.clone(),
    };
    if target.is_coloured() {
        return coloured::export_coloured(spec, &target, lang, form);
    }
    let id = spec.id();
    let (inst, shaded) = match lang {
        // BRDF Explorer evaluates the shaded BRDF, with its coefficients as expressions of
        // sliders where it has them.
        Lang::BrdfExplorer => (Instance::new(spec)?, Some(Instance::runtime(&target)?)),
        _ => (
            match form {
                Form::Literals => Instance::new(spec)?,
                Form::Runtime => Instance::runtime(spec)?,
            },
            None,
        ),
    };
    let form = if lang == Lang::BrdfExplorer {
        Form::Literals
    } else {
        form
    };
    let header = header::header(&inst, spec, lang, form, shaded.as_ref());
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
            return explorer::brdf_explorer(target, &header);
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
        Kind::Env => format!("{f}(0.9, 0.3{extra})"),
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => format!("{f}(0.9{extra})"),
    }
}
