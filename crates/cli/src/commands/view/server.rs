//! The explorer's transport: hyper's HTTP/1.1 on a 2-thread tokio runtime, the connection
//! cap and its 503, the HTTP/2 refusal, the timeouts, the computation permits, and each
//! request's [`handle`] on the blocking pool.

use super::api::Response;
use super::request::{Hosts, MAX_URL, Request, UPLOAD, cross_site, handle};
use super::state::{COMPUTE_WAIT, GONE, Hangup, MAX_WAITING, RENDER_SLOTS, State, compute_slots};
use crate::CliError;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

/// Writes `msg` and a newline on stderr, ignoring failures: after start-up stderr may be a
/// pipe whose reader has gone (`fastbrdf view 2>&1 | head -1`), which must not stop the server
/// (`eprintln!` panics on a failed write).
pub fn note(msg: &str) {
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
/// permit (an upload compiles a shader and a GPU pipeline, conform runs its 11 checks);
/// renders (`/api/render`) have their own slots ([`RENDER_SLOTS`], [`MAX_WAITING`]); the
/// others (the page, `/api/models`, `/api/shader`, `/api/material`, errors) answer at once.
const COMPUTED: [&str; 6] = [
    "/api/plots",
    "/api/panes",
    "/api/albedo",
    "/api/errors",
    UPLOAD,
    "/api/conform",
];

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
    /// The body of an upload, read ([`read_body`]).
    body: Option<Vec<u8>>,
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
            body: self.body.as_deref(),
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
    let mut head = Head {
        method,
        target,
        host,
        has_body,
        body: None,
        fetch_site: header("sec-fetch-site"),
        origin: header("origin"),
    };
    let incoming = req.into_body();
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
    // The one body read: an upload's, bounded ([`read_body`]); any other is left unread and
    // refused by `handle` (the connection then closes).
    let mut unread = has_body;
    if head.method == "POST" && path == UPLOAD && !refused && head.target.len() <= MAX_URL {
        match read_body(incoming, shared.limits.idle_timeout).await {
            Ok(b) => {
                head.body = Some(b);
                unread = false;
            }
            Err(r) => return to_hyper(r, true),
        }
    } else {
        drop(incoming);
    }
    let path = head.target.split('?').next().unwrap_or("");
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
                    unread,
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
    to_hyper(r, unread)
}

/// An upload's body: at most [`MAX_UPLOAD`](super::api::MAX_UPLOAD) bytes (a larger
/// `Content-Length` is 413 before a byte is read, a longer body 413 when the limit is
/// passed), complete within `wait` (else 408).
async fn read_body(body: hyper::body::Incoming, wait: Duration) -> Result<Vec<u8>, Response> {
    use http_body_util::BodyExt;
    use hyper::body::Body as _;
    let cap = super::api::MAX_UPLOAD;
    let too_large = || {
        Response::error(
            413,
            &format!("the body is over {cap} bytes: an uploaded model is at most {cap} bytes"),
        )
    };
    if body.size_hint().lower() > cap as u64 {
        return Err(too_large());
    }
    match tokio::time::timeout(wait, http_body_util::Limited::new(body, cap).collect()).await {
        Err(_) => Err(Response::error(
            408,
            &format!("the body did not arrive within {} s", wait.as_secs_f64()),
        )),
        Ok(Err(e)) if e.is::<http_body_util::LengthLimitError>() => Err(too_large()),
        Ok(Err(e)) => Err(Response::error(
            400,
            &format!("reading the body failed: {e}"),
        )),
        Ok(Ok(c)) => Ok(c.to_bytes().to_vec()),
    }
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
