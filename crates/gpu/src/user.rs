//! A user's own BRDF shader, evaluated on the GPU (issue 31): a BRDF Explorer `.brdf` file or a
//! function in WGSL (`.wgsl`) or GLSL (`.glsl`), read by [`UserShader`], translated by naga
//! into one WGSL module ([`UserShader::wgsl`]) and compiled into compute pipelines by
//! [`GpuBrdf`], which implements [`fastbrdf::user::UserBrdf`]. The formats are documented in
//! the book (`docs/book/src/user-shaders.md`).
//!
//! - `parse`: the text formats (the `.brdf` blocks, `// param` header lines, parameter
//!   values as users type them).
//! - `translate`: the wrapper around the user's code, naga's front ends, compile errors
//!   mapped back to the user's file, line and column, WGSL out.
//! - `eval`: the GPU side (batches in storage buffers, chunked, 2-D dispatches).

pub mod bench;
mod eval;
mod parse;
mod translate;

pub use eval::GpuBrdf;
pub use parse::ParamValue;

use std::fmt;
use std::io::Read;
use std::path::Path;

/// The largest shader file read (bytes): a BRDF is a page of code, not megabytes.
pub const MAX_SOURCE_BYTES: u64 = 4 << 20;

/// The source form of a user's shader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Language {
    /// A BRDF Explorer `.brdf` file: `::begin parameters` and `::begin shader` (GLSL) blocks.
    Brdf,
    /// A GLSL function file (`.glsl`, `.frag`, `.comp`): `brdf(wi, wo)`, `// param` lines.
    Glsl,
    /// A WGSL function file (`.wgsl`): `fn brdf(wi, wo)`, `// param` lines.
    Wgsl,
}

impl Language {
    /// The language a file name's extension says, `None` for an unknown one.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "brdf" => Some(Language::Brdf),
            "glsl" | "frag" | "comp" => Some(Language::Glsl),
            "wgsl" => Some(Language::Wgsl),
            _ => None,
        }
    }

    /// `brdf`, `glsl` or `wgsl`.
    pub fn name(&self) -> &'static str {
        match self {
            Language::Brdf => "brdf",
            Language::Glsl => "glsl",
            Language::Wgsl => "wgsl",
        }
    }
}

/// What kind of value a parameter holds, with its declared range and default.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    /// A number in `[min, max]`.
    Float { min: f64, max: f64, default: f64 },
    /// A switch (`0`/`1`, `false`/`true`); the shader reads a `bool`.
    Bool { default: bool },
    /// An RGB colour (any finite numbers); the shader reads a `vec3`.
    Color { default: [f32; 3] },
}

/// A parameter the shader declares: the shader reads it as a global of that name.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: String,
    pub kind: ParamKind,
    /// The line of the user's file that declares it (1-based).
    pub line: usize,
}

/// Which kind of failure: what the CLI's exit code says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UserErrorKind {
    /// The user's input: an unreadable or malformed file, a compile error, a bad parameter
    /// value (exit 2).
    Input,
    /// The GPU: no adapter, no device, a pipeline the driver refused, a lost device (exit 1).
    Gpu,
}

/// An error loading or evaluating a user's shader; the message names the file, and for
/// compile errors the line and column in the user's file (`walter.brdf:31:18: error: ...`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UserError {
    pub kind: UserErrorKind,
    pub message: String,
}

impl UserError {
    pub(crate) fn input(message: impl Into<String>) -> Self {
        Self {
            kind: UserErrorKind::Input,
            message: message.into(),
        }
    }

    pub(crate) fn gpu(message: impl Into<String>) -> Self {
        Self {
            kind: UserErrorKind::Gpu,
            message: message.into(),
        }
    }
}

impl fmt::Display for UserError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for UserError {}

/// A user's shader, read and checked by naga's front end and validator (compile errors come
/// out of [`UserShader::parse`]), not yet compiled into a GPU pipeline (that is [`GpuBrdf`]).
#[derive(Clone, Debug)]
pub struct UserShader {
    origin: String,
    language: Language,
    params: Vec<Param>,
    source: String,
    channels: usize,
    samples: bool,
    own_weight: bool,
    module: naga::Module,
}

impl UserShader {
    /// Reads the file at `path` (at most [`MAX_SOURCE_BYTES`], UTF-8) in the language its
    /// extension says, named in messages as `path` is written.
    pub fn load(path: &Path) -> Result<Self, UserError> {
        let origin = path.display().to_string();
        let lang = Language::from_path(path).ok_or_else(|| {
            UserError::input(format!(
                "{origin}: unknown shader language: the name must end in .brdf (BRDF \
                 Explorer), .wgsl or .glsl"
            ))
        })?;
        let bytes = read_bounded(path, &origin)?;
        let text = utf8(bytes, &origin)?;
        Self::parse(&text, &origin, lang)
    }

    /// Parses `text` in language `lang`; `origin` names it in messages (a file name).
    pub fn parse(text: &str, origin: &str, lang: Language) -> Result<Self, UserError> {
        let parsed = match lang {
            Language::Brdf => parse::brdf_file(text, origin)?,
            Language::Glsl | Language::Wgsl => parse::function_file(text, origin)?,
        };
        let t = translate::translate(&parsed, origin, lang)?;
        Ok(Self {
            origin: origin.to_string(),
            language: lang,
            params: parsed.params,
            source: text.to_string(),
            channels: t.channels,
            samples: t.samples,
            own_weight: t.own_weight,
            module: t.module,
        })
    }

    /// The name messages use (the file name as given).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// How users name the model: `file:ORIGIN`.
    pub fn name(&self) -> String {
        format!("file:{}", self.origin)
    }

    pub fn language(&self) -> Language {
        self.language
    }

    /// The declared parameters, in the file's order (the order of [`Self::param_block`]).
    pub fn params(&self) -> &[Param] {
        &self.params
    }

    /// The user's text as read.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// 3 (`.brdf` files and functions returning `vec3`) or 1 (functions returning a float).
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// Whether the shader defines `brdf_sample` and `brdf_pdf`.
    pub fn samples(&self) -> bool {
        self.samples
    }

    /// Whether the shader reports its own sample weight (`brdf_weight`).
    pub fn own_weight(&self) -> bool {
        self.own_weight
    }

    /// The user's model as WGSL, for a GPU renderer or the explorer to splice into its own
    /// module, with the parameter buffer at `@group(1) @binding(0)` (see [`Self::wgsl_at`]).
    ///
    /// Contract:
    /// - `fn fb_user_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32>`: `f` without the cosine
    ///   (a one-channel model's value in all three components), `wi` towards the light, `wo`
    ///   towards the viewer, normal +z, tangent +x, as given (not normalised).
    /// - when [`Self::samples`]: `fn fb_user_sample(wo: vec3<f32>, u: vec2<f32>) -> vec4<f32>`
    ///   (`wi` in xyz, its solid-angle pdf in w, pdf 0: no sample),
    ///   `fn fb_user_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32` and
    ///   `fn fb_user_weight(wo: vec3<f32>, wi: vec3<f32>, pdf: f32) -> vec3<f32>` (the shader's
    ///   own `brdf_weight`, else `f cos(theta_i) / pdf`).
    /// - `struct FbUserParams { p: array<vec4<f32>, K> }` and
    ///   `var<uniform> fb_user_params: FbUserParams`: parameter `k` of [`Self::params`] in
    ///   `p[k]` (floats and bools, 0 or 1, in `.x`; colours in `.xyz`); K is at least 1.
    ///   [`Self::param_block`] packs the values.
    /// - every other module-scope name of the user's code is prefixed `fbu_`, so names the
    ///   host uses outside `fbu_*`, `fb_user_*` and `FbUserParams` cannot collide. Each
    ///   `fb_user_*` function loads the parameters into `var<private>` globals first.
    pub fn wgsl(&self) -> Result<String, UserError> {
        self.wgsl_at(1, 0)
    }

    /// [`Self::wgsl`] with the parameter buffer at `@group(group) @binding(binding)`.
    pub fn wgsl_at(&self, group: u32, binding: u32) -> Result<String, UserError> {
        translate::write_wgsl(&self.module, group, binding)
            .map_err(|e| UserError::input(format!("{}: {e}", self.origin)))
    }

    /// The parameter buffer for `values` (one per parameter, as [`Self::values`] returns):
    /// one `vec4<f32>` per parameter, at least one.
    pub fn param_block(&self, values: &[ParamValue]) -> Vec<f32> {
        parse::param_block(values)
    }

    /// The values of every parameter: the defaults, replaced by the `given` `(name, value)`
    /// pairs (values as text: `0.3`; `1`, `0`, `true`, `false`; `r,g,b` or one grey number).
    /// Unknown names, values outside a declared range and repeated names are errors.
    pub fn values(&self, given: &[(String, String)]) -> Result<Vec<ParamValue>, UserError> {
        parse::values(&self.params, given, &self.name())
    }
}

/// Opens a GPU and compiles the shader file at `path` with the `given` parameter values
/// (see [`UserShader::values`]).
pub fn load(path: &Path, given: &[(String, String)]) -> Result<GpuBrdf, UserError> {
    let shader = UserShader::load(path)?;
    // Values are checked before a device is opened: a typo costs no GPU start.
    shader.values(given)?;
    let gpu = crate::Gpu::new().map_err(|e| UserError::gpu(e.to_string()))?;
    GpuBrdf::new(&gpu.device, &gpu.queue, shader, given)
}

/// Reads at most [`MAX_SOURCE_BYTES`] + 1 bytes of `path` (pipes and devices included).
fn read_bounded(path: &Path, origin: &str) -> Result<Vec<u8>, UserError> {
    if path.is_dir() {
        return Err(UserError::input(format!(
            "{origin}: is a folder, not a file"
        )));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| UserError::input(format!("{origin}: cannot open: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_SOURCE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| UserError::input(format!("{origin}: cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_SOURCE_BYTES {
        return Err(UserError::input(format!(
            "{origin}: larger than the {} MiB allowed for a shader file; nothing was read past \
             that",
            MAX_SOURCE_BYTES >> 20
        )));
    }
    Ok(bytes)
}

/// `bytes` as text, or an error naming the line and column of the first byte that is not
/// UTF-8.
fn utf8(bytes: Vec<u8>, origin: &str) -> Result<String, UserError> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let good = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
        let line = good.matches('\n').count() + 1;
        let col = good.rsplit('\n').next().unwrap_or("").chars().count() + 1;
        UserError::input(format!(
            "{origin}:{line}:{col}: not UTF-8 text (byte 0x{:02x}); save the shader as UTF-8",
            bytes[at]
        ))
    })
}
