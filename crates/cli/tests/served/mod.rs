//! `fastbrdf view` started on a free port for the explorer's tests (tests/view.rs,
//! tests/view_server.rs), killed on drop.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;

/// A `fastbrdf view` process on a free port, killed on drop.
pub struct Served {
    pub child: Child,
    pub addr: String,
    /// What the server wrote on stderr after its start-up line.
    pub log: Arc<std::sync::Mutex<String>>,
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `fastbrdf view --port 0 EXTRA`, under `ulimit -n NOFILE` when given.
pub fn serve_with(nofile: Option<u32>, extra: &[&str]) -> Served {
    start(nofile, extra, true)
}

/// As [`serve_with`], but the read end of the server's stderr is closed right after its
/// start-up line (`fastbrdf view 2>&1 | head -1`): every later write there fails.
pub fn serve_with_stderr_closed(nofile: Option<u32>, extra: &[&str]) -> Served {
    start(nofile, extra, false)
}

/// Starts the server; `keep_stderr`: read its stderr into `log` after the start-up line (else
/// close it).
fn start(nofile: Option<u32>, extra: &[&str], keep_stderr: bool) -> Served {
    let bin = env!("CARGO_BIN_EXE_fastbrdf");
    let mut cmd = match nofile {
        Some(n) => {
            let mut c = Command::new("sh");
            c.arg("-c")
                .arg(format!("ulimit -n {n} && exec \"$0\" \"$@\""))
                .arg(bin);
            c
        }
        None => Command::new(bin),
    };
    let child = cmd
        .args(["view", "--port", "0"])
        .args(extra)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start fastbrdf view");
    let mut served = Served {
        child,
        addr: String::new(),
        log: Arc::default(),
    };
    let mut err = BufReader::new(served.child.stderr.take().unwrap());
    let mut line = String::new();
    loop {
        line.clear();
        assert!(
            err.read_line(&mut line).unwrap() > 0,
            "view exited before serving"
        );
        if let Some(rest) = line.split("serving on http://").nth(1) {
            served.addr = rest.split('/').next().unwrap().to_string();
            if !keep_stderr {
                drop(err);
                return served;
            }
            let log = served.log.clone();
            std::thread::spawn(move || {
                let mut line = String::new();
                while err.read_line(&mut line).is_ok_and(|n| n > 0) {
                    log.lock().unwrap().push_str(&line);
                    line.clear();
                }
            });
            return served;
        }
    }
}

pub fn serve(extra: &[&str]) -> Served {
    serve_with(None, extra)
}
