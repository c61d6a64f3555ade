//! `fastbrdf bench --gpu --model file:PATH` (issue 31): a user's shader timed on the GPU beside
//! the built-in models, with its instruction count (`fastbrdf_gpu::cost` of its WGSL), in the
//! text table and in `--json`. The timed runs need a GPU (lavapipe in CI: they skip without an
//! adapter, and fail when `CI` is set); a bad file fails before any GPU is opened.

mod common;
use common::gpu_data as data;
use common::have_gpu;

use common::{stderr, stdout, temp_dir};
use std::process::{Command, Output, Stdio};

/// `fastbrdf` with `args` and the extra environment `env`.
fn fastbrdf(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fastbrdf"));
    c.args(args).stdin(Stdio::null());
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("the binary runs")
}

/// The smallest run bench allows: --quick, a batch of 1024, one built-in model beside the
/// user's (pow: its C peer is the quickest).
fn bench(user: &str, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let mut args = vec![
        "bench", "--gpu", "--quick", "--large", "1024", "--models", "pow", "--model", user,
    ];
    args.extend_from_slice(extra);
    fastbrdf(&args, env)
}

/// What the instruction column shows for counts `c`.
fn column(c: &fastbrdf_gpu::cost::Counts) -> String {
    format!(
        "{} ({}/{}/{})",
        c.total, c.transcendental, c.division_sqrt, c.branches
    )
}

/// The counts of the shader at `path` as `cost::of_wgsl` takes them from its WGSL; `None`
/// without spirv-opt (outside CI).
fn expected(path: &str) -> Option<fastbrdf_gpu::cost::Counts> {
    let shader = fastbrdf_gpu::user::UserShader::load(std::path::Path::new(path)).unwrap();
    let wgsl = shader.wgsl().unwrap();
    match fastbrdf_gpu::cost::of_wgsl(&wgsl, "fb_user_brdf") {
        Ok(c) => {
            assert_eq!(shader.instructions(), Ok(c));
            Some(c)
        }
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI is set: {e}"),
        Err(e) => {
            eprintln!("no instruction count here: {e}");
            None
        }
    }
}

/// A throughput as the text table prints it (`26.2 M`), in evaluations per second.
fn rate(value: &str, unit: &str) -> f64 {
    let x: f64 = value.parse().unwrap_or_else(|_| panic!("{value} {unit}"));
    x * match unit {
        "G" => 1e9,
        "M" => 1e6,
        "k" => 1e3,
        _ => panic!("unit {unit}"),
    }
}

#[test]
fn a_users_brdf_is_timed_beside_the_built_ins_with_its_instruction_count() {
    if !have_gpu() {
        return;
    }
    let path = data("brdf-explorer/walter.brdf");
    let user = format!("file:{path}");
    let want = expected(&path);
    let o = bench(&user, &["--param", "alphaG=0.3"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let name = format!("{user}[alphaG=0.3]");
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with(&format!("{name} ")))
        .unwrap_or_else(|| panic!("no row for {name}:\n{out}"));
    // model, five CPU columns (none for a shader), gpu, gpu+xfer, instr, isa.
    let f: Vec<&str> = line[line.find(&name).unwrap() + name.len()..]
        .split_whitespace()
        .collect();
    assert_eq!(&f[..5], ["-"; 5], "{line}");
    assert!(rate(f[5], f[6]) > 0.0 && rate(f[7], f[8]) > 0.0, "{line}");
    let instr = format!("{} {}", f[9], f[10]);
    match &want {
        Some(c) => assert_eq!(instr, column(c), "{line}"),
        None => assert!(f[9] == "-", "{line}"),
    }
    assert_eq!(f.last(), Some(&"gpu"), "{line}");
    // The built-in model is in the same table, with its committed count.
    let pow = fastbrdf_gpu::cost::lookup(&fastbrdf::ModelSpec::parse("pow", &[]).unwrap())
        .expect("pow's committed count");
    assert!(
        out.lines()
            .any(|l| l.trim_start().starts_with("pow ") && l.contains(&column(&pow))),
        "{out}"
    );

    // --json: the user's rows with the counts object; the built-in rows with theirs.
    let o = bench(&user, &["--json"], &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    let rows = v["kernels"].as_array().expect("kernels");
    let mine: Vec<&serde_json::Value> = rows.iter().filter(|r| r["model"] == user).collect();
    let variants: Vec<&str> = mine
        .iter()
        .map(|r| r["variant"].as_str().unwrap())
        .collect();
    assert_eq!(variants, ["gpu", "gpu+transfer"], "{mine:?}");
    for r in &mine {
        assert!(r["evals_per_s"].as_f64().unwrap() > 0.0, "{r}");
        assert_eq!(
            (r["batch"].as_u64(), r["isa"].as_str()),
            (Some(1024), Some("gpu"))
        );
        let want = want.map(|c| serde_json::to_value(c).unwrap());
        assert_eq!(
            r["instructions"],
            want.unwrap_or(serde_json::Value::Null),
            "{r}"
        );
    }
    let pow_rows: Vec<_> = rows.iter().filter(|r| r["model"] == "pow").collect();
    assert!(pow_rows.len() >= 3, "{pow_rows:?}");
    for r in pow_rows {
        assert_eq!(r["instructions"], serde_json::to_value(pow).unwrap(), "{r}");
    }
    // The C loops have no shader: null.
    let c_loop = rows
        .iter()
        .find(|r| r["model"] == "powf-loop")
        .expect("powf-loop");
    assert!(c_loop["instructions"].is_null(), "{c_loop}");
}

#[test]
fn without_spirv_opt_the_count_is_a_dash_and_a_note() {
    if !have_gpu() {
        return;
    }
    let path = data("brdf-explorer/walter.brdf");
    let user = format!("file:{path}");
    let missing = [("FASTBRDF_SPIRV_OPT", "/nonexistent/spirv-opt")];
    let o = bench(&user, &[], &missing);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let notes: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("note: instruction count of"))
        .collect();
    assert_eq!(notes.len(), 1, "{err}");
    assert!(
        notes[0].contains(&user) && notes[0].contains("spirv-opt"),
        "{err}"
    );
    let out = stdout(&o);
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with(&format!("{user} ")))
        .unwrap_or_else(|| panic!("no row for {user}:\n{out}"));
    let f: Vec<&str> = line.split_whitespace().collect();
    // ... gpu (2 tokens), gpu+xfer (2 tokens), instr, isa.
    assert_eq!(&f[f.len() - 2..], ["-", "gpu"], "{line}");
    let o = bench(&user, &["--json"], &missing);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    let mine = v["kernels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["model"] == user)
        .expect("the user's row");
    assert!(mine["instructions"].is_null(), "{mine}");
}

/// A compile error is exit 2 naming the file, line and column, before any timing or output;
/// so are a value outside the declared range and a value no file declares.
#[test]
fn a_bad_file_or_value_is_exit_2_with_nothing_on_stdout() {
    let d = temp_dir("bench-user");
    let bad = d.join("bad.brdf");
    let text = std::fs::read_to_string(data("brdf-explorer/walter.brdf"))
        .unwrap()
        .replace(
            "float sqr(float x) { return x*x; }",
            "float sqr(float x) { return x*y; }",
        );
    std::fs::write(&bad, text).unwrap();
    let user = format!("file:{}", bad.display());
    let o = bench(&user, &[], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(o.stdout.is_empty(), "{}", stdout(&o));
    let err = stderr(&o);
    let at = format!("{}:", bad.display());
    let rest = &err[err.find(&at).unwrap_or_else(|| panic!("{err}")) + at.len()..];
    let mut lc = rest.split(':');
    let (line, col) = (lc.next().unwrap(), lc.next().unwrap());
    assert!(
        line.parse::<usize>().is_ok() && col.parse::<usize>().is_ok(),
        "no line and column: {err}"
    );
    // The line named is the one with the error.
    let wrong = std::fs::read_to_string(&bad).unwrap();
    let named = wrong
        .lines()
        .nth(line.parse::<usize>().unwrap() - 1)
        .unwrap();
    assert!(named.contains("x*y"), "line {line} is '{named}': {err}");

    let good = format!("file:{}", data("brdf-explorer/walter.brdf"));
    for (param, what) in [("alphaG=7", "alphaG"), ("roughness=0.3", "roughness")] {
        let o = bench(&good, &["--param", param], &[]);
        assert_eq!(o.status.code(), Some(2), "{param}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{param}: {}", stdout(&o));
        assert!(stderr(&o).contains(what), "{param}: {}", stderr(&o));
    }
    // Without --gpu there is nothing to time it on.
    let o = fastbrdf(&["bench", "--quick", "--model", &good], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        o.stdout.is_empty() && stderr(&o).contains("--gpu"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&d);
}
