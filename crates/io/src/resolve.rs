//! Output resolution: what a path the user named for writing is (a file or nothing, a link,
//! a FIFO or device, this process's own stream, or something refused), decided before
//! anything is written; and the checked open of a FIFO or device written in place.

use crate::error::{IoError, input_err, output_err};
use std::fs;
use std::path::{Path, PathBuf};

/// Where a write to a path the user named goes (see [`resolve_output`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum OutputTarget {
    /// A regular file, or nothing yet: replaced atomically. The path is the end of the symlink
    /// chain (the temporary is made in its folder and renamed onto it, so a link stays a link
    /// and a dangling link's target is created).
    Replace(PathBuf),
    /// This process's standard output (`/dev/stdout`, `/dev/fd/1`, `/proc/self/fd/1`), written
    /// through the process's own handle whatever it is (terminal, pipe, socket, file).
    Stdout,
    /// This process's standard error (`/dev/stderr`, `/dev/fd/2`).
    Stderr,
    /// An existing FIFO or character device (`/dev/null`, `/dev/full`, a terminal), or another
    /// file-descriptor link (`/dev/fd/63` of a process substitution): opened for writing without
    /// truncating or replacing it, and written in place. A regular file reached through a
    /// descriptor link is appended to, as the open file it is.
    Direct { path: PathBuf, append: bool },
}

/// How many symbolic links [`resolve_output`] follows before giving up (Linux's own limit).
const MAX_LINKS: usize = 40;

/// Decides how a write to `path` is done, without writing anything:
///
/// - symbolic links are followed (up to 40) to the file they finally name; a regular file
///   there, or nothing (a new file, a dangling link), is [`OutputTarget::Replace`]d atomically
///   in its own folder;
/// - an existing FIFO or character device is written directly ([`OutputTarget::Direct`]):
///   replacing it by a regular file would break whoever reads it (a pipe's reader, `/dev/null`
///   as root); a FIFO's open waits for a reader, like the shell's `>`;
/// - `/dev/stdout` and `/dev/stderr` (and their `/dev/fd`, `/proc/self/fd` names) are this
///   process's own streams;
/// - a folder, a block device, a socket (other than stdout/stderr) or a link loop is refused
///   as bad usage ([`IoError::Input`], exit code 2): nothing sensible can be written there.
pub fn resolve_output(path: &Path) -> Result<OutputTarget, IoError> {
    let mut cur = path.to_path_buf();
    for _ in 0..=MAX_LINKS {
        if let Some(t) = fd_link(&cur)? {
            return Ok(t);
        }
        let md = match fs::symlink_metadata(&cur) {
            Ok(md) => md,
            // Nothing there (or a folder on the way that the write will report): a new file.
            Err(_) => return Ok(OutputTarget::Replace(cur)),
        };
        let ft = md.file_type();
        if ft.is_symlink() {
            refuse_foreign_in_sticky(path, &cur, &md, "a symbolic link")?;
            let to = fs::read_link(&cur).map_err(|e| output_err(path, e))?;
            cur = match cur.parent() {
                Some(dir) if to.is_relative() => dir.join(to),
                _ => to,
            };
            continue;
        }
        if ft.is_file() {
            return Ok(OutputTarget::Replace(cur));
        }
        if ft.is_dir() {
            // The user named a folder where a file is wanted: bad usage (exit 2), not an I/O
            // failure.
            return Err(input_err(
                path,
                format!("{}is a folder, not a file to write", via(path, &cur)),
            ));
        }
        if is_fifo(ft) {
            refuse_foreign_in_sticky(path, &cur, &md, "a FIFO")?;
        }
        return special(path, &cur, ft);
    }
    Err(input_err(
        path,
        format!("more than {MAX_LINKS} symbolic links in a row (a loop?); nothing was written"),
    ))
}

#[cfg(unix)]
fn is_fifo(ft: fs::FileType) -> bool {
    use std::os::unix::fs::FileTypeExt;
    ft.is_fifo()
}

#[cfg(not(unix))]
fn is_fifo(_ft: fs::FileType) -> bool {
    false
}

/// The kernel's `fs.protected_symlinks` and `fs.protected_fifos` rule, which never runs for a
/// link this crate reads itself or a FIFO it decided to open: a symbolic link or a FIFO (`md`,
/// not followed) in a sticky, world-writable folder (`/tmp`) whose owner is neither this
/// process's effective user nor the folder's owner is refused. Otherwise another user could
/// plant `/tmp/out.png -> ~/.bashrc` and have it replaced by whoever writes `/tmp/out.png`.
#[cfg(unix)]
fn refuse_foreign_in_sticky(
    path: &Path,
    cur: &Path,
    md: &fs::Metadata,
    what: &str,
) -> Result<(), IoError> {
    use std::os::unix::fs::MetadataExt;
    let dir = cur
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let Ok(dmd) = fs::metadata(dir) else {
        return Ok(());
    };
    let sticky_world_writable = dmd.mode() & 0o1002 == 0o1002;
    // SAFETY: geteuid has no preconditions and cannot fail.
    let euid = unsafe { libc::geteuid() };
    if sticky_world_writable && md.uid() != euid && md.uid() != dmd.uid() {
        return Err(input_err(
            path,
            format!(
                "{}is {what} owned by another user (uid {}) in the sticky, world-writable folder {}: \
                 refused, as the kernel's protected_symlinks/protected_fifos would (someone else \
                 could point it at your files); nothing was written",
                via(path, cur),
                md.uid(),
                dir.display()
            ),
        ));
    }
    Ok(())
}

#[cfg(not(unix))]
fn refuse_foreign_in_sticky(
    _path: &Path,
    _cur: &Path,
    _md: &fs::Metadata,
    _what: &str,
) -> Result<(), IoError> {
    Ok(())
}

/// Opens the FIFO or device `at` that [`resolve_output`] chose, for writing in place. A name
/// that is not a descriptor link is opened without following a link (`O_NOFOLLOW`), and the
/// opened file is checked to still be a FIFO or character device (and a FIFO still not a
/// foreign one in a sticky folder): a swap to a link or a regular file between the decision and
/// the open must not be written through.
#[cfg(unix)]
pub(crate) fn open_direct(path: &Path, at: &Path, append: bool) -> Result<fs::File, IoError> {
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    let fd = fd_link(at)?.is_some();
    let mut opts = fs::OpenOptions::new();
    opts.write(true).append(append);
    if !fd {
        opts.custom_flags(libc::O_NOFOLLOW);
    }
    let file = opts.open(at).map_err(|e| output_err(path, e))?;
    if !fd {
        let md = file.metadata().map_err(|e| output_err(path, e))?;
        let ft = md.file_type();
        if !(ft.is_fifo() || ft.is_char_device()) {
            return Err(input_err(
                path,
                format!(
                    "{}changed while being opened (no longer a FIFO or character device); \
                     nothing was written",
                    via(path, at)
                ),
            ));
        }
        if ft.is_fifo() {
            refuse_foreign_in_sticky(path, at, &md, "a FIFO")?;
        }
    }
    Ok(file)
}

#[cfg(not(unix))]
pub(crate) fn open_direct(path: &Path, at: &Path, append: bool) -> Result<fs::File, IoError> {
    fs::OpenOptions::new()
        .write(true)
        .append(append)
        .open(at)
        .map_err(|e| output_err(path, e))
}

/// "(a link to X) " when `cur` is not `path` itself.
pub(crate) fn via(path: &Path, cur: &Path) -> String {
    if path == cur {
        String::new()
    } else {
        format!("(a link to {}) ", cur.display())
    }
}

#[cfg(unix)]
fn special(path: &Path, cur: &Path, ft: fs::FileType) -> Result<OutputTarget, IoError> {
    use std::os::unix::fs::FileTypeExt;
    if ft.is_fifo() || ft.is_char_device() {
        return Ok(OutputTarget::Direct {
            path: cur.to_path_buf(),
            append: false,
        });
    }
    let kind = if ft.is_block_device() {
        "a block device"
    } else if ft.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    };
    Err(input_err(
        path,
        format!(
            "{}is {kind}: outputs go to regular files, FIFOs and character devices; nothing was written",
            via(path, cur)
        ),
    ))
}

#[cfg(not(unix))]
fn special(_path: &Path, cur: &Path, _ft: fs::FileType) -> Result<OutputTarget, IoError> {
    Ok(OutputTarget::Replace(cur.to_path_buf()))
}

/// `cur` as a file-descriptor link (`/proc/<pid>/fd/N`, which `/dev/fd/N`, `/dev/stdout` and
/// `/proc/self/fd/N` all lead to): its target is an open file, not a path to rename onto.
fn fd_link(cur: &Path) -> Result<Option<OutputTarget>, IoError> {
    let (Some(dir), Some(name)) = (cur.parent(), cur.file_name()) else {
        return Ok(None);
    };
    let Ok(n) = name.to_string_lossy().parse::<u32>() else {
        return Ok(None);
    };
    let Ok(dir) = fs::canonicalize(dir) else {
        return Ok(None);
    };
    let dir = dir.to_string_lossy().into_owned();
    if !(dir.starts_with("/proc/") && dir.ends_with("/fd")) {
        return Ok(None);
    }
    let pid = std::process::id();
    let own = dir == format!("/proc/{pid}/fd") || dir.starts_with(&format!("/proc/{pid}/task/"));
    if own && n == 1 {
        return Ok(Some(OutputTarget::Stdout));
    }
    if own && n == 2 {
        return Ok(Some(OutputTarget::Stderr));
    }
    match fs::metadata(cur) {
        Ok(md) if md.is_file() => Ok(Some(OutputTarget::Direct {
            path: cur.to_path_buf(),
            append: true,
        })),
        Ok(md) if md.is_dir() => Err(input_err(cur, "is a folder, not a file to write")),
        Ok(md) => special(cur, cur, md.file_type()).map(Some),
        // A closed descriptor: the write will report it.
        Err(_) => Ok(Some(OutputTarget::Direct {
            path: cur.to_path_buf(),
            append: false,
        })),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::scratch;
    #[cfg(unix)]
    #[test]
    fn direct_writes_do_not_follow_a_swap() {
        use std::os::unix::fs::symlink;
        let d = scratch("swap");
        fs::create_dir_all(&d).unwrap();
        // The FIFO decided on was swapped for a regular file: refused, the file untouched.
        let file = d.join("was-a-fifo");
        fs::write(&file, b"keep").unwrap();
        let e = open_direct(&file, &file, false).unwrap_err();
        assert!(matches!(e, IoError::Input { .. }), "{e:?}");
        assert!(e.to_string().contains("changed"), "{e}");
        // ... or for a link to a device: not followed.
        let link = d.join("was-a-device");
        symlink("/dev/null", &link).unwrap();
        assert!(open_direct(&link, &link, false).is_err());
        assert_eq!(fs::read(&file).unwrap(), b"keep");
        // The real thing still opens.
        assert!(open_direct(Path::new("/dev/null"), Path::new("/dev/null"), false).is_ok());
        fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn standard_streams_are_the_process_own() {
        for p in ["/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"] {
            assert_eq!(
                resolve_output(Path::new(p)).unwrap(),
                OutputTarget::Stdout,
                "{p}"
            );
        }
        assert_eq!(
            resolve_output(Path::new("/dev/stderr")).unwrap(),
            OutputTarget::Stderr
        );
        assert_eq!(
            resolve_output(Path::new("/dev/null")).unwrap(),
            OutputTarget::Direct {
                path: PathBuf::from("/dev/null"),
                append: false
            }
        );
        assert!(matches!(
            resolve_output(Path::new("/nonexistent-folder/x.csv")).unwrap(),
            OutputTarget::Replace(_)
        ));
    }
}
