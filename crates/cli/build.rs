//! The commit the binary is built from, for `fastbrdf --version`: benchmarks record that line
//! (`tools/equal_error.py`), so a published figure names the code that produced it. Outside a
//! git checkout (a source archive) or without git, "unknown".

use std::path::Path;
use std::process::Command;

/// `git args...` in this crate's folder: its trimmed output, if git ran and succeeded.
fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    let commit = git(&["rev-parse", "--short=12", "HEAD"]);
    println!(
        "cargo:rustc-env=FASTBRDF_COMMIT={}",
        commit.as_deref().unwrap_or("unknown")
    );
    // Built again when HEAD moves: HEAD itself (a checkout) and the branch it names (a
    // commit). Only files that exist: cargo reruns a script whose watched file is missing on
    // every build.
    println!("cargo:rerun-if-changed=build.rs");
    if let Some(dir) = git(&["rev-parse", "--absolute-git-dir"]) {
        let mut watch = vec![
            Path::new(&dir).join("HEAD"),
            Path::new(&dir).join("packed-refs"),
        ];
        if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
            watch.push(Path::new(&dir).join(branch));
        }
        for f in watch.iter().filter(|f| f.exists()) {
            println!("cargo:rerun-if-changed={}", f.display());
        }
    }
}
