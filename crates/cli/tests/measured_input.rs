//! Measured inputs that are valid files but implausible data (issue 27): MERL samples of 1e300
//! (finite) and environment maps of 3e38 texels are refused at read time naming the file (they
//! made `errors --measured` report zero albedos and `render` blame the model for non-finite
//! pixels); `measured info` on a file with no measured sample prints no NaN or inf; and
//! `fit-measured --param f=schlick` (README's example) recovers f0 and rho_s from exact data,
//! saying when a parameter asked for is not determined by the data.

mod common;

use common::{fastbrdf, listing, stderr, stdout, temp_dir};
use fastbrdf::measured::{from_half_diff, write_merl};
use std::f64::consts::PI;
use std::path::Path;
use std::process::Output;

/// A MERL file of `kd / pi + ks * model(params)` (-1, missing, below the horizon).
fn merl(path: &Path, id: &str, params: &[(&str, &str)], kd: [f64; 3], ks: [f64; 3]) {
    let fastbrdf::Model::Brdf(b) = fastbrdf::ModelSpec::parse(id, params)
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

/// Exit 2, the file and `expect` in the message, nothing on stdout.
fn refused(o: &Output, file: &Path, expect: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains(&file.display().to_string()),
        "{e:?} names {file:?}"
    );
    assert!(e.contains(expect), "{e:?} should contain {expect:?}");
    assert!(o.stdout.is_empty(), "{}", stdout(o));
}

#[test]
fn huge_merl_samples_are_refused_at_read_naming_the_file() {
    let d = temp_dir("measured-huge");
    let f = d.join("huge.binary");
    // Every sample 0.1 (stored / scale), one green sample 1e300: finite, not a measurement.
    let k = std::cell::Cell::new(0usize);
    write_merl(&f, |_, _, _| {
        k.set(k.get() + 1);
        if k.get() == 1000 {
            [0.1, 1e300, 0.1]
        } else {
            [0.1; 3]
        }
    })
    .unwrap();
    let fs = f.to_str().unwrap();
    let o = fastbrdf(&["measured", "info", fs], "");
    refused(&o, &f, "green channel, sample 999");
    assert!(stderr(&o).contains("1e8"), "{}", stderr(&o));
    let o = fastbrdf(
        &[
            "errors",
            "--model",
            "ward",
            "--measured",
            fs,
            "--m",
            "0.3",
            "--json",
        ],
        "",
    );
    refused(&o, &f, "sr^-1");
    let out = d.join("m.png");
    let o = fastbrdf(
        &[
            "measured",
            "render",
            fs,
            "--size",
            "16x16",
            "--spp",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    refused(&o, &f, "sr^-1");
    assert!(!stderr(&o).contains("non-finite pixels"), "{}", stderr(&o));
    assert_eq!(listing(&d), vec!["huge.binary"], "nothing written");
    // 1e8 sr^-1 itself is accepted (a mirror in MERL's smallest bin; see MAX_VALUE).
    write_merl(&f, |_, _, _| [fastbrdf::measured::MAX_VALUE; 3]).unwrap();
    let o = fastbrdf(&["measured", "info", fs, "--json"], "");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let mean = v["channels"][0]["mean"].as_f64().unwrap();
    assert!(
        (mean / fastbrdf::measured::MAX_VALUE - 1.0).abs() < 1e-9,
        "{v}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn measured_info_of_a_file_with_nothing_measured_prints_no_nan() {
    let d = temp_dir("measured-missing");
    let f = d.join("empty.binary");
    write_merl(&f, |_, _, _| [-1.0; 3]).unwrap();
    let fs = f.to_str().unwrap();
    let o = fastbrdf(&["measured", "info", fs], "");
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let low = text.to_lowercase();
    assert!(!low.contains("nan") && !low.contains("inf"), "{text}");
    assert!(text.contains("no measured sample"), "{text}");
    for ch in ["red", "green", "blue"] {
        let line = text.lines().find(|l| l.starts_with(ch)).unwrap();
        assert!(line.contains(" - ") && line.ends_with("1458000"), "{line}");
    }
    // JSON: null statistics, numbers for the counts.
    let o = fastbrdf(&["measured", "info", fs, "--json"], "");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for c in v["channels"].as_array().unwrap() {
        assert!(
            c["mean"].is_null() && c["min"].is_null() && c["max"].is_null(),
            "{c}"
        );
        assert_eq!(c["valid"], 0);
        assert_eq!(c["missing"], 1_458_000);
    }
    // A fit has nothing to fit: exit 2 naming the file.
    let o = fastbrdf(
        &["errors", "--model", "ward", "--measured", fs, "--m", "0.3"],
        "",
    );
    refused(&o, &f, "no valid");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_implausibly_bright_environment_map_is_refused_naming_it() {
    let d = temp_dir("measured-env");
    let env = d.join("bright.exr");
    exr::prelude::write_rgb_file(&env, 16, 8, |x, y| {
        if (x, y) == (3, 1) {
            (1.0f32, 3e38f32, 1.0f32)
        } else {
            (0.5, 0.5, 0.5)
        }
    })
    .unwrap();
    let out = d.join("r.png");
    let o = fastbrdf(
        &[
            "render",
            "--model",
            "ward",
            "--size",
            "16x16",
            "--env-samples",
            "2",
            "--env",
            env.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        "",
    );
    refused(&o, &env, "texel (3, 1) is implausibly bright");
    assert!(!stderr(&o).contains("the model"), "{}", stderr(&o));
    assert_eq!(listing(&d), vec!["bright.exr"], "nothing written");
    let _ = std::fs::remove_dir_all(&d);
}

/// Runs README's `fit-measured --param f=schlick` (with d = ggx) on `file`; its JSON.
fn fit_schlick(file: &Path, pic: &Path, extra: &[&str]) -> (serde_json::Value, String) {
    let mut args = vec![
        "fit-measured",
        "--data",
        file.to_str().unwrap(),
        "--model",
        "cook-torrance",
        "--param",
        "f=schlick",
        "--param",
        "d=ggx",
        "--samples",
        "1500",
        "--restarts",
        "3",
        "--size",
        "16x16",
        "--spp",
        "1",
        "--json",
        "--out",
        pic.to_str().unwrap(),
    ];
    args.extend(extra);
    let o = fastbrdf(&args, "");
    assert!(o.status.success(), "{}", stderr(&o));
    (serde_json::from_slice(&o.stdout).unwrap(), stderr(&o))
}

/// Issue 27: on exact data made with f0 0.04 and rho_s 1 the fit returned f0 0.0316, f90
/// 0.791, rho_s 1.265 (f90 free: only the products are determined), without a word. f90 is now
/// held at 1 and f0, rho_s come back; `--free f90` fits it and says what is not determined.
#[test]
fn fit_measured_schlick_recovers_f0_and_reports_what_is_undetermined() {
    let d = temp_dir("measured-schlick");
    let f = d.join("ct.binary");
    let p = [
        ("f", "schlick"),
        ("d", "ggx"),
        ("alpha", "0.3"),
        ("f0", "0.04"),
    ];
    merl(&f, "cook-torrance", &p, [0.1, 0.05, 0.02], [1.0; 3]);
    let pic = d.join("fit.png");
    let (v, err) = fit_schlick(&f, &pic, &[]);
    let f0 = v["params"]["f0"].as_f64().unwrap();
    assert!((f0 - 0.04).abs() < 0.02 * 0.04, "{v}");
    assert!(v["params"].get("f90").is_none(), "{v}");
    assert_eq!(v["held"]["f90"], 1.0, "{v}");
    for c in 0..3 {
        let rho_s = v["rho_s"][c].as_f64().unwrap();
        assert!((rho_s - 1.0).abs() < 0.02, "{v}");
    }
    assert_eq!(v["undetermined"], serde_json::json!([]), "{v}");
    assert!(!err.contains("warning"), "{err}");
    // Asked for, f90 is fitted and the degeneracy is reported, in JSON and on stderr.
    let (v, err) = fit_schlick(&f, &pic, &["--free", "f90"]);
    assert!(v["params"]["f90"].is_number(), "{v}");
    assert_eq!(
        v["undetermined"],
        serde_json::json!(["f0", "f90", "rho_s"]),
        "{v}"
    );
    assert!(
        err.contains("warning: the data do not determine f0, f90 and rho_s separately"),
        "{err}"
    );
    // A name that is not a parameter to free is bad usage.
    let o = fastbrdf(
        &[
            "fit-measured",
            "--data",
            f.to_str().unwrap(),
            "--model",
            "cook-torrance",
            "--free",
            "bogus",
            "--out",
            pic.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("bogus"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 27 review: `--free NAME` was silently a no-op when NAME was already fitted, when the
/// model with the given choices does not read it (f = none, a conductor Fresnel), or when its
/// requirements do not hold: the user believed it fitted. Each is now bad usage naming it.
#[test]
fn fit_measured_free_that_changes_nothing_is_refused() {
    let d = temp_dir("measured-free-noop");
    let f = d.join("ct.binary");
    merl(&f, "cook-torrance", &[("f", "schlick")], [0.1; 3], [1.0; 3]);
    let pic = d.join("fit.png");
    let cases: &[(&[&str], &str, &str)] = &[
        (&["--param", "f=none"], "f90", "does not read f90"),
        (&["--param", "f=conductor"], "f90", "does not read f90"),
        (&["--param", "f=none"], "f0", "does not read f0"),
        (
            &["--param", "f=schlick"],
            "alpha",
            "alpha is fitted already",
        ),
        (
            &[
                "--param",
                "d=ggx",
                "--param",
                "g=smith-ggx-correlated",
                "--param",
                "ms=kulla-conty",
            ],
            "alpha_x",
            "alpha_x is not read with these choices (it needs",
        ),
    ];
    for (params, name, why) in cases {
        let mut args = vec![
            "fit-measured",
            "--data",
            f.to_str().unwrap(),
            "--model",
            "cook-torrance",
            "--samples",
            "300",
            "--restarts",
            "1",
            "--size",
            "8x8",
            "--spp",
            "1",
            "--out",
            pic.to_str().unwrap(),
        ];
        args.extend(*params);
        args.extend(["--free", name]);
        let o = fastbrdf(&args, "");
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{params:?} --free {name}: {e}");
        assert!(e.contains(&format!("--free {name}: ")), "{e}");
        assert!(
            e.contains(why),
            "{params:?} --free {name}: {e:?} should say {why:?}"
        );
        assert!(o.stdout.is_empty(), "{}", stdout(&o));
        assert!(!pic.exists(), "{params:?} --free {name} wrote {pic:?}");
    }
    let _ = std::fs::remove_dir_all(&d);
}
