//! The documentation runs (issue 28): README.md and the book (`docs/book/src/**/*.md`).
//!
//! - Every fenced block has a language; ```` ```sh ````, ```` ```bash ```` and
//!   ```` ```console ```` blocks run with the built `fastbrdf` first on `PATH`. The blocks of
//!   one page run in order in one temporary folder (`target/docs-run/`), as a reader pasting
//!   them into one terminal would. An `sh`/`bash` block is one bash script (`set -e -o
//!   pipefail`): it must exit 0. A `console` block is `$ command` lines, each followed by the
//!   output it prints (stdout and stderr as a terminal shows them), compared line by line: a
//!   line `...` stands for any number of lines, `[..]` inside a line for any text. A failure
//!   names the file, the line and the output.
//! - A block marked on its fence line `full` (too slow for CI, or needs what CI lacks) runs only
//!   with `FASTBRDF_DOCS_FULL=1`; one marked `no-run` never runs (the set-up and test commands
//!   themselves). Either needs its reason in an HTML comment on the line before the fence:
//!   `<!-- full: why -->`, `<!-- no-run: why -->`.
//! - A block marked `gpu` needs a Vulkan driver (Mesa's lavapipe serves, chosen here as
//!   tools/test.sh chooses it): without one it is skipped, except under CI, where it fails.
//! - In CI mode a skipped block's `cargo run -p fastbrdf --example synthetic_merl -- ...` line
//!   is done here through the library (`stand_in`), so that the later blocks find its file.
//! - ```` ```python ```` blocks run from `python/tests/test_docs.py` (the installed package);
//!   ```` ```rust ```` blocks are not run, but `library.md`'s example is the body of
//!   `library_example` in `docs_support/library.rs` (a test keeps the two identical).
//! - Generated sections (`<!-- NAME:begin -->` ... `<!-- NAME:end -->`) equal the output of the
//!   command that makes them (`GENERATED`); `FASTBRDF_BLESS=1 cargo test -p fastbrdf-cli --test
//!   docs generated` rewrites them.
//! - Every relative link in README.md and the book names a file that exists, and SUMMARY.md
//!   lists every chapter.
//! - Every repository path in a code span of README.md, ARCHITECTURE.md and the book exists
//!   (the rule: `docs_support/paths.rs`); ARCHITECTURE.md names every model family file.
//!
//! `cargo test -p fastbrdf-cli --test docs -- --nocapture` prints each block's time;
//! `FASTBRDF_DOCS_ONLY=commands.md` runs the blocks of the pages whose path contains that text.
//!
//! The parts live in `tests/docs_support/` (one file per responsibility).

mod docs_support;
