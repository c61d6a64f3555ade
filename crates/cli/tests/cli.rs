//! The `fastbrdf` binary end to end: models, eval for every id, and clear errors with exit
//! code 2 and nothing on stdout for bad input.

mod common;

use common::{fastbrdf, stderr, stdout, temp_dir};
use std::io::Write;
use std::process::{Command, Output, Stdio};

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
                if fastbrdf::registry::build::<f64>(id, &[])
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

#[test]
fn analysis_commands_reject_bad_input_with_exit_code_2() {
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "errors",
                "--model",
                "flog",
                "--reference",
                "pow",
                "--n",
                "10..1",
            ],
            "is empty",
        ),
        (
            &[
                "errors",
                "--model",
                "flog",
                "--reference",
                "pow",
                "--n",
                "1..x",
            ],
            "not a number",
        ),
        (
            &[
                "errors",
                "--model",
                "flog",
                "--reference",
                "pow",
                "--n",
                "0..10",
            ],
            "parameter n = 0 is invalid",
        ),
        (
            &[
                "errors",
                "--model",
                "flogg",
                "--reference",
                "pow",
                "--n",
                "1..10",
            ],
            "unknown model id 'flogg'",
        ),
        (
            &[
                "errors",
                "--model",
                "flog",
                "--reference",
                "beckmann",
                "--n",
                "1..10",
            ],
            "is a distribution, but a lobe is needed",
        ),
        (
            &["errors", "--model", "flog", "--reference", "pow"],
            "give --n RANGE",
        ),
        (
            &[
                "errors",
                "--model",
                "beckmann-pow",
                "--reference",
                "beckmann-ct",
                "--n",
                "1..3",
            ],
            "has no parameter 'n'",
        ),
        (
            &[
                "errors",
                "--model",
                "flog",
                "--reference",
                "pow",
                "--n",
                "1..3",
                "--zone",
                "band:0.5,0.4",
            ],
            "need 0 <= LO < HI <= 1",
        ),
        (
            &["normalize", "--model", "beckmann", "--n", "1..3"],
            "normalize needs a lobe",
        ),
        (
            &["normalize", "--model", "flog", "--n", "1..3:-1"],
            "must be positive",
        ),
        (&["albedo", "--model", "smith"], "is a shadowing"),
        (
            &["albedo", "--model", "ward", "--angles", "0,95"],
            "outside [0, 90)",
        ),
        (&["plot", "polar", "--model", "pow"], "polar needs a BRDF"),
        (&["plot", "lobes", "--models", "pow,beckmann"], "not a lobe"),
    ];
    for (args, expected) in cases {
        let o = fastbrdf(args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}: {}", stdout(&o));
        assert!(
            stderr(&o).contains(expected),
            "{args:?}: stderr {:?} lacks {expected:?}",
            stderr(&o)
        );
    }
}

#[test]
fn errors_json_and_csv() {
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "flog",
            "--reference",
            "pow",
            "--n",
            "10,20",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!((v["worst"]["max_abs"].as_f64().unwrap() - 0.125).abs() < 1e-9);
    assert_eq!(v["rows"].as_array().unwrap().len(), 2);
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "rational",
            "--reference",
            "pow",
            "--n",
            "2..4",
            "--zone",
            "band:0.42,0.5",
            "--csv",
        ],
        "",
    );
    let out = stdout(&o);
    assert!(
        out.starts_with("n,max_abs,max_abs_at,max_rel,max_rel_at,rms,samples\n")
            && out.lines().count() == 4,
        "{out}"
    );
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "ward-power16",
            "--reference",
            "ward",
            "--m",
            "0.2,0.6",
            "--zone",
            "epicentre",
        ],
        "",
    );
    assert!(
        o.status.success() && stdout(&o).contains("max rel error"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn normalize_and_albedo_report() {
    let o = fastbrdf(
        &["normalize", "--model", "pow", "--n", "1..3", "--json"],
        "",
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let c = v["rows"][0]["coef"].as_f64().unwrap();
    assert!((c - 3.0 / (2.0 * std::f64::consts::PI)).abs() < 1e-9, "{c}");
    let o = fastbrdf(
        &[
            "normalize",
            "--model",
            "flog",
            "--n",
            "1..50",
            "--fit",
            "seed",
        ],
        "",
    );
    assert!(stdout(&o).contains("energy residual"), "{}", stdout(&o));
    let o = fastbrdf(
        &[
            "albedo", "--model", "ward", "--param", "alpha=1", "--angles", "0,89.9",
        ],
        "",
    );
    assert!(
        stdout(&o).contains("white furnace: FAILS"),
        "{}",
        stdout(&o)
    );
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "flog-normalized",
            "--param",
            "n=50",
            "--norm",
            "none",
            "--json",
        ],
        "",
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["conserves"], true);
}

/// `albedo --ms-compare` (issue 14): the furnace before and after energy compensation; a
/// compensated model's own furnace passes within its table error; a gated `ms` with another D
/// is exit 2 naming the requirement; `--ms-compare` is only for cook-torrance.
#[test]
fn albedo_shows_the_furnace_before_and_after_energy_compensation() {
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "cook-torrance",
            "--param",
            "alpha=1",
            "--angles",
            "0,60",
            "--ms-compare",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let dev = |ms: &str| v["ms"][ms]["max_dev"].as_f64().unwrap();
    assert!(dev("none") > 0.6, "{v}");
    assert!(dev("kulla-conty") < 0.01 && dev("filament") < 0.01, "{v}");
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "cook-torrance",
            "--param",
            "alpha=0.5",
            "--angles",
            "0,80",
            "--ms-compare",
        ],
        "",
    );
    assert!(stdout(&o).contains("kulla-conty"), "{}", stdout(&o));
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "cook-torrance",
            "--param",
            "alpha=1",
            "--param",
            "d=ggx",
            "--param",
            "g=smith-ggx-correlated",
            "--param",
            "ms=filament",
            "--angles",
            "0,70",
        ],
        "",
    );
    assert!(
        stdout(&o).contains("white furnace: passes") && stdout(&o).contains("seen from wo"),
        "{}",
        stdout(&o)
    );
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "cook-torrance",
            "--param",
            "ms=kulla-conty",
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("g = smith-ggx-correlated"),
        "{}",
        stderr(&o)
    );
    let o = fastbrdf(&["albedo", "--model", "ward", "--ms-compare"], "");
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn plots_are_written_as_png_and_svg() {
    let dir = std::env::temp_dir().join(format!("fastbrdf-plot-test-{}", std::process::id()));
    let base = dir.join("lobes");
    let o = fastbrdf(
        &[
            "plot",
            "lobes",
            "--models",
            "pow,flog",
            "--n",
            "20",
            "--out",
            base.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(base.with_extension("png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = std::fs::read_to_string(base.with_extension("svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("flog"));
    // A failing plot leaves nothing behind.
    let bad = dir.join("bad");
    let o = fastbrdf(
        &[
            "plot",
            "polar",
            "--model",
            "lambert",
            "--theta-i",
            "95",
            "--out",
            bad.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(!bad.with_extension("png").exists() && !bad.with_extension("svg").exists());
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("tmp"))
        .collect();
    assert!(leftovers.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reproduce_has_every_claim_and_readme_shows_its_output() {
    let o = fastbrdf(&["reproduce", "--json"], "");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let claims = v["claims"].as_array().unwrap();
    let ids: Vec<&str> = claims.iter().map(|c| c["id"].as_str().unwrap()).collect();
    for id in [
        "log.epicentre_rel_err_max",
        "log.abs_err_max",
        "log.schlick_abs_err_max",
        "log.zero_constant",
        "log.coef_table",
        "log.coef_formula_max_rel_dev",
        "log.energy_residual_max",
        "cubic.epicentre_abs_err_max",
        "cubic.schlick_ratio_epicentre",
        "cubic.whole_abs_err_max",
        "cubic3.whole_abs_err_max",
        "cubic3.epicentre_abs_err_max",
        "rational.rel_err_band_0.42_0.5",
        "rational.rel_err_band_0.37_0.42",
        "rational.rel_err_band_0.27_0.37",
        "power16.epicentre_rel_err_max",
        "beckmann_exp_power16.m0.2.epicentre_rel_err",
        "beckmann_exp_power16.m0.3.epicentre_rel_err",
        "beckmann_exp_power16.m0.4.epicentre_rel_err",
        "beckmann_exp_power16.m0.5.epicentre_rel_err",
        "beckmann_exp_power16.m0.6.epicentre_rel_err",
        "ct.speedup",
        "ward.speedup",
    ] {
        assert!(ids.contains(&id), "{id} missing");
    }
    let by_id = |id: &str| claims.iter().find(|c| c["id"] == id).unwrap();
    let epi = by_id("log.epicentre_rel_err_max");
    assert_eq!(epi["unit"], "percent");
    assert_eq!(epi["claimed"], 0.3);
    let m = epi["measured"].as_f64().unwrap();
    assert!(m > 0.0 && m < 1.0, "{epi}");
    assert_eq!(epi["measured_text"], format!("{m:.3}%"));
    assert_eq!(
        by_id("log.coef_table")["measured_values"]
            .as_array()
            .unwrap()
            .len(),
        7
    );
    for c in claims {
        for key in [
            "id",
            "seed",
            "claimed",
            "claimed_text",
            "measured",
            "measured_text",
            "unit",
            "claimed_values",
            "measured_values",
            "domain",
            "verdict",
        ] {
            assert!(c.get(key).is_some(), "{c} lacks {key}");
        }
        // Machine output carries numbers (issue 11: they were strings like "0.291%").
        for key in ["claimed", "measured"] {
            assert!(c[key].is_number() || c[key].is_null(), "{c}: {key}");
        }
        assert!(
            ["percent", "dimensionless", "ratio"].contains(&c["unit"].as_str().unwrap()),
            "{c}"
        );
        for key in ["claimed_values", "measured_values"] {
            assert!(c[key].as_array().unwrap().iter().all(|x| x.is_number()));
        }
        let verdict = c["verdict"].as_str().unwrap();
        assert!(["agrees", "differs", "no claim", "not measured"].contains(&verdict));
    }
    let bench = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let md = stdout(&fastbrdf(
        &["reproduce", "--markdown", "--speedups", bench],
        "",
    ));
    assert!(
        md.contains("| `ct.speedup` | 000 | 4.34 | 1."),
        "speed rows are filled from the saved run"
    );
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let open = "<!-- reproduce:begin -->\n";
    let start = readme.find(open).expect("README has the reproduce block") + open.len();
    let end = readme
        .find("<!-- reproduce:end -->")
        .expect("README closes the reproduce block");
    assert!(
        readme[start..end] == md,
        "README's reproduction table is stale: paste `fastbrdf reproduce --markdown --speedups docs/bench/bench.json`"
    );
    let doc = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/reproduction/REPRODUCTION.md"
    ))
    .unwrap();
    assert!(
        doc.ends_with(&md),
        "docs/reproduction is stale: run `fastbrdf reproduce --out docs/reproduction`"
    );
}

#[test]
fn bench_json_has_the_documented_shape_and_round_trips() {
    let o = fastbrdf(
        &[
            "bench",
            "--quick",
            "--models",
            "pow,power16,schlick,ward,ward-power16,cook-torrance",
            "--large",
            "4096",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for key in ["cpu", "isa", "fma_per_s", "kernels", "speedups"] {
        assert!(!v[key].is_null(), "no {key}");
    }
    assert!(v["fma_per_s"].as_f64().unwrap() > 0.0);
    assert!(v["div_per_s"].as_f64().unwrap() > 0.0);
    let kernels = v["kernels"].as_array().unwrap();
    // Each one-thread SIMD row names the limit it is held against, as a number.
    let limit = |m: &str| {
        let k = kernels
            .iter()
            .find(|k| k["model"] == m && k["variant"] == "simd" && k["batch"] == 4096)
            .unwrap();
        (k["limit"].as_str(), k["limit_fraction"].as_f64())
    };
    assert_eq!(limit("power16").0, Some("fma"));
    assert_eq!(limit("schlick").0, Some("divider"));
    assert!(limit("schlick").1.unwrap() > 0.0);
    assert_eq!(limit("pow"), (None, None));
    for k in kernels {
        for key in ["model", "variant", "batch", "evals_per_s"] {
            assert!(!k[key].is_null(), "{k} lacks {key}");
        }
        assert!(["scalar", "simd", "simd-threads"].contains(&k["variant"].as_str().unwrap()));
        assert!(k["evals_per_s"].as_f64().unwrap() > 0.0);
    }
    assert!(
        kernels.iter().any(|k| k["model"] == "power16"
            && k["variant"] == "simd-threads"
            && k["batch"] == 4096)
    );
    let names: Vec<&str> = v["speedups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"ward.speedup"), "{names:?}");
    let ward = v["speedups"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["name"] == "ward.speedup")
        .unwrap();
    assert_eq!(ward["claimed"], 2.0);
    // Render the saved run.
    let path = std::env::temp_dir().join(format!("fastbrdf-bench-{}.json", std::process::id()));
    std::fs::write(&path, &o.stdout).unwrap();
    let md = fastbrdf(
        &["bench", "--from", path.to_str().unwrap(), "--markdown"],
        "",
    );
    assert!(
        md.status.success() && stdout(&md).contains("| `power16` |"),
        "{}",
        stderr(&md)
    );
    std::fs::remove_file(&path).unwrap();
    // Bad input.
    let o = fastbrdf(&["bench", "--models", "nope"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("unknown model id 'nope'"));
    let o = fastbrdf(&["bench", "--from", "/nonexistent.json"], "");
    assert_eq!(o.status.code(), Some(2));
}

/// `bench --compare`: a run against itself gives ratio 1 everywhere and marks nothing; a row
/// made 3x slower is marked; a missing file is a clear error (exit 2, nothing on stdout).
/// No timing is asserted (both sides are saved runs).
#[test]
fn bench_compare_marks_slower_rows() {
    let saved = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let o = fastbrdf(
        &["bench", "--from", saved, "--compare", saved, "--json"],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = v["rows"].as_array().unwrap();
    assert!(rows.len() > 100, "{}", rows.len());
    assert!(
        rows.iter()
            .all(|r| r["ratio"] == 1.0 && r["slower"] == false)
    );
    assert_eq!(v["slower_below"], 0.8);
    // The old run three times faster on one row: that row, and only it, is slower.
    let mut old: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(saved).unwrap()).unwrap();
    let k = &mut old["kernels"][0];
    let (model, variant) = (k["model"].clone(), k["variant"].clone());
    k["evals_per_s"] = serde_json::json!(k["evals_per_s"].as_f64().unwrap() * 3.0);
    let d = temp_dir("bench-compare");
    let path = d.join("old.json");
    std::fs::write(&path, serde_json::to_string(&old).unwrap()).unwrap();
    let o = fastbrdf(
        &[
            "bench",
            "--from",
            saved,
            "--compare",
            path.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let slower: Vec<&str> = text.lines().filter(|l| l.ends_with("slower")).collect();
    assert_eq!(slower.len(), 1, "{text}");
    assert!(
        slower[0].starts_with(model.as_str().unwrap())
            && slower[0].contains(variant.as_str().unwrap()),
        "{text}"
    );
    assert!(text.contains("1 below 0.8"), "{text}");
    std::fs::remove_dir_all(&d).unwrap();
    let o = fastbrdf(
        &["bench", "--from", saved, "--compare", "/nonexistent.json"],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        o.stdout.is_empty() && stderr(&o).contains("/nonexistent.json"),
        "{}",
        stderr(&o)
    );
    // Without --from the saved run is read before any timing: the same refusal.
    let o = fastbrdf(&["bench", "--quick", "--compare", "/nonexistent.json"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        o.stdout.is_empty() && stderr(&o).contains("/nonexistent.json"),
        "{}",
        stderr(&o)
    );
}

/// Issue 13: every run races the batch kernels against their C peers; the "peers" rows have
/// the shape `bench --help` documents, render from a saved run, and runs saved before them
/// still load and print as they did. Shapes only: no timing is asserted.
#[test]
fn bench_peers_have_the_documented_shape_and_old_runs_still_load() {
    let o = fastbrdf(
        &[
            "bench",
            "--quick",
            "--models",
            "pow,power16,beckmann,ward",
            "--large",
            "4096",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let peers = v["peers"].as_array().expect("a peers array");
    let models: Vec<&str> = peers.iter().map(|p| p["model"].as_str().unwrap()).collect();
    assert_eq!(models, ["pow", "power16", "beckmann"], "ward has no C peer");
    for p in peers {
        for key in [
            "model",
            "params",
            "batch",
            "repeats",
            "rounds",
            "isa",
            "kernel_evals_per_s",
            "peer_evals_per_s",
            "ratio",
            "kernel_max_error",
            "peer_max_error",
            "peer",
            "compiler",
            "flags",
            "libmvec",
            "ftz",
            "daz",
        ] {
            assert!(p.get(key).is_some(), "{p} lacks {key}");
        }
        for spread in ["kernel_evals_per_s", "peer_evals_per_s", "ratio"] {
            for stat in ["median", "q1", "q3", "min", "max"] {
                let x = p[spread][stat].as_f64().unwrap_or(-1.0);
                assert!(x.is_finite() && x > 0.0, "{spread}.{stat} = {x}");
            }
        }
        assert_eq!(p["batch"], 4096);
        assert!(p["peer_max_error"].as_f64().unwrap() <= 1e-5, "{p}");
        assert!(p["kernel_max_error"].as_f64().unwrap() <= 1e-5, "{p}");
        assert!(p["flags"].as_str().unwrap().starts_with("-O3"));
        assert!(!p["compiler"].as_str().unwrap().is_empty());
        assert_eq!(p["ftz"].is_boolean(), cfg!(target_arch = "x86_64"), "{p}");
        assert_eq!(p["peer"], format!("peer_{}", p["model"].as_str().unwrap()));
    }
    assert_eq!(peers[2]["params"], "alpha=0.3");
    // power16 is held against the FMA pipes, and so is its C loop (same operation count);
    // pow's transcendental is uncounted: no fraction on either side; beckmann counts its
    // kernel (its exp2's polynomial, on FMA instruction sets), while its C loop, which calls
    // libm's expf, gets none.
    assert_eq!(peers[1]["kernel_limit"], "fma");
    let (k, c) = (
        peers[1]["kernel_limit_fraction"].as_f64().unwrap(),
        peers[1]["peer_limit_fraction"].as_f64().unwrap(),
    );
    let ratio = peers[1]["kernel_evals_per_s"]["median"].as_f64().unwrap()
        / peers[1]["peer_evals_per_s"]["median"].as_f64().unwrap();
    assert!(
        c > 0.0 && ((k / c) / ratio - 1.0).abs() < 1e-9,
        "{k} {c} {ratio}"
    );
    assert!(peers[0]["peer_limit_fraction"].is_null() && peers[2]["peer_limit_fraction"].is_null());
    assert!(peers[0]["kernel_limit_fraction"].is_null());
    let fma_isa = matches!(peers[2]["isa"].as_str(), Some("avx512" | "avx2+fma"));
    let b = peers[2]["kernel_limit_fraction"].as_f64();
    assert_eq!(b.is_some(), fma_isa, "{}", peers[2]);
    if fma_isa {
        assert!(b.unwrap() > 0.0 && b.unwrap() < 2.0, "{}", peers[2]);
        let unit = peers[2]["kernel_limit"].as_str().unwrap();
        assert!(unit == "fma" || unit == "divider", "{unit}");
    }
    // The saved run renders its peer table (Markdown and text).
    let d = temp_dir("bench-peers");
    let path = d.join("run.json");
    std::fs::write(&path, &o.stdout).unwrap();
    let f = path.to_str().unwrap();
    let md = fastbrdf(&["bench", "--from", f, "--markdown"], "");
    assert!(md.status.success(), "{}", stderr(&md));
    let md = stdout(&md);
    assert!(
        md.contains("| model | kernel | C peer | kernel / C |") && md.contains("| C % of limit |"),
        "{md}"
    );
    assert!(
        md.contains("| `power16` n=200 |") && md.contains("FTZ"),
        "{md}"
    );
    let text = stdout(&fastbrdf(&["bench", "--from", f], ""));
    assert!(
        text.contains("C peers") && text.contains("beckmann alpha=0.3"),
        "{text}"
    );
    // An impossible peer figure is refused like any other.
    let mut bad = v.clone();
    bad["peers"][0]["ratio"]["median"] = serde_json::json!(-1.0);
    std::fs::write(&path, serde_json::to_string(&bad).unwrap()).unwrap();
    let o = fastbrdf(&["bench", "--from", f], "");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("peers[0]"), "{}", stderr(&o));
    std::fs::remove_dir_all(&d).unwrap();
    // Runs saved before issue 13 have no "peers" (the saved GPU run is one): they load, print
    // without a peer table, and re-export with an empty array.
    let old = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/bench/bench-gpu.json"
    );
    assert!(!std::fs::read_to_string(old).unwrap().contains("\"peers\""));
    for flags in [&["--markdown"][..], &[][..]] {
        let o = fastbrdf(&[&["bench", "--from", old][..], flags].concat(), "");
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!stdout(&o).contains("C peer"), "{flags:?}");
    }
    let o = fastbrdf(&["bench", "--from", old, "--json"], "");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["peers"], serde_json::json!([]));
    assert!(!v["kernels"].as_array().unwrap().is_empty());
    // --help documents the shape.
    let help = stdout(&fastbrdf(&["bench", "--help"], ""));
    for word in [
        "\"peers\"",
        "peer_evals_per_s",
        "ratio",
        "ftz",
        "-march=native",
    ] {
        assert!(help.contains(word), "--help lacks {word}");
    }
}

#[test]
fn readme_benchmark_tables_are_the_saved_run() {
    let bench = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let md = stdout(&fastbrdf(&["bench", "--from", bench, "--markdown"], ""));
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let open = "<!-- bench:begin -->\n";
    let start = readme.find(open).expect("README has the bench block") + open.len();
    let end = readme
        .find("<!-- bench:end -->")
        .expect("README closes the bench block");
    assert!(
        readme[start..end] == md,
        "README's benchmark tables are stale: paste `fastbrdf bench --from docs/bench/bench.json --markdown`"
    );
}

#[test]
fn render_bad_input_is_exit_2_and_leaves_no_file() {
    let d = temp_dir("render-bad");
    let out = d.join("x.png");
    let o = out.to_str().unwrap();
    let obj = d.join("bad.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let nan = d.join("nan.obj");
    std::fs::write(&nan, "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let empty = d.join("empty.obj");
    std::fs::write(&empty, "v 0 0 0\n").unwrap();
    let notex = d.join("missing.png");
    let junk = d.join("junk.png");
    std::fs::write(&junk, "not an image").unwrap();
    let (bad, nan, empty, notex, junk) = (
        obj.to_str().unwrap(),
        nan.to_str().unwrap(),
        empty.to_str().unwrap(),
        notex.to_str().unwrap(),
        junk.to_str().unwrap(),
    );
    let jpg = d.join("x.jpg");
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["render", "--model", "pow", "--mesh", bad, "--out", o],
            format!("{bad}:4: face: vertex index 9 is out of range"),
        ),
        (
            vec!["render", "--model", "pow", "--mesh", nan, "--out", o],
            format!("{nan}:2: vertex: 'NaN' is not a finite number"),
        ),
        (
            vec!["render", "--model", "pow", "--mesh", empty, "--out", o],
            format!("{empty}: no faces"),
        ),
        (
            vec![
                "render",
                "--model",
                "pow",
                "--mesh",
                "/nonexistent.obj",
                "--out",
                o,
            ],
            "/nonexistent.obj: cannot read".into(),
        ),
        (
            vec!["render", "--model", "pow", "--texture", notex, "--out", o],
            format!("{notex}: cannot read the texture"),
        ),
        (
            vec!["render", "--model", "pow", "--texture", junk, "--out", o],
            format!("{junk}: cannot read the texture"),
        ),
        (
            vec!["render", "--model", "pow", "--size", "0x10", "--out", o],
            "both sides must be at least 1".into(),
        ),
        (
            vec![
                "render",
                "--model",
                "pow",
                "--size",
                "100000x100000",
                "--out",
                o,
            ],
            "is too large: at most 8192 per side".into(),
        ),
        (
            vec![
                "render",
                "--model",
                "pow",
                "--size",
                "8192x8192",
                "--out",
                o,
            ],
            "is too large".into(),
        ),
        (
            vec!["render", "--model", "nope", "--out", o],
            "unknown model id 'nope'".into(),
        ),
        (
            vec!["render", "--model", "smith", "--out", o],
            "'smith' is a shadowing, not something to shade with".into(),
        ),
        (
            vec!["render", "--model", "pow", "--param", "n=-3", "--out", o],
            "parameter n = -3 is invalid".into(),
        ),
        (
            vec!["render", "--model", "pow", "--light", "dir:0,0", "--out", o],
            "--light 'dir:0,0': three finite numbers needed".into(),
        ),
        (
            vec!["render", "--model", "pow", "--spp", "0", "--out", o],
            "--spp 0: must be 1 to 16".into(),
        ),
        (
            vec!["render", "--model", "pow", "--out", jpg.to_str().unwrap()],
            "must end in .png or .exr".into(),
        ),
        (
            vec![
                "compare",
                "--models",
                "flog",
                "--reference",
                "pow",
                "--param",
                "alpha=0.3",
                "--out",
                o,
            ],
            "--param alpha: none of the models takes it".into(),
        ),
    ];
    for (args, expected) in cases {
        let r = fastbrdf(&args, "");
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
        assert!(
            stderr(&r).contains(&expected),
            "{args:?}: {:?} lacks {expected:?}",
            stderr(&r)
        );
        assert!(r.stdout.is_empty());
        assert!(!out.exists(), "{args:?} left {o}");
    }
    assert!(
        std::fs::read_dir(&d).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .contains("tmp"))
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn render_writes_png_and_exr_and_compare_reports_metrics() {
    let d = temp_dir("render-ok");
    for ext in ["png", "exr"] {
        let out = d.join(format!("s.{ext}"));
        let r = fastbrdf(
            &[
                "render",
                "--model",
                "ward",
                "--param",
                "alpha=0.3",
                "--size",
                "48x32",
                "--spp",
                "1",
                "--out",
                out.to_str().unwrap(),
            ],
            "",
        );
        assert!(r.status.success(), "{}", stderr(&r));
        let img = image::open(&out).unwrap();
        assert_eq!((img.width(), img.height()), (48, 32));
    }
    let out = d.join("cmp.png");
    let r = fastbrdf(
        &[
            "compare",
            "--models",
            "pow,flog",
            "--reference",
            "pow",
            "--param",
            "n=40",
            "--size",
            "64x64",
            "--spp",
            "1",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let m = v["metrics"].as_array().unwrap();
    assert_eq!(m[0]["model"], "pow n=40");
    assert_eq!(m[0]["rmse"], 0.0);
    assert!(
        m[0]["psnr"].is_null(),
        "identical images: infinite PSNR is null in JSON"
    );
    assert!(m[1]["rmse"].as_f64().unwrap() > 0.0 && m[1]["flip"].as_f64().unwrap() > 0.0);
    assert!(out.exists());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn demo_writes_every_picture_and_an_index() {
    let d = temp_dir("demo");
    let r = fastbrdf(&["demo", "--out", d.to_str().unwrap(), "--size", "96"], "");
    assert!(r.status.success(), "{}", stderr(&r));
    let html = std::fs::read_to_string(d.join("index.html")).unwrap();
    for f in [
        "lobes-n20.png",
        "lobes-n200.png",
        "seed001-flog.png",
        "seed003-cubic-rational.png",
        "seed000-cook-torrance-skin.png",
        "seed000-ward-skin.png",
        "seed000-cook-torrance-face.png",
        "seed000-ward-face.png",
        "tuned-vs-untuned.png",
        "plots/seed001-fig3-max-rel-epicentre.png",
        "plots/seed000-fig2-4-relative-error.png",
    ] {
        assert!(d.join(f).exists(), "{f} missing");
        assert!(
            html.contains(&format!("src=\"{f}\"")),
            "index.html does not show {f}"
        );
    }
    assert!(html.contains("log.abs_err_max") && html.contains("<th>FLIP</th>"));
    // The face sections: captioned, each with its metrics table (a row per compared form).
    for (file, rows) in [
        ("seed000-cook-torrance-face.png", ["D16", "one-pow D"]),
        ("seed000-ward-face.png", ["ward-power16", "ward-pow"]),
    ] {
        let at = html.find(&format!("src=\"{file}\"")).unwrap();
        let figure = &html[at..at + html[at..].find("</figure>").unwrap()];
        assert!(
            figure.contains("canonical face") && figure.contains("built-in sky"),
            "{figure}"
        );
        assert!(figure.contains("<th>FLIP</th>"), "{file}: no metrics");
        for r in rows {
            assert!(
                figure.contains(&format!("<tr><td>{r}")),
                "{file}: no row {r}"
            );
        }
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn fit_and_pareto_commands() {
    let r = fastbrdf(
        &[
            "fit",
            "--family",
            "power16",
            "--reference",
            "pow",
            "--n",
            "8,16,40,100,300",
            "--json",
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    for row in v["rows"].as_array().unwrap() {
        let (e, u) = (
            row["error"].as_f64().unwrap(),
            row["untuned_error"].as_f64().unwrap(),
        );
        assert!(e <= 0.5 * u || u < 1e-12, "{row}");
    }
    assert_eq!(v["closed_form"]["r"].as_array().unwrap().len(), 5);
    let r = fastbrdf(
        &[
            "fit",
            "--family",
            "power16",
            "--reference",
            "pow",
            "--n",
            "40,200",
            "--normalized",
            "--json",
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(v["normalized"], true);
    for row in v["rows"].as_array().unwrap() {
        assert!(
            row["error"].as_f64().unwrap() < row["untuned_error"].as_f64().unwrap(),
            "{row}"
        );
    }
    for (args, expected) in [
        (
            vec![
                "fit",
                "--family",
                "power16",
                "--reference",
                "beckmann-ct",
                "--n",
                "8",
            ],
            "approximates pow",
        ),
        (
            vec![
                "fit",
                "--family",
                "beckmann-power16",
                "--reference",
                "beckmann-ct",
                "--n",
                "8",
            ],
            "takes --m RANGE",
        ),
        (
            vec![
                "fit",
                "--family",
                "power16",
                "--reference",
                "pow",
                "--n",
                "0..4",
            ],
            "n = 0 is outside",
        ),
    ] {
        let r = fastbrdf(&args, "");
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        assert!(stderr(&r).contains(expected), "{args:?}: {}", stderr(&r));
    }
    let bench = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let out = std::env::temp_dir().join(format!("fastbrdf-pareto-{}", std::process::id()));
    let r = fastbrdf(
        &[
            "pareto",
            "--bench",
            bench,
            "--markdown",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let md = stdout(&r);
    assert!(out.with_extension("png").exists() && out.with_extension("svg").exists());
    for ext in ["png", "svg"] {
        std::fs::remove_file(out.with_extension(ext)).unwrap();
    }
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let open = "<!-- pareto:begin -->\n";
    let start = readme.find(open).expect("README has the pareto block") + open.len();
    let end = readme
        .find("<!-- pareto:end -->")
        .expect("README closes the pareto block");
    assert!(
        readme[start..end] == md,
        "README's Pareto table is stale: paste `fastbrdf pareto --bench docs/bench/bench.json --markdown`"
    );
}

/// Issue 14: `pareto --brdf`, every Cook-Torrance configuration against an exact one. The quick
/// form runs in a few seconds; speed is measured, never asserted.
#[test]
fn pareto_brdf_quick_json_has_every_field_and_a_front() {
    let r = fastbrdf(&["pareto", "--brdf", "--quick", "--json"], "");
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(
        v["reference_label"],
        "ggx / smith-ggx-correlated / dielectric eta=1.5"
    );
    assert_eq!(v["alphas"], serde_json::json!([0.3]));
    assert_eq!(v["size"], 32);
    let rows = v["rows"].as_array().unwrap();
    assert!(rows.len() >= 30, "{}", rows.len());
    for row in rows {
        for k in [
            "alpha",
            "ns_per_eval",
            "cost_ratio",
            "max_rel_peak",
            "rms_rel",
            "rms_abs",
            "flip_sphere",
        ] {
            assert!(row[k].as_f64().is_some_and(|x| x >= 0.0), "{k}: {row}");
        }
        for k in ["label", "d", "g", "f", "denominator"] {
            assert!(row[k].is_string(), "{k}: {row}");
        }
        assert!(
            row["flip_mesh"].is_null() && row["pareto"].is_boolean() && row["simd"].is_boolean()
        );
    }
    let reference: Vec<_> = rows.iter().filter(|r| r["reference"] == true).collect();
    assert_eq!(reference.len(), 1);
    for k in ["max_rel_peak", "rms_rel", "rms_abs", "flip_sphere"] {
        assert_eq!(reference[0][k], 0.0, "{k}");
    }
    assert_eq!(reference[0]["cost_ratio"], 1.0);
    // The reference has zero error, so it is on the front (nothing is both cheaper and exact).
    assert_eq!(reference[0]["pareto"], true);
    assert!(rows.iter().filter(|r| r["pareto"] == true).count() >= 2);
    // Two alphas: one group each, the front per group; text and Markdown name the columns.
    let r = fastbrdf(
        &[
            "pareto",
            "--brdf",
            "--quick",
            "--size",
            "0",
            "--alpha",
            "0.1,0.6",
            "--markdown",
        ],
        "",
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let md = stdout(&r);
    assert!(
        md.starts_with("| alpha | D | G | F | ns/eval | x ref |"),
        "{md}"
    );
    assert!(md.contains("| 0.1 | `ggx` | `smith-ggx-correlated` | `dielectric eta=1.5` |"));
    assert!(md.contains("| 0.6 | `beckmann-power16` |"));
    for (args, expected) in [
        (vec!["pareto", "--brdf", "--alpha", "2"], "outside"),
        (
            vec!["pareto", "--brdf", "--reference", "alpha=0.2"],
            "--reference",
        ),
        (
            vec!["pareto", "--brdf", "--reference", "d=nope"],
            "--reference",
        ),
        (
            vec!["pareto", "--brdf", "--bench", "x.json"],
            "cannot be used with",
        ),
        (vec!["pareto", "--alpha", "0.3"], "--brdf"),
        (vec!["pareto", "--brdf", "--grid", "48x95"], "phi even"),
        (vec!["pareto", "--brdf", "--grid", "48"], "THETAxPHI"),
        (
            vec!["pareto", "--brdf", "--costs", "/dev/null"],
            "--costs /dev/null",
        ),
        (
            vec![
                "pareto",
                "--brdf",
                "--all",
                "--costs",
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../../docs/bench/pareto-brdf.json"
                ),
            ],
            "the saved costs lack",
        ),
    ] {
        let r = fastbrdf(&args, "");
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        assert!(stderr(&r).contains(expected), "{args:?}: {}", stderr(&r));
        assert!(r.stdout.is_empty());
    }
}

/// README's BRDF table is `fastbrdf pareto --brdf --costs docs/bench/pareto-brdf.json --mesh
/// crates/render/data/canonical_face_model.obj --markdown`: the errors recomputed, the costs from
/// the saved run (the release build's `--json`).
#[test]
fn readme_pareto_brdf_table_is_current() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let r = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
        .current_dir(root)
        .args([
            "pareto",
            "--brdf",
            "--costs",
            "docs/bench/pareto-brdf.json",
            "--mesh",
            "crates/render/data/canonical_face_model.obj",
            "--markdown",
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", stderr(&r));
    let md = stdout(&r);
    let readme = std::fs::read_to_string(format!("{root}/README.md")).unwrap();
    let open = "<!-- pareto-brdf:begin -->\n";
    let start = readme.find(open).expect("README has the pareto-brdf block") + open.len();
    let end = readme
        .find("<!-- pareto-brdf:end -->")
        .expect("README closes the pareto-brdf block");
    assert!(
        readme[start..end] == md,
        "README's BRDF Pareto table is stale: paste `fastbrdf pareto --brdf --costs docs/bench/pareto-brdf.json --mesh crates/render/data/canonical_face_model.obj --markdown`"
    );
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

/// Issue 11: one vocabulary for the swept parameter in every format (its own name).
#[test]
fn errors_and_fit_name_the_parameter_the_same_way_in_json_and_csv() {
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "flog",
            "--reference",
            "pow",
            "--n",
            "10,20",
            "--json",
        ],
        "",
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["param"], "n");
    for row in v["rows"].as_array().unwrap() {
        assert!(row["n"].is_number() && row.get("param").is_none(), "{row}");
    }
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "flog",
            "--reference",
            "pow",
            "--n",
            "10,20",
            "--csv",
        ],
        "",
    );
    assert!(stdout(&o).starts_with("n,max_abs,"));
    // One spelling of "no finite value": null in JSON, an empty field in CSV (was `inf`).
    // gauss is positive at c = 0 where pow is 0: an infinite relative error.
    let args = [
        "errors",
        "--model",
        "gauss",
        "--reference",
        "pow",
        "--n",
        "10",
    ];
    let o = fastbrdf(&[&args[..], &["--csv"]].concat(), "");
    let row = stdout(&o).lines().nth(1).unwrap().to_string();
    assert_eq!(row.split(',').nth(3), Some(""), "{row}");
    assert!(!row.contains("inf"), "{row}");
    let o = fastbrdf(&[&args[..], &["--json"]].concat(), "");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["rows"][0]["max_rel"].is_null() && v["worst"]["max_rel"].is_null());
    let o = fastbrdf(
        &[
            "fit",
            "--family",
            "beckmann-power16",
            "--reference",
            "beckmann-ct",
            "--m",
            "0.3",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["param"], "alpha");
    let row = &v["rows"][0];
    assert!(
        row["alpha"].is_number() && row.get("param").is_none(),
        "{row}"
    );
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

/// Issue 11: saved runs were read with `read_to_string`, without a limit (`/dev/zero` grew
/// until memory ran out). Every one is read once, at most 64 MiB.
#[cfg(unix)]
#[test]
fn saved_runs_are_read_with_a_bound() {
    for args in [
        vec!["bench", "--from", "/dev/zero", "--markdown"],
        vec!["pareto", "--bench", "/dev/zero"],
        vec!["reproduce", "--speedups", "/dev/zero"],
    ] {
        let o = fastbrdf(&args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(
            stderr(&o).contains("/dev/zero: larger than the 64 MiB"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// Issue 11, found by a hostile review after the first fixes: an empty zone reported error 0,
/// a fit through fewer points than constants reported a perfect fit, albedo's parameters were
/// strings in JSON, and CR-only line endings gave the wrong line.
#[test]
fn empty_measurements_are_refused_and_json_parameters_are_numbers() {
    for args in [
        &[
            "errors",
            "--model",
            "flog",
            "--reference",
            "pow",
            "--n",
            "20",
            "--zone",
            "band:0,1e-300",
            "--json",
        ][..],
        &["normalize", "--model", "flog", "--n", "5", "--fit", "seed"][..],
        &[
            "normalize",
            "--model",
            "flog",
            "--n",
            "5,10,20",
            "--fit",
            "seed",
        ][..],
        &[
            "normalize",
            "--model",
            "flog",
            "--n",
            "5",
            "--fit",
            "linear",
        ][..],
    ] {
        let o = fastbrdf(args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
    }
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "flog",
            "--reference",
            "pow",
            "--n",
            "20",
            "--zone",
            "band:0,1e-300",
        ],
        "",
    );
    assert!(stderr(&o).contains("no sample"), "{}", stderr(&o));
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "cook-torrance",
            "--param",
            "alpha=0.3",
            "--param",
            "f=schlick",
            "--angles",
            "0,45",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        v["params"]["alpha"],
        serde_json::json!(0.3),
        "{}",
        v["params"]
    );
    assert_eq!(v["params"]["f"], "schlick", "{}", v["params"]);
    let o = fastbrdf(&["eval", "--model", "pow"], "cos,cos\n0.5,0.6\n");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("more than once"), "{}", stderr(&o));
    let o = fastbrdf(
        &["eval", "--model", "pow", "--param", "n=2"],
        "cos\r0.5\r2\r",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("line 3, field 1 ('cos')"),
        "{}",
        stderr(&o)
    );
}

/// Issue 11 (review): saved runs with impossible figures were printed as if measured
/// ("FMA peak -0", "-1.00x", 300-digit throughputs).
#[test]
fn saved_runs_with_impossible_figures_are_refused() {
    let d = temp_dir("impossible-bench");
    let saved = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(saved).unwrap()).unwrap();
    type Edit = fn(&mut serde_json::Value);
    let edits: [(&str, Edit); 3] = [
        ("fma", |v| v["fma_per_s"] = serde_json::json!(-5.0)),
        ("speedup", |v| {
            v["speedups"][0]["measured"] = serde_json::json!(-1.0)
        }),
        ("evals", |v| {
            v["kernels"][3]["evals_per_s"] = serde_json::json!(1e308)
        }),
    ];
    for (name, edit) in edits {
        let mut v = good.clone();
        edit(&mut v);
        let f = d.join(format!("{name}.json"));
        std::fs::write(&f, serde_json::to_string(&v).unwrap()).unwrap();
        let f = f.to_str().unwrap();
        for args in [
            &["bench", "--from", f][..],
            &["reproduce", "--speedups", f, "--json"][..],
            &["pareto", "--bench", f, "--json"][..],
        ] {
            let o = fastbrdf(args, "");
            assert_eq!(o.status.code(), Some(2), "{name} {args:?}: {}", stderr(&o));
            assert!(o.stdout.is_empty(), "{name} {args:?}");
            assert!(stderr(&o).contains(f), "{}", stderr(&o));
        }
    }
    // The saved run itself is accepted.
    assert!(fastbrdf(&["bench", "--from", saved], "").status.success());
    std::fs::remove_dir_all(&d).unwrap();
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
