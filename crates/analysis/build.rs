//! Compiles `c/peer.c`, the C loops `fastbrdf bench` races the batch kernels against (issue
//! 13), with the system C compiler at `-O3 -march=native -ffast-math`, as a performance-minded
//! user would. Without `-march=native` (a compiler that lacks it) the flags fall back to
//! `-O3 -ffast-math`, and the benchmark's output says so (`FASTBRDF_PEER_FLAGS`). Vectorised
//! `powf`/`expf`/`exp2f` calls become glibc's libmvec (`_ZGV*` symbols), which is then linked.
//! No C compiler is a build error that says so.

use std::path::Path;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=c/peer.c");
    println!("cargo:rerun-if-changed=build.rs");
    let mut build = cc::Build::new();
    build.file("c/peer.c").opt_level(3).flag("-ffast-math");
    let mut flags = String::from("-O3 -ffast-math");
    let native = build.is_flag_supported("-march=native").unwrap_or(false);
    if native {
        build.flag("-march=native");
        flags = "-O3 -march=native -ffast-math".into();
    } else {
        println!(
            "cargo:warning=the C compiler does not accept -march=native: the C peers are compiled with -O3 -ffast-math only"
        );
        flags.push_str(" (no -march=native: the compiler lacks it)");
    }
    let compiler = build.get_compiler();
    let version = Command::new(compiler.path())
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8(o.stdout)
                .ok()
                .and_then(|s| s.lines().next().map(|l| l.trim().to_string()))
        })
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| compiler.path().display().to_string());
    if let Err(e) = build.try_compile("fastbrdf_peer") {
        panic!(
            "\n\nfastbrdf-analysis needs a C compiler (cc, gcc or clang; set CC to choose one) to \
             build the C peers of `fastbrdf bench` (crates/analysis/c/peer.c), and none worked:\n  \
             {e}\nInstall one (Debian/Ubuntu: apt-get install gcc).\n"
        );
    }
    // Link libmvec when the compiler vectorised a libm call into it (GCC with glibc).
    let out = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR");
    let lib = Path::new(&out).join("libfastbrdf_peer.a");
    let bytes = std::fs::read(&lib).unwrap_or_default();
    let mvec = bytes.windows(4).any(|w| w == b"_ZGV");
    if mvec {
        println!("cargo:rustc-link-lib=mvec");
    }
    println!("cargo:rustc-env=FASTBRDF_PEER_CC={version}");
    println!("cargo:rustc-env=FASTBRDF_PEER_FLAGS={flags}");
    println!(
        "cargo:rustc-env=FASTBRDF_PEER_LIBMVEC={}",
        if mvec { "yes" } else { "no" }
    );
}
