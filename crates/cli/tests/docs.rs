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
//!   `library_example` below (a test keeps the two identical).
//! - Generated sections (`<!-- NAME:begin -->` ... `<!-- NAME:end -->`) equal the output of the
//!   command that makes them (`GENERATED`); `FASTBRDF_BLESS=1 cargo test -p fastbrdf-cli --test
//!   docs generated` rewrites them.
//! - Every relative link in README.md and the book names a file that exists, and SUMMARY.md
//!   lists every chapter.
//!
//! `cargo test -p fastbrdf-cli --test docs -- --nocapture` prints each block's time;
//! `FASTBRDF_DOCS_ONLY=commands.md` runs the blocks of the pages whose path contains that text.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const BOOK: &str = "docs/book/src";
/// Languages of blocks that are not run here (shown as they are, or run by another test).
const SHOWN: &[&str] = &[
    "text", "rust", "python", "json", "csv", "toml", "wgsl", "glsl", "hlsl", "msl", "html",
];
const RUN: &[&str] = &["sh", "bash", "console"];
/// A block that runs longer is stopped and fails (a server left in the foreground); the full
/// mode's blocks (`check` of every bound in the debug build) get an hour.
fn block_timeout() -> Duration {
    Duration::from_secs(if full_mode() { 3600 } else { 600 })
}

fn root() -> PathBuf {
    std::fs::canonicalize(ROOT).unwrap()
}

fn full_mode() -> bool {
    std::env::var("FASTBRDF_DOCS_FULL").is_ok_and(|v| v == "1")
}

/// README.md and every page of the book, relative to the repository root, in a fixed order.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "md") {
                out.push(p);
            }
        }
    }
    let root = root();
    let mut out = vec![root.join("README.md")];
    walk(&root.join(BOOK), &mut out);
    out.into_iter()
        .map(|p| p.strip_prefix(&root).unwrap().to_path_buf())
        .collect()
}

#[derive(Debug, Clone)]
struct Block {
    page: PathBuf,
    /// 1-based line of the opening fence.
    line: usize,
    lang: String,
    attrs: Vec<String>,
    /// The HTML comment on the line before the fence, if any.
    comment: Option<String>,
    body: String,
}

impl Block {
    fn is(&self, attr: &str) -> bool {
        self.attrs.iter().any(|a| a == attr)
    }
    fn at(&self) -> String {
        format!("{}:{}", self.page.display(), self.line)
    }
}

fn blocks_of(page: &Path, text: &str) -> Vec<Block> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i];
        let fence_len = l.len() - l.trim_start_matches('`').len();
        if fence_len >= 3 && !l.starts_with("    ") {
            let fence = &l[..fence_len];
            let info = l[fence_len..].trim();
            let mut words = info.split([' ', ',']).filter(|w| !w.is_empty());
            let lang = words.next().unwrap_or("").to_string();
            let attrs = words.map(str::to_string).collect();
            let comment = lines[..i]
                .iter()
                .rev()
                .find(|l| !l.trim().is_empty())
                .map(|l| l.trim())
                .filter(|l| l.starts_with("<!--") && l.ends_with("-->"))
                .map(|l| l[4..l.len() - 3].trim().to_string());
            let start = i;
            let mut body = String::new();
            i += 1;
            while i < lines.len() && lines[i].trim_end() != fence {
                body.push_str(lines[i]);
                body.push('\n');
                i += 1;
            }
            assert!(
                i < lines.len(),
                "{}:{}: unclosed code block",
                page.display(),
                start + 1
            );
            out.push(Block {
                page: page.to_path_buf(),
                line: start + 1,
                lang,
                attrs,
                comment,
                body,
            });
        }
        i += 1;
    }
    out
}

fn all_blocks() -> Vec<Block> {
    let root = root();
    pages()
        .iter()
        .flat_map(|p| blocks_of(p, &std::fs::read_to_string(root.join(p)).unwrap()))
        .collect()
}

#[test]
fn every_block_has_a_known_language_and_its_marks_give_a_reason() {
    let mut bad = Vec::new();
    for b in all_blocks() {
        if !RUN.contains(&b.lang.as_str()) && !SHOWN.contains(&b.lang.as_str()) {
            bad.push(format!(
                "{}: a block needs a language (sh, console, python, text, ...), not {:?}",
                b.at(),
                b.lang
            ));
        }
        for a in &b.attrs {
            if !["full", "no-run", "gpu"].contains(&a.as_str()) {
                bad.push(format!(
                    "{}: unknown mark {a:?} (full, no-run, gpu)",
                    b.at()
                ));
                continue;
            }
            if !RUN.contains(&b.lang.as_str()) {
                bad.push(format!("{}: {a} on a block that is not run", b.at()));
            }
            if a == "gpu" {
                continue;
            }
            let reason = b
                .comment
                .as_deref()
                .and_then(|c| c.strip_prefix(&format!("{a}:")));
            if reason.is_none_or(|r| r.trim().len() < 10) {
                bad.push(format!(
                    "{}: a block marked {a} needs `<!-- {a}: the reason -->` on the line before",
                    b.at()
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_readme_is_a_front_door() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let n = readme.lines().count();
    assert!(
        n <= 400,
        "README.md has {n} lines: at most 400; move the detail into the book (docs/book/src)"
    );
}

// --- Running the blocks -------------------------------------------------------------------

/// What a page's blocks ran: failures (with their output) and (block, seconds) for the report.
struct PageRun {
    failures: Vec<String>,
    times: Vec<(String, f64, &'static str)>,
}

/// The output of a process: status (None if it timed out) and stdout + stderr as written.
struct Ran {
    status: Option<i32>,
    output: String,
}

/// Runs `bash` with `args` in `dir`, stdout and stderr into one file (the order a terminal
/// shows), in a process group of its own, killed when the script ends (a server started with
/// `&`) or after `block_timeout()`.
fn run_bash(dir: &Path, args: &[&str], full: bool) -> Ran {
    use std::os::unix::process::CommandExt;
    let bin = Path::new(env!("CARGO_BIN_EXE_fastbrdf")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out_path = dir.join(".docs-output");
    let out = std::fs::File::create(&out_path).unwrap();
    let mut cmd = Command::new("bash");
    cmd.args(args)
        .current_dir(dir)
        .env("PATH", path)
        .stdin(Stdio::null())
        .stdout(out.try_clone().unwrap())
        .stderr(out)
        .process_group(0);
    // As tools/test.sh does: Mesa's software Vulkan driver when it is there and no driver is
    // chosen, so that `--gpu` blocks run on machines without a GPU.
    if std::env::var_os("VK_ICD_FILENAMES").is_none()
        && std::env::var_os("VK_DRIVER_FILES").is_none()
    {
        let lvp = format!(
            "/usr/share/vulkan/icd.d/lvp_icd.{}.json",
            std::env::consts::ARCH
        );
        if Path::new(&lvp).exists() {
            cmd.env("VK_ICD_FILENAMES", lvp);
        }
    }
    if std::env::var_os("WGPU_BACKEND").is_none() {
        cmd.env("WGPU_BACKEND", "vulkan");
    }
    if full {
        // A nested cargo (the `synthetic_merl` example) builds in a folder of its own: the
        // cargo running this test may hold the lock on target/.
        cmd.env("CARGO_TARGET_DIR", root().join("target/docs-cargo"));
    }
    let mut child = cmd.spawn().expect("bash runs");
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code().or(Some(-1));
        }
        if started.elapsed() > block_timeout() {
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    // The group: whatever the block left running in the background.
    let _ = Command::new("kill")
        .args(["-TERM", "--", &format!("-{}", child.id())])
        .stderr(Stdio::null())
        .status();
    let _ = child.wait();
    let output = std::fs::read(&out_path).unwrap_or_default();
    let _ = std::fs::remove_file(&out_path);
    Ran {
        status,
        output: String::from_utf8_lossy(&output).into_owned(),
    }
}

fn tail(s: &str, lines: usize) -> String {
    let v: Vec<&str> = s.lines().collect();
    let from = v.len().saturating_sub(lines);
    let mut t = v[from..].join("\n");
    if from > 0 {
        t = format!("[{from} lines before]\n{t}");
    }
    t
}

/// An `sh`/`bash` block: one script. The ERR trap names the block's line that failed.
fn run_script(dir: &Path, b: &Block, full: bool) -> Result<(), String> {
    const PRELUDE: usize = 2;
    let script = format!(
        "set -e -o pipefail\ntrap 'echo \"docs: exit $? at {}:$((LINENO - {PRELUDE} + {}))\" >&2' ERR\n{}",
        b.page.display(),
        b.line,
        b.body
    );
    let ran = run_bash(dir, &["-c", &script], full);
    match ran.status {
        Some(0) => Ok(()),
        Some(code) => Err(format!(
            "{}: the block exited {code}; its output:\n{}",
            b.at(),
            tail(&ran.output, 40)
        )),
        None => Err(format!(
            "{}: the block ran past {} s; its output:\n{}",
            b.at(),
            block_timeout().as_secs(),
            tail(&ran.output, 40)
        )),
    }
}

/// Does `actual` match `pattern`, a line of expected output where `[..]` is any text?
fn line_matches(pattern: &str, actual: &str) -> bool {
    let parts: Vec<&str> = pattern.split("[..]").collect();
    if parts.len() == 1 {
        return pattern == actual;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !actual.starts_with(first) || actual.len() < first.len() + last.len() {
        return false;
    }
    let mut rest = &actual[first.len()..];
    for p in &parts[1..parts.len() - 1] {
        match rest.find(p) {
            Some(k) => rest = &rest[k + p.len()..],
            None => return false,
        }
    }
    rest.ends_with(last)
}

/// Expected lines (with `...` for any lines) against actual lines.
fn lines_match(expected: &[&str], actual: &[&str]) -> bool {
    match expected.split_first() {
        None => actual.is_empty(),
        Some((&"...", rest)) => (0..=actual.len()).any(|k| lines_match(rest, &actual[k..])),
        Some((e, rest)) => {
            !actual.is_empty() && line_matches(e, actual[0]) && lines_match(rest, &actual[1..])
        }
    }
}

/// A `console` block: `$ command` (continued by a trailing `\`), then its expected output.
fn run_console(dir: &Path, b: &Block, full: bool) -> Result<(), String> {
    let lines: Vec<&str> = b.body.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let Some(first) = lines[i].strip_prefix("$ ") else {
            return Err(format!(
                "{}: line {}: a console block is `$ command` lines and their output",
                b.at(),
                b.line + 1 + i
            ));
        };
        let cmd_line = b.line + 1 + i;
        let mut cmd = first.to_string();
        while cmd.ends_with('\\') && i + 1 < lines.len() {
            i += 1;
            cmd.push('\n');
            cmd.push_str(lines[i]);
        }
        i += 1;
        let mut expected = Vec::new();
        while i < lines.len() && !lines[i].starts_with("$ ") {
            expected.push(lines[i].trim_end());
            i += 1;
        }
        while expected.last() == Some(&"") {
            expected.pop();
        }
        let ran = run_bash(dir, &["-o", "pipefail", "-c", &cmd], full);
        let actual: Vec<&str> = ran.output.lines().map(str::trim_end).collect();
        let mut actual = actual.as_slice();
        while actual.last() == Some(&"") {
            actual = &actual[..actual.len() - 1];
        }
        let at = format!("{}:{cmd_line}", b.page.display());
        if ran.status != Some(0) {
            return Err(format!(
                "{at}: `{cmd}` exited {:?} (a console command must succeed; show a failure \
                 with `; echo \"exit $?\"`); its output:\n{}",
                ran.status,
                tail(&ran.output, 40)
            ));
        }
        if !lines_match(&expected, actual) {
            return Err(format!(
                "{at}: `{cmd}` printed other lines than the block shows.\nexpected:\n{}\nactual:\n{}",
                expected.join("\n"),
                tail(&ran.output, 60)
            ));
        }
    }
    Ok(())
}

/// In CI mode, what a skipped block leaves behind that later blocks need: the synthetic MERL
/// file of `cargo run -p fastbrdf --example synthetic_merl -- OUT MODEL KD KS [NAME=VALUE]...`,
/// written here as the example writes it (`kd/pi + ks * model` at the bin centres).
fn stand_in(dir: &Path, b: &Block) -> Result<(), String> {
    const EXAMPLE: &str = "cargo run -p fastbrdf --example synthetic_merl -- ";
    for l in b.body.lines() {
        let Some(args) = l.trim().strip_prefix(EXAMPLE) else {
            continue;
        };
        let args: Vec<&str> = args
            .split_whitespace()
            .take_while(|w| !w.starts_with('#'))
            .collect();
        let rgb = |s: &str| -> Result<[f64; 3], String> {
            let v: Vec<f64> = s
                .split(',')
                .map(|x| x.parse().map_err(|e| format!("{s}: {e}")))
                .collect::<Result<_, _>>()?;
            v.try_into().map_err(|_| format!("{s}: three numbers"))
        };
        let (kd, ks) = (rgb(args[2])?, rgb(args[3])?);
        let given: Vec<(&str, &str)> = args[4..]
            .iter()
            .map(|p| p.split_once('=').ok_or(format!("{p}: NAME=VALUE")))
            .collect::<Result<_, _>>()?;
        let spec = fastbrdf::ModelSpec::parse(args[1], &given).map_err(|e| e.to_string())?;
        let fastbrdf::Model::Brdf(brdf) = spec.model::<f64>().map_err(|e| e.to_string())? else {
            return Err(format!("{}: {} is not a BRDF", b.at(), args[1]));
        };
        fastbrdf::measured::write_merl(&dir.join(args[0]), |th, td, pd| {
            let (wi, wo) = fastbrdf::measured::from_half_diff(th, td, pd);
            if wi[2] <= 0.0 || wo[2] <= 0.0 {
                return [-1.0; 3];
            }
            let s = brdf.eval(wi, wo);
            [0, 1, 2].map(|c| kd[c] / std::f64::consts::PI + ks[c] * s)
        })
        .map_err(|e| format!("{}: {e}", b.at()))?;
    }
    Ok(())
}

/// Is a Vulkan driver there (chosen by the environment, or an ICD file installed)? The GPU
/// tests' rule: without one a `gpu` block is skipped, except under CI, where it fails.
fn vulkan_driver() -> bool {
    if std::env::var_os("VK_ICD_FILENAMES").is_some()
        || std::env::var_os("VK_DRIVER_FILES").is_some()
    {
        return true;
    }
    [
        "/usr/share/vulkan/icd.d",
        "/etc/vulkan/icd.d",
        "/usr/local/share/vulkan/icd.d",
    ]
    .iter()
    .filter_map(|d| std::fs::read_dir(d).ok())
    .flatten()
    .any(|e| e.is_ok_and(|e| e.path().extension().is_some_and(|x| x == "json")))
}

fn run_page(page: &Path, blocks: &[Block], full: bool) -> PageRun {
    let name = page.to_string_lossy().replace(['/', '.'], "-");
    let dir = root()
        .join("target/docs-run")
        .join(format!("{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut run = PageRun {
        failures: Vec::new(),
        times: Vec::new(),
    };
    for b in blocks.iter().filter(|b| RUN.contains(&b.lang.as_str())) {
        if b.is("gpu") && !vulkan_driver() {
            if std::env::var_os("CI").is_some() {
                run.failures.push(format!(
                    "{}: a `gpu` block and no Vulkan driver (tools/test.sh installs Mesa's lavapipe)",
                    b.at()
                ));
                continue;
            } else {
                eprintln!(
                    "docs: {}: skipped, no Vulkan driver (CI fails here)",
                    b.at()
                );
                run.times.push((b.at(), 0.0, "never"));
                continue;
            }
        }
        let skipped = b.is("no-run") || (b.is("full") && !full);
        if skipped {
            if let Err(e) = stand_in(&dir, b) {
                run.failures.push(e);
            }
            let why = if b.is("no-run") { "never" } else { "full" };
            run.times.push((b.at(), 0.0, why));
            continue;
        }
        let t = Instant::now();
        let r = if b.lang == "console" {
            run_console(&dir, b, full)
        } else {
            run_script(&dir, b, full)
        };
        let mode = if b.is("full") { "full" } else { "ci" };
        run.times.push((b.at(), t.elapsed().as_secs_f64(), mode));
        if let Err(e) = r {
            run.failures
                .push(format!("{e}\n(working folder kept: {})", dir.display()));
        }
    }
    if run.failures.is_empty() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    run
}

/// Every shell block of README.md and the book, each page in its own folder, the pages in
/// parallel (a few at a time).
#[test]
fn every_shell_block_runs() {
    let full = full_mode();
    let blocks = all_blocks();
    // FASTBRDF_DOCS_ONLY=TEXT: only the pages whose path contains TEXT (one page at a time).
    let only = std::env::var("FASTBRDF_DOCS_ONLY").unwrap_or_default();
    let pages: Vec<PathBuf> = pages()
        .into_iter()
        .filter(|p| p.to_string_lossy().contains(&only))
        .collect();
    let queue = Mutex::new(pages.iter());
    let results = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism()
        .map_or(2, |n| n.get())
        .clamp(2, 4);
    let started = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                loop {
                    let Some(page) = queue.lock().unwrap().next() else {
                        break;
                    };
                    let own: Vec<Block> =
                        blocks.iter().filter(|b| &b.page == page).cloned().collect();
                    let r = run_page(page, &own, full);
                    results.lock().unwrap().push(r);
                }
            });
        }
    });
    let results = results.into_inner().unwrap();
    let mut times: Vec<_> = results.iter().flat_map(|r| r.times.clone()).collect();
    times.sort_by(|a, b| b.1.total_cmp(&a.1));
    let count = |m: &str| times.iter().filter(|t| t.2 == m).count();
    eprintln!(
        "docs: {} shell blocks: {} run in CI, {} in full mode only{}, {} never; {:.1} s",
        times.len(),
        count("ci"),
        count("full"),
        if full { " (run)" } else { " (skipped)" },
        count("never"),
        started.elapsed().as_secs_f64()
    );
    for (at, secs, mode) in times.iter().filter(|t| t.1 > 0.0) {
        eprintln!("  {secs:7.2} s  {mode:4}  {at}");
    }
    let failures: Vec<String> = results.into_iter().flat_map(|r| r.failures).collect();
    assert!(
        failures.is_empty(),
        "{} documentation block(s) failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn the_output_matcher_elides_and_fails() {
    assert!(lines_match(&["a", "...", "d"], &["a", "b", "c", "d"]));
    assert!(lines_match(&["a", "...", "d"], &["a", "d"]));
    assert!(!lines_match(&["a", "...", "d"], &["a", "b"]));
    assert!(lines_match(&["x [..] z"], &["x yyy z"]));
    assert!(!lines_match(&["x [..] z"], &["x yyy w"]));
    assert!(!lines_match(&["a"], &["a", "b"]));
    assert!(!lines_match(&["a", "b"], &["a"]));
    assert!(lines_match(&["[..]"], &[""]));
}

// --- Generated sections --------------------------------------------------------------------

/// A section of the documentation that is a command's output: its marker, its page, the
/// command (run in the repository root), and whether the output sits in a ```text block.
struct Generated {
    marker: &'static str,
    page: &'static str,
    args: &'static [&'static str],
    fenced: bool,
    /// Turns the command's output into the section (default: the output as it is).
    render: Option<fn(&str) -> String>,
}

const GENERATED: &[Generated] = &[
    Generated {
        marker: "models-detail",
        page: "docs/book/src/models.md",
        args: &["models", "--json"],
        fenced: false,
        render: Some(model_details),
    },
    Generated {
        marker: "models",
        page: "docs/book/src/models.md",
        args: &["models"],
        fenced: true,
        render: None,
    },
    Generated {
        marker: "bench",
        page: "docs/book/src/speed.md",
        args: &["bench", "--from", "docs/bench/bench.json", "--markdown"],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "bench-gpu",
        page: "docs/book/src/gpu.md",
        args: &[
            "bench",
            "--from",
            "docs/bench/bench-gpu.json",
            "--gpu-only",
            "--markdown",
        ],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "pareto",
        page: "docs/book/src/tuned.md",
        args: &["pareto", "--bench", "docs/bench/bench.json", "--markdown"],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "pareto-brdf",
        page: "docs/book/src/pareto-brdf.md",
        args: &[
            "pareto",
            "--brdf",
            "--costs",
            "docs/bench/pareto-brdf.json",
            "--mesh",
            "crates/render/data/canonical_face_model.obj",
            "--markdown",
        ],
        fenced: false,
        render: None,
    },
    Generated {
        marker: "reproduce",
        page: "docs/book/src/reproduction.md",
        args: &[
            "reproduce",
            "--markdown",
            "--speedups",
            "docs/bench/bench.json",
        ],
        fenced: false,
        render: None,
    },
];

fn bless() -> bool {
    std::env::var("FASTBRDF_BLESS").is_ok_and(|v| v == "1")
}

/// The section `g` of its page equals the command's output (with FASTBRDF_BLESS=1: is
/// rewritten to it).
fn check_generated(marker: &str) {
    let g = GENERATED.iter().find(|g| g.marker == marker).unwrap();
    let root = root();
    let o = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
        .current_dir(&root)
        .args(g.args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "fastbrdf {}: {}",
        g.args.join(" "),
        String::from_utf8_lossy(&o.stderr)
    );
    let out = String::from_utf8(o.stdout).unwrap();
    let out = match g.render {
        Some(render) => render(&out),
        None => out,
    };
    let want = if g.fenced {
        format!("```text\n{out}```\n")
    } else {
        out
    };
    let path = root.join(g.page);
    let page = std::fs::read_to_string(&path).unwrap();
    let open = format!("<!-- {marker}:begin -->\n");
    let close = format!("<!-- {marker}:end -->");
    let start = page
        .find(&open)
        .unwrap_or_else(|| panic!("{} has no {open}", g.page))
        + open.len();
    let end = start
        + page[start..]
            .find(&close)
            .unwrap_or_else(|| panic!("{} does not close {marker}", g.page));
    if page[start..end] == want {
        return;
    }
    if bless() {
        let new = format!("{}{want}{}", &page[..start], &page[end..]);
        std::fs::write(&path, new).unwrap();
        return;
    }
    panic!(
        "{}'s section {marker} is stale: it is the output of `fastbrdf {}`. Regenerate it with \
         `FASTBRDF_BLESS=1 cargo test -p fastbrdf-cli --test docs generated` and review the diff",
        g.page,
        g.args.join(" ")
    );
}

#[test]
fn generated_models_reference_is_the_registry() {
    check_generated("models");
    check_generated("models-detail");
}

/// The model reference's sections, one per model, from `fastbrdf models --json`: formula,
/// source, note, parameters (range, default, choices), bounds, f32 bound and operation counts.
fn model_details(json: &str) -> String {
    use serde_json::Value;
    use std::fmt::Write;
    let v: Value = serde_json::from_str(json).unwrap();
    let num = |x: &Value| match x.as_f64() {
        Some(f) if f != 0.0 && f.abs() < 1e-3 => format!("{f:e}"),
        Some(f) => format!("{f}"),
        None => x.to_string(),
    };
    let mut out = String::new();
    let mut kind = String::new();
    for m in v["models"].as_array().unwrap() {
        let k = m["kind"].as_str().unwrap();
        if k != kind {
            kind = k.to_string();
            let _ = write!(out, "\n### Kind `{kind}`\n");
        }
        let _ = write!(out, "\n#### `{}`\n\n", m["id"].as_str().unwrap());
        let _ = writeln!(out, "- formula: `{}`", m["formula"].as_str().unwrap_or(""));
        let _ = writeln!(out, "- source: {}", m["source"].as_str().unwrap_or(""));
        if let Some(note) = m["note"].as_str().filter(|s| !s.is_empty()) {
            let _ = writeln!(out, "- note: {note}");
        }
        for p in m["params"].as_array().unwrap() {
            let name = p["name"].as_str().unwrap();
            let doc = p["doc"].as_str().unwrap_or("");
            if p["type"] == "number" {
                let _ = writeln!(
                    out,
                    "- `{name}` in [{}, {}], default {}: {doc}",
                    num(&p["min"]),
                    num(&p["max"]),
                    num(&p["default"])
                );
            } else {
                let options: Vec<String> = p["options"]
                    .as_array()
                    .map(|o| {
                        o.iter()
                            .map(|x| format!("`{}`", x.as_str().unwrap()))
                            .collect()
                    })
                    .unwrap_or_default();
                let _ = writeln!(
                    out,
                    "- `{name}`, one of {}; default `{}`: {doc}",
                    options.join(", "),
                    p["default"].as_str().unwrap_or("")
                );
            }
        }
        for b in m["bounds"].as_array().unwrap() {
            let range = &b["param"];
            let _ = writeln!(
                out,
                "- bound against `{}`: {} {} (divided by the {}) <= {}, {} in [{}, {}]",
                b["reference"].as_str().unwrap_or(""),
                b["metric"].as_str().unwrap_or(""),
                b["zone"].as_str().unwrap_or(""),
                b["divided_by"].as_str().unwrap_or(""),
                num(&b["bound"]),
                range[0].as_str().unwrap_or(""),
                num(&range[1]),
                num(&range[2])
            );
        }
        let o = &m["ops"];
        let _ = writeln!(
            out,
            "- f32 bound {}; operations (multiplies/adds/divides/square roots/transcendentals) {}/{}/{}/{}/{}",
            num(&m["f32_bound"]),
            num(&o["mul"]),
            num(&o["add"]),
            num(&o["div"]),
            num(&o["sqrt"]),
            num(&o["transcendental"])
        );
    }
    out
}

#[test]
fn generated_bench_tables_are_the_saved_run() {
    check_generated("bench");
}

#[test]
fn generated_gpu_bench_tables_are_the_saved_run() {
    check_generated("bench-gpu");
}

#[test]
fn generated_pareto_table_is_current() {
    check_generated("pareto");
}

#[test]
fn generated_pareto_brdf_table_is_current() {
    check_generated("pareto-brdf");
}

#[test]
fn generated_reproduction_table_is_current() {
    check_generated("reproduce");
}

/// Every `<!-- NAME:begin -->` in the documentation is one of `GENERATED` (a section nobody
/// regenerates would go stale), on the page named there, once.
#[test]
fn every_generated_section_is_checked() {
    let root = root();
    let mut found = Vec::new();
    for p in pages() {
        let text = std::fs::read_to_string(root.join(&p)).unwrap();
        for line in text.lines() {
            if let Some(m) = line
                .strip_prefix("<!-- ")
                .and_then(|l| l.strip_suffix(":begin -->"))
            {
                found.push((m.to_string(), p.clone()));
            }
        }
    }
    for (marker, page) in &found {
        let g = GENERATED.iter().find(|g| g.marker == marker);
        assert!(
            g.is_some_and(|g| Path::new(g.page) == page),
            "{}: section {marker} is not in docs.rs's GENERATED list (or not on its page)",
            page.display()
        );
    }
    for g in GENERATED {
        assert_eq!(
            found.iter().filter(|(m, _)| m == g.marker).count(),
            1,
            "section {} appears once",
            g.marker
        );
    }
}

// --- Links ---------------------------------------------------------------------------------

/// The link targets of a Markdown text: `[..](target)`, `![..](target)`, `[..]: target` and
/// `src="target"`, outside code blocks and code spans.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_code = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        // Code spans hold no links.
        let mut plain = String::new();
        for (k, part) in line.split('`').enumerate() {
            if k % 2 == 0 {
                plain.push_str(part);
            }
        }
        let mut rest = plain.as_str();
        while let Some(k) = rest.find("](") {
            let after = &rest[k + 2..];
            let end = after.find(')').unwrap_or(after.len());
            out.push((n + 1, after[..end].to_string()));
            rest = &after[end..];
        }
        let t = plain.trim_start();
        if t.starts_with('[')
            && let Some(k) = t.find("]: ")
        {
            out.push((n + 1, t[k + 3..].trim().to_string()));
        }
        let mut rest = plain.as_str();
        while let Some(k) = rest.find("src=\"") {
            let after = &rest[k + 5..];
            let end = after.find('"').unwrap_or(after.len());
            out.push((n + 1, after[..end].to_string()));
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_names_a_file() {
    let root = root();
    let mut bad = Vec::new();
    let mut count = 0;
    for p in pages() {
        let text = std::fs::read_to_string(root.join(&p)).unwrap();
        for (line, target) in link_targets(&text) {
            let target = target.split_whitespace().next().unwrap_or("");
            if target.is_empty()
                || target.starts_with('#')
                || target.contains("://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            count += 1;
            let file = target.split('#').next().unwrap();
            let resolved = root.join(p.parent().unwrap()).join(file);
            if !resolved.exists() {
                bad.push(format!("{}:{line}: {target} does not exist", p.display()));
            } else if !std::fs::canonicalize(&resolved).unwrap().starts_with(&root) {
                bad.push(format!(
                    "{}:{line}: {target} leaves the repository",
                    p.display()
                ));
            }
        }
    }
    assert!(
        count >= 20,
        "only {count} relative links found: the scan is broken"
    );
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_summary_lists_every_chapter() {
    let root = root();
    let summary = std::fs::read_to_string(root.join(BOOK).join("SUMMARY.md")).unwrap();
    let listed: Vec<String> = link_targets(&summary).into_iter().map(|t| t.1).collect();
    for p in pages() {
        let Ok(rel) = p.strip_prefix(BOOK) else {
            continue;
        };
        let rel = rel.to_string_lossy();
        if rel != "SUMMARY.md" {
            assert!(
                listed.iter().any(|l| *l == rel),
                "docs/book/src/SUMMARY.md does not list {rel}"
            );
        }
    }
    let toml = std::fs::read_to_string(root.join("docs/book/book.toml")).unwrap();
    assert!(toml.contains("[book]"), "book.toml");
}

// --- The library chapter's example ---------------------------------------------------------

/// The ```rust block of docs/book/src/library.md is this function's body, text for text
/// (between the `doc:library` markers), so it compiles with the library as it is.
#[allow(dead_code)]
fn library_example() -> Result<(), fastbrdf::Error> {
    // doc:library:begin
    use fastbrdf::{Given, Model, ModelSpec};

    // Text from a command line or a file: parsed and validated once.
    let spec = ModelSpec::parse(
        "cook-torrance",
        &[("alpha", "0.2"), ("d", "beckmann-power16")],
    )?;
    let Model::Brdf(ct) = spec.model::<f32>()? else {
        unreachable!("cook-torrance is a BRDF")
    };
    let f = ct.eval([0.3, 0.0, 0.95], [-0.3, 0.1, 0.95]);
    assert!(f > 0.0);

    // Typed values (a fit, a slider): no text on the way.
    let ggx = ModelSpec::new("ggx", &[("alpha", Given::Num(0.3))])?;
    let Model::Distribution(d) = ggx.model::<f64>()? else {
        unreachable!("ggx is a distribution")
    };
    assert!(d.eval(1.0) > 0.0);

    // The SIMD batch kernel of the same spec.
    let kernel = fastbrdf::batch::Kernel::from_spec(&ggx)?;
    assert!(kernel.simd());
    // doc:library:end
    Ok(())
}

#[test]
fn library_example_runs_and_is_the_chapters_block() {
    library_example().unwrap();
    let me = include_str!("docs.rs");
    let begin = me.find("// doc:library:begin\n").unwrap() + "// doc:library:begin\n".len();
    let end = me.find("    // doc:library:end").unwrap();
    let body: String = me[begin..end]
        .lines()
        .map(|l| l.strip_prefix("    ").unwrap_or(l))
        .map(|l| format!("{l}\n"))
        .collect();
    let chapter = std::fs::read_to_string(root().join(BOOK).join("library.md")).unwrap();
    let block = blocks_of(Path::new("library.md"), &chapter)
        .into_iter()
        .find(|b| b.lang == "rust")
        .expect("library.md has a rust block");
    assert_eq!(
        block.body, body,
        "docs/book/src/library.md's rust block must be library_example's body in crates/cli/tests/docs.rs"
    );
}

// --- ARCHITECTURE.md's list of model files --------------------------------------------------

/// ARCHITECTURE.md's "Where a model lives" names every family file of the core crate (the
/// ids they serve are the generated model reference), so a new family cannot be left out.
#[test]
fn architecture_names_every_family_file() {
    let root = root();
    let arch = std::fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
    let section = &arch[arch
        .find("## Where a model lives")
        .expect("ARCHITECTURE.md has 'Where a model lives'")..];
    let block = blocks_of(Path::new("ARCHITECTURE.md"), section)
        .into_iter()
        .next()
        .expect("a code block listing the files")
        .body;
    let words: Vec<&str> = block
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .collect();
    let mut missing = Vec::new();
    for dir in ["lobes", "microfacet", "brdf"] {
        for e in std::fs::read_dir(root.join("crates/fastbrdf/src").join(dir)).unwrap() {
            let p = e.unwrap().path();
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            if p.extension().is_some_and(|x| x == "rs")
                && stem != "mod"
                && !words.contains(&stem.as_str())
            {
                missing.push(format!("src/{dir}/{stem}.rs"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's 'Where a model lives' does not name {missing:?}"
    );
}
