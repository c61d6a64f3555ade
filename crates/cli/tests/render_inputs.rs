//! End-to-end tests of `render`, `compare` and `demo` on hostile inputs (issue 11): every bad
//! input gives exit code 2, a message naming the file (and line), nothing on stdout and no
//! file; inputs are read once (pipes work); write failures give exit code 3 and leave nothing.

mod common;

use common::{TempDir, listing, temp_dir};
use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_fastbrdf");

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// Runs `fastbrdf ARGS` through bash with SIGXFSZ ignored and a file-size limit of `kib` KiB,
/// so that a write fails with EFBIG (a full disk) instead of killing the process.
fn run_limited(kib: u32, args: &[&str]) -> Output {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    Command::new("bash")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f {kib}; exec '{BIN}' {}",
            quoted.join(" ")
        ))
        .output()
        .unwrap()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh folder for one test (removed when it passes, kept and named when it fails).
fn dir(name: &str) -> TempDir {
    temp_dir(&format!("render-inputs-{name}"))
}

fn face() -> String {
    concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../render/data/canonical_face_model.obj"
    )
    .into()
}

/// Bad input: exit 2, the message, nothing on stdout, no output file.
fn refused(o: &Output, out: &Path, expect: &str) {
    assert_eq!(o.status.code(), Some(2), "{}", err(o));
    assert!(
        err(o).contains(expect),
        "{:?} should contain {expect:?}",
        err(o)
    );
    assert!(o.stdout.is_empty());
    assert!(!out.exists());
}

const BAD: &[(&[u8], &str)] = &[
    (
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 nan\nf 1/1 2/1 3/1\n",
        "bad.obj:4: |(column 8)",
    ),
    (
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
        "bad.obj:4: |(column 7)",
    ),
    (
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "bad.obj:4: |(column 3)",
    ),
    (
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1 2/1 3\n",
        "bad.obj:5: |(column 5)",
    ),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "bad.obj:4:"),
    (b"v 0 0 0\nv 1 0\n", "bad.obj:2:"),
    (
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\xff\n",
        "bad.obj: line 4, column 1: not UTF-8",
    ),
];

#[test]
fn bad_meshes_exit_2_with_file_line_and_column() {
    let d = dir("bad");
    let obj = d.join("bad.obj");
    let tex = d.join("tex.png");
    image::RgbImage::from_pixel(4, 4, image::Rgb([200, 100, 50]))
        .save(&tex)
        .unwrap();
    let out = d.join("out.png");
    for (text, expect) in BAD {
        std::fs::write(&obj, text).unwrap();
        let o = run(&[
            "render",
            "--model",
            "flog",
            "--param",
            "n=50",
            "--size",
            "16x16",
            "--mesh",
            obj.to_str().unwrap(),
            "--texture",
            tex.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        // "FILE:LINE: |(column COL)": the file and line first, the column in the message.
        let (head, col) = expect.split_once('|').unwrap_or((expect, ""));
        refused(&o, &out, &format!("{}", d.join(head).display()));
        assert!(err(&o).contains(col), "{}", err(&o));
    }
    assert_eq!(listing(&d), ["bad.obj", "tex.png"]);
}

#[test]
fn valid_obj_forms_render() {
    let d = dir("good");
    let obj = d.join("good.obj");
    let out = d.join("out.png");
    for text in [
        "mtllib /dev/zero\no a\ng b\ns 1\nusemtl m\nv 0.1 0.2 0.3 # note\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1 # face\n",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf -4//-1 -3//-1 -2//-1 -1//-1\n",
    ] {
        std::fs::write(&obj, text).unwrap();
        let o = run(&[
            "render",
            "--model",
            "flog",
            "--param",
            "n=50",
            "--size",
            "16x16",
            "--mesh",
            obj.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{text:?}: {}", err(&o));
        assert!(out.exists());
        std::fs::remove_file(&out).unwrap();
    }
}

#[test]
fn a_mesh_from_a_pipe_or_a_fifo_is_read_once() {
    let d = dir("pipe");
    let out = d.join("out.png");
    let o = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "exec '{BIN}' render --model flog --param n=50 --size 16x16 --mesh <(cat '{}') --out '{}'",
            face(),
            out.display()
        ))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(out.exists());
    std::fs::remove_file(&out).unwrap();
    let fifo = d.join("face.fifo");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(&fifo, std::fs::read(face()).unwrap()).unwrap())
    };
    let o = run(&[
        "render",
        "--model",
        "flog",
        "--param",
        "n=50",
        "--size",
        "16x16",
        "--mesh",
        fifo.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    writer.join().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(out.exists());
}

#[test]
fn unbounded_inputs_are_refused_with_a_clear_message() {
    let d = dir("unbounded");
    let out = d.join("out.png");
    let o = run(&[
        "render",
        "--model",
        "flog",
        "--size",
        "16x16",
        "--mesh",
        "/dev/zero",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(
        &o,
        &out,
        "/dev/zero: larger than the 256 MiB allowed for an OBJ mesh",
    );
    // A PNG header declaring 20000x20000 pixels: refused before decoding.
    let tex = d.join("huge.png");
    // 65 bytes whose header declares 20000x20000 RGB pixels (made and checked by
    // crates/render/tests/inputs.rs).
    let png = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../render/tests/data/declares-20000x20000.png"
    ))
    .unwrap();
    std::fs::write(&tex, &png).unwrap();
    let o = run(&[
        "render",
        "--model",
        "flog",
        "--size",
        "16x16",
        "--mesh",
        &face(),
        "--texture",
        tex.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&o, &out, "declares 20000x20000 pixels");
}

#[test]
fn options_that_cannot_render_finitely_are_refused() {
    let d = dir("finite");
    let out = d.join("out.exr");
    for (opt, val, expect) in [
        ("--light", "dir:0,0,1:3e38,3e38,3e38:3e38", "at most 1e6"),
        ("--light", "point:0,0,3:1,1,1:1e30", "at most 1e6"),
        ("--weights", "0.6,3e38", "0 to 1000"),
        ("--albedo", "1e30,1,1", "0 to 1000"),
        ("--exposure", "3e38", "at most 1000000"),
        ("--bump", "1e30,0.5", "--bump"),
        ("--bump", "40,1e30", "--bump"),
    ] {
        let o = run(&[
            "render",
            "--model",
            "flog",
            "--size",
            "16x16",
            opt,
            val,
            "--out",
            out.to_str().unwrap(),
        ]);
        refused(&o, &out, expect);
    }
    // A model whose value overflows f32 is caught by the film check: no file.
    let o = run(&[
        "render",
        "--model",
        "cook-torrance",
        "--param",
        "alpha=1e-30",
        "--size",
        "16x16",
        "--out",
        out.to_str().unwrap(),
    ]);
    if o.status.code() != Some(0) {
        assert!(!out.exists());
        assert!(o.stdout.is_empty());
    }
}

#[test]
fn compare_caps_the_whole_grid_and_work_before_rendering() {
    let d = dir("cap");
    let out = d.join("cmp.png");
    let models = vec!["flog"; 30].join(",");
    let t0 = std::time::Instant::now();
    let o = run(&[
        "compare",
        "--models",
        &models,
        "--reference",
        "pow",
        "--param",
        "n=50",
        "--size",
        "8192x1",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&o, &out, "the comparison picture would be");
    let o = run(&[
        "compare",
        "--models",
        "flog,schlick",
        "--reference",
        "pow",
        "--param",
        "n=50",
        "--size",
        "2048x2048",
        "--spp",
        "16",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused(&o, &out, "samples");
    assert!(
        t0.elapsed().as_secs_f64() < 10.0,
        "refused before rendering"
    );
}

#[test]
fn compare_reports_linear_metrics_that_see_the_highlight() {
    let d = dir("linear");
    let out = d.join("cmp.png");
    let o = run(&[
        "compare",
        "--models",
        "rational,cubic-rational",
        "--reference",
        "pow",
        "--param",
        "n=100",
        "--size",
        "96x96",
        "--spp",
        "1",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = v["metrics"].as_array().unwrap();
    let f = |i: usize, k: &str| m[i][k].as_f64().unwrap_or_else(|| panic!("{k}: a number"));
    for k in [
        "rmse",
        "flip",
        "rmse_linear",
        "psnr_linear",
        "psnr_linear_peak",
        "flip_reinhard",
    ] {
        f(0, k);
    }
    assert!(f(0, "rmse_linear") > 1.1 * f(1, "rmse_linear"), "{v}");
    assert!(f(0, "psnr_linear_peak") > 1.0);
}

#[test]
fn exr_holds_linear_radiance_whatever_the_exposure() {
    let d = dir("exr");
    let (a, b) = (d.join("a.exr"), d.join("b.exr"));
    for (out, e) in [(&a, "1"), (&b, "4")] {
        let o = run(&[
            "render",
            "--model",
            "flog",
            "--size",
            "16x16",
            "--exposure",
            e,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn a_failed_write_exits_3_and_leaves_nothing() {
    let d = dir("full");
    let out = d.join("out.png");
    let o = run_limited(
        1,
        &[
            "render",
            "--model",
            "flog",
            "--param",
            "n=50",
            "--size",
            "256x256",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(3), "{}", err(&o));
    assert!(err(&o).contains("out.png"), "{}", err(&o));
    assert!(listing(&d).is_empty(), "{:?}", listing(&d));
    let o = run_limited(
        1,
        &[
            "compare",
            "--models",
            "flog",
            "--reference",
            "pow",
            "--param",
            "n=50",
            "--size",
            "128x128",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(3), "{}", err(&o));
    assert!(listing(&d).is_empty(), "{:?}", listing(&d));
}

#[test]
fn demo_checks_the_mesh_before_writing_and_writes_all_or_nothing() {
    let d = dir("demo");
    let bad = d.join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let out = d.join("demo-out");
    let o = run(&[
        "demo",
        "--size",
        "64",
        "--mesh",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(
        err(&o).contains("bad.obj:4: face: vertex index 9 is out of range"),
        "{}",
        err(&o)
    );
    assert!(err(&o).contains("(column 7)"), "{}", err(&o));
    assert!(!out.exists(), "nothing written");
    // A write that fails part-way: exit 3, no folder, no staging left.
    let o = run_limited(4, &["demo", "--size", "64", "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3), "{}", err(&o));
    assert!(!out.exists(), "nothing written");
    assert_eq!(listing(&d), ["bad.obj"]);
}

#[test]
fn builtin_face_and_skin_by_name_and_files_of_those_names_by_path() {
    let d = dir("builtin");
    // A file named `face` in the working directory: `face` is still the built-in (with a note),
    // `./face` reads the file.
    std::fs::write(d.join("face"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let in_dir = |args: &[&str]| {
        Command::new(BIN)
            .current_dir(&*d)
            .args(args)
            .output()
            .unwrap()
    };
    let o = in_dir(&[
        "render",
        "--model",
        "ward",
        "--param",
        "alpha=0.35",
        "--mesh",
        "face",
        "--texture",
        "skin",
        "--env",
        "sky",
        "--env-samples",
        "2",
        "--size",
        "48x48",
        "--spp",
        "1",
        "--out",
        "face.png",
    ]);
    assert!(o.status.success(), "{}", err(&o));
    assert!(
        err(&o).contains("note: --mesh face is the embedded face") && err(&o).contains("./face"),
        "{}",
        err(&o)
    );
    let png = image::open(d.join("face.png")).unwrap().to_rgb8();
    let c = png.get_pixel(24, 24);
    assert!(c[0] > c[2] && c[0] > 40, "skin at the centre: {c:?}");
    let o = in_dir(&[
        "render", "--model", "ward", "--mesh", "./face", "--size", "48x48", "--out", "f2.png",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("face:2"), "{}", err(&o));
    // `./skin` is a file too: none here.
    let o = in_dir(&[
        "render",
        "--model",
        "ward",
        "--texture",
        "./skin",
        "--size",
        "48x48",
        "--out",
        "f3.png",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("./skin"), "{}", err(&o));
    assert_eq!(listing(&d), ["face", "face.png"]);
}
