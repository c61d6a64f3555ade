//! File plumbing shared by every fastbrdf crate that touches the file system.
//!
//! - Reads of untrusted inputs are bounded: [`read_bounded`] reads at most `limit + 1` bytes and
//!   refuses a larger input with a message naming the file and the limit, so `/dev/zero`, a
//!   named pipe or a huge file never takes more memory than the caller allowed. Every input is
//!   read once (pipes and process substitutions cannot be read twice).
//! - [`read_text_bounded`] also checks UTF-8 and names the line and column of the first invalid
//!   byte.
//! - Writes are atomic: [`write_atomic`] writes a uniquely named temporary file in the target's
//!   folder and renames it; on every error path the temporary file (and any folder the call
//!   created) is removed, so a failure leaves nothing behind. What the path names decides how
//!   ([`resolve_output`]): a symbolic link is followed and the file it names is replaced (the
//!   link stays a link); a FIFO, a character device (`/dev/null`, a terminal) and
//!   `/dev/stdout` are written in place, never replaced; a block device, a socket or a folder
//!   is refused (exit code 2). As the kernel's `protected_symlinks`/`protected_fifos` would,
//!   another user's link or FIFO in a sticky world-writable folder (`/tmp`) is refused too.
//! - Multi-file outputs are all-or-nothing: [`OutputSet`] stages every file in a hidden
//!   temporary folder beside the destination and moves them into place only in
//!   [`OutputSet::commit`]; dropping it uncommitted (an error, a panic) removes the staging
//!   folder and any destination folder it created. Its files follow links too, and refuse
//!   anything that is not a regular file.
//!
//! Written by hand because the crates that do atomic writes (`tempfile`, `atomicwrites`) do not
//! remove the folders they did not create, do not stage several files, and pull in more than
//! these ~200 lines.

use std::fmt;
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// An I/O failure, split by who is at fault: an input the user named (exit code 2) or an output
/// the tool could not write (exit code 3).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum IoError {
    /// An input could not be read, is too large or is not text. `message` names the problem.
    Input { path: String, message: String },
    /// An output could not be written.
    Output { path: String, message: String },
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IoError::Input { path, message } => write!(f, "{path}: {message}"),
            IoError::Output { path, message } => write!(f, "cannot write {path}: {message}"),
        }
    }
}

impl std::error::Error for IoError {}

fn input_err(path: &Path, message: impl Into<String>) -> IoError {
    IoError::Input {
        path: path.display().to_string(),
        message: message.into(),
    }
}

fn output_err(path: &Path, e: impl fmt::Display) -> IoError {
    IoError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// `limit` bytes in words: "64 MiB", "512 KiB", "100 bytes".
pub fn human_size(limit: u64) -> String {
    if limit >= 1 << 20 && limit.is_multiple_of(1 << 20) {
        format!("{} MiB", limit >> 20)
    } else if limit >= 1 << 10 && limit.is_multiple_of(1 << 10) {
        format!("{} KiB", limit >> 10)
    } else {
        format!("{limit} bytes")
    }
}

/// Reads all of `reader` (named `name` in messages), refusing more than `limit` bytes: at most
/// `limit + 1` bytes are ever read or held. `what` says what the input is ("an OBJ mesh").
pub fn read_reader_bounded(
    mut reader: impl Read,
    name: &Path,
    limit: u64,
    what: &str,
) -> Result<Vec<u8>, IoError> {
    let mut bytes = Vec::new();
    reader
        .by_ref()
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| input_err(name, format!("cannot read: {e}")))?;
    if bytes.len() as u64 > limit {
        return Err(input_err(
            name,
            format!(
                "larger than the {} allowed for {what}; nothing was read past that",
                human_size(limit)
            ),
        ));
    }
    Ok(bytes)
}

/// Reads the file at `path` once, refusing more than `limit` bytes (see [`read_reader_bounded`]).
/// Works on pipes, process substitutions and devices: the size is never asked of the file system.
pub fn read_bounded(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>, IoError> {
    if path.is_dir() {
        return Err(input_err(path, "is a folder, not a file"));
    }
    let file = fs::File::open(path).map_err(|e| input_err(path, format!("cannot open: {e}")))?;
    read_reader_bounded(file, path, limit, what)
}

/// Converts `bytes` (read from `name`) to text, naming the line and column (1-based, columns in
/// bytes) of the first byte that is not UTF-8.
pub fn utf8_text(bytes: Vec<u8>, name: &Path) -> Result<String, IoError> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let (line, col) = line_col(bytes, at);
        input_err(
            name,
            format!(
                "line {line}, column {col}: not UTF-8 text (byte 0x{:02x})",
                bytes[at]
            ),
        )
    })
}

/// Line and column (1-based; columns count bytes) of byte offset `at` in `bytes`.
pub fn line_col(bytes: &[u8], at: usize) -> (usize, usize) {
    let before = &bytes[..at.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let col = at
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1)
        + 1;
    (line, col)
}

/// [`read_bounded`] then [`utf8_text`].
pub fn read_text_bounded(path: &Path, limit: u64, what: &str) -> Result<String, IoError> {
    utf8_text(read_bounded(path, limit, what)?, path)
}

/// Shortens `s` for an error message: at most `max` characters, the rest replaced by
/// "... (N more bytes)". Control characters are escaped so a message stays on one line.
pub fn shorten(s: &str, max: usize) -> String {
    let mut out = String::new();
    for (taken, (i, ch)) in s.char_indices().enumerate() {
        if taken == max {
            out.push_str(&format!("... ({} more bytes)", s.len() - i));
            return out;
        }
        out.extend(ch.escape_debug());
    }
    out
}

static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A name no other call of this process (or another process) uses in the same folder.
fn unique_tmp(dir: &Path, stem: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    dir.join(format!(".{stem}.{}-{n}.tmp", std::process::id()))
}

/// Creates `dir` and its missing ancestors; returns the ones it created, outermost first, so
/// that a failure can remove them again.
fn create_dirs(dir: &Path) -> io::Result<Vec<PathBuf>> {
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
fn remove_dirs(created: &[PathBuf]) {
    for p in created.iter().rev() {
        let _ = fs::remove_dir(p);
    }
}

/// Removes a temporary file when dropped, unless disarmed: covers every error path and panics.
struct TmpGuard(Option<PathBuf>);

impl Drop for TmpGuard {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = fs::remove_file(p);
        }
    }
}

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
fn open_direct(path: &Path, at: &Path, append: bool) -> Result<fs::File, IoError> {
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
fn open_direct(path: &Path, at: &Path, append: bool) -> Result<fs::File, IoError> {
    fs::OpenOptions::new()
        .write(true)
        .append(append)
        .open(at)
        .map_err(|e| output_err(path, e))
}

/// "(a link to X) " when `cur` is not `path` itself.
fn via(path: &Path, cur: &Path) -> String {
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

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, flushed, then
/// renamed over `path`. Missing folders are created; on failure the temporary file and the
/// folders this call created are removed and `path` is untouched. Symbolic links are followed
/// and FIFOs, character devices and stdout are written in place: see [`resolve_output`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// [`write_atomic`] with the content streamed by `fill`.
///
/// A write into a FIFO, a device or stdout cannot be atomic: what was written before an error
/// has been delivered. A full device (`/dev/full`) is an [`IoError::Output`] naming `path`.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), IoError> {
    if path.file_name().is_none() {
        return Err(output_err(path, "not a file name"));
    }
    if path.is_dir() {
        return Err(input_err(path, "is a folder, not a file to write"));
    }
    match resolve_output(path)? {
        OutputTarget::Replace(target) => replace_atomic(path, &target, fill),
        OutputTarget::Stdout => write_direct(path, io::stdout().lock(), fill),
        OutputTarget::Stderr => write_direct(path, io::stderr().lock(), fill),
        OutputTarget::Direct { path: at, append } => {
            // No truncation (a device or FIFO has nothing to truncate; a descriptor's file is
            // appended to), no creation (it exists).
            let file = open_direct(path, &at, append)?;
            write_direct(path, file, fill)
        }
    }
}

/// Streams `fill` into `w` and flushes; errors name `path`.
fn write_direct(
    path: &Path,
    w: impl Write,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), IoError> {
    let mut w = io::BufWriter::new(w);
    fill(&mut w)
        .and_then(|()| w.flush())
        .map_err(|e| output_err(path, e))
}

/// Writes a temporary file beside `target` (a regular file or nothing; symlinks resolved) and
/// renames it onto `target`. Errors name `path`, what the user asked for.
fn replace_atomic(
    path: &Path,
    target: &Path,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), IoError> {
    let name = target
        .file_name()
        .ok_or_else(|| output_err(path, format!("{}is not a file name", via(path, target))))?
        .to_string_lossy()
        .into_owned();
    let dir = target
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let created = create_dirs(dir).map_err(|e| output_err(path, e))?;
    let result = (|| {
        let tmp = unique_tmp(dir, &name);
        let mut guard = TmpGuard(Some(tmp.clone()));
        let mut file = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        {
            let mut w = io::BufWriter::new(&mut file);
            fill(&mut w)?;
            w.flush()?;
        }
        // A replaced file keeps its permissions.
        if let Ok(md) = fs::metadata(target) {
            file.set_permissions(md.permissions())?;
        }
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, target)?;
        guard.0 = None;
        Ok(())
    })();
    result.map_err(|e: io::Error| {
        remove_dirs(&created);
        output_err(path, e)
    })
}

/// A set of output files written all-or-nothing into one folder.
///
/// Files are staged in a hidden folder inside `dir` (`.fastbrdf-staging-<pid>-<n>`); only
/// [`OutputSet::commit`] moves them into place, each by a rename. Dropping the set without
/// committing (an error, a panic) removes the staging folder and any folder the set created.
pub struct OutputSet {
    dir: PathBuf,
    staging: PathBuf,
    created: Vec<PathBuf>,
    files: Vec<PathBuf>,
    committed: bool,
}

impl OutputSet {
    /// Starts a set of files to be written into `dir` (created if missing).
    pub fn new(dir: &Path) -> Result<Self, IoError> {
        if dir.exists() && !dir.is_dir() {
            // Bad usage (exit 2): the user named a file where a folder is wanted.
            return Err(input_err(dir, "exists and is not a folder"));
        }
        let created = create_dirs(dir).map_err(|e| output_err(dir, e))?;
        let staging = unique_tmp(dir, "fastbrdf-staging");
        if let Err(e) = fs::create_dir(&staging) {
            remove_dirs(&created);
            return Err(output_err(dir, e));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            staging,
            created,
            files: Vec::new(),
            committed: false,
        })
    }

    /// The destination folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Stages `bytes` as `name` (a path relative to the destination folder; subfolders are
    /// allowed). The error names the destination path.
    pub fn write(&mut self, name: impl AsRef<Path>, bytes: &[u8]) -> Result<(), IoError> {
        self.write_with(name, |w| w.write_all(bytes))
    }

    /// [`OutputSet::write`] with the content streamed by `fill`.
    pub fn write_with(
        &mut self,
        name: impl AsRef<Path>,
        fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), IoError> {
        let name = name.as_ref();
        let dest = self.dir.join(name);
        if name.is_absolute()
            || name
                .components()
                .any(|c| !matches!(c, std::path::Component::Normal(_)))
        {
            return Err(output_err(&dest, "not a plain relative file name"));
        }
        let staged = self.staging.join(name);
        (|| {
            if let Some(parent) = staged.parent() {
                fs::create_dir_all(parent)?;
            }
            let mut file = fs::File::create(&staged)?;
            {
                let mut w = io::BufWriter::new(&mut file);
                fill(&mut w)?;
                w.flush()?;
            }
            file.sync_all()
        })()
        .map_err(|e: io::Error| output_err(&dest, e))?;
        self.files.push(name.to_path_buf());
        Ok(())
    }

    /// The destination paths staged so far.
    pub fn files(&self) -> Vec<PathBuf> {
        self.files.iter().map(|f| self.dir.join(f)).collect()
    }

    /// Moves every staged file into place and removes the staging folder. Returns the
    /// destination paths.
    ///
    /// A destination that is a symbolic link is followed: the file it names is replaced (a
    /// temporary beside it, renamed) and the link stays. A destination that exists and is not a
    /// regular file (a FIFO, a device, a socket, a folder) is refused as bad usage before
    /// anything moves: one file of a set cannot be streamed into a device all-or-nothing.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, IoError> {
        let mut targets = Vec::with_capacity(self.files.len());
        for f in &self.files {
            let dest = self.dir.join(f);
            if let Some(parent) = dest.parent() {
                fs::create_dir_all(parent).map_err(|e| output_err(&dest, e))?;
            }
            match resolve_output(&dest)? {
                OutputTarget::Replace(target) => targets.push(target),
                _ => {
                    return Err(input_err(
                        &dest,
                        "exists and is not a regular file: the files of an output set are \
                         written to regular files only; nothing was written",
                    ));
                }
            }
        }
        for (f, target) in self.files.iter().zip(&targets) {
            let dest = self.dir.join(f);
            let staged = self.staging.join(f);
            if *target == dest {
                fs::rename(&staged, &dest).map_err(|e| output_err(&dest, e))?;
            } else {
                // A link to elsewhere (maybe another file system): copy beside the target.
                replace_atomic(&dest, target, |w| {
                    io::copy(&mut fs::File::open(&staged)?, w).map(|_| ())
                })?;
            }
        }
        let _ = fs::remove_dir_all(&self.staging);
        self.committed = true;
        Ok(self.files())
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.staging);
        if !self.committed {
            remove_dirs(&self.created);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("fastbrdf-io-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        d
    }

    fn listing(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(d)
            .map(|r| {
                r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        v.sort();
        v
    }

    #[test]
    fn bounded_reads_stop_at_the_limit() {
        let d = scratch("read");
        fs::create_dir_all(&d).unwrap();
        let f = d.join("a.txt");
        fs::write(&f, b"12345").unwrap();
        assert_eq!(read_bounded(&f, 5, "x").unwrap(), b"12345");
        let e = read_bounded(&f, 4, "a test file").unwrap_err().to_string();
        assert!(
            e.contains("a.txt") && e.contains("4 bytes") && e.contains("a test file"),
            "{e}"
        );
        // An endless input is refused after limit + 1 bytes.
        let e = read_reader_bounded(io::repeat(0), Path::new("/dev/zero"), 1 << 20, "x");
        assert!(e.unwrap_err().to_string().contains("1 MiB"));
        assert!(
            read_bounded(&d, 10, "x")
                .unwrap_err()
                .to_string()
                .contains("folder")
        );
        assert!(read_bounded(&d.join("missing"), 10, "x").is_err());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn non_utf8_names_line_and_column() {
        let e = utf8_text(b"a,b\n\n1,\xff2\n".to_vec(), Path::new("in.csv")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "in.csv: line 3, column 3: not UTF-8 text (byte 0xff)"
        );
        assert_eq!(line_col(b"ab", 0), (1, 1));
        assert_eq!(line_col(b"a\nb", 2), (2, 1));
    }

    #[test]
    fn shorten_caps_and_escapes() {
        assert_eq!(shorten("abc", 5), "abc");
        assert_eq!(shorten("abcdef", 3), "abc... (3 more bytes)");
        assert_eq!(shorten("a\nb", 5), "a\\nb");
        let long = "x".repeat(10_000_000);
        assert!(shorten(&long, 40).len() < 80);
    }

    #[test]
    fn atomic_write_replaces_and_cleans_up() {
        let d = scratch("atomic");
        let f = d.join("sub/out.txt");
        write_atomic(&f, b"one").unwrap();
        write_atomic(&f, b"two").unwrap();
        assert_eq!(fs::read(&f).unwrap(), b"two");
        assert_eq!(listing(&d.join("sub")), vec!["out.txt"]);
        // A failing writer leaves the old file and no temporary.
        let e = write_atomic_with(&f, |_| Err(io::Error::other("disk full"))).unwrap_err();
        assert!(matches!(e, IoError::Output { .. }) && e.to_string().contains("disk full"));
        assert_eq!(fs::read(&f).unwrap(), b"two");
        assert_eq!(listing(&d.join("sub")), vec!["out.txt"]);
        // A failure in a folder the call created removes that folder too.
        let g = d.join("new/deeper/out.txt");
        write_atomic_with(&g, |_| Err(io::Error::other("no"))).unwrap_err();
        assert!(!d.join("new").exists());
        // A panic in the writer leaves no temporary either.
        let r = std::panic::catch_unwind(|| {
            let _ = write_atomic_with(&d.join("sub/p.txt"), |_| panic!("boom"));
        });
        assert!(r.is_err());
        assert_eq!(listing(&d.join("sub")), vec!["out.txt"]);
        assert!(matches!(
            write_atomic(&d.join("sub"), b"x"),
            Err(IoError::Input { .. })
        ));
        assert!(matches!(
            OutputSet::new(&d.join("sub/out.txt")),
            Err(IoError::Input { .. })
        ));
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn output_sets_are_all_or_nothing() {
        let d = scratch("set");
        {
            let mut set = OutputSet::new(&d.join("out")).unwrap();
            set.write("a.txt", b"a").unwrap();
            set.write("x/b.txt", b"b").unwrap();
            // Dropped without commit: nothing, not even the folder it created.
        }
        assert!(!d.join("out").exists());
        let mut set = OutputSet::new(&d.join("out")).unwrap();
        set.write("a.txt", b"a").unwrap();
        set.write("x/b.txt", b"b").unwrap();
        assert!(set.write("../evil", b"").is_err());
        let files = set.commit().unwrap();
        assert_eq!(files.len(), 2);
        assert_eq!(listing(&d.join("out")), vec!["a.txt", "x"]);
        assert_eq!(fs::read(d.join("out/x/b.txt")).unwrap(), b"b");
        // An existing folder is kept when a later set fails.
        {
            let mut set = OutputSet::new(&d.join("out")).unwrap();
            set.write("c.txt", b"c").unwrap();
        }
        assert_eq!(listing(&d.join("out")), vec!["a.txt", "x"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    fn is_link(p: &Path) -> bool {
        fs::symlink_metadata(p).unwrap().file_type().is_symlink()
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_and_stay_links() {
        use std::os::unix::fs::{PermissionsExt, symlink};
        let d = scratch("links");
        fs::create_dir_all(d.join("real")).unwrap();
        fs::create_dir_all(d.join("out")).unwrap();
        let target = d.join("real/t.csv");
        fs::write(&target, b"old").unwrap();
        fs::set_permissions(&target, fs::Permissions::from_mode(0o640)).unwrap();
        // A relative link in another folder: the target is replaced beside itself.
        let link = d.join("out/l.csv");
        symlink("../real/t.csv", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(is_link(&link), "the link was replaced by a file");
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(
            fs::metadata(&target).unwrap().permissions().mode() & 0o777,
            0o640
        );
        assert_eq!(listing(&d.join("real")), vec!["t.csv"]);
        assert_eq!(listing(&d.join("out")), vec!["l.csv"]);
        // A chain of two links.
        let chain = d.join("chain.csv");
        symlink(&link, &chain).unwrap();
        write_atomic(&chain, b"chained").unwrap();
        assert!(is_link(&chain) && is_link(&link));
        assert_eq!(fs::read(&target).unwrap(), b"chained");
        // A dangling link: its target is created, the link stays.
        let dangling = d.join("dangling.csv");
        symlink("real/new.csv", &dangling).unwrap();
        write_atomic(&dangling, b"created").unwrap();
        assert!(is_link(&dangling));
        assert_eq!(fs::read(d.join("real/new.csv")).unwrap(), b"created");
        // A failing writer leaves the target and no temporary beside it.
        write_atomic_with(&link, |_| Err(io::Error::other("disk full"))).unwrap_err();
        assert_eq!(fs::read(&target).unwrap(), b"chained");
        assert_eq!(listing(&d.join("real")), vec!["new.csv", "t.csv"]);
        // A loop is bad usage.
        symlink("loop-b", d.join("loop-a")).unwrap();
        symlink("loop-a", d.join("loop-b")).unwrap();
        let e = write_atomic(&d.join("loop-a"), b"x").unwrap_err();
        assert!(matches!(e, IoError::Input { .. }) && e.to_string().contains("symbolic links"));
        assert!(is_link(&d.join("loop-a")) && is_link(&d.join("loop-b")));
        // A link to a folder is a folder.
        symlink("real", d.join("dirlink")).unwrap();
        assert!(matches!(
            write_atomic(&d.join("dirlink"), b"x"),
            Err(IoError::Input { .. })
        ));
        fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    fn mkfifo(p: &Path) {
        let ok = std::process::Command::new("mkfifo")
            .arg(p)
            .status()
            .expect("mkfifo runs");
        assert!(ok.success());
    }

    #[cfg(unix)]
    fn file_type(p: &Path) -> fs::FileType {
        fs::symlink_metadata(p).unwrap().file_type()
    }

    #[cfg(unix)]
    #[test]
    fn fifos_and_devices_are_written_in_place() {
        use std::os::unix::fs::FileTypeExt;
        let d = scratch("special");
        fs::create_dir_all(&d).unwrap();
        let fifo = d.join("pipe");
        mkfifo(&fifo);
        // The reader reports through a channel so that a regression (the FIFO replaced while
        // the reader waits in open) fails after 30 s instead of hanging.
        let (tx, rx) = std::sync::mpsc::channel();
        {
            let fifo = fifo.clone();
            std::thread::spawn(move || tx.send(fs::read(fifo).unwrap()));
        }
        write_atomic(&fifo, b"through the pipe").unwrap();
        assert!(file_type(&fifo).is_fifo(), "the FIFO was replaced");
        let got = rx.recv_timeout(std::time::Duration::from_secs(30));
        assert_eq!(got.expect("the reader got the bytes"), b"through the pipe");
        assert_eq!(listing(&d), vec!["pipe"]);
        // A character device that takes everything.
        write_atomic(Path::new("/dev/null"), b"gone").unwrap();
        assert!(file_type(Path::new("/dev/null")).is_char_device());
        // A full one: an output error naming it, and the device stays.
        if fs::OpenOptions::new().write(true).open("/dev/full").is_ok() {
            let e = write_atomic(Path::new("/dev/full"), b"x").unwrap_err();
            assert!(matches!(e, IoError::Output { .. }), "{e:?}");
            assert!(e.to_string().contains("/dev/full"), "{e}");
            assert!(file_type(Path::new("/dev/full")).is_char_device());
        }
        // A socket cannot be opened: refused, and it stays a socket.
        let sock = d.join("sock");
        let _listener = std::os::unix::net::UnixListener::bind(&sock).unwrap();
        let e = write_atomic(&sock, b"x").unwrap_err();
        assert!(
            matches!(e, IoError::Input { .. }) && e.to_string().contains("socket"),
            "{e}"
        );
        assert!(file_type(&sock).is_socket());
        fs::remove_dir_all(&d).unwrap();
    }

    /// Root (this machine, CI) can give a file away with `lchown`; others skip, except under CI.
    #[cfg(unix)]
    fn can_chown() -> bool {
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

    #[cfg(unix)]
    #[test]
    fn foreign_links_and_fifos_in_sticky_folders_are_refused() {
        use std::os::unix::fs::{PermissionsExt, lchown, symlink};
        if !can_chown() {
            return;
        }
        let d = scratch("sticky");
        let tmp = d.join("tmp");
        fs::create_dir_all(&tmp).unwrap();
        fs::set_permissions(&tmp, fs::Permissions::from_mode(0o1777)).unwrap();
        let victim = d.join("bashrc");
        fs::write(&victim, b"mine").unwrap();
        // Another user's link in a sticky, world-writable folder: not followed.
        let link = tmp.join("out.png");
        symlink(&victim, &link).unwrap();
        lchown(&link, Some(12345), Some(12345)).unwrap();
        let e = write_atomic(&link, b"owned").unwrap_err();
        assert!(matches!(e, IoError::Input { .. }), "{e:?}");
        let m = e.to_string();
        assert!(
            m.contains("out.png") && m.contains("another user") && m.contains("sticky"),
            "{m}"
        );
        assert_eq!(fs::read(&victim).unwrap(), b"mine");
        assert!(is_link(&link));
        // Also as a member of an output set, and through a chain that starts elsewhere.
        let chain = d.join("chain.png");
        symlink(&link, &chain).unwrap();
        assert!(matches!(
            write_atomic(&chain, b"owned"),
            Err(IoError::Input { .. })
        ));
        let mut set = OutputSet::new(&tmp).unwrap();
        set.write("out.png", b"owned").unwrap();
        assert!(matches!(set.commit(), Err(IoError::Input { .. })));
        assert_eq!(fs::read(&victim).unwrap(), b"mine");
        // Our own link there is followed as before.
        fs::remove_file(&link).unwrap();
        symlink(&victim, &link).unwrap();
        write_atomic(&link, b"ours").unwrap();
        assert_eq!(fs::read(&victim).unwrap(), b"ours");
        // Another user's FIFO there is refused before the open (which would wait for a reader:
        // the write runs in a thread so that a regression fails instead of hanging).
        let fifo = tmp.join("pipe");
        mkfifo(&fifo);
        lchown(&fifo, Some(12345), Some(12345)).unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        {
            let fifo = fifo.clone();
            std::thread::spawn(move || tx.send(write_atomic(&fifo, b"x")));
        }
        let got = rx.recv_timeout(std::time::Duration::from_secs(10));
        let e = got.expect("refused, not opened").unwrap_err();
        assert!(
            matches!(e, IoError::Input { .. }) && e.to_string().contains("FIFO"),
            "{e:?}"
        );
        fs::remove_dir_all(&d).unwrap();
    }

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

    #[cfg(unix)]
    #[test]
    fn output_sets_follow_links_and_refuse_special_files() {
        use std::os::unix::fs::{FileTypeExt, symlink};
        let d = scratch("set-links");
        fs::create_dir_all(d.join("out")).unwrap();
        fs::create_dir_all(d.join("elsewhere")).unwrap();
        fs::write(d.join("elsewhere/a.txt"), b"old").unwrap();
        symlink(d.join("elsewhere/a.txt"), d.join("out/a.txt")).unwrap();
        let mut set = OutputSet::new(&d.join("out")).unwrap();
        set.write("a.txt", b"new").unwrap();
        set.commit().unwrap();
        assert!(is_link(&d.join("out/a.txt")));
        assert_eq!(fs::read(d.join("elsewhere/a.txt")).unwrap(), b"new");
        assert_eq!(listing(&d.join("elsewhere")), vec!["a.txt"]);
        // A FIFO among the destinations: refused before anything moves.
        mkfifo(&d.join("out/b.txt"));
        let mut set = OutputSet::new(&d.join("out")).unwrap();
        set.write("a.txt", b"newer").unwrap();
        set.write("b.txt", b"b").unwrap();
        let e = set.commit().unwrap_err();
        assert!(matches!(e, IoError::Input { .. }), "{e:?}");
        assert!(file_type(&d.join("out/b.txt")).is_fifo());
        assert_eq!(fs::read(d.join("elsewhere/a.txt")).unwrap(), b"new");
        assert_eq!(listing(&d.join("out")), vec!["a.txt", "b.txt"]);
        fs::remove_dir_all(&d).unwrap();
    }
}
