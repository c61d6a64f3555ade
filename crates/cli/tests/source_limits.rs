//! No source file over 800 lines (issue 28, "Rooms too big to read"): every `.rs` file under
//! `crates/` and `python/` (build outputs and hidden folders aside) has at most `MAX_LINES`
//! lines. A file that grows past it is split along its responsibilities (a folder module).

use std::path::{Path, PathBuf};

const MAX_LINES: usize = 800;

fn root() -> PathBuf {
    std::fs::canonicalize(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).unwrap()
}

/// Every `.rs` file under `dir`, skipping `target/` and hidden folders.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy();
        if name.starts_with('.') || name == "target" {
            continue;
        }
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The files over `max` lines, as `path (N lines)`, relative to `root`.
fn over(root: &Path, max: usize) -> (usize, Vec<String>) {
    let mut files = Vec::new();
    for d in ["crates", "python"] {
        rust_files(&root.join(d), &mut files);
    }
    files.sort();
    let long = files
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).unwrap().lines().count();
            (n > max).then(|| format!("{} ({n} lines)", f.strip_prefix(root).unwrap().display()))
        })
        .collect();
    (files.len(), long)
}

#[test]
fn no_source_file_is_over_800_lines() {
    let (count, long) = over(&root(), MAX_LINES);
    assert!(
        count >= 100,
        "only {count} .rs files found: the walk is broken"
    );
    assert!(
        long.is_empty(),
        "source files over {MAX_LINES} lines (split each along its responsibilities):\n{}",
        long.join("\n")
    );
}

/// The check sees a long file: with a low limit, this crate's own sources are over it.
#[test]
fn the_limit_check_names_long_files() {
    let (_, long) = over(&root(), 50);
    assert!(
        long.iter()
            .any(|l| l.starts_with("crates/cli/tests/source_limits.rs (")),
        "{long:?}"
    );
}
