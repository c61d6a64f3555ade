//! What the explorer's handlers share: the measured reference, the users' models, the loaded scenes, the bench
//! run, the render slots and per-client generations, the FLIP pool, the computation cap, and
//! whether the client of the request being handled has gone.

use super::flip::Flips;
use super::users::UserModel;
use crate::CliError;
use fastbrdf_render::setup::{self, Loaded, SceneSpec};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex, RwLock};
use std::time::Duration;

/// Renders running at once (the renderer itself is parallel over tiles).
pub const RENDER_SLOTS: usize = 2;
/// Renders waiting for a slot; more get 503.
pub const MAX_WAITING: usize = 8;
/// Longest a plots, albedo or errors request waits for a computation permit before its 503.
pub const COMPUTE_WAIT: Duration = Duration::from_secs(1);

/// Plots, albedo and errors computations running at once: as many as CPUs, at least 2 (each
/// is parallel over its models, so more would only share the same cores, and ones whose
/// client has gone keep running).
pub fn compute_slots() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get().max(2))
}

thread_local! {
    /// Set while a handler runs on a blocking-pool thread: raised when its client has gone
    /// (hyper drops the request's future when the connection ends).
    pub static GONE: std::cell::RefCell<Option<Arc<std::sync::atomic::AtomicBool>>> =
        const { std::cell::RefCell::new(None) };
}

/// Whether the client of the request this thread is handling has gone (hung up): a render
/// checks it before each model's render and stops (nobody would read the answer).
pub fn client_gone() -> bool {
    GONE.with(|g| {
        g.borrow()
            .as_ref()
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    })
}

/// Raises its flag when dropped: with the request's future, when hyper drops it because the
/// client has gone, or once the answer is made (then no one looks).
pub struct Hangup(pub Arc<std::sync::atomic::AtomicBool>);

impl Drop for Hangup {
    fn drop(&mut self) {
        self.0.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Uploaded users' models kept (`POST /api/user`): one more drops the oldest upload (the
/// start-up ones stay).
pub const MAX_UPLOADS: usize = 16;

/// Clients whose latest render generation is remembered.
const MAX_CLIENTS: usize = 1024;

/// A measured material loaded at start-up: the reference the page may choose.
pub struct Measured {
    /// What the page and the API call it: the file's name (prefixed with `measured ` if that
    /// is a registry id).
    pub name: String,
    pub path: PathBuf,
    pub brdf: Arc<fastbrdf::measured::MeasuredBrdf>,
    /// The bins `fastbrdf errors --measured` compares at (its default sample count).
    pub data: fastbrdf_analysis::measured_fit::Data,
}

impl Measured {
    /// Reads `path` (the CLI's errors for a malformed file).
    pub fn load(path: &std::path::Path) -> Result<Self, CliError> {
        use fastbrdf_analysis::measured_fit::{self, DEFAULT_SAMPLES, Data};
        let brdf = fastbrdf::measured::MeasuredBrdf::read(path)?;
        let data = Data::from_measured(&brdf, DEFAULT_SAMPLES);
        if data.is_empty() {
            return Err(CliError::input(format!(
                "{}: no valid (measured) bin within {} degrees of the normal",
                path.display(),
                measured_fit::MAX_THETA_DEG
            )));
        }
        let file = path.file_name().map_or_else(
            || path.display().to_string(),
            |f| f.to_string_lossy().into_owned(),
        );
        let name = if fastbrdf::registry::find(&file).is_ok() {
            format!("measured {file}")
        } else {
            file
        };
        Ok(Self {
            name,
            path: path.to_path_buf(),
            brdf: Arc::new(brdf),
            data,
        })
    }
}

/// What the handlers share.
pub struct State {
    pub measured: Option<Measured>,
    /// The users' models: `--model file:PATH` in the order given, then the uploads
    /// (`POST /api/user`), oldest first; read through [`State::users`] and [`State::user`].
    users: RwLock<Vec<Arc<UserModel>>>,
    /// The GPU the users' models run on: the start-up ones', else opened at the first upload.
    gpu: Mutex<Option<Arc<fastbrdf_gpu::Gpu>>>,
    pub loaded_sphere: Loaded,
    pub loaded_mesh: Option<Loaded>,
    pub mesh_path: Option<PathBuf>,
    pub mesh_name: Option<String>,
    /// `--env FILE`: the lat-long map the page's WebGPU pictures may be lit by (`env=file`).
    pub env_file: Option<(String, Arc<fastbrdf_render::env::EnvMap>)>,
    bench: Option<fastbrdf_analysis::speed::Report>,
    pub bench_source: Option<String>,
    generations: Mutex<HashMap<String, u64>>,
    /// FLIP of the pictures, off the requests' critical path ([`super::flip`]).
    pub flips: Arc<Flips>,
    slots: Mutex<(usize, usize)>,
    freed: Condvar,
}

/// A render slot, given back on drop.
pub struct Slot<'a>(&'a State);

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        let mut s = self.0.slots.lock().unwrap_or_else(|e| e.into_inner());
        s.0 -= 1;
        self.0.freed.notify_one();
    }
}

impl State {
    /// The state for a server with an optional mesh and bench run; a FLIP thread per CPU.
    pub fn new(
        mesh: Option<PathBuf>,
        bench: Option<PathBuf>,
        measured: Option<PathBuf>,
    ) -> Result<Self, CliError> {
        Self::with_flip_threads(mesh, bench, measured, compute_slots())
    }

    /// [`State::new`] with `flip_threads` FLIP threads (tests: 0, and run the pool by hand).
    pub fn with_flip_threads(
        mesh: Option<PathBuf>,
        bench: Option<PathBuf>,
        measured: Option<PathBuf>,
        flip_threads: usize,
    ) -> Result<Self, CliError> {
        let measured = measured.as_deref().map(Measured::load).transpose()?;
        let loaded_sphere = setup::load(&SceneSpec::new())?;
        let loaded_mesh = match &mesh {
            Some(m) => {
                let mut spec = SceneSpec::new();
                spec.mesh = Some(m.clone());
                Some(setup::load(&spec)?)
            }
            None => None,
        };
        let report = bench
            .as_deref()
            .map(fastbrdf_analysis::speed::Report::load)
            .transpose()?;
        Ok(Self {
            measured,
            users: RwLock::new(Vec::new()),
            gpu: Mutex::new(None),
            loaded_sphere,
            loaded_mesh,
            mesh_name: mesh.as_ref().map(|m| m.display().to_string()),
            mesh_path: mesh,
            env_file: None,
            bench: report,
            bench_source: bench.map(|b| b.display().to_string()),
            generations: Mutex::new(HashMap::new()),
            flips: Flips::new(flip_threads),
            slots: Mutex::new((0, 0)),
            freed: Condvar::new(),
        })
    }

    /// The state with the environment map of `--env FILE` (read once; a bad file is exit 2).
    pub fn with_env(mut self, path: Option<&std::path::Path>) -> Result<Self, CliError> {
        if let Some(p) = path {
            let map = fastbrdf_render::env::EnvMap::load(p)?;
            self.env_file = Some((p.display().to_string(), Arc::new(map)));
        }
        Ok(self)
    }

    /// The state with the users' models `users` (loaded by [`super::users::load`]).
    pub fn with_users(self, users: Vec<UserModel>) -> Self {
        if let Some(u) = users.first() {
            *self.gpu.lock().unwrap_or_else(|e| e.into_inner()) = Some(u.gpu().clone());
        }
        *self.users.write().unwrap_or_else(|e| e.into_inner()) =
            users.into_iter().map(Arc::new).collect();
        self
    }

    /// The user's model the page and the API call `name` (a start-up one or an upload).
    pub fn user(&self, name: &str) -> Option<Arc<UserModel>> {
        let users = self.users.read().unwrap_or_else(|e| e.into_inner());
        users.iter().find(|u| u.name == name).cloned()
    }

    /// The users' models now (a snapshot: an upload after the call is not in it).
    pub fn users(&self) -> Vec<Arc<UserModel>> {
        self.users.read().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// The GPU for users' models: the start-up models', else one opened now (and kept). No
    /// adapter is the server's failure (exit 1: HTTP 500), naming `what`.
    pub fn gpu(&self, what: &str) -> Result<Arc<fastbrdf_gpu::Gpu>, CliError> {
        let mut g = self.gpu.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(gpu) = g.as_ref() {
            return Ok(gpu.clone());
        }
        let gpu = Arc::new(fastbrdf_gpu::Gpu::new().map_err(|e| CliError {
            code: crate::EXIT_CHECK_FAILED,
            message: format!("{what}: no GPU: {e}"),
        })?);
        *g = Some(gpu.clone());
        Ok(gpu)
    }

    /// Adds the upload `u`: it replaces an earlier upload of its name, and past
    /// [`MAX_UPLOADS`] the oldest upload goes. A start-up model, the measured file or a
    /// registry model of its name is an error naming it (nothing changes).
    pub fn add_upload(&self, u: UserModel) -> Result<Arc<UserModel>, CliError> {
        let name = u.name.clone();
        let taken = |why: &str| {
            CliError::input(format!(
                "name {}: taken by {why}; send the file under another name",
                fastbrdf_io::shorten(&name, 64)
            ))
        };
        if self.measured.as_ref().is_some_and(|m| m.name == u.name) {
            return Err(taken("the measured file"));
        }
        if fastbrdf::registry::find(&u.name).is_ok() {
            return Err(taken("a registry model"));
        }
        let u = Arc::new(u);
        let mut users = self.users.write().unwrap_or_else(|e| e.into_inner());
        if users.iter().any(|x| x.name == u.name && !x.uploaded) {
            return Err(taken("a --model file given at start-up"));
        }
        users.retain(|x| x.name != u.name);
        while users.iter().filter(|x| x.uploaded).count() >= MAX_UPLOADS {
            let oldest = users.iter().position(|x| x.uploaded).expect("an upload");
            users.remove(oldest);
        }
        users.push(u.clone());
        Ok(u)
    }

    /// Model `id`'s measured throughput in the bench run, evaluations per second: the best
    /// row of each CPU variant (`scalar`, `simd`, `simd-threads`: one core's batch kernel, all
    /// cores), or None (no run given, or the model is not in it).
    pub fn cost(&self, id: &str) -> Option<serde_json::Value> {
        let r = self.bench.as_ref()?;
        let mut best = serde_json::Map::new();
        for k in r
            .kernels
            .iter()
            .filter(|k| fastbrdf_analysis::speed::registry_id(&k.model) == id && k.isa != "gpu")
        {
            let e = best
                .entry(k.variant.clone())
                .or_insert(serde_json::json!(0.0));
            if k.evals_per_s > e.as_f64().unwrap_or(0.0) {
                *e = serde_json::json!(k.evals_per_s);
            }
        }
        (!best.is_empty()).then_some(serde_json::Value::Object(best))
    }

    /// Records `generation` as the newest of `client` (if it is newer); the client's FLIP
    /// jobs of older generations end (superseded).
    pub fn note_generation(&self, client: &str, generation: u64) {
        if client.is_empty() {
            return;
        }
        let mut g = self.generations.lock().unwrap_or_else(|e| e.into_inner());
        if g.len() >= MAX_CLIENTS && !g.contains_key(client) {
            g.clear();
        }
        let e = g
            .entry(fastbrdf_io::shorten(client, 64))
            .or_insert(generation);
        *e = (*e).max(generation);
        drop(g);
        self.flips.supersede(client, generation);
    }

    /// Whether `client` has asked for something newer than `generation`.
    pub fn superseded(&self, client: &str, generation: u64) -> bool {
        let g = self.generations.lock().unwrap_or_else(|e| e.into_inner());
        g.get(&fastbrdf_io::shorten(client, 64))
            .is_some_and(|&latest| latest > generation)
    }

    /// Waits (at most 30 s) for a render slot; None when too many wait already or time ran out.
    pub fn render_slot(&self) -> Option<Slot<'_>> {
        let mut s = self.slots.lock().unwrap_or_else(|e| e.into_inner());
        if s.1 >= MAX_WAITING {
            return None;
        }
        s.1 += 1;
        let deadline = std::time::Instant::now() + Duration::from_secs(30);
        while s.0 >= RENDER_SLOTS {
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            if left.is_zero() {
                s.1 -= 1;
                return None;
            }
            s = self
                .freed
                .wait_timeout(s, left)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
        s.1 -= 1;
        s.0 += 1;
        Some(Slot(self))
    }
}

impl Drop for State {
    fn drop(&mut self) {
        self.flips.stop();
    }
}
