//! Scratch folders and file-type helpers for the unit tests.

use std::fs;
use std::path::{Path, PathBuf};

pub(crate) fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("fastbrdf-io-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    d
}

pub(crate) fn listing(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(d)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[cfg(unix)]
pub(crate) fn is_link(p: &Path) -> bool {
    fs::symlink_metadata(p).unwrap().file_type().is_symlink()
}

#[cfg(unix)]
pub(crate) fn mkfifo(p: &Path) {
    let ok = std::process::Command::new("mkfifo")
        .arg(p)
        .status()
        .expect("mkfifo runs");
    assert!(ok.success());
}

#[cfg(unix)]
pub(crate) fn file_type(p: &Path) -> fs::FileType {
    fs::symlink_metadata(p).unwrap().file_type()
}

/// Root (this machine, CI) can give a file away with `lchown`; others skip, except under CI.
#[cfg(unix)]
pub(crate) fn can_chown() -> bool {
    // SAFETY: geteuid has no preconditions and cannot fail.
    if unsafe { libc::geteuid() } == 0 {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "CI is set and the test is not root: it cannot make a file another user's"
    );
    eprintln!("skipped: not root, cannot make a link or FIFO another user's");
    false
}
