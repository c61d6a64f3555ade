//! Helpers shared by the CLI's end-to-end tests: run the binary, read its output, a fresh
//! temporary folder per test. (Each test file uses some of them.)
#![allow(dead_code)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// Runs `fastbrdf` with `args`, `stdin` on its standard input.
pub fn fastbrdf(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // A command that does not read its input may have exited already: ignore a broken pipe.
    let _ = child.stdin.take().unwrap().write_all(stdin.as_bytes());
    child.wait_with_output().unwrap()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

/// An empty folder `fastbrdf-<tag>-<pid>` under the system's temporary folder, removed with
/// everything in it when the returned guard is dropped, unless the test is failing (a
/// panicking thread): then it is kept for a look, and its path printed.
pub fn temp_dir(tag: &str) -> TempDir {
    let d = std::env::temp_dir().join(format!("fastbrdf-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    TempDir(d)
}

/// A folder of [`temp_dir`]; derefs to its path.
pub struct TempDir(PathBuf);

impl TempDir {
    /// The path, the folder no longer removed by the guard (the caller removes it).
    pub fn keep(self) -> PathBuf {
        let p = self.0.clone();
        std::mem::forget(self);
        p
    }
}

impl std::ops::Deref for TempDir {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept for a look: {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// The names in folder `d`, sorted.
pub fn listing(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Whether a GPU adapter is there (lavapipe serves): without one a GPU test skips, except when
/// `CI` is set, where a missing adapter fails it.
pub fn have_gpu() -> bool {
    match fastbrdf_gpu::Gpu::new() {
        Ok(_) => true,
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI is set and there is no GPU: {e}"),
        Err(e) => {
            eprintln!("skipping: {e}");
            false
        }
    }
}

/// The path of a test file of the GPU crate (`brdf-explorer/`, `user/`: users' shaders).
pub fn gpu_data(rel: &str) -> String {
    format!("{}/../gpu/tests/data/{rel}", env!("CARGO_MANIFEST_DIR"))
}

/// A flat (uncompressed) Radiance file: `w` x `h` texels of radiance 1 (RGBE 128,128,128,129).
pub fn hdr(w: u32, h: u32) -> Vec<u8> {
    let mut b = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    for _ in 0..w * h {
        b.extend([128, 128, 128, 129]);
    }
    b
}

/// `--repeat`'s bracket after `key` in a render's report ("render 0.01 s (then 0.008 s, 0.007
/// s: --repeat 3)" with `key` "render "; "draws " for the GPU's draws): the later renders'
/// seconds and what follows them ("--repeat 3"); `None` without a bracket there.
#[allow(dead_code)]
pub fn then_times(report: &str, key: &str) -> Option<(Vec<f64>, String)> {
    let (_, rest) = report.split_once(key)?.1.split_once(" s (then ")?;
    let (times, tail) = rest.split(')').next()?.split_once(": ")?;
    let secs = times
        .split(", ")
        .map(|t| t.strip_suffix(" s").and_then(|t| t.parse().ok()))
        .collect::<Option<Vec<f64>>>()?;
    Some((secs, tail.to_string()))
}
