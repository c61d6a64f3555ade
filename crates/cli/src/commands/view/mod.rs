//! `fastbrdf view`: an interactive explorer in the browser. An HTTP/1.1 server (hyper on a small
//! tokio runtime, loopback only unless `--allow-remote`) serves one page embedded in the binary
//! (`page/`: hand-written HTML, CSS and JavaScript, joined into one page, plots drawn on `<canvas>` from the JSON
//! numbers; no CDN, works offline; every string from the link, a file name or the server goes into
//! the page as text, never as HTML) and the JSON API of [`api`] that the page calls.
//!
//! One client must never take the explorer down. The limits:
//! - connections: at most [`MAX_CONNECTIONS`] open (`--max-connections`, lowered to leave
//!   [`FD_RESERVE`] of the open-file limit free); more get a short 503 and are closed, and a failed
//!   accept (out of file descriptors) is retried after [`ACCEPT_RETRY`](server::ACCEPT_RETRY),
//!   never the end of the listener;
//! - request heads: at most [`MAX_HEAD`](server::MAX_HEAD) bytes and
//!   [`MAX_HEADERS`](server::MAX_HEADERS) fields (431, hyper's), the target at most `MAX_URL` bytes
//!   (414); a request with a body is refused (413, connection closed) without reading it: the API
//!   is GET-only;
//! - time: a connection that sends nothing for [`IDLE_TIMEOUT_S`] seconds (at its start, or after
//!   an answer: idle keep-alive) is closed, and a request head must be complete within as long of
//!   its first byte (or of the previous answer); a write the client does not read for
//!   [`WRITE_TIMEOUT_S`] seconds closes the connection (a client that pipelines and never reads
//!   stalls only itself);
//! - `Host` (or an absolute target's authority) must name the bound address (see
//!   [`Hosts`](request::Hosts)): 403 otherwise (DNS rebinding);
//! - HTTP/2 is not spoken: its preface gets an HTTP/2 GOAWAY (HTTP_1_1_REQUIRED), a request line of
//!   another version hyper's 400;
//! - work: each request's [`handle`](request::handle) runs on the runtime's blocking pool. A
//!   computation cannot be interrupted once it runs, so one client asking and hanging up could pile
//!   them up: at most [`compute_slots`](state::compute_slots) (as many as CPUs, at least 2) plots,
//!   albedo and errors computations run at once, a further one waits at most
//!   [`COMPUTE_WAIT`](state::COMPUTE_WAIT) for a permit, then gets 503; renders take one of
//!   [`RENDER_SLOTS`](state::RENDER_SLOTS) slots (at most [`MAX_WAITING`](state::MAX_WAITING) wait,
//!   the rest get 503), each at most `api::MAX_SIZE` square and `api::MAX_SPP` samples per axis;
//!   their FLIP runs in [`flip`]'s pool (a thread per CPU, lower priority, the pictures of at
//!   most [`FLIP_JOBS`](flip::FLIP_JOBS) renders held; a render that finds them taken computes
//!   FLIP in its slot), so the pictures answer before it (`flip=later`, then `/api/flip`).
//!   The pool has a thread for each of these and for each connection, so a quick request (the page,
//!   `/api/models`) never waits behind computations, and the two runtime workers (accept, HTTP)
//!   compete with a bounded number of busy threads. A render whose client has gone
//!   ([`client_gone`](state::client_gone)), or has sent a newer generation since (409), is dropped
//!   before each model's render. Every handler runs under `catch_unwind`: a panic is a 500, never a
//!   dead server;
//! - cross-site requests: a page of another site can make the browser send requests to 127.0.0.1
//!   (its `Host` passes), so `/api/*` refuses (403) a request marked `Sec-Fetch-Site: cross-site`
//!   or `same-site`, or whose `Origin` is not `http://` (or `https://`) and an allowed host (see
//!   [`cross_site`](request::cross_site)); the page's own requests and tools such as curl (no such
//!   header) are served;
//! - stderr: after start-up the server writes to stderr ignoring failures (a closed pipe, as in
//!   `fastbrdf view 2>&1 | head -1`), so that losing stderr never stops it.
//!
//! Where it lives: [`state`] (what the handlers share), [`users`] (the users' models of
//! `--model file:PATH`, compiled on the GPU per set of values), [`flip`] (FLIP off the requests'
//! critical path), [`request`] (the checks and
//! [`handle`](request::handle)), [`server`] (the transport), [`api`] (the endpoints: the query
//! parsed into model specs once per request), `page/` (index.html and its scripts, joined by `request::PAGE`), [`cdp`] (the DevTools client).

pub mod api;
pub mod cdp;
mod flip;
mod measure;
mod request;
mod server;
mod state;
mod users;

use crate::CliError;
use request::host_name;
use server::{FD_RESERVE, IDLE_TIMEOUT_S, Limits, MAX_CONNECTIONS, Server, WRITE_TIMEOUT_S, note};
use state::State;
use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf view                          (http://127.0.0.1:8000/)\n  \
fastbrdf view --port 9000 --open\n  \
fastbrdf view --mesh face              (the embedded face beside the sphere)\n  \
fastbrdf view --mesh head.obj --bench bench.json   (your mesh; costs from `fastbrdf bench --json`)\n  \
fastbrdf view --screenshot docs/images/view.png   (headless Chromium, then exit)\n  \
fastbrdf view --measure-frames 20 --state 'models=flog,power16,schlick&ref=pow&n=100'   (WebGPU redraw times, JSON)\n  \
fastbrdf view --measured gold-metallic-paint.binary   (the MERL file as a reference: #models=ward&ref=gold-metallic-paint.binary)\n  \
fastbrdf view --model file:walter.brdf --param alphaG=0.2   (your BRDF beside the built-ins: #models=walter.brdf,cook-torrance)\n  \
curl 'http://127.0.0.1:8000/api/errors?model=flog&ref=pow&n=100'\n\n\
The whole view lives in the URL after #, so a link reproduces it. The JSON API (the book's\n\
docs/book/src/explorer.md): /api/models, /api/plots, /api/panes, /api/albedo, /api/render, /api/flip, /api/errors, /api/shader, /api/material,\n\
/api/gpu/scene, /api/gpu/shader (the page's WebGPU pictures), POST /api/user, /api/conform.\n\
Bad requests get HTTP 400 with the message the CLI prints for the same input.\n\n\
Limits (one client cannot take the server down): HTTP/1.1 only (HTTP/2 is refused with a GOAWAY);\n\
at most 128 connections (--max-connections; lowered to leave 64 of the open-file limit free),\n\
more get 503; request heads at most 16 KiB and 64 fields (431), targets 8 KiB (414); GET only\n\
but POST /api/user (a user's model, at most 256 KiB), other bodies refused (413); a request head must arrive within 20 s (idle connections are closed), a\n\
client that does not read an answer for 30 s is dropped; Host must name the bound address\n\
(127.0.0.1, localhost or [::1] on loopback; --allow-host NAME for a proxy), else 403; /api/*\n\
refuses cross-site requests (Sec-Fetch-Site cross-site or same-site, or an Origin that is not\n\
an allowed host) with 403; as many plots/albedo/errors computations at once as CPUs (at least\n\
2), one more waits 1 s then gets 503; 2 renders at once and 8 waiting (503 beyond), 1024x1024\n\
and 4x4 samples at most; FLIP on a thread per CPU at a lower priority, for at most 4 renders'\n\
pictures at once (a render beyond computes it itself)."
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
    /// A latitude-longitude environment map (Radiance .hdr or OpenEXR, as `render --env`)
    /// the page's WebGPU pictures may be lit by (its "light" menu: file); the built-in sky is
    /// always offered.
    #[arg(long, value_name = "FILE")]
    env: Option<PathBuf>,
    /// A user's model, file:PATH (a BRDF Explorer .brdf file, or a .wgsl or .glsl function; the
    /// book's user-shaders page), listed beside the registry's models, as a model or a
    /// reference, evaluated on the GPU (Mesa's lavapipe without one); repeatable. A bad file or
    /// a compile error is exit 2 at start-up, naming the file, line and column.
    #[arg(long = "model", value_name = "file:PATH")]
    model: Vec<String>,
    /// A value of a --model file's parameter, NAME=VALUE (its start-up value; the page's
    /// sliders change it), checked against the range the file declares; repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    param: Vec<String>,
    /// Take a screenshot of the page in headless Chromium to this PNG file, then exit.
    #[arg(long, value_name = "FILE.png")]
    screenshot: Option<PathBuf>,
    /// Measure how fast the page redraws as a control moves, with WebGPU in headless
    /// Chromium (its software adapter, SwiftShader): N moves of the first numeric slider of
    /// --state's view, then print the page's own measures as JSON (`fastbrdf:frame`, control
    /// to drawn frame; `fastbrdf:settle`; frames drawn back to back) and exit.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1000))]
    measure_frames: Option<u32>,
    /// With --screenshot or --measure-frames: the view (the part of the page's URL after #).
    #[arg(long, default_value = "models=flog,schlick&ref=pow&n=60&theta=35")]
    state: String,
    /// The Chromium executable (default: chromium, chromium-browser or google-chrome on PATH).
    #[arg(long, value_name = "PATH")]
    browser: Option<PathBuf>,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let loopback = a.host.is_loopback();
    if !loopback && !a.allow_remote {
        return Err(CliError::input(format!(
            "--host {}: not a loopback address; add --allow-remote to serve other machines",
            a.host
        )));
    }
    let state = State::new(a.mesh.clone(), a.bench.clone(), a.measured.clone())?;
    let taken: Vec<&str> = state.measured.iter().map(|m| m.name.as_str()).collect();
    let users = users::load(&a.model, &a.param, &taken)?;
    let state = Arc::new(state.with_users(users).with_env(a.env.as_deref())?);
    let port = if a.screenshot.is_some() || a.measure_frames.is_some() {
        0
    } else {
        a.port
    };
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
    if let Some(moves) = a.measure_frames {
        let url = format!("{}#{}", server.url(), a.state);
        let m = measure::measure(a.browser.as_deref(), &url, moves)
            .map_err(|e| CliError::input(format!("--measure-frames: {e}")));
        server.stop();
        let m = m?;
        let f = &m["frame_ms"];
        note(&format!(
            "control to frame: median {:.1} ms over {} moves ({} pictures; {}x{} when a frame is fast, else {}x{} while moving); full size drawn back to back: median {:.1} ms",
            f["median"].as_f64().unwrap_or(f64::NAN),
            moves,
            m["pictures"],
            m["size"],
            m["size"],
            m["preview_size"],
            m["preview_size"],
            m["alone_ms"]["size"]["median"].as_f64().unwrap_or(f64::NAN)
        ));
        return crate::commands::write_stdout(
            format!("{}\n", serde_json::to_string_pretty(&m).unwrap_or_default()).as_bytes(),
        );
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
    use super::request::MAX_URL;
    use super::server::{MAX_HEAD, MAX_HEADERS};
    use super::state::{COMPUTE_WAIT, MAX_WAITING, RENDER_SLOTS};
    use super::*;

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
            format!(
                "at most {} renders' pictures at once",
                super::flip::FLIP_JOBS
            ),
            "as many plots/albedo/errors computations at once as CPUs (at least 2)".into(),
            format!("waits {} s then gets 503", COMPUTE_WAIT.as_secs()),
            "refuses cross-site requests".into(),
        ] {
            assert!(help.contains(&stated), "--help lacks '{stated}': {help}");
        }
    }
}
