//! `--model file:PATH` end to end (issue 31): a user's `.brdf`, `.wgsl` or `.glsl` file in
//! `eval`, `render` and `compare`, evaluated on the GPU (lavapipe in CI: these tests skip
//! without an adapter, and fail when `CI` is set).

mod common;
use common::have_gpu;

use common::{listing, stderr, stdout, temp_dir};
use std::process::Output;

fn fastbrdf(args: &[&str], stdin: &str) -> Output {
    common::fastbrdf(args, stdin)
}

/// `file:` and the path of a test file of the GPU crate (`brdf-explorer/` or `user/`).
fn model(rel: &str) -> String {
    format!("file:{}", common::gpu_data(rel))
}

/// Unit directions (exact in decimal: the shaders take them as given, unnormalised).
const PAIRS: &str = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n0.6,0,0.8,-0.6,0,0.8\n\
0.36,0.48,0.8,0.48,-0.6,0.64\n-0.8,0,0.6,0,0.6,0.8\n0.6,0,0.8,-0.36,-0.48,0.8\n";

/// The value columns of `eval`'s output, per row.
fn values(csv: &str, first: usize) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .skip(first)
                .map(|x| x.parse().unwrap())
                .collect()
        })
        .collect()
}

#[test]
fn eval_of_walter_brdf_is_cook_torrance_ggx() {
    if !have_gpu() {
        return;
    }
    let user = model("brdf-explorer/walter.brdf");
    let o = fastbrdf(
        &[
            "eval",
            "--model",
            &user,
            "--param",
            "Ks=1",
            "--param",
            "alphaG=0.2",
        ],
        PAIRS,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.starts_with("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,value_r,value_g,value_b\n"),
        "{out}"
    );
    let o = fastbrdf(
        &[
            "eval",
            "--model",
            "cook-torrance",
            "--param",
            "d=ggx",
            "--param",
            "g=smith-ggx",
            "--param",
            "alpha=0.2",
            "--precision",
            "f64",
        ],
        PAIRS,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let want = values(&stdout(&o), 6);
    let got = values(&out, 6);
    let peak = want.iter().map(|r| r[0]).fold(0.0, f64::max);
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        for c in g {
            assert!((c - w[0]).abs() <= 1e-5 * peak, "{g:?} against {w:?}");
        }
    }
}

#[test]
fn a_wgsl_function_evaluates_with_its_declared_parameter() {
    if !have_gpu() {
        return;
    }
    let user = model("user/ggx_sampled.wgsl");
    let one = fastbrdf(&["eval", "--model", &user], PAIRS);
    assert!(one.status.success(), "{}", stderr(&one));
    assert!(stdout(&one).lines().next().unwrap().ends_with(",value"));
    let two = fastbrdf(&["eval", "--model", &user, "--param", "scale=2"], PAIRS);
    assert!(two.status.success(), "{}", stderr(&two));
    for (a, b) in values(&stdout(&one), 6)
        .iter()
        .zip(values(&stdout(&two), 6))
    {
        assert!(
            (2.0 * a[0] - b[0]).abs() <= 1e-6 * b[0].abs().max(1e-30),
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn bad_user_models_are_exit_2_naming_the_input_with_nothing_on_stdout() {
    let walter = model("brdf-explorer/walter.brdf");
    let glsl = model("user/compile_error.glsl");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["eval", "--model", "file:/no/such/file.brdf"],
            "/no/such/file.brdf",
        ),
        (vec!["eval", "--model", "file:"], "no path after 'file:'"),
        (vec!["eval", "--model", &walter, "--param", "Ks=3"], "'Ks'"),
        (
            vec!["eval", "--model", &walter, "--param", "nope=1"],
            "'nope'",
        ),
        (
            vec!["eval", "--model", &walter, "--metal", "gold"],
            "--metal gold",
        ),
        (vec!["eval", "--model", &glsl], "compile_error.glsl:7:"),
    ];
    for (args, needle) in cases {
        let o = fastbrdf(&args, PAIRS);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn render_and_compare_take_a_user_model() {
    if !have_gpu() {
        return;
    }
    let d = temp_dir("user-models");
    let walter = model("brdf-explorer/walter.brdf");
    let png = d.join("walter.png");
    let o = fastbrdf(
        &[
            "render",
            "--model",
            &walter,
            "--param",
            "Ks=1",
            "--size",
            "64x64",
            "--out",
            png.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&png).unwrap().to_luma8();
    // The highlight: the brightest pixel is far brighter than the darkest lit one.
    let max = img.pixels().map(|p| p[0]).max().unwrap();
    assert!(max > 200, "max {max}");
    let cmp = d.join("cmp.png");
    let o = fastbrdf(
        &[
            "compare",
            "--models",
            &walter,
            "--reference",
            "cook-torrance",
            "--param",
            "d=ggx",
            "--param",
            "g=smith-ggx",
            "--param",
            "alpha=0.1",
            "--param",
            "alphaG=0.1",
            "--param",
            "Ks=1",
            "--weights",
            "0,1",
            "--size",
            "48x48",
            "--json",
            "--out",
            cmp.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let m = &j["metrics"][0];
    // The same BRDF through the GPU evaluator (f32) and the registry: a near-perfect match.
    assert!(m["psnr"].as_f64().is_none_or(|p| p > 40.0), "{j}");
    assert_eq!(listing(&d), ["cmp.png", "walter.png"]);
}

#[test]
fn errors_and_albedo_take_a_user_model() {
    if !have_gpu() {
        return;
    }
    let walter = model("brdf-explorer/walter.brdf");
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            &walter,
            "--reference",
            "cook-torrance",
            "--param",
            "Ks=1",
            "--param",
            "alphaG=0.2",
            "--param",
            "alpha=0.2",
            "--param",
            "d=ggx",
            "--param",
            "g=smith-ggx",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    // The same BRDF: within 1e-5 of the reference's peak on conform's pair set.
    assert!(j["max_abs_of_peak"].as_f64().unwrap() < 1e-5, "{j}");
    assert!(j["pairs"].as_u64().unwrap() > 20_000, "{j}");
    // A different roughness is seen.
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            &walter,
            "--reference",
            "cook-torrance",
            "--param",
            "Ks=1",
            "--param",
            "alphaG=0.25",
            "--param",
            "alpha=0.2",
            "--param",
            "d=ggx",
            "--param",
            "g=smith-ggx",
            "--csv",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let row: Vec<String> = stdout(&o)
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(String::from)
        .collect();
    assert!(row[4].parse::<f64>().unwrap() > 1e-3, "{row:?}");
    // --n sweeps registry parameters: refused with a user's model.
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            &walter,
            "--reference",
            "ward",
            "--m",
            "0.1",
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            &model("user/broken_energy_gain.brdf"),
            "--angles",
            "0,60",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j["conserves"], false, "{j}");
    let a = j["rows"][0]["albedo"].as_f64().unwrap();
    assert!((a - 1.2).abs() < 1e-4, "{j}");
}
