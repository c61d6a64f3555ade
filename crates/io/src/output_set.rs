//! Multi-file outputs written all-or-nothing: staged in a hidden folder, moved into place
//! only on commit.

use crate::error::{IoError, input_err, output_err};
use crate::resolve::{OutputTarget, resolve_output};
use crate::tmp::{create_dirs, remove_dirs, unique_tmp};
use crate::write::replace_atomic;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

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
    use crate::testutil::*;
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
