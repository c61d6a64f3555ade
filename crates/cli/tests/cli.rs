//! The `fastbrdf` binary end to end: models, eval for every id, and clear errors with exit
//! code 2 and nothing on stdout for bad input. Other commands' end-to-end tests are in the
//! `cli_*.rs` files beside this one (analysis, fit and pareto, bench, render, exit codes).

mod common;

use common::{fastbrdf, stderr, stdout};
use std::io::Write;
use std::process::{Command, Stdio};

#[test]
fn models_lists_every_id_in_table_and_json() {
    let o = fastbrdf(&["models"], "");
    assert!(o.status.success());
    let table = stdout(&o);
    let o = fastbrdf(&["models", "--json"], "");
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let ids: Vec<&str> = json["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    for id in [
        "pow",
        "schlick",
        "schlick-modified",
        "gauss",
        "flog",
        "flog-normalized",
        "cubic",
        "cubic3",
        "rational",
        "cubic-rational",
        "power4",
        "power8",
        "power16",
        "sg",
        "ue4-phong-approx",
        "beckmann",
        "beckmann-ct",
        "beckmann-pow",
        "beckmann-power4",
        "beckmann-power8",
        "beckmann-power16",
        "v-cavity",
        "smith",
        "smith-rational",
        "cook-torrance",
        "ward",
        "ward-pow",
        "ward-power16",
        "lambert",
        "phong",
        "blinn-phong",
    ] {
        assert!(ids.contains(&id), "{id} missing from --json");
        assert!(
            table
                .lines()
                .any(|l| l.split_whitespace().next() == Some(id)),
            "{id} missing from the table"
        );
    }
    let m = &json["models"][0];
    for key in [
        "id",
        "kind",
        "params",
        "formula",
        "source",
        "ops",
        "bounds",
        "f32_bound",
    ] {
        assert!(!m[key].is_null(), "JSON lacks {key}");
    }
    assert!(m["ops"]["transcendental"].is_number());
}

fn sample_input(columns: &[&str]) -> String {
    let rows: [[f64; 6]; 3] = [
        [1.0, 0.0, 1.0, 0.0, 0.0, 1.0],
        [0.3, 0.1, 0.9, -0.3, -0.1, 0.9],
        [0.9, 0.5, 0.7, -0.2, 0.4, 0.8],
    ];
    let mut s = columns.join(",") + "\n";
    for r in rows {
        // Cosine kinds: values in (0, 1] taken from the z components and their neighbours.
        let cosines = [r[2], r[5], (r[2] + r[5]) / 2.0, r[2].max(r[5])];
        let vals: Vec<String> = (0..columns.len())
            .map(|i| {
                if columns.len() == 6 {
                    r[i].to_string()
                } else {
                    cosines[i].to_string()
                }
            })
            .collect();
        s += &(vals.join(",") + "\n");
    }
    s
}

#[test]
fn eval_answers_for_every_id() {
    let json: serde_json::Value =
        serde_json::from_slice(&fastbrdf(&["models", "--json"], "").stdout).unwrap();
    for m in json["models"].as_array().unwrap() {
        let id = m["id"].as_str().unwrap();
        let columns: &[&str] = match m["kind"].as_str().unwrap() {
            "lobe" => &["cos"],
            "distribution" => &["cos_h"],
            // The half-vector terms (v-cavity, kelemen) also read cos_h and cos_vh.
            "shadowing"
                if fastbrdf::ModelSpec::parse(id, &[])
                    .and_then(|s| s.model::<f64>())
                    .unwrap()
                    .columns()
                    .0
                    .contains(&"cos_vh") =>
            {
                &["cos_v", "cos_l", "cos_h", "cos_vh"]
            }
            "shadowing" => &["cos_v", "cos_l"],
            "fresnel" => &["cos_vh"],
            // alpha from the same sample cosines: all inside [0.005, 1].
            "env" => &["cos_v", "alpha"],
            _ => &["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"],
        };
        for precision in ["f32", "f64"] {
            let o = fastbrdf(
                &["eval", "--model", id, "--precision", precision],
                &sample_input(columns),
            );
            assert!(o.status.success(), "{id} {precision}: {}", stderr(&o));
            let out = stdout(&o);
            let lines: Vec<&str> = out.lines().collect();
            assert_eq!(lines.len(), 4, "{id}: {out}");
            assert!(lines[0].ends_with(",value"));
            for l in &lines[1..] {
                let v: f64 = l.rsplit(',').next().unwrap().parse().unwrap();
                assert!(v.is_finite() && v >= 0.0, "{id}: {l}");
            }
        }
    }
}

#[test]
fn eval_values_are_right_and_columns_pass_through() {
    let o = fastbrdf(
        &[
            "eval",
            "--model",
            "pow",
            "--param",
            "n=2",
            "--precision",
            "f64",
        ],
        "id,cos\na,0.5\nb,1\n",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), "id,cos,value\na,0.5,0.25\nb,1,1\n");
    let o = fastbrdf(
        &[
            "eval",
            "--model",
            "lambert",
            "--param",
            "albedo=0.5",
            "--precision",
            "f64",
        ],
        "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n",
    );
    assert_eq!(
        stdout(&o).lines().nth(1).unwrap(),
        format!("0,0,1,0,0,1,{}", 0.5 / std::f64::consts::PI)
    );
}

#[test]
fn bad_input_is_a_clear_error_with_exit_code_2_and_no_stdout() {
    let cases: &[(&[&str], &str, &str)] = &[
        (
            &["eval", "--model", "pow"],
            "cos\n0.5\nabc\n",
            "line 3, field 1 ('cos'): 'abc' is not a number",
        ),
        (
            &["eval", "--model", "pow"],
            "cos\n0.5\n1.5\n",
            "line 3, field 1 ('cos'): input cos: 1.5 is outside the domain [0, 1]",
        ),
        (
            &["eval", "--model", "pow"],
            "cos\nNaN\n",
            "line 2, field 1 ('cos'): input cos: NaN is not a finite number",
        ),
        (
            &["eval", "--model", "pow"],
            "c\n0.5\n",
            "line 1: missing column 'cos'",
        ),
        (
            &["eval", "--model", "pow"],
            "cos\n0.5,3\n",
            "line 2: expected 1 fields, found 2",
        ),
        (
            &["eval", "--model", "ward"],
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n0,0,0,0,0,1\n",
            "line 3, field 1 ('wi_x'): input wi: zero-length vector",
        ),
        (
            &["eval", "--model", "ward"],
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0.2,-1,0,0,1\n",
            "line 2, field 1 ('wi_x'): input wi: below the horizon",
        ),
        (
            &["eval", "--model", "phong-fast"],
            "cos\n0.5\n",
            "unknown model id 'phong-fast'",
        ),
        (
            &["eval", "--model", "pow", "--param", "n=0"],
            "cos\n0.5\n",
            "parameter n = 0 is invalid: expected a number in [1, 100000]",
        ),
        (
            &["eval", "--model", "pow", "--param", "n=nan"],
            "cos\n0.5\n",
            "parameter n = nan is invalid",
        ),
        (
            &["eval", "--model", "beckmann", "--param", "alpha=-1"],
            "cos_h\n0.5\n",
            "alpha = -1 is invalid",
        ),
        (
            &["eval", "--model", "pow", "--param", "n"],
            "cos\n0.5\n",
            "expected NAME=VALUE",
        ),
        (
            &["eval", "--model", "pow", "--param", "m=3"],
            "cos\n0.5\n",
            "model 'pow' has no parameter 'm'",
        ),
        (
            &["eval", "--model", "pow", "--input", "/nonexistent/x.csv"],
            "",
            "/nonexistent/x.csv: cannot open",
        ),
    ];
    for (args, input, expected) in cases {
        let o = fastbrdf(args, input);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            o.stdout.is_empty(),
            "{args:?} wrote to stdout: {}",
            stdout(&o)
        );
        assert!(
            stderr(&o).contains(expected),
            "{args:?}: stderr {:?} lacks {expected:?}",
            stderr(&o)
        );
    }
}

#[test]
fn check_verifies_one_model() {
    let o = fastbrdf(&["check", "--model", "flog", "--json"], "");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["ok"], true);
    // The seed's two rows (n = 1..1000) and the same two over the whole domain (n to 1e5).
    assert_eq!(v["bounds"].as_array().unwrap().len(), 4);
    for abs in [&v["bounds"][0], &v["bounds"][1]] {
        assert!(
            (abs["measured"].as_f64().unwrap() - 0.125).abs() < 1e-9,
            "{abs}"
        );
    }
    // Its batch kernel on every instruction set of this CPU, against f64.
    let k = &v["kernels"][0];
    assert_eq!(v["kernels"].as_array().unwrap().len(), 1);
    assert_eq!(
        (&k["model"], &k["ok"], &k["finite"]),
        (&"flog".into(), &true.into(), &true.into())
    );
    assert!(
        k["measured"].as_f64().unwrap() <= k["documented"].as_f64().unwrap(),
        "{k}"
    );
    assert_eq!(k["isas"].as_array().unwrap().last().unwrap(), "sse2");
}

// The model reference (docs/book/src/models.md) is `fastbrdf models`' output: tests/docs.rs,
// generated_models_reference_is_the_registry.

/// Issue 11: eval named the wrong line after blank lines or quoted multi-line fields, no line
/// for non-UTF-8 input, echoed a 10 MB field whole and read /dev/zero without limit.
#[test]
fn eval_errors_point_at_the_record_and_stay_short() {
    let cases: &[(&[u8], &str)] = &[
        (
            b"cos\n\n\n0.5\nabc\n",
            "<stdin>: line 5, field 1 ('cos'): 'abc' is not a number",
        ),
        (
            b"cos,note\n0.5,\"two\nlines\"\n0.7,\"a\n\nb\"\nx,y\n",
            "<stdin>: line 7, field 1 ('cos'): 'x' is not a number",
        ),
        (
            b"cos\n0.5\n\n1.5\n",
            "<stdin>: line 4, field 1 ('cos'): input cos: 1.5",
        ),
        (
            b"cos\n0.5\n0.\xff5\n",
            "<stdin>: line 3, column 3: not UTF-8 text",
        ),
        (
            b"note,cos\n\"a\nb\",0.5\n\"c\nd\",0.5,9\n",
            "<stdin>: line 4: expected 2 fields, found 3",
        ),
    ];
    for (input, expected) in cases {
        let mut child = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
            .args(["eval", "--model", "pow", "--param", "n=2"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let _ = child.stdin.take().unwrap().write_all(input);
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{expected}: {}", stderr(&o));
        assert!(o.stdout.is_empty());
        assert!(
            stderr(&o).contains(expected),
            "{:?} lacks {expected:?}",
            stderr(&o)
        );
    }
    let big = format!("cos\n0.5\n{}\n", "9".repeat(10_000_000) + "x");
    let o = fastbrdf(&["eval", "--model", "pow"], &big);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.len() < 500 && e.contains("line 3") && e.contains("more bytes"),
        "{}",
        &e[..e.len().min(500)]
    );
    let o = fastbrdf(
        &[
            "eval",
            "--model",
            "pow",
            "--input",
            "/dev/zero",
            "--max-input-mib",
            "1",
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("/dev/zero: larger than the 1 MiB"),
        "{}",
        stderr(&o)
    );
    assert!(o.stdout.is_empty());
}

/// issue 14: `eval` of anisotropic `cook-torrance` (`alpha_x`, `alpha_y`) differs along x
/// and y; one slope alone, or a D, G or `ms` without an anisotropic form, is exit 2 naming
/// the requirement, with nothing on stdout.
#[test]
fn anisotropic_cook_torrance_evaluates_and_refuses_what_it_cannot_stretch() {
    let input = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0.3,0,0.954,-0.2,0,0.98\n0,0.3,0.954,0,-0.2,0.98\n";
    let o = fastbrdf(
        &[
            "eval",
            "--model",
            "cook-torrance",
            "--param",
            "d=ggx",
            "--param",
            "g=smith-ggx-correlated",
            "--param",
            "alpha_x=0.05",
            "--param",
            "alpha_y=0.4",
        ],
        input,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let vals: Vec<f64> = stdout(&o)
        .lines()
        .filter_map(|l| l.rsplit(',').next()?.trim().parse().ok())
        .collect();
    assert_eq!(vals.len(), 2, "{}", stdout(&o));
    assert!(vals[0] < 0.5 * vals[1], "{vals:?}");
    for (extra, want) in [
        (&["alpha_x=0.1"][..], "alpha_y"),
        (
            &["alpha_x=0.1", "alpha_y=0.2", "d=beckmann-pow"][..],
            "d in {beckmann, beckmann-ct, ggx}",
        ),
        (
            &["alpha_x=0.1", "alpha_y=0.2", "g=kelemen"][..],
            "given d = beckmann, g = kelemen",
        ),
        (
            &[
                "alpha_x=0.1",
                "alpha_y=0.2",
                "d=ggx",
                "g=smith-ggx-correlated",
                "ms=kulla-conty",
            ][..],
            "ms in {none}",
        ),
    ] {
        let mut args = vec!["eval", "--model", "cook-torrance"];
        for p in extra {
            args.extend(["--param", p]);
        }
        let o = fastbrdf(&args, input);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(stdout(&o).is_empty(), "{extra:?}");
        assert!(stderr(&o).contains(want), "{extra:?}: {}", stderr(&o));
    }
}

/// A user's clone has nothing beside it: no test, script or source reads the project's
/// `../shared` folder (issue 27: six tests failed and one hung on a clone without it). The data
/// the tests need lives in the repository (crates/render/data, crates/analysis/data).
#[test]
fn nothing_reads_beside_the_repository() {
    fn walk(dir: &std::path::Path, hits: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy();
            if p.is_dir() {
                if !name.starts_with('.') && name != "target" && name != "node_modules" {
                    walk(&p, hits);
                }
            } else if ["rs", "py", "sh", "toml", "html", "js"]
                .iter()
                .any(|x| p.extension().is_some_and(|e| e == *x))
            {
                let text = std::fs::read_to_string(&p).unwrap_or_default();
                for (i, line) in text.lines().enumerate() {
                    // Built from pieces so that this test's own source does not match.
                    if line.contains(&["shared", "/data/"].concat()) {
                        hits.push(format!("{}:{}: {}", p.display(), i + 1, line.trim()));
                    }
                }
            }
        }
    }
    let root = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut hits = Vec::new();
    for d in ["crates", "python", "tools", ".ci"] {
        if root.join(d).is_dir() {
            walk(&root.join(d), &mut hits);
        }
    }
    assert!(
        hits.is_empty(),
        "paths outside the repository:\n{}",
        hits.join("\n")
    );
}

/// `--version` names the package's version and the commit the binary was built from (what
/// tools/equal_error.py records beside its figures): in a git checkout, HEAD's.
#[test]
fn version_names_the_commit() {
    let r = fastbrdf(&["--version"], "");
    assert!(r.status.success());
    let out = stdout(&r);
    let prefix = format!("fastbrdf {} (commit ", env!("CARGO_PKG_VERSION"));
    let commit = out
        .trim()
        .strip_prefix(&prefix)
        .and_then(|c| c.strip_suffix(')'))
        .unwrap_or_else(|| panic!("{out}"));
    let head = Command::new("git")
        .args(["rev-parse", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string());
    match head {
        Some(head) => assert!(
            commit.len() == 12 && head.starts_with(commit),
            "{commit} is not HEAD ({head})"
        ),
        None => assert_eq!(commit, "unknown"),
    }
}
