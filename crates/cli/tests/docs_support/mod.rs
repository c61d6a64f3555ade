//! The documentation test's parts (see `tests/docs.rs`): the pages and the mode here,
//! Markdown's fenced blocks (`markdown`), running the shell and console blocks (`run`), the
//! generated sections (`generated`), links and repository paths (`links`, `paths`), and the
//! library chapter's example with ARCHITECTURE.md's family list (`library`).

mod generated;
mod library;
mod links;
mod markdown;
mod paths;
mod run;

pub(crate) use markdown::{Block, all_blocks, blocks_of};

use std::path::{Path, PathBuf};
use std::time::Duration;

pub(crate) const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
pub(crate) const BOOK: &str = "docs/book/src";
/// Languages of blocks that are not run here (shown as they are, or run by another test).
pub(crate) const SHOWN: &[&str] = &[
    "text", "rust", "python", "json", "csv", "toml", "wgsl", "glsl", "hlsl", "msl", "html",
];
pub(crate) const RUN: &[&str] = &["sh", "bash", "console"];
/// A block that runs longer is stopped and fails (a server left in the foreground); the full
/// mode's blocks (`check` of every bound in the debug build) get an hour.
pub(crate) fn block_timeout() -> Duration {
    Duration::from_secs(if full_mode() { 3600 } else { 600 })
}

pub(crate) fn root() -> PathBuf {
    std::fs::canonicalize(ROOT).unwrap()
}

pub(crate) fn full_mode() -> bool {
    std::env::var("FASTBRDF_DOCS_FULL").is_ok_and(|v| v == "1")
}

/// README.md and every page of the book, relative to the repository root, in a fixed order.
pub(crate) fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "md") {
                out.push(p);
            }
        }
    }
    let root = root();
    let mut out = vec![root.join("README.md")];
    walk(&root.join(BOOK), &mut out);
    out.into_iter()
        .map(|p| p.strip_prefix(&root).unwrap().to_path_buf())
        .collect()
}
