//! `fit` and `pareto` end to end (the Pareto table of lobes and of full BRDFs; the book's
//! copies are checked by tests/docs.rs), and how `errors` and `fit` name parameters and refuse empty measurements.

mod common;

use common::{fastbrdf, stderr, stdout};

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
    // The book's copy (docs/book/src/tuned.md): tests/docs.rs, generated_pareto_table_is_current.
    assert!(md.starts_with("| model |"), "{md}");
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
    // How many rows the front holds depends on measured speed (under CI's load the reference
    // can time cheapest and stand alone), so the test recomputes the front from the printed
    // numbers instead: a row is on it exactly when no row is at least as cheap and as exact,
    // and better on one of the two (the error named by "front_on").
    let on = v["front_on"].as_str().unwrap();
    assert_eq!(on, "rms_rel");
    let point =
        |r: &serde_json::Value| (r["ns_per_eval"].as_f64().unwrap(), r[on].as_f64().unwrap());
    for (i, row) in rows.iter().enumerate() {
        let (c, e) = point(row);
        let dominated = rows.iter().enumerate().any(|(j, other)| {
            let (cj, ej) = point(other);
            j != i && cj <= c && ej <= e && (cj < c || ej < e)
        });
        assert_eq!(row["pareto"], !dominated, "{row}");
    }
    // The rows come cheapest first (mark_front's order); with the loop above, the cheapest
    // row is on the front unless a row as cheap is more exact.
    assert!(rows.windows(2).all(|w| point(&w[0]).0 <= point(&w[1]).0));
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

// The book's BRDF table (docs/book/src/pareto-brdf.md) is `fastbrdf pareto --brdf --costs
// docs/bench/pareto-brdf.json --mesh crates/render/data/canonical_face_model.obj --markdown`:
// tests/docs.rs, generated_pareto_brdf_table_is_current.

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
