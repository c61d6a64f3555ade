//! `fastbrdf fit-measured`, `measured render`, `errors --measured` and `compare --measured` end
//! to end on synthetic MERL files tabulated from known models (no real MERL file is reachable
//! from the test machines), and their bad inputs: exit 2 naming the file, nothing on stdout,
//! no picture written.

mod common;

use common::{fastbrdf, listing, stderr, stdout, temp_dir};
use fastbrdf::Model;
use fastbrdf::measured::{from_half_diff, write_merl};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Ngan et al. 2005's Ward fit of blue-rubber (`fastbrdf materials`): alpha and the albedos.
const ALPHA: f64 = 0.289;
const KD: [f64; 3] = [0.0309, 0.0601, 0.0891];
const KS: [f64; 3] = [0.0399, 0.0343, 0.0237];

/// A MERL file of `kd / pi + ks * model(params)` at the bin centres.
fn synthetic(path: &Path, id: &str, params: &[(&str, &str)], kd: [f64; 3], ks: [f64; 3]) {
    let Model::Brdf(b) = fastbrdf::ModelSpec::parse(id, params)
        .and_then(|s| s.model::<f64>())
        .unwrap()
    else {
        panic!("a BRDF")
    };
    write_merl(path, |th, td, pd| {
        let (wi, wo) = from_half_diff(th, td, pd);
        if wi[2] <= 0.0 || wo[2] <= 0.0 {
            return [-1.0; 3];
        }
        let s = b.eval(wi, wo);
        [0, 1, 2].map(|c| kd[c] / PI + ks[c] * s)
    })
    .unwrap();
}

fn ward_file(dir: &Path) -> PathBuf {
    let p = dir.join("ward.binary");
    synthetic(&p, "ward", &[("alpha", &ALPHA.to_string())], KD, KS);
    p
}

fn json(o: &std::process::Output) -> serde_json::Value {
    assert_eq!(o.status.code(), Some(0), "{}", stderr(o));
    serde_json::from_str(&stdout(o)).unwrap()
}

/// The fit recovers the Ward it was made from: alpha and the six albedos within 1 % (measured:
/// 1e-6 and better; the data are exact at the bin centres the fit samples); Blinn-Phong, the
/// wrong model, leaves an ngan-l2 residual more than 10 times larger; the picture is written.
/// Then errors --measured: the true alpha has the smallest residual of the sweep.
#[test]
fn fit_recovers_the_model_and_a_wrong_model_does_worse() {
    let dir = temp_dir("fit-measured");
    let f = ward_file(&dir);
    let f = f.to_str().unwrap();
    let pic = dir.join("fit.png");
    let common = [
        "--samples",
        "1500",
        "--restarts",
        "2",
        "--size",
        "48x48",
        "--spp",
        "1",
    ];
    let mut args = vec![
        "fit-measured",
        "--data",
        f,
        "--model",
        "ward",
        "--json",
        "--out",
    ];
    args.push(pic.to_str().unwrap());
    args.extend(common);
    let v = json(&fastbrdf(&args, ""));
    let alpha = v["params"]["alpha"].as_f64().unwrap();
    assert!((alpha - ALPHA).abs() < 0.01 * ALPHA, "{v}");
    for c in 0..3 {
        let (d, s) = (
            v["rho_d"][c].as_f64().unwrap(),
            v["rho_s"][c].as_f64().unwrap(),
        );
        assert!((d - KD[c]).abs() < 0.01 * KD[c], "{v}");
        assert!((s - KS[c]).abs() < 0.01 * KS[c], "{v}");
    }
    let right = v["residuals"]["ngan-l2"].as_f64().unwrap();
    assert!(right < 1e-5, "{v}");
    assert_eq!(v["samples"], 1500);
    assert!(pic.exists());
    let png = image::open(&pic).unwrap();
    assert!(png.width() > 96 && png.height() > 48);

    let mut args = vec![
        "fit-measured",
        "--data",
        f,
        "--model",
        "blinn-phong",
        "--json",
        "--out",
    ];
    let pic2 = dir.join("bp.png");
    args.push(pic2.to_str().unwrap());
    args.extend(common);
    let w = json(&fastbrdf(&args, ""));
    let wrong = w["residuals"]["ngan-l2"].as_f64().unwrap();
    assert!(wrong > 10.0 * right.max(1e-6), "{wrong} vs {right}");

    // The table form names the fitted parameter and the residuals.
    let mut args = vec![
        "fit-measured",
        "--data",
        f,
        "--model",
        "ward",
        "--metric",
        "max",
        "--out",
    ];
    let pic3 = dir.join("max.png");
    args.push(pic3.to_str().unwrap());
    args.extend(common);
    let o = fastbrdf(&args, "");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(
        s.contains("alpha") && s.contains("residuals: ngan-l2"),
        "{s}"
    );

    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "ward",
            "--measured",
            f,
            "--m",
            "0.2,0.25,0.289,0.33,0.4",
            "--samples",
            "1500",
            "--json",
        ],
        "",
    );
    let v = json(&o);
    let rows = v["rows"].as_array().unwrap();
    let best = rows
        .iter()
        .min_by(|a, b| {
            a["ngan_l2"]
                .as_f64()
                .unwrap()
                .total_cmp(&b["ngan_l2"].as_f64().unwrap())
        })
        .unwrap();
    assert_eq!(best["alpha"].as_f64().unwrap(), 0.289, "{v}");
    assert!(best["ngan_l2"].as_f64().unwrap() < 1e-5, "{v}");

    // compare --measured: the file as the reference.
    let cmp = dir.join("cmp.png");
    let o = fastbrdf(
        &[
            "compare",
            "--models",
            "ward",
            "--measured",
            f,
            "--param",
            "alpha=0.289",
            "--size",
            "32x32",
            "--spp",
            "1",
            "--json",
            "--out",
            cmp.to_str().unwrap(),
        ],
        "",
    );
    let v = json(&o);
    assert_eq!(v["reference"], f);
    assert!(cmp.exists());
}

/// A grey measured file made from cook-torrance (alpha 0.3, no diffuse) renders like `render
/// --model cook-torrance --weights 0,1`: the nearest-bin quantisation of MERL's table is the
/// only difference. Measured on 64x64 EXRs: mean |difference| 1.0 % of the mean value, largest
/// pixel difference 1.8 % of the peak; the bounds are 3 % and 10 %.
#[test]
fn measured_render_matches_the_model_it_was_made_from() {
    let dir = temp_dir("measured-render");
    let f = dir.join("ct.binary");
    synthetic(&f, "cook-torrance", &[("alpha", "0.3")], [0.0; 3], [1.0; 3]);
    let (m, r) = (dir.join("m.exr"), dir.join("r.exr"));
    let o = fastbrdf(
        &[
            "measured",
            "render",
            f.to_str().unwrap(),
            "--size",
            "64x64",
            "--out",
            m.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    let o = fastbrdf(
        &[
            "render",
            "--model",
            "cook-torrance",
            "--param",
            "alpha=0.3",
            "--weights",
            "0,1",
            "--size",
            "64x64",
            "--out",
            r.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let a = image::open(&m).unwrap().to_rgb32f();
    let b = image::open(&r).unwrap().to_rgb32f();
    let (mut diff, mut sum, mut max_rel) = (0.0f64, 0.0f64, 0.0f64);
    let peak = b.pixels().flat_map(|p| p.0).fold(0.0f32, f32::max) as f64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            let (x, y) = (p.0[c] as f64, q.0[c] as f64);
            diff += (x - y).abs();
            sum += y;
            max_rel = max_rel.max((x - y).abs() / peak);
        }
    }
    assert!(sum > 0.0);
    assert!(diff / sum < 0.03, "mean relative difference {}", diff / sum);
    assert!(max_rel < 0.1, "max difference / peak {max_rel}");
}

/// Bad inputs: a malformed file, a non-BRDF model, a bad --param: exit 2 naming the culprit,
/// nothing on stdout, no picture.
#[test]
fn bad_inputs_exit_2_and_write_nothing() {
    let dir = temp_dir("fit-measured-bad");
    let short = dir.join("short.binary");
    std::fs::write(&short, vec![0u8; 1000]).unwrap();
    let pic = dir.join("out.png");
    let (s, p) = (short.to_str().unwrap(), pic.to_str().unwrap());
    for (args, want) in [
        (
            vec!["fit-measured", "--data", s, "--model", "ward", "--out", p],
            "short.binary",
        ),
        (
            vec!["fit-measured", "--data", s, "--model", "flog", "--out", p],
            "needs a BRDF",
        ),
        (
            vec![
                "fit-measured",
                "--data",
                s,
                "--model",
                "ward",
                "--param",
                "alpha=7",
                "--out",
                p,
            ],
            "alpha",
        ),
        (
            vec![
                "fit-measured",
                "--data",
                s,
                "--model",
                "ward",
                "--out",
                "x.jpg",
            ],
            "--out",
        ),
        (vec!["measured", "render", s, "--out", p], "short.binary"),
        (
            vec!["errors", "--model", "ward", "--measured", s, "--m", "0.2"],
            "short.binary",
        ),
        (
            vec!["errors", "--model", "fresnel-schlick", "--measured", s],
            "fresnel",
        ),
        (
            vec!["compare", "--models", "ward", "--measured", s, "--out", p],
            "short.binary",
        ),
    ] {
        let o = fastbrdf(&args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
        assert_eq!(listing(&dir), ["short.binary"], "{args:?}");
    }
}
