//! `fastbrdf metals`, `--metal NAME` and per-channel parameters (`eta=R,G,B`) end to end
//! (issue 14): the JSON shape, coloured `eval`, coloured `render` and `compare`, and the
//! errors (exit 2, a message naming the parameter and channel, nothing on stdout, no file).

mod common;

use common::{listing, stderr, stdout, temp_dir};
use std::process::Output;

fn fastbrdf(args: &[&str]) -> Output {
    common::fastbrdf(args, "")
}

#[test]
fn metals_json_has_numbers_per_channel() {
    let o = fastbrdf(&["metals", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(
        v["wavelengths_nm"],
        serde_json::json!([650.0, 550.0, 450.0])
    );
    let all = v["metals"].as_array().expect("metals");
    let ids: Vec<&str> = all.iter().map(|m| m["id"].as_str().unwrap()).collect();
    assert_eq!(
        ids,
        ["gold", "silver", "copper", "aluminium", "chromium", "iron"]
    );
    for m in all {
        for key in ["eta", "k", "f0"] {
            let a = m[key].as_array().unwrap_or_else(|| panic!("{key}: {m}"));
            assert!(
                a.len() == 3 && a.iter().all(|x| x.as_f64().is_some()),
                "{m}"
            );
        }
        for c in 0..3 {
            let (n, k) = (m["eta"][c].as_f64().unwrap(), m["k"][c].as_f64().unwrap());
            let f0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            assert!((m["f0"][c].as_f64().unwrap() - f0).abs() < 1e-12, "{m}");
        }
        assert!(m["source"].as_str().unwrap().contains("19"), "{m}");
        assert!(m["symbol"].is_string());
    }
    let table = fastbrdf(&["metals"]);
    assert!(table.status.success());
    assert!(stdout(&table).contains("Johnson & Christy 1972"));
}

#[test]
fn eval_of_a_coloured_model_writes_three_value_columns() {
    let o = common::fastbrdf(
        &["eval", "--model", "fresnel-conductor", "--metal", "gold"],
        "cos_vh\n1\n",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let mut lines = out.lines();
    assert_eq!(lines.next(), Some("cos_vh,value_r,value_g,value_b"));
    let v: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    // F0 of gold per channel (f32), red > green > blue.
    assert!(
        (v[1] - 0.94423).abs() < 1e-4 && (v[3] - 0.37340).abs() < 1e-4,
        "{v:?}"
    );
    // Grey stays one column.
    let g = common::fastbrdf(
        &[
            "eval",
            "--model",
            "fresnel-conductor",
            "--param",
            "eta=0.18299",
            "--param",
            "k=3.4242",
        ],
        "cos_vh\n1\n",
    );
    let grey = stdout(&g);
    assert!(grey.starts_with("cos_vh,value\n"), "{grey}");
    assert_eq!(
        grey.lines()
            .nth(1)
            .unwrap()
            .split(',')
            .nth(1)
            .unwrap()
            .parse::<f64>()
            .unwrap(),
        v[1]
    );
}

#[test]
fn render_and_compare_with_a_metal_write_coloured_pictures() {
    let d = temp_dir("metal-render");
    let out = d.join("gold.png");
    let o = fastbrdf(&[
        "render",
        "--model",
        "cook-torrance",
        "--param",
        "d=ggx",
        "--param",
        "alpha=0.2",
        "--metal",
        "gold",
        "--size",
        "64x64",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap().to_rgb8();
    let (mut r, mut b) = (0u64, 0u64);
    // Over the sphere (the background is grey: equal channels).
    for p in img.pixels().filter(|p| p[0] != p[2]) {
        r += u64::from(p[0]);
        b += u64::from(p[2]);
    }
    // F0 0.94 against 0.37 in linear terms: about 1.5 in sRGB.
    assert!(10 * r > 13 * b, "gold: red {r} against blue {b}");
    let cmp = d.join("cmp.png");
    let o = fastbrdf(&[
        "compare",
        "--models",
        "ggx",
        "--reference",
        "cook-torrance",
        "--param",
        "alpha=0.2",
        "--metal",
        "copper",
        "--size",
        "32x32",
        "--json",
        "--out",
        cmp.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(cmp.exists());
}

#[test]
fn bad_channels_and_metals_are_exit_2_naming_the_parameter() {
    let d = temp_dir("metal-errors");
    let out = d.join("x.png");
    let o = out.to_str().unwrap();
    let ct = [
        "render",
        "--model",
        "cook-torrance",
        "--param",
        "f=conductor",
        "--size",
        "16x16",
    ];
    let cases: [(Vec<&str>, &str); 6] = [
        (vec!["--param", "eta=0.2,0.4"], "eta = 0.2,0.4"),
        (
            vec!["--param", "eta=0.2,gold,1.3"],
            "eta (channel G, 550 nm)",
        ),
        (vec!["--param", "k=3,2,25"], "k (channel B, 450 nm)"),
        (vec!["--param", "d=ggx,ggx,ggx"], "parameter d"),
        (
            vec!["--metal", "brass"],
            "gold, silver, copper, aluminium, chromium, iron",
        ),
        (vec!["--metal", "gold", "--gpu"], "CPU-only"),
    ];
    for (extra, says) in cases {
        let mut args = ct.to_vec();
        args.extend(extra.iter());
        args.extend(["--out", o]);
        let r = fastbrdf(&args);
        assert_eq!(r.status.code(), Some(2), "{extra:?}: {}", stderr(&r));
        assert!(stderr(&r).contains(says), "{extra:?}: {}", stderr(&r));
        assert!(r.stdout.is_empty(), "{extra:?}");
        assert!(listing(&d).is_empty(), "{extra:?}: {:?}", listing(&d));
    }
    let r = fastbrdf(&["render", "--model", "ward", "--metal", "gold", "--out", o]);
    assert_eq!(r.status.code(), Some(2));
    assert!(
        stderr(&r).contains("no conductor Fresnel term"),
        "{}",
        stderr(&r)
    );
    let r = fastbrdf(&[
        "compare",
        "--models",
        "ggx,flog",
        "--reference",
        "cook-torrance",
        "--metal",
        "gold",
        "--out",
        o,
    ]);
    assert_eq!(r.status.code(), Some(2));
    assert!(stderr(&r).contains("'flog'"), "{}", stderr(&r));
    assert!(listing(&d).is_empty());
    let r = common::fastbrdf(
        &[
            "eval",
            "--model",
            "fresnel-conductor",
            "--param",
            "eta=1,2,3,4",
        ],
        "cos_vh\n1\n",
    );
    assert_eq!(r.status.code(), Some(2));
    assert!(
        stderr(&r).contains("4 given") && r.stdout.is_empty(),
        "{}",
        stderr(&r)
    );
}

#[test]
fn shader_with_a_metal_exports_the_vector_function() {
    let o = fastbrdf(&[
        "shader",
        "--model",
        "cook-torrance",
        "--param",
        "d=ggx",
        "--metal",
        "gold",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("fn fb_cook_torrance_rgb(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32>"));
    assert!(
        text.contains("fb_f_conductor(p.cos_ih, 0.18299f, 3.4242f)"),
        "{text}"
    );
    for bad in [
        vec!["--model", "ggx", "--metal", "gold"],
        vec![
            "--model",
            "cook-torrance",
            "--metal",
            "gold",
            "--runtime-params",
        ],
        vec!["--model", "cook-torrance", "--param", "eta=1,2"],
    ] {
        let mut args = vec!["shader"];
        args.extend(bad.iter());
        let r = fastbrdf(&args);
        assert_eq!(r.status.code(), Some(2), "{bad:?}: {}", stderr(&r));
        assert!(r.stdout.is_empty(), "{bad:?}");
    }
}
