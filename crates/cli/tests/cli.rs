//! The `fastbrdf` binary end to end: models, eval for every id, and clear errors with exit
//! code 2 and nothing on stdout for bad input.

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn fastbrdf(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // The binary may exit before reading stdin (argument errors): a broken pipe is fine.
    let _ = child.stdin.take().unwrap().write_all(stdin.as_bytes());
    child.wait_with_output().unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

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
            "shadowing" if id == "v-cavity" => &["cos_v", "cos_l", "cos_h", "cos_vh"],
            "shadowing" => &["cos_v", "cos_l"],
            "fresnel" => &["cos_vh"],
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
            "line 3, column 'cos': 'abc' is not a number",
        ),
        (
            &["eval", "--model", "pow"],
            "cos\n0.5\n1.5\n",
            "line 3: input cos: 1.5 is outside the domain [0, 1]",
        ),
        (
            &["eval", "--model", "pow"],
            "cos\nNaN\n",
            "line 2: input cos: NaN is not a finite number",
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
            "line 3: input wi: zero-length vector",
        ),
        (
            &["eval", "--model", "ward"],
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0.2,-1,0,0,1\n",
            "line 2: input wi: below the horizon",
        ),
        (
            &["eval", "--model", "phong-fast"],
            "cos\n0.5\n",
            "unknown model id 'phong-fast'",
        ),
        (
            &["eval", "--model", "pow", "--param", "n=0"],
            "cos\n0.5\n",
            "parameter n = 0 is invalid: expected a number in [1, 10000]",
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
            "cannot read /nonexistent/x.csv",
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
    assert_eq!(v["bounds"].as_array().unwrap().len(), 2);
    let abs = &v["bounds"][0];
    assert!(
        (abs["measured"].as_f64().unwrap() - 0.125).abs() < 1e-9,
        "{abs}"
    );
}

#[test]
fn readme_model_table_is_the_output_of_fastbrdf_models() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let open = "<!-- models:begin -->\n```text\n";
    let start = readme.find(open).expect("README has the models block") + open.len();
    let end = readme
        .find("```\n<!-- models:end -->")
        .expect("README closes the models block");
    let o = fastbrdf(&["models"], "");
    assert!(
        readme[start..end] == stdout(&o),
        "README's table is stale: paste the output of `fastbrdf models` between the markers"
    );
}
