//! `fastbrdf view`: an interactive explorer in the browser. A small synchronous HTTP server
//! (tiny_http, loopback only unless `--allow-remote`) serves one page embedded in the binary
//! (`page.html`: hand-written HTML, CSS and JavaScript, plots drawn on `<canvas>` from the JSON
//! numbers; no CDN, works offline) and the JSON API of [`api`] that the page calls.
//!
//! Bounded work: a fixed pool of worker threads answers requests; renders take one of
//! [`RENDER_SLOTS`] slots (at most [`MAX_WAITING`] wait, the rest get 503), each at most
//! `api::MAX_SIZE` square and `api::MAX_SPP` samples per axis; a render whose client has sent a
//! newer generation since is dropped before each model's render (409). Every handler runs
//! under `catch_unwind`: a panic is a 500, never a dead server.

pub mod api;
pub mod cdp;

use crate::CliError;
use api::{Query, Response};
use fastbrdf_render::setup::{self, Loaded, SceneSpec};
use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

/// The page, embedded.
pub const PAGE: &str = include_str!("page.html");

/// Renders running at once (the renderer itself is parallel over tiles).
pub const RENDER_SLOTS: usize = 2;
/// Renders waiting for a slot; more get 503.
pub const MAX_WAITING: usize = 8;
/// Worker threads answering requests.
const WORKERS: usize = 6;
/// Longest request target (path and query) accepted.
const MAX_URL: usize = 8192;
/// Clients whose latest render generation is remembered.
const MAX_CLIENTS: usize = 1024;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf view                          (http://127.0.0.1:8000/)\n  \
fastbrdf view --port 9000 --open\n  \
fastbrdf view --mesh face              (the embedded face beside the sphere)\n  \
fastbrdf view --mesh head.obj --bench bench.json   (your mesh; costs from `fastbrdf bench --json`)\n  \
fastbrdf view --screenshot docs/images/view.png   (headless Chromium, then exit)\n  \
fastbrdf view --measured gold-metallic-paint.binary   (the MERL file as a reference: #models=ward&ref=gold-metallic-paint.binary)\n  \
curl 'http://127.0.0.1:8000/api/errors?model=flog&ref=pow&n=100'\n\n\
The whole view lives in the URL after #, so a link reproduces it. The JSON API (README,\n\
\"Explorer\"): /api/models, /api/plots, /api/albedo, /api/render, /api/errors, /api/shader, /api/material.\n\
Bad requests get HTTP 400 with the message the CLI prints for the same input."
)]
pub struct Args {
    /// TCP port (0: any free port; the address is printed on stderr).
    #[arg(long, default_value_t = 8000)]
    port: u16,
    /// Address to listen on. Anything but a loopback address needs --allow-remote.
    #[arg(long, default_value = "127.0.0.1")]
    host: IpAddr,
    /// Allow listening on a non-loopback address (anyone who reaches it can use the server).
    #[arg(long)]
    allow_remote: bool,
    /// Open the page in the browser (xdg-open, or the Chromium found).
    #[arg(long)]
    open: bool,
    /// An OBJ mesh offered beside the sphere; `face`: the embedded face.
    #[arg(long)]
    mesh: Option<PathBuf>,
    /// A saved `fastbrdf bench --json` run: the page shows each model's measured cost.
    #[arg(long, value_name = "FILE")]
    bench: Option<PathBuf>,
    /// A measured material (MERL .binary, see `fastbrdf measured`) offered as a reference,
    /// named after the file: residuals as `fastbrdf errors --measured`, pictures as `fastbrdf
    /// compare --measured`. A malformed file is exit 2 at start-up.
    #[arg(long, value_name = "FILE")]
    measured: Option<PathBuf>,
    /// Take a screenshot of the page in headless Chromium to this PNG file, then exit.
    #[arg(long, value_name = "FILE.png")]
    screenshot: Option<PathBuf>,
    /// With --screenshot: the view (the part of the page's URL after #).
    #[arg(long, default_value = "models=flog,schlick&ref=pow&n=60&theta=35")]
    state: String,
    /// The Chromium executable (default: chromium, chromium-browser or google-chrome on PATH).
    #[arg(long, value_name = "PATH")]
    browser: Option<PathBuf>,
}

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
    pub loaded_sphere: Loaded,
    pub loaded_mesh: Option<Loaded>,
    pub mesh_path: Option<PathBuf>,
    pub mesh_name: Option<String>,
    bench: Option<fastbrdf_analysis::speed::Report>,
    pub bench_source: Option<String>,
    generations: Mutex<HashMap<String, u64>>,
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
    /// The state for a server with an optional mesh and bench run.
    pub fn new(
        mesh: Option<PathBuf>,
        bench: Option<PathBuf>,
        measured: Option<PathBuf>,
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
            loaded_sphere,
            loaded_mesh,
            mesh_name: mesh.as_ref().map(|m| m.display().to_string()),
            mesh_path: mesh,
            bench: report,
            bench_source: bench.map(|b| b.display().to_string()),
            generations: Mutex::new(HashMap::new()),
            slots: Mutex::new((0, 0)),
            freed: Condvar::new(),
        })
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

    /// Records `generation` as the newest of `client` (if it is newer).
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

/// Answers one request (method, request target). Never panics: a handler's panic is a 500.
pub fn handle(state: &State, method: &str, target: &str) -> Response {
    if target.len() > MAX_URL {
        return Response::error(414, &format!("request target longer than {MAX_URL} bytes"));
    }
    if method != "GET" {
        return Response::error(
            405,
            &format!("method {}: only GET", fastbrdf_io::shorten(method, 16)),
        );
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let q = Query::parse(query);
        let r: Result<Response, CliError> = match path {
            "/" | "/index.html" => Ok(Response {
                status: 200,
                content_type: "text/html; charset=utf-8",
                body: PAGE.as_bytes().to_vec(),
            }),
            "/api/models" => Ok(api::models(state)),
            "/api/plots" => api::plots(state, &q),
            "/api/albedo" => api::albedo_endpoint(state, &q),
            "/api/render" => api::render_endpoint(state, &q),
            "/api/errors" => api::errors_endpoint(state, &q),
            "/api/shader" => api::shader(&q),
            "/api/material" => api::material(&q),
            // Nothing else exists: no file is ever read from a path, so `..` leads nowhere.
            _ => Ok(Response::error(
                404,
                &format!("no such page: {}", fastbrdf_io::shorten(path, 64)),
            )),
        };
        r.unwrap_or_else(Response::from)
    }));
    result.unwrap_or_else(|_| Response::error(500, "internal error (a panic); the server goes on"))
}

/// A running server: its address, and the threads that answer.
pub struct Server {
    pub addr: SocketAddr,
    http: Arc<tiny_http::Server>,
    workers: Vec<std::thread::JoinHandle<()>>,
}

impl Server {
    /// Binds `addr` and starts the workers.
    pub fn start(addr: SocketAddr, state: Arc<State>) -> Result<Self, CliError> {
        let http = Arc::new(
            tiny_http::Server::http(addr)
                .map_err(|e| CliError::input(format!("cannot listen on {addr}: {e}")))?,
        );
        let addr = http
            .server_addr()
            .to_ip()
            .ok_or_else(|| CliError::input("not an IP listener"))?;
        let workers = (0..WORKERS)
            .map(|_| {
                let http = http.clone();
                let state = state.clone();
                std::thread::spawn(move || {
                    for req in http.incoming_requests() {
                        let r = handle(&state, req.method().as_str(), req.url());
                        // Content-Length always (no chunking): the simplest clients can read it.
                        let mut resp = tiny_http::Response::from_data(r.body)
                            .with_status_code(r.status)
                            .with_chunked_threshold(usize::MAX);
                        for (k, v) in [
                            ("Content-Type", r.content_type),
                            ("Cache-Control", "no-store"),
                            ("X-Content-Type-Options", "nosniff"),
                        ] {
                            resp.add_header(
                                tiny_http::Header::from_bytes(k.as_bytes(), v.as_bytes())
                                    .expect("valid header"),
                            );
                        }
                        // A client that went away is not the server's problem.
                        let _ = req.respond(resp);
                    }
                })
            })
            .collect();
        Ok(Self {
            addr,
            http,
            workers,
        })
    }

    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Blocks until the server stops (it does not, short of a signal).
    pub fn wait(self) {
        for w in self.workers {
            let _ = w.join();
        }
    }

    /// Stops answering.
    pub fn stop(&self) {
        self.http.unblock();
    }
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let loopback = a.host.is_loopback();
    if !loopback && !a.allow_remote {
        return Err(CliError::input(format!(
            "--host {}: not a loopback address; add --allow-remote to serve other machines",
            a.host
        )));
    }
    let state = Arc::new(State::new(
        a.mesh.clone(),
        a.bench.clone(),
        a.measured.clone(),
    )?);
    let port = if a.screenshot.is_some() { 0 } else { a.port };
    let server = Server::start(SocketAddr::new(a.host, port), state)?;
    if !loopback {
        eprintln!(
            "warning: serving on {}: every machine that reaches this address can use the explorer (no authentication)",
            server.addr
        );
    }
    if let Some(out) = &a.screenshot {
        let url = format!("{}#{}", server.url(), a.state);
        let png = cdp::screenshot(a.browser.as_deref(), &url, 1400, 1050)
            .map_err(|e| CliError::input(format!("--screenshot: {e}")))?;
        fastbrdf_io::write_atomic(out, &png)?;
        eprintln!("wrote {} ({} bytes, from {url})", out.display(), png.len());
        server.stop();
        return Ok(());
    }
    eprintln!(
        "fastbrdf view: serving on {} (Ctrl-C to stop)",
        server.url()
    );
    if a.open {
        let url = server.url();
        let opener = cdp::find_browser(a.browser.as_deref())
            .map(|b| b.display().to_string())
            .unwrap_or_else(|_| "xdg-open".into());
        if let Err(e) = std::process::Command::new(&opener).arg(&url).spawn() {
            eprintln!("warning: --open: cannot start {opener}: {e}; open {url} yourself");
        }
    }
    server.wait();
    Ok(())
}
