//! Helpers shared by the explorer's end-to-end tests (tests/view.rs, view_page.rs,
//! view_measured.rs): raw HTTP requests to a served `fastbrdf view`, the CLI's numbers to
//! compare with, and the headless browser (the DevTools client of `fastbrdf view
//! --screenshot`, included from the binary's source).
#![allow(dead_code)]

#[allow(dead_code)]
#[path = "../../src/commands/view/cdp.rs"]
pub mod cdp;

use crate::common::{fastbrdf, stderr};
use serde_json::Value;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// One raw HTTP request (the target is sent exactly as given: no client-side normalising).
pub fn request(addr: &str, method: &str, target: &str) -> (u16, String, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    write!(
        s,
        "{method} {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut buf = vec![];
    s.read_to_end(&mut buf).unwrap();
    let split = buf
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("headers");
    let head = String::from_utf8_lossy(&buf[..split]).to_string();
    let status: u16 = head.split(' ').nth(1).unwrap().parse().unwrap();
    let ctype = head
        .lines()
        .find_map(|l| {
            l.to_ascii_lowercase()
                .strip_prefix("content-type: ")
                .map(str::to_string)
        })
        .unwrap_or_default();
    (status, ctype, buf[split + 4..].to_vec())
}

pub fn get_json(addr: &str, target: &str) -> (u16, Value) {
    let (status, ctype, body) = request(addr, "GET", target);
    assert!(ctype.starts_with("application/json"), "{target}: {ctype}");
    (status, serde_json::from_slice(&body).unwrap())
}

pub fn ok_json(addr: &str, target: &str) -> Value {
    let (status, v) = get_json(addr, target);
    assert_eq!(status, 200, "{target}: {v}");
    v
}

/// `fastbrdf errors --json` at one parameter value: rows[0].
pub fn cli_errors(model: &str, reference: &str, flag: &str, value: &str) -> Value {
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            model,
            "--reference",
            reference,
            flag,
            value,
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    v["rows"][0].clone()
}

/// The CLI's message for a bad input (stderr without "error: ").
pub fn cli_message(args: &[&str]) -> String {
    let o = fastbrdf(args, "");
    assert_eq!(o.status.code(), Some(2), "{args:?}");
    stderr(&o)
        .trim()
        .strip_prefix("error: ")
        .unwrap()
        .to_string()
}

/// The browser, or None (skip) outside CI; under CI a missing browser fails.
pub fn browser() -> Option<std::path::PathBuf> {
    match cdp::find_browser(None) {
        Ok(b) => Some(b),
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI is set and {e}"),
        Err(e) => {
            eprintln!("skipping the end-to-end test: {e} (tools/test.sh installs it)");
            None
        }
    }
}
