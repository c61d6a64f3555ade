//! `fastbrdf conform` end to end (issue 31): text and JSON reports, exit codes 0, 1 and 2.

mod common;
use common::{fastbrdf, stderr, stdout};

#[test]
fn a_builtin_conforms_one_line_per_check() {
    let o = fastbrdf(&["conform", "cook-torrance", "--param", "d=ggx"], "");
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 12, "{out}");
    for (line, check) in lines.iter().zip(fastbrdf_checks()) {
        let want = if check == "reference" { "SKIP" } else { "PASS" };
        assert!(
            line.starts_with(&format!("{want} {check} ")),
            "{check}: {line}"
        );
    }
    let recip = lines[3];
    assert!(
        recip.contains("max |f(wi,wo)-f(wo,wi)| cos_i cos_o = ")
            && recip.contains("of its peak")
            && recip.contains("(limit 0.001)"),
        "{recip}"
    );
    assert!(
        lines[4].contains("max albedo 0.") && lines[4].contains("deg"),
        "{}",
        lines[4]
    );
    assert!(
        lines[11]
            .starts_with("cook-torrance d=ggx conforms (ci mode: 10 checks passed, 1 skipped)"),
        "{}",
        lines[11]
    );
}

fn fastbrdf_checks() -> [&'static str; 11] {
    [
        "finite",
        "non-negative",
        "non-finite-input",
        "reciprocity",
        "energy",
        "reference",
        "chi2",
        "weight",
        "pdf-integral",
        "pdf-coverage",
        "pdf-sample",
    ]
}

#[test]
fn json_is_the_report_and_a_failed_check_is_exit_1() {
    let o = fastbrdf(
        &[
            "conform",
            "cook-torrance",
            "--param",
            "alpha=0.3",
            "--reference",
            "cook-torrance",
            "--reference-param",
            "alpha=0.33",
            "--json",
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["model"], "cook-torrance alpha=0.3");
    assert_eq!(v["mode"], "ci");
    assert_eq!(v["passed"], false);
    let checks = v["checks"].as_array().unwrap();
    let names: Vec<&str> = checks
        .iter()
        .map(|c| c["check"].as_str().unwrap())
        .collect();
    assert_eq!(names, fastbrdf_checks());
    for c in checks {
        let want = if c["check"] == "reference" {
            "fail"
        } else {
            "pass"
        };
        assert_eq!(c["status"], want, "{c}");
    }
    let r = &checks[5];
    assert!(r["value"].as_f64().unwrap() > r["limit"].as_f64().unwrap());
    assert_eq!(r["at"]["wo"].as_array().unwrap().len(), 3);
    assert!(stderr(&o).contains("failed reference"), "{}", stderr(&o));

    // The same reference as the model: every check passes, exit 0.
    let o = fastbrdf(
        &["conform", "lambert", "--reference", "lambert", "--json"],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["passed"], true);
    assert_eq!(v["checks"][5]["status"], "pass");
    assert_eq!(v["checks"][5]["value"], 0.0);
}

#[test]
fn a_failed_check_in_text_is_exit_1_with_the_verdict() {
    let o = fastbrdf(
        &[
            "conform",
            "lambert",
            "--param",
            "albedo=0.5",
            "--reference",
            "lambert",
            "--strategy",
            "cosine",
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("\nFAIL reference "), "{out}");
    assert!(
        out.trim_end()
            .ends_with("lambert albedo=0.5 does not conform (ci mode): reference failed"),
        "{out}"
    );
}

#[test]
fn bad_input_is_exit_2_naming_it_with_nothing_on_stdout() {
    for (args, names) in [
        (vec!["conform", "no-such-model"], "no-such-model"),
        (vec!["conform", "flog"], "flog"),
        (
            vec!["conform", "lambert", "--strategy", "sideways"],
            "sideways",
        ),
        (vec!["conform", "lambert", "--strategy", "vndf"], "vndf"),
        (vec!["conform", "ggx", "--param", "alpha=9"], "alpha"),
        (vec!["conform", "lambert", "--param", "n"], "--param 'n'"),
        (vec!["conform", "lambert", "--reference", "nope"], "nope"),
        (
            vec![
                "conform",
                "lambert",
                "--reference",
                "lambert",
                "--reference-param",
                "albedo=7",
            ],
            "albedo",
        ),
        (
            vec!["conform", "file:/no/such/file.brdf"],
            "/no/such/file.brdf",
        ),
    ] {
        let o = fastbrdf(&args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stdout(&o).is_empty(), "{args:?}: {}", stdout(&o));
        assert!(stderr(&o).contains(names), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn help_has_examples() {
    let o = fastbrdf(&["conform", "--help"], "");
    assert!(o.status.success());
    let out = stdout(&o);
    assert!(out.contains("Examples:") && out.contains("fastbrdf conform cook-torrance"));
    assert!(out.contains("--reference-param") && out.contains("--full"));
}
