//! A minimal Chrome DevTools Protocol client over `--remote-debugging-pipe` (JSON messages
//! ended by a NUL byte on file descriptors 3 and 4): enough to load a page, run JavaScript,
//! send mouse events and take a screenshot, with no WebSocket or async runtime to compile.
//! Used by `fastbrdf view --screenshot` and by the end-to-end test (`tests/explorer/mod.rs` includes
//! this file).

use serde_json::{Value, json};
use std::io::{BufRead, BufReader, Write};
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::time::{Duration, Instant};

/// The Chromium to run: `explicit`, else `$FASTBRDF_BROWSER`, else the first of chromium,
/// chromium-browser, google-chrome on PATH.
pub fn find_browser(explicit: Option<&Path>) -> Result<PathBuf, String> {
    if let Some(p) = explicit {
        return Ok(p.to_path_buf());
    }
    if let Some(p) = std::env::var_os("FASTBRDF_BROWSER") {
        return Ok(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        for dir in std::env::split_paths(&path) {
            let p = dir.join(name);
            if p.is_file() {
                return Ok(p);
            }
        }
    }
    Err("no Chromium found (install Debian's chromium, or give --browser PATH)".into())
}

/// A headless Chromium driven over the pipe; killed (and its profile removed) on drop.
pub struct Browser {
    child: Child,
    to_chrome: std::fs::File,
    from_chrome: Receiver<Value>,
    next_id: u64,
    profile: PathBuf,
}

fn pipe() -> Result<(OwnedFd, OwnedFd), String> {
    let mut fds = [0; 2];
    // SAFETY: pipe2 writes two new descriptors into the array we own.
    let rc = unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) };
    if rc != 0 {
        return Err(format!("pipe: {}", std::io::Error::last_os_error()));
    }
    // SAFETY: both descriptors were just created and are owned by nobody else.
    Ok(unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) })
}

impl Browser {
    /// Starts `browser` headless with a new empty profile (the flags that keep it from
    /// reaching for the network, which hangs it on a closed machine).
    pub fn start(browser: &Path) -> Result<Self, String> {
        Self::start_with(browser, false)
    }

    /// [`Browser::start`], with WebGPU on the software adapter (SwiftShader) when `webgpu`:
    /// the explorer then draws its pictures itself; without it the page has no WebGPU and
    /// shows the server's.
    pub fn start_with(browser: &Path, webgpu: bool) -> Result<Self, String> {
        use std::os::fd::AsRawFd;
        static STARTED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let profile = std::env::temp_dir().join(format!(
            "fastbrdf-chromium-{}-{}",
            std::process::id(),
            STARTED.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
        ));
        // A new, empty profile: a left-over one from a killed run is removed first.
        let _ = std::fs::remove_dir_all(&profile);
        std::fs::create_dir_all(&profile).map_err(|e| format!("{}: {e}", profile.display()))?;
        let (chrome_reads, we_write) = pipe()?;
        let (we_read, chrome_writes) = pipe()?;
        let (r, w) = (chrome_reads.as_raw_fd(), chrome_writes.as_raw_fd());
        let mut cmd = Command::new(browser);
        if webgpu {
            cmd.args(["--enable-unsafe-webgpu", "--use-webgpu-adapter=swiftshader"]);
            if let Ok(extra) = std::env::var("FASTBRDF_CHROMIUM_FLAGS") {
                cmd.args(extra.split_whitespace());
            }
        } else {
            cmd.arg("--disable-gpu");
        }
        cmd.args([
            "--headless",
            "--no-sandbox",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--hide-scrollbars",
            "--mute-audio",
            "--remote-debugging-pipe",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("about:blank")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null());
        // SAFETY: only async-signal-safe calls (fcntl, dup2) between fork and exec.
        unsafe {
            cmd.pre_exec(move || {
                // Move both ends above 4 first, so that dup2 onto 3 and 4 cannot clobber one.
                let a = libc::fcntl(r, libc::F_DUPFD, 10);
                let b = libc::fcntl(w, libc::F_DUPFD, 10);
                if a < 0 || b < 0 || libc::dup2(a, 3) < 0 || libc::dup2(b, 4) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let child = cmd
            .spawn()
            .map_err(|e| format!("cannot start {}: {e}", browser.display()))?;
        drop((chrome_reads, chrome_writes));
        let (tx, rx) = channel();
        let reader = std::fs::File::from(we_read);
        std::thread::spawn(move || {
            let mut r = BufReader::new(reader);
            let mut buf = vec![];
            loop {
                buf.clear();
                match r.read_until(0, &mut buf) {
                    Ok(0) | Err(_) => return,
                    Ok(_) => {
                        if buf.last() == Some(&0) {
                            buf.pop();
                        }
                        if let Ok(v) = serde_json::from_slice::<Value>(&buf)
                            && tx.send(v).is_err()
                        {
                            return;
                        }
                    }
                }
            }
        });
        Ok(Self {
            child,
            to_chrome: std::fs::File::from(we_write),
            from_chrome: rx,
            next_id: 1,
            profile,
        })
    }

    /// Sends a command (to a page's `session`, or to the browser) and waits for its result.
    pub fn call(
        &mut self,
        session: Option<&str>,
        method: &str,
        params: Value,
    ) -> Result<Value, String> {
        let id = self.next_id;
        self.next_id += 1;
        let mut msg = json!({"id": id, "method": method, "params": params});
        if let Some(s) = session {
            msg["sessionId"] = json!(s);
        }
        let mut bytes = serde_json::to_vec(&msg).expect("serialisable");
        bytes.push(0);
        self.to_chrome
            .write_all(&bytes)
            .map_err(|e| format!("{method}: the browser went away: {e}"))?;
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.from_chrome.recv_timeout(left) {
                Ok(v) if v["id"] == json!(id) => {
                    if let Some(e) = v.get("error") {
                        return Err(format!("{method}: {e}"));
                    }
                    return Ok(v["result"].clone());
                }
                Ok(_) => {} // an event, or another answer
                Err(RecvTimeoutError::Timeout) => {
                    return Err(format!("{method}: no answer in 60 s"));
                }
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(format!("{method}: the browser closed its pipe"));
                }
            }
        }
    }

    /// Opens `url` in a new page of `width` x `height` CSS pixels; returns its session.
    pub fn open(&mut self, url: &str, width: u32, height: u32) -> Result<String, String> {
        let t = self.call(None, "Target.createTarget", json!({"url": "about:blank"}))?;
        let target = t["targetId"].as_str().ok_or("no targetId")?.to_string();
        let a = self.call(
            None,
            "Target.attachToTarget",
            json!({"targetId": target, "flatten": true}),
        )?;
        let s = a["sessionId"].as_str().ok_or("no sessionId")?.to_string();
        self.call(
            Some(&s),
            "Emulation.setDeviceMetricsOverride",
            json!({"width": width, "height": height, "deviceScaleFactor": 1, "mobile": false}),
        )?;
        self.call(Some(&s), "Page.navigate", json!({"url": url}))?;
        Ok(s)
    }

    /// Evaluates JavaScript in the page (promises awaited); returns its value.
    pub fn eval(&mut self, session: &str, expression: &str) -> Result<Value, String> {
        let r = self.call(
            Some(session),
            "Runtime.evaluate",
            json!({"expression": expression, "awaitPromise": true, "returnByValue": true}),
        )?;
        if let Some(e) = r.get("exceptionDetails") {
            return Err(format!("JavaScript exception in `{expression}`: {e}"));
        }
        Ok(r["result"]["value"].clone())
    }

    /// Polls `expression` until it is true (every 50 ms, at most `timeout`).
    pub fn wait_for(
        &mut self,
        session: &str,
        expression: &str,
        timeout: Duration,
    ) -> Result<(), String> {
        let deadline = Instant::now() + timeout;
        loop {
            if self
                .eval(session, expression)
                .is_ok_and(|v| v == json!(true))
            {
                return Ok(());
            }
            if Instant::now() > deadline {
                return Err(format!("`{expression}` not true within {timeout:?}"));
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// A mouse event (`mousePressed`, `mouseMoved`, `mouseReleased`) at CSS pixel (x, y).
    #[allow(dead_code)] // the end-to-end test drags sliders with it
    pub fn mouse(&mut self, session: &str, kind: &str, x: f64, y: f64) -> Result<(), String> {
        self.call(
            Some(session),
            "Input.dispatchMouseEvent",
            json!({"type": kind, "x": x, "y": y, "button": "left", "buttons": if kind == "mouseReleased" { 0 } else { 1 }, "clickCount": 1}),
        )
        .map(|_| ())
    }

    /// A PNG of the page as shown.
    pub fn screenshot(&mut self, session: &str) -> Result<Vec<u8>, String> {
        let r = self.call(
            Some(session),
            "Page.captureScreenshot",
            json!({"format": "png"}),
        )?;
        base64_decode(r["data"].as_str().ok_or("no screenshot data")?)
    }
}

impl Drop for Browser {
    /// Asks the browser to close (so that its helper processes stop writing to the profile),
    /// kills it after 5 s, then removes the profile (again after a moment: a helper may still
    /// be finishing a write).
    fn drop(&mut self) {
        let mut bytes =
            serde_json::to_vec(&json!({"id": 0, "method": "Browser.close"})).expect("serialisable");
        bytes.push(0);
        let _ = self.to_chrome.write_all(&bytes);
        let deadline = Instant::now() + Duration::from_secs(5);
        while Instant::now() < deadline && matches!(self.child.try_wait(), Ok(None)) {
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        for _ in 0..5 {
            if std::fs::remove_dir_all(&self.profile).is_ok() || !self.profile.exists() {
                break;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

/// Loads `url` in headless Chromium, waits until the page says it is ready (plots drawn and
/// the full renders shown), and returns a PNG screenshot.
pub fn screenshot(
    browser: Option<&Path>,
    url: &str,
    width: u32,
    height: u32,
) -> Result<Vec<u8>, String> {
    let mut b = Browser::start(&find_browser(browser)?)?;
    let s = b.open(url, width, height)?;
    b.wait_for(
        &s,
        "document.body && document.body.dataset.ready === '1'",
        Duration::from_secs(120),
    )?;
    b.screenshot(&s)
}

/// Standard base64 decoding (whitespace ignored).
pub fn base64_decode(s: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let (mut acc, mut bits) = (0u32, 0);
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            b'=' | b'\n' | b'\r' | b' ' => continue,
            _ => return Err(format!("invalid base64 byte {c}")),
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Ok(out)
}
