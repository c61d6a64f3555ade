//! Atomic writes of one file: a unique temporary beside the target, renamed onto it, with
//! everything this call created removed on failure; FIFOs, devices and the standard streams
//! written in place (see [`crate::resolve_output`]).

use crate::error::{IoError, input_err, output_err};
use crate::resolve::{OutputTarget, open_direct, resolve_output, via};
use crate::tmp::{TmpGuard, create_dirs, remove_dirs, unique_tmp};
use std::fs;
use std::io::{self, Write};
use std::path::Path;

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
pub(crate) fn replace_atomic(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OutputSet;
    use crate::error::IoError;
    use crate::testutil::*;
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
}
