//! Bounded reads of untrusted inputs: at most `limit + 1` bytes are ever read or held, and
//! every input is read once.

use crate::error::{IoError, input_err};
use crate::text::utf8_text;
use std::fs;
use std::io::Read;
use std::path::Path;

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

/// [`read_bounded`] then [`utf8_text`].
pub fn read_text_bounded(path: &Path, limit: u64, what: &str) -> Result<String, IoError> {
    utf8_text(read_bounded(path, limit, what)?, path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::scratch;
    use std::io;
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
}
