//! Exit codes and outputs (issue 11): degenerate ranges refused before any output, write and
//! stdout failures are exit 3 and leave nothing behind, no file written unasked, and every
//! option and subcommand documented in `--help`.

mod common;

use common::{fastbrdf, stderr, stdout, temp_dir};
use std::process::{Command, Output};

/// Runs the binary through bash (for `ulimit -f` and redirections); `script` uses `$B` for it.
fn bash(script: &str, dir: &std::path::Path) -> Output {
    Command::new("bash")
        .arg("-c")
        .arg(script)
        .env("B", env!("CARGO_BIN_EXE_fastbrdf"))
        .current_dir(dir)
        .output()
        .unwrap()
}

/// Everything under `d`, relative, sorted (hidden staging folders and temporaries included).
fn tree(d: &std::path::Path) -> Vec<String> {
    fn walk(root: &std::path::Path, d: &std::path::Path, out: &mut Vec<String>) {
        if let Ok(r) = std::fs::read_dir(d) {
            for e in r.flatten() {
                let p = e.path();
                out.push(p.strip_prefix(root).unwrap().display().to_string());
                if p.is_dir() {
                    walk(root, &p, out);
                }
            }
        }
    }
    let mut v = vec![];
    walk(d, d, &mut v);
    v.sort();
    v
}

/// Issue 11: degenerate ranges panicked (index out of bounds), printed a header first, or
/// exited 0 with empty output. Every command taking a range refuses them before any output.
#[test]
fn every_range_argument_refuses_degenerate_ranges_before_any_output() {
    let d = temp_dir("ranges");
    let out = d.join("plot");
    let o = out.to_str().unwrap();
    let bad = [
        "1..2:1e-300",
        "1e308..1.7e308",
        "-1.7e308..1.7e308",
        "5..1",
        "1..5:0",
        "1..5:-1",
        "1..5:nan",
        "1..inf",
        "1..1e9",
        "",
        "1,,2",
    ];
    for r in bad {
        let cases: Vec<Vec<&str>> = vec![
            vec!["errors", "--model", "flog", "--reference", "pow", "--n", r],
            vec![
                "errors",
                "--model",
                "beckmann-power16",
                "--reference",
                "beckmann-ct",
                "--m",
                r,
            ],
            vec!["normalize", "--model", "flog", "--n", r],
            vec![
                "albedo",
                "--model",
                "ward",
                "--param",
                "alpha=0.3",
                "--angles",
                r,
            ],
            vec!["plot", "max-error", "--n", r, "--out", o],
            vec!["plot", "coef", "--n", r, "--out", o],
            vec!["fit", "--family", "power16", "--reference", "pow", "--n", r],
            vec![
                "fit",
                "--family",
                "beckmann-power16",
                "--reference",
                "beckmann-ct",
                "--m",
                r,
            ],
        ];
        for args in cases {
            let res = fastbrdf(&args, "");
            assert_eq!(res.status.code(), Some(2), "{args:?}: {}", stderr(&res));
            assert!(res.stdout.is_empty(), "{args:?}: {}", stdout(&res));
            assert!(!stderr(&res).contains("panicked"), "{args:?}");
        }
    }
    assert!(tree(&d).is_empty(), "{:?}", tree(&d));
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 11: a file-size limit killed the process (SIGXFSZ) and left temporaries and some of
/// `shader --all`'s 41 files. Now: exit code 3, a message, and nothing left behind.
#[cfg(unix)]
#[test]
fn write_failures_exit_3_and_leave_nothing_behind() {
    let d = temp_dir("efbig");
    for (script, target) in [
        (
            "ulimit -f 1; exec \"$B\" shader --model cook-torrance --param alpha=0.2 --out s.wgsl",
            "s.wgsl",
        ),
        // 2 KiB: some files fit, others do not; none may remain.
        (
            "ulimit -f 2; exec \"$B\" shader --all --lang glsl --out all",
            "all",
        ),
        (
            "ulimit -f 8; exec \"$B\" plot lobes --out plots/lobes",
            "plots",
        ),
        (
            "ulimit -f 8; exec \"$B\" plot coef --n 1..50 --out coef",
            "coef",
        ),
        ("ulimit -f 16; exec \"$B\" reproduce --out report", "report"),
    ] {
        let o = bash(script, &d);
        assert_eq!(o.status.code(), Some(3), "{script}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("cannot write") && stderr(&o).contains("too large"),
            "{script}: {}",
            stderr(&o)
        );
        assert!(o.stdout.is_empty(), "{script}");
        assert!(
            tree(&d).is_empty(),
            "{script} left {:?} ({target})",
            tree(&d)
        );
    }
    // Without the limit the same --all writes every file: one per registered model.
    let o = bash("exec \"$B\" shader --all --lang glsl --out all", &d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_dir(d.join("all")).unwrap().count(),
        fastbrdf::registry::all().len()
    );
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 11: a plot write failure was exit code 1; `pareto --json` wrote
/// fastbrdf-out/pareto.png and .svg into the current folder unasked.
#[test]
fn pareto_writes_a_plot_only_when_asked() {
    let d = temp_dir("pareto-cwd");
    let bench = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    for flag in ["--json", "--markdown"] {
        let o = bash(&format!("exec \"$B\" pareto --bench {bench} {flag}"), &d);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!o.stdout.is_empty());
        assert!(tree(&d).is_empty(), "{flag} wrote {:?}", tree(&d));
    }
    let o = bash(
        &format!("exec \"$B\" pareto --bench {bench} --json --out p/pareto"),
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(tree(&d), vec!["p", "p/pareto.png", "p/pareto.svg"]);
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 11: a failed stdout write was exit code 1 (eval) or a panic (println!, exit 101).
/// Exit codes are documented in --help.
#[cfg(unix)]
#[test]
fn stdout_failures_are_exit_3_and_exit_codes_are_documented() {
    let d = temp_dir("stdout-full");
    for script in [
        "printf 'cos\\n0.5\\n' | \"$B\" eval --model pow --param n=2 > /dev/full",
        "exec \"$B\" models --json > /dev/full",
        "exec \"$B\" errors --model flog --reference pow --n 10,20 --csv > /dev/full",
        "exec \"$B\" shader --model pow > /dev/full",
        // check prints with println! (another slice's file): main's panic hook maps it.
        "exec \"$B\" check --model flog > /dev/full",
    ] {
        let o = bash(script, &d);
        assert_eq!(o.status.code(), Some(3), "{script}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("cannot write to stdout") && !stderr(&o).contains("panicked"),
            "{script}: {}",
            stderr(&o)
        );
    }
    // A reader that went away (EPIPE) is not a panic either.
    let o = bash(
        "(sleep 0.3; exec \"$B\" models --json) | true; echo \"rc=${PIPESTATUS[0]}\"",
        &d,
    );
    assert_eq!(stdout(&o).trim(), "rc=3", "{}", stderr(&o));
    let help = stdout(&fastbrdf(&["--help"], ""));
    for needle in [
        "Exit codes:",
        "0  success",
        "1  a check failed",
        "2  bad usage",
        "3  an output",
    ] {
        assert!(help.contains(needle), "--help lacks {needle:?}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// Issue 11: `plot` subcommand options had no help text.
#[test]
fn every_plot_option_has_help_and_every_subcommand_an_example() {
    for sub in ["lobes", "error", "max-error", "coef", "polar", "albedo"] {
        let o = fastbrdf(&["plot", sub, "--help"], "");
        assert!(o.status.success());
        let h = stdout(&o);
        assert!(h.contains("Example"), "plot {sub} has no example");
        let opts = &h[h.find("Options:").expect("an options section")..];
        let lines: Vec<&str> = opts.lines().skip(1).collect();
        for (i, line) in lines.iter().enumerate() {
            let t = line.trim_start();
            if !t.starts_with('-') || t.starts_with("-h, --help") {
                continue;
            }
            // The description: after the option on the same line, or on the next lines.
            let same = t.split_once("  ").map_or("", |(_, d)| d.trim());
            let next = lines
                .get(i + 1)
                .filter(|l| !l.trim_start().starts_with('-'))
                .map_or("", |l| l.trim());
            let text = format!("{same} {next}");
            let stripped: String = text.split('[').next().unwrap_or("").trim().to_string();
            assert!(!stripped.is_empty(), "plot {sub}: {t:?} has no help text");
        }
    }
}
