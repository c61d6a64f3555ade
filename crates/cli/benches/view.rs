//! Latency of `fastbrdf view`'s API as the page sees it: a real HTTP request to the server
//! (the release binary on a free port), per slider move and per picture. The quality bars of
//! issue 16: new plots within 50 ms of a slider move, a 512x512 sphere within 150 ms.
//! Run: `cargo bench -p fastbrdf-cli --bench view` (numbers in README, "Explorer").

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Mutex, OnceLock};

struct Served {
    child: Mutex<Child>,
    addr: String,
}

static SERVER: OnceLock<Served> = OnceLock::new();

fn server() -> &'static str {
    &SERVER
        .get_or_init(|| {
            let mut child = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
                .args(["view", "--port", "0"])
                .stderr(Stdio::piped())
                .spawn()
                .expect("start fastbrdf view");
            let mut err = BufReader::new(child.stderr.take().unwrap());
            let mut line = String::new();
            let addr = loop {
                line.clear();
                assert!(err.read_line(&mut line).unwrap() > 0, "view exited");
                if let Some(rest) = line.split("serving on http://").nth(1) {
                    break rest.split('/').next().unwrap().to_string();
                }
            };
            std::thread::spawn(move || {
                let mut sink = String::new();
                let _ = err.read_to_string(&mut sink);
            });
            Served {
                child: Mutex::new(child),
                addr,
            }
        })
        .addr
}

/// One GET; panics unless 200.
fn get(target: &str) -> usize {
    let addr = server();
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut buf = vec![];
    s.read_to_end(&mut buf).unwrap();
    assert!(
        buf.starts_with(b"HTTP/1.1 200"),
        "{target}: {}",
        String::from_utf8_lossy(&buf[..buf.len().min(300)])
    );
    buf.len()
}

/// A different n each call, as a dragged slider sends.
fn next_n() -> f64 {
    static K: AtomicU32 = AtomicU32::new(0);
    20.0 + f64::from(K.fetch_add(1, Ordering::Relaxed) % 500)
}

fn main() {
    divan::main();
    // The server runs until killed.
    if let Some(s) = SERVER.get() {
        let mut c = s.child.lock().unwrap();
        let _ = c.kill();
        let _ = c.wait();
    }
}

/// A slider move with one model and its reference (polar, lobe, error curves, slice, the
/// refined maxima): `/api/plots`.
#[divan::bench(sample_count = 30)]
fn plots_one_model_and_reference() -> usize {
    get(&format!(
        "/api/plots?models=flog&ref=pow&n={}&theta=30",
        next_n()
    ))
}

/// The same with three models and the reference.
#[divan::bench(sample_count = 30)]
fn plots_three_models_and_reference() -> usize {
    get(&format!(
        "/api/plots?models=flog,schlick,cubic-rational&ref=pow&n={}&theta=30",
        next_n()
    ))
}

/// Cook-Torrance against itself with a distribution approximation.
#[divan::bench(sample_count = 30)]
fn plots_microfacet() -> usize {
    get(&format!(
        "/api/plots?models=beckmann-power16&ref=cook-torrance&alpha={}&theta=30",
        next_n() / 1000.0
    ))
}

/// The albedo curve (10 angles, adaptive quadrature) and furnace verdict of one model and its
/// reference: `/api/albedo`, sent beside /api/plots.
#[divan::bench(sample_count = 10)]
fn albedo_one_model_and_reference() -> usize {
    get(&format!("/api/albedo?models=flog&ref=pow&n={}", next_n()))
}

/// The quick estimate the page draws first (`quick=1`: a fixed quadrature, no verdict).
#[divan::bench(sample_count = 30)]
fn albedo_quick_one_model_and_reference() -> usize {
    get(&format!(
        "/api/albedo?models=flog&ref=pow&n={}&quick=1",
        next_n()
    ))
}

/// The quick estimate for a Beckmann approximation against Cook-Torrance.
#[divan::bench(sample_count = 30)]
fn albedo_quick_microfacet() -> usize {
    get(&format!(
        "/api/albedo?models=beckmann-power16&ref=cook-torrance&alpha={}&quick=1",
        next_n() / 1000.0
    ))
}

/// The quick estimate with three models and the reference.
#[divan::bench(sample_count = 30)]
fn albedo_quick_three_models_and_reference() -> usize {
    get(&format!(
        "/api/albedo?models=flog,schlick,cubic-rational&ref=pow&n={}&quick=1",
        next_n()
    ))
}

/// One 512x512 sphere, 1 sample per pixel, PNG-encoded in the JSON.
#[divan::bench(sample_count = 10)]
fn render_sphere_512_spp1() -> usize {
    get(&format!(
        "/api/render?models=flog&n={}&size=512&spp=1",
        next_n()
    ))
}

/// The page's full picture: model and reference at 512x512, 2x2 samples per pixel, with the
/// difference map and RMSE/PSNR/FLIP.
#[divan::bench(sample_count = 10)]
fn render_compare_512_spp2() -> usize {
    get(&format!(
        "/api/render?models=flog&ref=pow&n={}&size=512&spp=2",
        next_n()
    ))
}

/// The page's quick preview: model and reference at 128x128, 1 sample per pixel.
#[divan::bench(sample_count = 30)]
fn render_preview_128() -> usize {
    get(&format!(
        "/api/render?models=flog&ref=pow&n={}&size=128&spp=1",
        next_n()
    ))
}

/// One 512x512 sphere with the page's 2 x 2 samples per pixel, no reference.
#[divan::bench(sample_count = 10)]
fn render_sphere_512_spp2() -> usize {
    get(&format!(
        "/api/render?models=flog&n={}&size=512&spp=2",
        next_n()
    ))
}
