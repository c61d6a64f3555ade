//! Running the `sh`/`bash` and `console` blocks: one temporary folder per page, the pages in
//! parallel, a process group per command, the output matcher (`...`, `[..]`).

use super::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

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
