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
//!   created) is removed, so a failure leaves nothing behind.
//! - Multi-file outputs are all-or-nothing: [`OutputSet`] stages every file in a hidden
//!   temporary folder beside the destination and moves them into place only in
//!   [`OutputSet::commit`]; dropping it uncommitted (an error, a panic) removes the staging
//!   folder and any destination folder it created.
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

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, flushed, then
/// renamed over `path`. Missing folders are created; on failure the temporary file and the
/// folders this call created are removed and `path` is untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// [`write_atomic`] with the content streamed by `fill`.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), IoError> {
    let name = path
        .file_name()
        .ok_or_else(|| output_err(path, "not a file name"))?
        .to_string_lossy()
        .into_owned();
    if path.is_dir() {
        // The user named a folder where a file is wanted: bad usage (exit 2), not an I/O failure.
        return Err(input_err(path, "is a folder, not a file to write"));
    }
    let dir = path
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
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, path)?;
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
    pub fn commit(mut self) -> Result<Vec<PathBuf>, IoError> {
        for f in &self.files {
            let dest = self.dir.join(f);
            if let Some(parent) = dest.parent() {
                fs::create_dir_all(parent).map_err(|e| output_err(&dest, e))?;
            }
            if dest.is_dir() {
                return Err(output_err(&dest, "is a folder"));
            }
        }
        for f in &self.files {
            let dest = self.dir.join(f);
            fs::rename(self.staging.join(f), &dest).map_err(|e| output_err(&dest, e))?;
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
}
