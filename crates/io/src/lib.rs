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
//! these modules (about 700 lines beside their tests).

mod error;
mod output_set;
mod read;
mod resolve;
#[cfg(test)]
mod testutil;
mod text;
mod tmp;
mod write;

pub use error::IoError;
pub use output_set::OutputSet;
pub use read::{human_size, read_bounded, read_reader_bounded, read_text_bounded};
pub use resolve::{OutputTarget, resolve_output};
pub use text::{line_col, shorten, shorten_middle, utf8_text};
pub use write::{write_atomic, write_atomic_with};
