//! `render`, `compare` and `demo` end to end: bad input is exit 2 and leaves no file; PNG and
//! EXR outputs and the comparison's metrics; every demo picture and its index.

mod common;

use common::{fastbrdf, stderr, temp_dir};

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
            vec!["render", "--model", "pow", "--repeat", "0", "--out", o],
            "invalid value '0' for '--repeat <N>'".into(),
        ),
        (
            vec!["render", "--model", "pow", "--repeat", "101", "--out", o],
            "invalid value '101' for '--repeat <N>'".into(),
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

/// `--repeat N` renders N times, reports the later renders' times apart from the first's and
/// writes the same picture as one render.
#[test]
fn render_repeat_times_each_render_and_writes_the_same_picture() {
    let d = temp_dir("render-repeat");
    let mut files = Vec::new();
    for repeat in ["1", "3"] {
        let out = d.join(format!("r{repeat}.exr"));
        let r = fastbrdf(
            &[
                "render",
                "--model",
                "ggx",
                "--mesh",
                "face",
                "--size",
                "40x30",
                "--spp",
                "2",
                "--repeat",
                repeat,
                "--out",
                out.to_str().unwrap(),
            ],
            "",
        );
        assert!(r.status.success(), "{}", stderr(&r));
        let e = stderr(&r);
        let then = common::then_times(&e, "render ");
        match repeat {
            "1" => assert!(then.is_none() && !e.contains("(then "), "{e}"),
            _ => {
                let (secs, tail) = then.unwrap_or_else(|| panic!("no 'render X s (then ' in {e}"));
                assert_eq!(tail, "--repeat 3", "{e}");
                assert_eq!(secs.len(), 2, "{e}");
                assert!(secs.iter().all(|&s| s > 0.0 && s < 60.0), "{e}");
            }
        }
        files.push(std::fs::read(&out).unwrap());
    }
    assert!(files[0] == files[1], "--repeat changed the picture");
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
        "gltf-scene.png",
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
    // The built-in glTF scene: the writer's bytes (tests/gltf_validator.rs validates them).
    let glb = std::fs::read(d.join("scene.glb")).unwrap();
    assert_eq!(glb, fastbrdf_render::gltf_write::demo_scene());
    assert!(html.contains("href=\"scene.glb\""));
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
