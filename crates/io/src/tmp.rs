//! Temporary names and folders: unique temporary files beside a target, folders created
//! (and removed again on failure), and a guard that removes a temporary file on every error
//! path and on panic.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A name no other call of this process (or another process) uses in the same folder.
pub(crate) fn unique_tmp(dir: &Path, stem: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{stem}.{}-{n}.tmp", std::process::id()))
}

/// Creates `dir` and its missing ancestors; returns the ones it created, outermost first, so
/// that a failure can remove them again.
pub(crate) fn create_dirs(dir: &Path) -> io::Result<Vec<PathBuf>> {
    let mut missing = Vec::new();
    let mut d = Some(dir);
    while let Some(p) = d.filter(|p| !p.as_os_str().is_empty()) {
        if p.exists() {
            break;
        }
        missing.push(p.to_path_buf());
        d = p.parent();
    }
    missing.reverse();
    for (i, p) in missing.iter().enumerate() {
        if let Err(e) = fs::create_dir(p)
            && !(e.kind() == io::ErrorKind::AlreadyExists && p.is_dir())
        {
            remove_dirs(&missing[..i]);
            return Err(e);
        }
    }
    Ok(missing)
}

/// Removes folders created by [`create_dirs`], innermost first (only if empty).
pub(crate) fn remove_dirs(created: &[PathBuf]) {
    for p in created.iter().rev() {
        let _ = fs::remove_dir(p);
    }
}

/// Removes a temporary file when dropped, unless disarmed: covers every error path and panics.
pub(crate) struct TmpGuard(pub(crate) Option<PathBuf>);

impl Drop for TmpGuard {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = fs::remove_file(p);
        }
    }
}
