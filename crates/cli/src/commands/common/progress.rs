//! The progress bar every long command draws on stderr.

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar on stderr (drawn only on a terminal).
pub fn bar(len: u64, msg: &'static str) -> ProgressBar {
    let b = ProgressBar::new(len);
    b.set_style(
        ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} {elapsed}")
            .expect("valid template"),
    );
    b.set_message(msg);
    b
}
