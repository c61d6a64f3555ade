//! Users' own models in the explorer (issue 31): `fastbrdf view --model file:PATH` (a BRDF
//! Explorer `.brdf` file or a `.wgsl`/`.glsl` function), read and compiled at start-up (a bad
//! file or a compile error is exit 2 there, naming the file, line and column), then listed by
//! `/api/models` beside the registry's and evaluated on the GPU in batches
//! (`fastbrdf_gpu::user::GpuBrdf`). A request's parameter values are checked against the
//! ranges the file declares; each distinct set of values is compiled once and kept (the last
//! [`KEPT_VALUE_SETS`]).

use crate::CliError;
use crate::model_args::{self, USER_PREFIX, is_user};
use fastbrdf_gpu::user::{GpuBrdf, ParamKind, ParamValue, UserError, UserErrorKind, UserShader};
use serde_json::{Value, json};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// Compiled parameter sets kept per user's model (a slider move compiles a new one).
pub const KEPT_VALUE_SETS: usize = 8;

/// A user's model: loaded at start-up (`--model file:PATH`) or uploaded (`POST /api/user`).
pub struct UserModel {
    /// What the page and the API call it: the file's name (the path as given when that name
    /// is taken by a registry model, the measured file or another user's model); an upload's
    /// is `file:NAME`.
    pub name: String,
    /// The file (an upload: its name as sent).
    pub path: PathBuf,
    pub shader: UserShader,
    /// Sent to the running server (`POST /api/user`), not given at start-up.
    pub uploaded: bool,
    /// The `--param` values given at start-up: the values a request does not give.
    pub given: Vec<(String, String)>,
    gpu: Arc<fastbrdf_gpu::Gpu>,
    /// Compiled instances by their values (most recent last).
    kept: Mutex<VecDeque<(Vec<ParamValue>, Arc<GpuBrdf>)>>,
    /// Its SPIR-V instruction counts after `spirv-opt -O` (`UserShader::instructions`), counted
    /// once at start-up; `None` without spirv-opt (a note on stderr says so).
    instructions: Option<fastbrdf_gpu::cost::Counts>,
}

/// A [`UserError`] as the CLI reports it: the user's input exit 2 (HTTP 400), the GPU exit 1
/// (HTTP 500).
fn cli_error(e: UserError) -> CliError {
    CliError {
        code: match e.kind {
            UserErrorKind::Input => crate::EXIT_INPUT,
            UserErrorKind::Gpu => crate::EXIT_CHECK_FAILED,
        },
        message: e.message,
    }
}

impl UserModel {
    /// The model of `shader` (read from `path`) with the start-up values `given`, on `gpu`:
    /// its instruction counts taken (a note on stderr without spirv-opt) and its default
    /// instance compiled, so that a shader the GPU refuses fails here, not at the first request.
    pub fn new(
        name: String,
        path: PathBuf,
        shader: UserShader,
        given: Vec<(String, String)>,
        gpu: Arc<fastbrdf_gpu::Gpu>,
        uploaded: bool,
    ) -> Result<Self, CliError> {
        let instructions = match shader.instructions() {
            Ok(c) => Some(c),
            Err(e) => {
                // As the server's notes: on stderr (no link to the server module).
                eprintln!("note: instruction count of {} unknown: {e}", shader.name());
                None
            }
        };
        let u = UserModel {
            name,
            path,
            shader,
            uploaded,
            given,
            gpu,
            kept: Mutex::new(VecDeque::new()),
            instructions,
        };
        u.instance(&[])?;
        Ok(u)
    }

    /// The GPU its instances run on.
    pub fn gpu(&self) -> &Arc<fastbrdf_gpu::Gpu> {
        &self.gpu
    }

    /// Whether the file declares parameter `name`.
    pub fn declares(&self, name: &str) -> bool {
        self.shader.params().iter().any(|p| p.name == name)
    }

    /// The model with the start-up values replaced by `given` (pairs of parameters it
    /// declares), compiled once per distinct set of values. A value outside the declared range,
    /// not a number, or an unknown name is exit 2 (HTTP 400) naming the parameter and file.
    pub fn instance(&self, given: &[(String, String)]) -> Result<Arc<GpuBrdf>, CliError> {
        let mut merged: Vec<(String, String)> = self
            .given
            .iter()
            .filter(|(k, _)| !given.iter().any(|(g, _)| g == k))
            .cloned()
            .collect();
        merged.extend(given.iter().cloned());
        let values = self.shader.values(&merged).map_err(cli_error)?;
        {
            let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(at) = kept.iter().position(|(v, _)| *v == values) {
                let hit = kept.remove(at).expect("found");
                let b = hit.1.clone();
                kept.push_back(hit);
                return Ok(b);
            }
        }
        // Compiled outside the lock: another request's values need not wait for this one.
        let b = Arc::new(
            GpuBrdf::new(
                &self.gpu.device,
                &self.gpu.queue,
                self.shader.clone(),
                &merged,
            )
            .map_err(cli_error)?,
        );
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if kept.len() >= KEPT_VALUE_SETS {
            kept.pop_front();
        }
        kept.push_back((values, b.clone()));
        Ok(b)
    }

    /// The declared parameters for the page's controls: ranges, the file's defaults
    /// (`declared`) and the values a request that gives none runs with (`default`).
    pub fn params_json(&self) -> Value {
        let now = self.shader.values(&self.given).unwrap_or_default();
        let params: Vec<Value> = self
            .shader
            .params()
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let doc = format!("declared at {}:{}", self.shader.origin(), p.line);
                match (&p.kind, now.get(k)) {
                    (ParamKind::Float { min, max, default }, v) => {
                        let d = match v {
                            Some(ParamValue::Float(x)) => *x,
                            _ => *default,
                        };
                        json!({"name": p.name, "type": "number", "min": min, "max": max,
                               "default": d, "declared": default, "doc": doc,
                               "log": *min > 0.0 && max / min >= 50.0})
                    }
                    (ParamKind::Bool { default }, v) => {
                        let d = match v {
                            Some(ParamValue::Bool(b)) => *b,
                            _ => *default,
                        };
                        let s = |b: bool| if b { "1" } else { "0" };
                        json!({"name": p.name, "type": "choice", "options": ["0", "1"],
                               "default": s(d), "declared": s(*default), "doc": doc})
                    }
                    (ParamKind::Color { default }, v) => {
                        let d = match v {
                            Some(ParamValue::Color(c)) => *c,
                            _ => *default,
                        };
                        json!({"name": p.name, "type": "color", "default": d,
                               "declared": default, "doc": doc})
                    }
                }
            })
            .collect();
        json!(params)
    }

    /// The entry of `/api/models`: the fields a registry model's entry has, and the file's.
    pub fn entry_json(&self) -> Value {
        json!({
            "id": self.name, "kind": "user", "params": self.params_json(),
            "file": self.path.display().to_string(), "language": self.shader.language().name(),
            "channels": self.shader.channels(), "samples": self.shader.samples(),
            "formula": Value::Null, "source": format!("{USER_PREFIX}{}", self.path.display()),
            "bounds": [], "ops": Value::Null, "swept": Value::Null, "cost": Value::Null,
            "instructions": self.instructions, "uploaded": self.uploaded,
        })
    }
}

/// Reads and compiles the users' models `ids` (`file:PATH` each) with the `--param` texts
/// `params` (each to the models whose file declares it), on one GPU opened for them all; no
/// GPU is opened without one. `taken`: names already in use (the measured file's).
pub fn load(ids: &[String], params: &[String], taken: &[&str]) -> Result<Vec<UserModel>, CliError> {
    let pairs = model_args::pairs(params)?;
    if ids.is_empty() {
        if let Some((k, _)) = pairs.first() {
            return Err(CliError::input(format!(
                "--param {}: the explorer takes --param for a user's model only (--model \
                 file:PATH); registry models' values are set in the page",
                fastbrdf_io::shorten(k, 40)
            )));
        }
        return Ok(vec![]);
    }
    let mut shaders = Vec::new();
    for id in ids {
        if !is_user(id) {
            return Err(CliError::input(format!(
                "--model {}: the explorer lists the registry's models already; --model takes \
                 a user's model, file:PATH (a .brdf, .wgsl or .glsl file)",
                fastbrdf_io::shorten(id, 40)
            )));
        }
        let path = PathBuf::from(&id[USER_PREFIX.len()..]);
        if path.as_os_str().is_empty() {
            return Err(CliError::input(
                "--model file:: no path after 'file:' (e.g. --model file:my.brdf)",
            ));
        }
        let shader = UserShader::load(&path).map_err(cli_error)?;
        shaders.push((path, shader));
    }
    for (k, _) in &pairs {
        if !shaders
            .iter()
            .any(|(_, s)| s.params().iter().any(|p| &p.name == k))
        {
            let names: Vec<String> = shaders.iter().map(|(_, s)| s.name()).collect();
            return Err(CliError::input(format!(
                "--param {}: no --model file declares it ({})",
                fastbrdf_io::shorten(k, 40),
                names.join(", ")
            )));
        }
    }
    // The values are checked before a GPU is opened: a typo costs no GPU start.
    let mut owned = Vec::new();
    for (path, shader) in shaders {
        let own: Vec<(String, String)> = pairs
            .iter()
            .filter(|(k, _)| shader.params().iter().any(|p| &p.name == k))
            .cloned()
            .collect();
        shader.values(&own).map_err(cli_error)?;
        owned.push((path, shader, own));
    }
    let gpu = Arc::new(fastbrdf_gpu::Gpu::new().map_err(|e| CliError {
        code: crate::EXIT_CHECK_FAILED,
        message: format!("--model {}: no GPU: {e}", owned[0].1.name()),
    })?);
    let mut out: Vec<UserModel> = Vec::new();
    for (path, shader, given) in owned {
        let file = path.file_name().map_or_else(
            || path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        );
        let in_use = |n: &str| {
            taken.contains(&n)
                || fastbrdf::registry::find(n).is_ok()
                || out.iter().any(|u| u.name == n)
        };
        let name = if in_use(&file) {
            path.display().to_string()
        } else {
            file
        };
        if in_use(&name) || name.contains(',') {
            return Err(CliError::input(format!(
                "--model {}: the explorer names it '{}', which is taken or holds a comma; \
                 give each file its own name",
                shader.name(),
                fastbrdf_io::shorten(&name, 60)
            )));
        }
        // Compiled now: a shader the GPU refuses fails at start-up, not at the first request.
        out.push(UserModel::new(
            name,
            path,
            shader,
            given,
            gpu.clone(),
            false,
        )?);
    }
    Ok(out)
}
