//! `fastbrdf view`: an interactive explorer in the browser. An HTTP/1.1 server (hyper on a
//! small tokio runtime, loopback only unless `--allow-remote`) serves one page embedded in the
//! binary (`page.html`: hand-written HTML, CSS and JavaScript, plots drawn on `<canvas>` from
//! the JSON numbers; no CDN, works offline; every string from the link, a file name or the
//! server goes into the page as text, never as HTML) and the JSON API of [`api`] that the page
//! calls.
//!
//! One client must never take the explorer down. The limits:
//! - connections: at most [`MAX_CONNECTIONS`] open (`--max-connections`, lowered to leave
//!   [`FD_RESERVE`] of the open-file limit free); more get a short 503 and are closed, and a
//!   failed accept (out of file descriptors) is retried after [`ACCEPT_RETRY`], never the end
//!   of the listener;
//! - request heads: at most [`MAX_HEAD`] bytes and [`MAX_HEADERS`] fields (431, hyper's), the
//!   target at most `MAX_URL` bytes (414); a request with a body is refused (413, connection
//!   closed) without reading it: the API is GET-only;
//! - time: a connection that sends nothing for [`IDLE_TIMEOUT_S`] seconds (at its start, or
//!   after an answer: idle keep-alive) is closed, and a request head must be complete within
//!   as long of its first byte (or of the previous answer); a write the client does not read
//!   for [`WRITE_TIMEOUT_S`] seconds closes the connection (a client that pipelines and never
//!   reads stalls only itself);
//! - `Host` (or an absolute target's authority) must name the bound address (see [`Hosts`]):
//!   403 otherwise (DNS rebinding);
//! - HTTP/2 is not spoken: its preface gets an HTTP/2 GOAWAY (HTTP_1_1_REQUIRED), a request
//!   line of another version hyper's 400;
//! - work: each request's [`handle`] runs on the runtime's blocking pool. A computation cannot
//!   be interrupted once it runs, so one client asking and hanging up could pile them up: at
//!   most [`compute_slots`] (as many as CPUs, at least 2) plots, albedo and errors computations
//!   run at once, a further one waits at most [`COMPUTE_WAIT`] for a permit, then gets 503;
//!   renders take one of [`RENDER_SLOTS`] slots (at most [`MAX_WAITING`] wait, the rest get
//!   503), each at most `api::MAX_SIZE` square and `api::MAX_SPP` samples per axis. The pool
//!   has a thread for each of these and for each connection, so a quick request (the page,
//!   `/api/models`) never waits behind computations, and the two runtime workers (accept,
//!   HTTP) compete with a bounded number of busy threads. A render whose client has gone
//!   ([`client_gone`]), or has sent a newer generation since (409), is dropped before each
//!   model's render. Every handler runs under `catch_unwind`: a panic is a 500, never a dead
//!   server;
//! - cross-site requests: a page of another site can make the browser send requests to
//!   127.0.0.1 (its `Host` passes), so `/api/*` refuses (403) a request marked
//!   `Sec-Fetch-Site: cross-site` or `same-site`, or whose `Origin` is not `http://` (or
//!   `https://`) and an allowed host (see [`cross_site`]); the page's own requests and tools
//!   such as curl (no such header) are served;
//! - stderr: after start-up the server writes to stderr ignoring failures (a closed pipe, as
//!   in `fastbrdf view 2>&1 | head -1`), so that losing stderr never stops it.

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
    static GONE: std::cell::RefCell<Option<Arc<std::sync::atomic::AtomicBool>>> =
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
struct Hangup(Arc<std::sync::atomic::AtomicBool>);

impl Drop for Hangup {
    fn drop(&mut self) {
        self.0.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Writes `msg` and a newline on stderr, ignoring failures: after start-up stderr may be a
/// pipe whose reader has gone (`fastbrdf view 2>&1 | head -1`), which must not stop the server
/// (`eprintln!` panics on a failed write).
fn note(msg: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{msg}");
}
/// Connections served at once by default (`--max-connections`); more get a short 503.
pub const MAX_CONNECTIONS: usize = 128;
/// File descriptors left free of connections (listener, runtime, the files handlers open,
/// refusals): the connection cap is lowered to fit the open-file limit less this.
pub const FD_RESERVE: u64 = 64;
/// 503 answers being written at once; past it a connection over the cap is closed unanswered.
const MAX_REFUSING: usize = 16;
/// Longest a 503 or an HTTP/2 refusal may take to write (and, for HTTP/2, read the preface).
const REFUSAL_TIME: Duration = Duration::from_secs(1);
/// How long a 503 then reads what the client sent before closing.
const REFUSAL_DRAIN: Duration = Duration::from_millis(200);
/// Pause after a failed accept (out of file descriptors) before the next.
pub const ACCEPT_RETRY: Duration = Duration::from_millis(100);
/// Largest request head (request line and header fields), bytes: beyond, 431.
pub const MAX_HEAD: usize = 16 * 1024;
/// Most header fields in a request: beyond, 431.
pub const MAX_HEADERS: usize = 64;
/// hyper's connection buffer (read side: pipelined requests wait there, unread beyond it).
const MAX_BUF: usize = 64 * 1024;
/// Default seconds within which a request head must arrive (`--idle-timeout`).
pub const IDLE_TIMEOUT_S: u64 = 20;
/// Default seconds a write may wait for the client to read (`--write-timeout`).
pub const WRITE_TIMEOUT_S: u64 = 30;
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
Bad requests get HTTP 400 with the message the CLI prints for the same input.\n\n\
Limits (one client cannot take the server down): HTTP/1.1 only (HTTP/2 is refused with a GOAWAY);\n\
at most 128 connections (--max-connections; lowered to leave 64 of the open-file limit free),\n\
more get 503; request heads at most 16 KiB and 64 fields (431), targets 8 KiB (414); GET only,\n\
bodies refused (413); a request head must arrive within 20 s (idle connections are closed), a\n\
client that does not read an answer for 30 s is dropped; Host must name the bound address\n\
(127.0.0.1, localhost or [::1] on loopback; --allow-host NAME for a proxy), else 403; /api/*\n\
refuses cross-site requests (Sec-Fetch-Site cross-site or same-site, or an Origin that is not\n\
an allowed host) with 403; as many plots/albedo/errors computations at once as CPUs (at least\n\
2), one more waits 1 s then gets 503; 2 renders at once and 8 waiting (503 beyond), 1024x1024\n\
and 4x4 samples at most."
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
    /// Another name the server answers to (the `Host` a reverse proxy forwards), `NAME` (any
    /// port) or `NAME:PORT`; repeatable. Requests for names not allowed get 403.
    #[arg(long = "allow-host", value_name = "NAME", value_parser = host_name)]
    allow_host: Vec<String>,
    /// Connections served at once; more get 503 (lowered to fit the open-file limit).
    #[arg(long, default_value_t = MAX_CONNECTIONS as u32, value_parser = clap::value_parser!(u32).range(1..=65536))]
    max_connections: u32,
    /// Seconds within which a request head must arrive (tests lower it).
    #[arg(long, hide = true, default_value_t = IDLE_TIMEOUT_S, value_parser = clap::value_parser!(u64).range(1..=3600))]
    idle_timeout: u64,
    /// Seconds a write may wait for the client to read (tests lower it).
    #[arg(long, hide = true, default_value_t = WRITE_TIMEOUT_S, value_parser = clap::value_parser!(u64).range(1..=3600))]
    write_timeout: u64,
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

/// `--allow-host`'s value: a host name or address, optionally with `:PORT`.
fn host_name(s: &str) -> Result<String, String> {
    let ok = !s.is_empty()
        && s.len() <= 253
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"-._:[]".contains(&b))
        && Hosts::split(&s.to_ascii_lowercase()).is_some();
    if ok {
        Ok(s.to_string())
    } else {
        Err(format!(
            "'{}' is not a host name (letters, digits, '-', '.', an optional ':PORT')",
            fastbrdf_io::shorten(s, 64)
        ))
    }
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

/// One request as [`handle`] sees it.
pub struct Request<'a> {
    pub method: &'a str,
    /// The request target: path and query.
    pub target: &'a str,
    /// The authority the client asked for: the absolute-form target's, else the `Host` header
    /// (None: neither, as an HTTP/1.0 client may send).
    pub host: Option<&'a str>,
    /// Whether the request carries a body (a `Content-Length` above 0, or chunked).
    pub has_body: bool,
    /// The `Sec-Fetch-Site` header (a browser's: `same-origin`, `same-site`, `cross-site`,
    /// `none`), if any.
    pub fetch_site: Option<&'a str>,
    /// The `Origin` header, if any.
    pub origin: Option<&'a str>,
}

/// Why a request for `/api/*` is refused as cross-site, or None. A page of another site can
/// make the browser send requests here (its `Host` is this server's), so refused are: a
/// request the browser marks `Sec-Fetch-Site: cross-site` or `same-site` (another port or
/// name of the same site), and one whose `Origin` is present and not `http://HOST[:PORT]` (or
/// `https://`, a proxy's) of an allowed host (`null` included). The page's own requests
/// (`same-origin`, a typed address: `none`) and clients that send neither header (curl) pass.
pub fn cross_site(hosts: &Hosts, req: &Request<'_>) -> Option<String> {
    if let Some(site) = req.fetch_site {
        let site = site.trim().to_ascii_lowercase();
        if site == "cross-site" || site == "same-site" {
            return Some(format!(
                "cross-site request refused (Sec-Fetch-Site: {}): the API answers the explorer's own page only",
                fastbrdf_io::shorten(&site, 32)
            ));
        }
    }
    if let Some(origin) = req.origin {
        let o = origin.trim();
        let authority = o
            .strip_prefix("http://")
            .or_else(|| o.strip_prefix("https://"));
        if !authority.is_some_and(|a| !a.is_empty() && !a.contains('/') && hosts.allows(a)) {
            return Some(format!(
                "cross-site request refused (Origin '{}' is not this server, {}): the API answers the explorer's own page only",
                fastbrdf_io::shorten(origin, 64),
                hosts.expected()
            ));
        }
    }
    None
}

/// The names the server answers to (`Host`): the bound address with the bound port; on a
/// loopback address also `localhost`, `127.0.0.1` and `[::1]`; on an unspecified address
/// (`0.0.0.0`, `::`) any IP literal and `localhost`; and each `--allow-host` (`NAME`: any
/// port, `NAME:PORT`: that one). A page served under another name that resolves to this
/// machine (DNS rebinding) gets 403 instead of the API.
pub struct Hosts {
    ip: IpAddr,
    port: u16,
    extra: Vec<String>,
}

impl Hosts {
    pub fn new(bound: SocketAddr, extra: &[String]) -> Self {
        Self {
            ip: bound.ip(),
            port: bound.port(),
            extra: extra
                .iter()
                .map(|e| e.trim().to_ascii_lowercase())
                .collect(),
        }
    }

    /// Splits `name[:port]` (`[v6]:port` for IPv6); None when the port is not a number.
    fn split(host: &str) -> Option<(&str, Option<u16>)> {
        let (name, port) = if let Some(rest) = host.strip_prefix('[') {
            let (name, after) = rest.split_once(']')?;
            match after {
                "" => (name, None),
                _ => (name, Some(after.strip_prefix(':')?)),
            }
        } else {
            match host.rsplit_once(':') {
                Some((n, p)) if !n.contains(':') => (n, Some(p)),
                _ => (host, None),
            }
        };
        let port = match port {
            Some(p) => Some(p.parse().ok()?),
            None => None,
        };
        Some((name, port))
    }

    /// Whether a request for `host` is answered.
    pub fn allows(&self, host: &str) -> bool {
        let host = host.trim().to_ascii_lowercase();
        let Some((name, port)) = Self::split(&host) else {
            return false;
        };
        let name = name.strip_suffix('.').unwrap_or(name);
        for e in &self.extra {
            match Self::split(e) {
                Some((n, None)) if n == name => return true,
                Some((n, Some(p))) if n == name && Some(p) == port => return true,
                _ => {}
            }
        }
        if port.unwrap_or(80) != self.port {
            return false;
        }
        let local = self.ip.is_loopback() || self.ip.is_unspecified();
        match name.parse::<IpAddr>() {
            Ok(ip) => {
                ip == self.ip
                    || self.ip.is_unspecified()
                    || (self.ip.is_loopback() && ip.is_loopback())
            }
            Err(_) => local && name == "localhost",
        }
    }

    /// What the bound address is called in messages.
    fn expected(&self) -> String {
        SocketAddr::new(self.ip, self.port).to_string()
    }
}

/// Answers one request: the one place that does, for every request hyper parsed (the
/// transport only adds refusals before a request exists: the connection cap's 503, hyper's
/// 400/431 for a malformed or oversized head, the HTTP/2 preface's GOAWAY). Never panics: a
/// handler's panic is a 500.
pub fn handle(state: &State, hosts: &Hosts, req: &Request<'_>) -> Response {
    if let Some(host) = req.host
        && !hosts.allows(host)
    {
        return Response::error(
            403,
            &format!(
                "Host '{}' is not this server's address ({}); requests for other names are refused (DNS rebinding). Add --allow-host NAME to serve under another name (a reverse proxy)",
                fastbrdf_io::shorten(host, 64),
                hosts.expected()
            ),
        );
    }
    if req.target.starts_with("/api/")
        && let Some(why) = cross_site(hosts, req)
    {
        return Response::error(403, &why);
    }
    if req.has_body {
        return Response::error(
            413,
            "request bodies are refused: the API is GET-only, parameters go in the query",
        );
    }
    let (method, target) = (req.method, req.target);
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
            // No icon: an empty answer instead of a 404 (a console error on every page load).
            "/favicon.ico" => Ok(Response {
                status: 204,
                content_type: "image/x-icon",
                body: Vec::new(),
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

/// The transport's limits (the defaults are the constants above; `fastbrdf view` takes them
/// from its arguments, the tests lower them).
#[derive(Clone, Debug)]
pub struct Limits {
    /// Connections served at once (lowered to fit the open-file limit).
    pub max_connections: usize,
    /// A connection silent this long (at its start, or after an answer) is closed, and a
    /// request head must be complete within this of its first byte or of the previous answer.
    pub idle_timeout: Duration,
    /// A write the client does not take for this long closes the connection.
    pub write_timeout: Duration,
    /// `--allow-host` names.
    pub allow_hosts: Vec<String>,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_connections: MAX_CONNECTIONS,
            idle_timeout: Duration::from_secs(IDLE_TIMEOUT_S),
            write_timeout: Duration::from_secs(WRITE_TIMEOUT_S),
            allow_hosts: Vec::new(),
        }
    }
}

/// `wanted`, lowered so that connections leave [`FD_RESERVE`] descriptors of the open-file
/// limit free (at least 1).
fn fit_to_fd_limit(wanted: usize) -> usize {
    #[cfg(unix)]
    {
        let mut r = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes the struct it is given and nothing else.
        if unsafe { libc::getrlimit(libc::RLIMIT_NOFILE, &mut r) } == 0
            && r.rlim_cur != libc::RLIM_INFINITY
        {
            let free = r.rlim_cur.saturating_sub(FD_RESERVE).max(1);
            return wanted.min(usize::try_from(free).unwrap_or(usize::MAX));
        }
    }
    wanted
}

/// What every connection's task shares.
struct Shared {
    state: Arc<State>,
    hosts: Hosts,
    limits: Limits,
    /// Computations ([`COMPUTED`] paths) under way, one permit each, held until the handler
    /// returns, even when its client has gone: [`compute_slots`].
    computing: Arc<tokio::sync::Semaphore>,
    computing_max: usize,
}

/// The endpoints that compute (time in the milliseconds to seconds) under a computation
/// permit; renders (`/api/render`) have their own slots ([`RENDER_SLOTS`], [`MAX_WAITING`]);
/// the others (the page, `/api/models`, `/api/shader`, `/api/material`, errors) answer at once.
const COMPUTED: [&str; 3] = ["/api/plots", "/api/albedo", "/api/errors"];

/// A running server: its address and the runtime that serves it.
pub struct Server {
    pub addr: SocketAddr,
    /// The connection cap in force (`Limits::max_connections` fitted to the open-file limit).
    pub max_connections: usize,
    runtime: Option<tokio::runtime::Runtime>,
    stop: Arc<tokio::sync::Notify>,
    accepting: Option<tokio::task::JoinHandle<()>>,
}

impl Server {
    /// Binds `addr` and starts serving: a tokio runtime of 2 threads accepts and speaks
    /// HTTP/1.1 (hyper); each request's [`handle`] runs on the runtime's blocking pool, which
    /// has a thread for every connection the cap allows (so a cheap request never waits for a
    /// thread behind renders; renders themselves wait for [`RENDER_SLOTS`]).
    pub fn start(addr: SocketAddr, state: Arc<State>, limits: Limits) -> Result<Self, CliError> {
        let std_listener = std::net::TcpListener::bind(addr)
            .map_err(|e| CliError::input(format!("cannot listen on {addr}: {e}")))?;
        let addr = std_listener
            .local_addr()
            .map_err(|e| CliError::input(format!("cannot listen on {addr}: {e}")))?;
        std_listener
            .set_nonblocking(true)
            .map_err(|e| CliError::input(format!("cannot listen on {addr}: {e}")))?;
        let max_connections = fit_to_fd_limit(limits.max_connections.max(1));
        let computing_max = compute_slots();
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            // A thread for each connection's request, and for each computation or render
            // (running or waiting for a slot) whose client has gone: nothing ever waits in
            // the pool's queue.
            .max_blocking_threads(max_connections + computing_max + RENDER_SLOTS + MAX_WAITING + 8)
            .thread_name("fastbrdf-view")
            .enable_io()
            .enable_time()
            .build()
            .map_err(|e| CliError::input(format!("cannot start the server's runtime: {e}")))?;
        let listener = {
            let _inside = runtime.enter();
            tokio::net::TcpListener::from_std(std_listener)
                .map_err(|e| CliError::input(format!("cannot listen on {addr}: {e}")))?
        };
        let shared = Arc::new(Shared {
            state,
            hosts: Hosts::new(addr, &limits.allow_hosts),
            limits,
            computing: Arc::new(tokio::sync::Semaphore::new(computing_max)),
            computing_max,
        });
        let stop = Arc::new(tokio::sync::Notify::new());
        let accepting = runtime.spawn(accept_loop(listener, shared, max_connections, stop.clone()));
        Ok(Self {
            addr,
            max_connections,
            runtime: Some(runtime),
            stop,
            accepting: Some(accepting),
        })
    }

    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Blocks until the server stops ([`Server::stop`] from another thread, or a signal); an
    /// error if the accept loop ended otherwise (a panic), so that the exit status says so.
    pub fn wait(mut self) -> Result<(), CliError> {
        if let (Some(rt), Some(task)) = (self.runtime.as_ref(), self.accepting.take()) {
            rt.block_on(task).map_err(|e| {
                CliError::io(format!(
                    "fastbrdf view: the server stopped unexpectedly: {e}"
                ))
            })?;
        }
        Ok(())
    }

    /// Stops accepting connections (those open finish their request).
    pub fn stop(&self) {
        self.stop.notify_one();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        // A render still running on the blocking pool cannot be interrupted: leave it behind
        // rather than wait for it.
        if let Some(rt) = self.runtime.take() {
            rt.shutdown_background();
        }
    }
}

/// Accepts until stopped. Over the cap a connection gets a short 503 and is closed; a failed
/// accept (out of file descriptors: EMFILE, ENFILE; or a connection reset before it was
/// accepted) is retried after [`ACCEPT_RETRY`]: the listener is never dropped.
async fn accept_loop(
    listener: tokio::net::TcpListener,
    shared: Arc<Shared>,
    max_connections: usize,
    stop: Arc<tokio::sync::Notify>,
) {
    let open = Arc::new(tokio::sync::Semaphore::new(max_connections));
    let refusing = Arc::new(tokio::sync::Semaphore::new(MAX_REFUSING));
    let mut last_warning: Option<std::time::Instant> = None;
    loop {
        let accepted = tokio::select! {
            _ = stop.notified() => return,
            r = listener.accept() => r,
        };
        match accepted {
            Ok((stream, _)) => {
                if let Ok(permit) = open.clone().try_acquire_owned() {
                    let shared = shared.clone();
                    tokio::spawn(async move {
                        serve_connection(stream, &shared).await;
                        drop(permit);
                    });
                } else if let Ok(permit) = refusing.clone().try_acquire_owned() {
                    tokio::spawn(async move {
                        refuse(stream, max_connections).await;
                        drop(permit);
                    });
                }
                // Else: too many refusals under way already; the connection closes unanswered.
            }
            Err(e) => {
                if last_warning.is_none_or(|t| t.elapsed() >= Duration::from_secs(10)) {
                    note(&format!(
                        "warning: fastbrdf view: accepting a connection failed: {e}; retrying"
                    ));
                    last_warning = Some(std::time::Instant::now());
                }
                tokio::time::sleep(ACCEPT_RETRY).await;
            }
        }
    }
}

/// The 503 of a connection over the cap: written and the sending side shut within
/// [`REFUSAL_TIME`].
async fn refuse(mut stream: tokio::net::TcpStream, cap: usize) {
    use tokio::io::AsyncWriteExt;
    let body = Response::error(
        503,
        &format!("too many connections ({cap} open); try again when one closes"),
    )
    .body;
    let head = format!(
        "HTTP/1.1 503 Service Unavailable\r\ncontent-type: application/json\r\ncontent-length: {}\r\nretry-after: 1\r\ncache-control: no-store\r\nconnection: close\r\n\r\n",
        body.len()
    );
    let _ = tokio::time::timeout(REFUSAL_TIME, async {
        stream.write_all(head.as_bytes()).await?;
        stream.write_all(&body).await?;
        stream.shutdown().await?;
        Ok::<_, std::io::Error>(())
    })
    .await;
    // Read what the client sent meanwhile, briefly, so that the close does not reset the
    // answer away; the slot is free again within [`REFUSAL_DRAIN`].
    let _ = tokio::time::timeout(REFUSAL_DRAIN, drain(&mut stream)).await;
}

/// Reads and drops what the client sends until it closes (at most 64 KiB).
async fn drain(stream: &mut tokio::net::TcpStream) -> std::io::Result<()> {
    use tokio::io::AsyncReadExt;
    let mut sink = [0u8; 4096];
    let mut total = 0;
    while total < 65536 {
        let n = stream.read(&mut sink).await?;
        if n == 0 {
            break;
        }
        total += n;
    }
    Ok(())
}

/// The HTTP/2 connection preface (RFC 9113, section 3.4).
const H2_PREFACE: &[u8; 24] = b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n";

/// How a connection opens.
enum Opening {
    /// The HTTP/2 preface ("prior knowledge").
    H2,
    /// Anything else: hyper reads it (every HTTP/1 request differs from the preface at its
    /// first bytes).
    Http1,
    /// Nothing within the idle timeout, or the end of the stream: nothing to answer.
    Silent,
}

/// Looks at the first bytes, waiting at most `wait` for them; only peeks, so that hyper reads
/// everything itself.
async fn opening(stream: &tokio::net::TcpStream, wait: Duration) -> Opening {
    let deadline = tokio::time::Instant::now() + wait;
    let mut buf = [0u8; 24];
    loop {
        let n = match tokio::time::timeout_at(deadline, stream.peek(&mut buf)).await {
            Ok(Ok(n)) => n,
            _ => return Opening::Silent,
        };
        if n == 0 {
            return Opening::Silent;
        }
        if buf[..n] != H2_PREFACE[..n] {
            return Opening::Http1;
        }
        if n == H2_PREFACE.len() {
            return Opening::H2;
        }
        // Part of the preface: wait for the rest (hyper would only wait as long).
        if tokio::time::Instant::now() >= deadline {
            return Opening::Silent;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
}

/// Refuses an HTTP/2 connection in HTTP/2 (hyper's HTTP/1 server would close it without a
/// word): an empty SETTINGS frame, then GOAWAY with HTTP_1_1_REQUIRED (0xd, RFC 9113 section
/// 7) and a reason, which HTTP/2 clients report (curl then retries in HTTP/1.1).
async fn refuse_h2(mut stream: tokio::net::TcpStream) {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    const WHY: &[u8] = b"fastbrdf view speaks HTTP/1.1 only";
    let mut out = vec![0, 0, 0, 4, 0, 0, 0, 0, 0];
    let len = 8 + WHY.len();
    out.extend([
        (len >> 16) as u8,
        (len >> 8) as u8,
        len as u8,
        7,
        0,
        0,
        0,
        0,
        0,
    ]);
    out.extend([0, 0, 0, 0, 0, 0, 0, 0x0d]);
    out.extend(WHY);
    let _ = tokio::time::timeout(REFUSAL_TIME, async {
        let mut preface = [0u8; 24];
        stream.read_exact(&mut preface).await?;
        stream.write_all(&out).await?;
        stream.shutdown().await?;
        drain(&mut stream).await
    })
    .await;
}

/// Serves one connection in HTTP/1.1 until it closes, goes idle past the idle timeout, or
/// stops reading past the write timeout.
async fn serve_connection(stream: tokio::net::TcpStream, shared: &Arc<Shared>) {
    let limits = &shared.limits;
    let _ = stream.set_nodelay(true);
    match opening(&stream, limits.idle_timeout).await {
        Opening::H2 => return refuse_h2(stream).await,
        Opening::Silent => return,
        Opening::Http1 => {}
    }
    let mut io = tokio_io_timeout::TimeoutStream::new(stream);
    io.set_write_timeout(Some(limits.write_timeout));
    let io = hyper_util::rt::TokioIo::new(Box::pin(io));
    let for_service = shared.clone();
    let service = hyper::service::service_fn(move |req: hyper::Request<hyper::body::Incoming>| {
        let shared = for_service.clone();
        async move { Ok::<_, std::convert::Infallible>(answer(shared, req).await) }
    });
    let _ = hyper::server::conn::http1::Builder::new()
        .timer(hyper_util::rt::TokioTimer::new())
        .header_read_timeout(limits.idle_timeout)
        .max_header_size(MAX_HEAD)
        .max_headers(MAX_HEADERS)
        .max_buf_size(MAX_BUF)
        .serve_connection(io, service)
        .await;
}

/// What [`answer`] reads of a request, owned so that the blocking pool can take it; lent to
/// the checks and to [`handle`] as a [`Request`].
struct Head {
    method: String,
    target: String,
    host: Option<String>,
    has_body: bool,
    fetch_site: Option<String>,
    origin: Option<String>,
}

impl Head {
    fn request(&self) -> Request<'_> {
        Request {
            method: &self.method,
            target: &self.target,
            host: self.host.as_deref(),
            has_body: self.has_body,
            fetch_site: self.fetch_site.as_deref(),
            origin: self.origin.as_deref(),
        }
    }
}

/// Runs [`handle`] for one parsed request on the blocking pool and turns its answer into
/// hyper's.
async fn answer(
    shared: Arc<Shared>,
    req: hyper::Request<hyper::body::Incoming>,
) -> hyper::Response<http_body_util::Full<bytes::Bytes>> {
    use hyper::body::Body as _;
    let method = req.method().as_str().to_owned();
    let target = req
        .uri()
        .path_and_query()
        .map_or_else(|| req.uri().to_string(), |p| p.as_str().to_owned());
    let host = match req.uri().authority() {
        Some(a) => Some(a.as_str().to_owned()),
        None => req
            .headers()
            .get(hyper::header::HOST)
            .map(|h| String::from_utf8_lossy(h.as_bytes()).into_owned()),
    };
    let has_body = !req.body().is_end_stream();
    let header = |name: &str| {
        req.headers()
            .get(name)
            .map(|h| String::from_utf8_lossy(h.as_bytes()).into_owned())
    };
    let head = Head {
        method,
        target,
        host,
        has_body,
        fetch_site: header("sec-fetch-site"),
        origin: header("origin"),
    };
    drop(req);
    // A computation keeps running when its client goes (it cannot be interrupted), so a
    // client that asks and hangs up, again and again, could pile them up: at most
    // `computing_max` run, one more waits `COMPUTE_WAIT` then gets 503, and the quick requests
    // never wait for a thread.
    let path = head.target.split('?').next().unwrap_or("");
    // A refused request (foreign Host, cross-site) takes no permit: `handle` answers it.
    let refused = head
        .host
        .as_deref()
        .is_some_and(|h| !shared.hosts.allows(h))
        || cross_site(&shared.hosts, &head.request()).is_some();
    let permit = if COMPUTED.contains(&path) && !refused {
        match tokio::time::timeout(COMPUTE_WAIT, shared.computing.clone().acquire_owned()).await {
            Ok(Ok(p)) => Some(p),
            _ => {
                return to_hyper(
                    Response::error(
                        503,
                        &format!(
                            "busy: {} computations under way (some for clients that have gone); try again shortly",
                            shared.computing_max
                        ),
                    ),
                    has_body,
                );
            }
        }
    } else {
        None
    };
    let for_handler = shared.clone();
    let gone = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let _hangup = Hangup(gone.clone());
    let r = tokio::task::spawn_blocking(move || {
        let _permit = permit;
        GONE.with(|g| *g.borrow_mut() = Some(gone));
        struct Clear;
        impl Drop for Clear {
            fn drop(&mut self) {
                GONE.with(|g| *g.borrow_mut() = None);
            }
        }
        let _clear = Clear;
        handle(&for_handler.state, &for_handler.hosts, &head.request())
    })
    .await
    .unwrap_or_else(|_| Response::error(500, "internal error (a panic); the server goes on"));
    to_hyper(r, has_body)
}

/// hyper's response for `r`; `close`: the connection ends with it (a request body was left
/// unread).
fn to_hyper(r: Response, close: bool) -> hyper::Response<http_body_util::Full<bytes::Bytes>> {
    let mut b = hyper::Response::builder()
        .status(r.status)
        .header(hyper::header::CONTENT_TYPE, r.content_type)
        .header(hyper::header::CACHE_CONTROL, "no-store")
        .header("x-content-type-options", "nosniff")
        .header("x-frame-options", "DENY");
    if close {
        b = b.header(hyper::header::CONNECTION, "close");
    }
    b.body(http_body_util::Full::new(bytes::Bytes::from(r.body)))
        .unwrap_or_else(|_| {
            let mut r = hyper::Response::new(http_body_util::Full::new(bytes::Bytes::new()));
            *r.status_mut() = hyper::StatusCode::INTERNAL_SERVER_ERROR;
            r
        })
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
    let limits = Limits {
        max_connections: a.max_connections as usize,
        idle_timeout: Duration::from_secs(a.idle_timeout),
        write_timeout: Duration::from_secs(a.write_timeout),
        allow_hosts: a.allow_host.clone(),
    };
    let server = Server::start(SocketAddr::new(a.host, port), state, limits)?;
    if server.max_connections < a.max_connections as usize {
        note(&format!(
            "note: at most {} connections at once (the open-file limit less {FD_RESERVE})",
            server.max_connections
        ));
    }
    if !loopback {
        note(&format!(
            "warning: serving on {}: every machine that reaches this address can use the explorer (no authentication)",
            server.addr
        ));
    }
    if let Some(out) = &a.screenshot {
        let url = format!("{}#{}", server.url(), a.state);
        let png = cdp::screenshot(a.browser.as_deref(), &url, 1400, 1050)
            .map_err(|e| CliError::input(format!("--screenshot: {e}")))?;
        fastbrdf_io::write_atomic(out, &png)?;
        note(&format!(
            "wrote {} ({} bytes, from {url})",
            out.display(),
            png.len()
        ));
        server.stop();
        return Ok(());
    }
    note(&format!(
        "fastbrdf view: serving on {} (Ctrl-C to stop)",
        server.url()
    ));
    if a.open {
        let url = server.url();
        let opener = cdp::find_browser(a.browser.as_deref())
            .map(|b| b.display().to_string())
            .unwrap_or_else(|_| "xdg-open".into());
        if let Err(e) = std::process::Command::new(&opener).arg(&url).spawn() {
            note(&format!(
                "warning: --open: cannot start {opener}: {e}; open {url} yourself"
            ));
        }
    }
    server.wait()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hosts_name_the_bound_address_only() {
        let loopback = Hosts::new("127.0.0.1:8000".parse().unwrap(), &[]);
        for ok in [
            "127.0.0.1:8000",
            "localhost:8000",
            "LocalHost.:8000",
            "[::1]:8000",
            "127.0.0.2:8000",
        ] {
            assert!(loopback.allows(ok), "{ok}");
        }
        for bad in [
            "evil.example:8000",
            "localhost",
            "localhost:8001",
            "127.0.0.1",
            "10.0.0.1:8000",
            "[::1]",
            "[::1:8000",
            "localhost:80x",
            "",
        ] {
            assert!(!loopback.allows(bad), "{bad}");
        }
        let on_80 = Hosts::new("[::1]:80".parse().unwrap(), &["proxy.example:443".into()]);
        assert!(on_80.allows("localhost") && on_80.allows("[::1]"));
        assert!(on_80.allows("proxy.example:443") && !on_80.allows("proxy.example"));
        let any = Hosts::new("0.0.0.0:9000".parse().unwrap(), &["box.lan".into()]);
        assert!(any.allows("192.168.1.7:9000") && any.allows("localhost:9000"));
        assert!(any.allows("box.lan") && any.allows("box.lan:1234"));
        assert!(!any.allows("evil.example:9000") && !any.allows("192.168.1.7:9001"));
        let lan = Hosts::new("192.168.1.7:9000".parse().unwrap(), &[]);
        assert!(lan.allows("192.168.1.7:9000"));
        assert!(!lan.allows("localhost:9000") && !lan.allows("127.0.0.1:9000"));
    }

    /// The numbers `fastbrdf view --help` states are the constants in force.
    #[test]
    fn help_states_the_limits() {
        use clap::Args as _;
        let help = Args::augment_args(clap::Command::new("view"))
            .render_long_help()
            .to_string()
            .replace('\n', " ");
        for stated in [
            format!("at most {MAX_CONNECTIONS} connections"),
            format!("leave {FD_RESERVE} of the open-file limit"),
            format!("at most {} KiB and {MAX_HEADERS} fields", MAX_HEAD / 1024),
            format!("targets {} KiB", MAX_URL / 1024),
            format!("within {IDLE_TIMEOUT_S} s"),
            format!("for {WRITE_TIMEOUT_S} s"),
            format!("{RENDER_SLOTS} renders at once and {MAX_WAITING} waiting"),
            "as many plots/albedo/errors computations at once as CPUs (at least 2)".into(),
            format!("waits {} s then gets 503", COMPUTE_WAIT.as_secs()),
            "refuses cross-site requests".into(),
        ] {
            assert!(help.contains(&stated), "--help lacks '{stated}': {help}");
        }
    }
}
