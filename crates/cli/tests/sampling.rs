//! `fastbrdf sample` and `fastbrdf chi2` end to end (issue 15).

mod common;
use common::{fastbrdf, stderr, stdout, temp_dir};

fn rows(csv: &str) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn sample_writes_wi_weight_pdf_and_zeros_for_no_sample() {
    let input = "wo_x,wo_y,wo_z,u1,u2,tag\n0.5,0,0.866,0.3,0.7,1\n0,0,1,0.99,0.1,2\n";
    for precision in ["f32", "f64"] {
        let o = fastbrdf(
            &[
                "sample",
                "--model",
                "cook-torrance",
                "--param",
                "d=ggx",
                "--param",
                "alpha=0.2",
                "--precision",
                precision,
            ],
            input,
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let out = stdout(&o);
        assert!(out.starts_with("wo_x,wo_y,wo_z,u1,u2,tag,wi_x,wi_y,wi_z,weight,pdf\n"));
        let r = rows(&out);
        assert_eq!(r.len(), 2);
        let wi = &r[0][6..9];
        let len = (wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-5 && wi[2] > 0.0 && r[0][10] > 0.0);
        // VNDF at normal incidence, u1 = 0.99: a grazing normal, wi below the horizon.
        assert_eq!(&r[1][6..], &[0.0; 5]);
    }
    // Lambert, cosine: the weight is the albedo, the pdf cos / pi, and --pdf agrees.
    let o = fastbrdf(
        &[
            "sample",
            "--model",
            "lambert",
            "--param",
            "albedo=0.7",
            "--precision",
            "f64",
        ],
        "wo_x,wo_y,wo_z,u1,u2\n0,0.3,1,0.25,0.5\n",
    );
    let r = rows(&stdout(&o));
    assert!((r[0][8] - 0.7).abs() < 1e-12, "{:?}", r[0]);
    assert!((r[0][9] - r[0][7] / std::f64::consts::PI).abs() < 1e-12);
    let q = format!(
        "wo_x,wo_y,wo_z,wi_x,wi_y,wi_z\n0,0.3,1,{},{},{}\n",
        r[0][5], r[0][6], r[0][7]
    );
    let o = fastbrdf(
        &[
            "sample",
            "--model",
            "lambert",
            "--pdf",
            "--precision",
            "f64",
        ],
        &q,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let p = rows(&stdout(&o))[0][6];
    assert!((p - r[0][9]).abs() < 1e-12);
}

#[test]
fn sample_refuses_bad_input_and_strategies_with_exit_2() {
    let good = "wo_x,wo_y,wo_z,u1,u2\n0,0,1,0.5,0.5\n";
    for (args, input, needle) in [
        (
            vec!["sample", "--model", "lambert"],
            "wo_x,wo_y,wo_z,u1,u2\n0,0,1,0.5,0.5\n0,0,1,1.5,0.5\n",
            "line 3, field 4 ('u1'): 1.5 is outside [0, 1)",
        ),
        (
            vec!["sample", "--model", "lambert"],
            "wo_x,wo_y,wo_z,u1\n0,0,1,0.5\n",
            "missing column 'u2'",
        ),
        (
            vec!["sample", "--model", "lambert"],
            "wo_x,wo_y,wo_z,u1,u2\n0,0,x,0.5,0.5\n",
            "line 2, field 3 ('wo_z'): 'x' is not a number",
        ),
        (
            vec!["sample", "--model", "lambert"],
            "wo_x,wo_y,wo_z,u1,u2\n0,0,-1,0.5,0.5\n",
            "field 1 ('wo_x'): wo is below the horizon",
        ),
        (
            vec!["sample", "--model", "lambert", "--strategy", "vndf"],
            good,
            "strategy vndf does not apply to this model; valid: auto, cosine",
        ),
        (
            vec!["sample", "--model", "ward", "--strategy", "fast"],
            good,
            "--strategy 'fast': expected one of auto, cosine, lobe, d-cos, vndf, twin",
        ),
        (
            vec!["sample", "--model", "pow"],
            good,
            "only full BRDFs sample",
        ),
        (
            vec![
                "sample",
                "--model",
                "cook-torrance",
                "--param",
                "d=beckmann-power8",
                "--strategy",
                "vndf",
            ],
            good,
            "valid: auto, twin, cosine",
        ),
    ] {
        let o = fastbrdf(&args, input);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn chi2_passes_prints_json_and_draws_the_histograms() {
    let d = temp_dir("chi2");
    let png = d.join("h.png");
    let o = fastbrdf(
        &[
            "chi2",
            "--model",
            "cook-torrance",
            "--param",
            "d=ggx",
            "--param",
            "alpha=0.2",
            "--theta-i",
            "60",
            "--json",
            "--out",
            png.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["strategy"], "vndf");
    assert_eq!(v["passed"], true);
    assert!(v["p_value"].as_f64().unwrap() > 0.01);
    let img = image::open(&png).unwrap();
    assert!(img.width() > 3 * img.height());
    // Text mode names the verdict; an invalid strategy is usage (exit 2).
    let o = fastbrdf(&["chi2", "--model", "phong", "--param", "n=100"], "");
    assert!(
        o.status.success() && stdout(&o).contains("PASS"),
        "{}",
        stdout(&o)
    );
    let o = fastbrdf(&["chi2", "--model", "phong", "--strategy", "vndf"], "");
    assert_eq!(o.status.code(), Some(2));
    let o = fastbrdf(&["chi2", "--model", "phong", "--theta-i", "90"], "");
    assert_eq!(o.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn help_lists_sample_and_chi2() {
    let h = stdout(&fastbrdf(&["--help"], ""));
    assert!(h.contains("sample") && h.contains("chi2"), "{h}");
    for sub in ["sample", "chi2"] {
        let o = fastbrdf(&[sub, "--help"], "");
        assert!(
            o.status.success() && stdout(&o).contains("Example"),
            "{sub}"
        );
    }
}
