//! `fastbrdf lut` end to end: the CSV's texels are `fastbrdf eval`'s values at the same
//! (cos_v, alpha); EXR and PNG decode to the same table; the furnace anchor where a texel
//! centre lands on it; bad input is exit 2 with nothing written, a failed write exit 3 with
//! nothing left behind.

mod common;

use common::{fastbrdf, listing, temp_dir};
use std::path::Path;
use std::process::Command;

/// Runs `fastbrdf lut` with `args`; asserts success and an empty stdout.
fn lut(args: &[&str]) {
    let o = fastbrdf(&[&["lut"], args].concat(), "");
    assert!(
        o.status.success(),
        "lut {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.stdout.is_empty(), "lut writes nothing on stdout");
}

/// The CSV's rows as `[cos_v, roughness, alpha, scale, bias]`.
fn read_csv(path: &Path) -> Vec<[f32; 5]> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("cos_v,roughness,alpha,scale,bias"));
    lines
        .map(|l| {
            let v: Vec<f32> = l.split(',').map(|x| x.parse().unwrap()).collect();
            v.try_into().unwrap()
        })
        .collect()
}

/// `fastbrdf eval --model MODEL --param term=TERM` on the (cos_v, alpha) pairs.
fn eval(model: &str, term: &str, pts: &[(f32, f32)]) -> Vec<f32> {
    let mut input = String::from("cos_v,alpha\n");
    for (c, a) in pts {
        input += &format!("{c},{a}\n");
    }
    let term = format!("term={term}");
    let o = fastbrdf(&["eval", "--model", model, "--param", &term], &input);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect()
}

/// The batch kernel (fast math) and `eval`'s scalar model may round differently in the last
/// bits (2e-7 measured for env-brdf at N = 16).
const TOL: f32 = 1e-6;

fn check_against_eval(model: &str, rows: &[[f32; 5]]) {
    let pts: Vec<(f32, f32)> = rows.iter().map(|r| (r[0], r[2])).collect();
    for (term, col) in [("scale", 3), ("bias", 4)] {
        let want = eval(model, term, &pts);
        assert_eq!(want.len(), rows.len());
        for (r, w) in rows.iter().zip(&want) {
            assert!(
                (r[col] - w).abs() <= TOL,
                "{model} {term} at cos_v {}, alpha {}: lut {} eval {w}",
                r[0],
                r[2],
                r[col]
            );
        }
    }
}

#[test]
fn csv_texels_are_evals_at_texel_centres() {
    let d = temp_dir("csv");
    let n = 8;
    let out = d.join("dfg.csv");
    lut(&["--out", out.to_str().unwrap(), "--size", "8"]);
    let rows = read_csv(&out);
    assert_eq!(rows.len(), n * n);
    for (k, r) in rows.iter().enumerate() {
        let (j, i) = (k / n, k % n);
        let c = ((i as f64 + 0.5) / n as f64) as f32;
        let t = ((j as f64 + 0.5) / n as f64) as f32;
        assert_eq!(r[0], c, "cos_v of texel ({i}, {j})");
        assert_eq!(r[1], t, "roughness of texel ({i}, {j})");
        let alpha = ((t as f64 * t as f64) as f32).max(0.005);
        assert_eq!(r[2], alpha, "alpha of texel ({i}, {j})");
        // Split-sum terms: both in [0, 1], their sum the albedo, at most 1.
        assert!(r[3] >= 0.0 && r[4] >= 0.0 && r[3] + r[4] <= 1.0, "{r:?}");
    }
    // Row 0 (r = 1/16, r^2 < 0.005) is clamped; row 1 (r = 3/16) is not.
    assert_eq!(rows[0][2], 0.005);
    assert!(rows[n][2] > 0.005);
    check_against_eval("env-brdf", &rows);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn alpha_axis_and_other_models_match_eval() {
    let d = temp_dir("axis");
    let n = 6;
    let out = d.join("t.csv");
    lut(&[
        "--out",
        out.to_str().unwrap(),
        "--size",
        "6",
        "--axis",
        "alpha",
        "--model",
        "env-brdf-approx-tuned",
    ]);
    let rows = read_csv(&out);
    assert_eq!(rows.len(), n * n);
    for (k, r) in rows.iter().enumerate() {
        let t = ((k / n) as f64 + 0.5) / n as f64;
        assert_eq!(r[2], (t as f32).max(0.005));
        assert_eq!(r[1], t.sqrt() as f32, "the row's nominal r = sqrt(alpha)");
    }
    check_against_eval("env-brdf-approx-tuned", &rows);
    // --format wins over the extension.
    let out = d.join("t.txt");
    lut(&[
        "--out",
        out.to_str().unwrap(),
        "--size",
        "3",
        "--format",
        "csv",
        "--model",
        "env-brdf-approx",
    ]);
    check_against_eval("env-brdf-approx", &read_csv(&out));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn furnace_anchor_at_a_texel_centre() {
    // At N = 3 the middle texel is (cos_v, r) = (0.5, 0.5): single-scattering albedo 0.857
    // (three.js's published 0.86).
    let d = temp_dir("anchor");
    let out = d.join("a.csv");
    lut(&["--out", out.to_str().unwrap(), "--size", "3"]);
    let rows = read_csv(&out);
    let mid = rows[4];
    assert_eq!((mid[0], mid[1], mid[2]), (0.5, 0.5, 0.25));
    let albedo = mid[3] + mid[4];
    assert!((albedo - 0.857).abs() < 2e-3, "albedo {albedo}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn exr_and_png_decode_to_the_table() {
    let d = temp_dir("img");
    let n = 8;
    let (csv, exr, png) = (d.join("t.csv"), d.join("t.exr"), d.join("t.png"));
    for p in [&csv, &exr, &png] {
        lut(&["--out", p.to_str().unwrap(), "--size", "8"]);
    }
    let rows = read_csv(&csv);
    let img = image::open(&exr).unwrap();
    assert_eq!((img.width(), img.height()), (n as u32, n as u32));
    let f = img.to_rgb32f();
    let p16 = image::open(&png).unwrap();
    assert_eq!(p16.color(), image::ColorType::Rgb16, "16-bit RGB PNG");
    let p16 = p16.to_rgb16();
    assert_eq!((p16.width(), p16.height()), (n as u32, n as u32));
    let q = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u16;
    for (k, r) in rows.iter().enumerate() {
        // Image row 0 (the top) is table row 0, the smallest roughness.
        let (x, y) = ((k % n) as u32, (k / n) as u32);
        let e = f.get_pixel(x, y).0;
        assert_eq!(e, [r[3], r[4], 0.0], "EXR texel ({x}, {y})");
        let p = p16.get_pixel(x, y).0;
        assert_eq!(p, [q(r[3]), q(r[4]), 0], "PNG texel ({x}, {y})");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_input_is_exit_2_and_writes_nothing() {
    let d = temp_dir("bad");
    let path = |name: &str| d.join(name).to_str().unwrap().to_string();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--out".into(), path("a.csv"), "--size".into(), "0".into()],
            "--size 0",
        ),
        (
            vec![
                "--out".into(),
                path("a.csv"),
                "--size".into(),
                "4097".into(),
            ],
            "1 to 4096",
        ),
        (
            vec![
                "--out".into(),
                path("a.csv"),
                "--size".into(),
                "99999999999999999999".into(),
            ],
            "size",
        ),
        (vec!["--out".into(), path("a.txt")], ".exr, .png or .csv"),
        (vec!["--out".into(), path("noext")], ".exr, .png or .csv"),
        (
            vec![
                "--out".into(),
                path("a.csv"),
                "--format".into(),
                "tiff".into(),
            ],
            "tiff",
        ),
        (
            vec![
                "--out".into(),
                path("a.csv"),
                "--model".into(),
                "ggx".into(),
            ],
            "env",
        ),
        (
            vec![
                "--out".into(),
                path("a.csv"),
                "--model".into(),
                "nope".into(),
            ],
            "nope",
        ),
        (
            vec!["--out".into(), path("a.csv"), "--axis".into(), "r2".into()],
            "r2",
        ),
        // A folder where the file should go.
        (
            vec![
                "--out".into(),
                d.to_str().unwrap().into(),
                "--format".into(),
                "csv".into(),
                "--size".into(),
                "2".into(),
            ],
            "folder",
        ),
    ];
    for (args, needle) in cases {
        let args: Vec<&str> = std::iter::once("lut")
            .chain(args.iter().map(String::as_str))
            .collect();
        let o = fastbrdf(&args, "");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(o.stdout.is_empty(), "{args:?}: nothing on stdout");
        assert!(
            err.contains(needle),
            "{args:?}: '{err}' should name {needle}"
        );
        assert!(listing(&d).is_empty(), "{args:?} wrote {:?}", listing(&d));
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn failed_write_is_exit_3_and_leaves_nothing() {
    let d = temp_dir("io");
    let file = d.join("plain");
    std::fs::write(&file, "x").unwrap();
    // The output's folder is a file: the write fails after the table is computed.
    for name in ["t.csv", "t.exr", "t.png"] {
        let out = file.join(name);
        let o = fastbrdf(&["lut", "--out", out.to_str().unwrap(), "--size", "2"], "");
        assert_eq!(
            o.status.code(),
            Some(3),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(o.stdout.is_empty());
        assert_eq!(listing(&d), vec!["plain".to_string()]);
    }
    // A file-size limit (EFBIG) on a table larger than it: no partial file, no temporary.
    #[cfg(unix)]
    {
        let out = d.join("big.csv");
        let o = Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -f 1 && exec \"$0\" lut --out '{}' --size 64 --model env-brdf-approx",
                out.display()
            ))
            .arg(env!("CARGO_BIN_EXE_fastbrdf"))
            .output()
            .unwrap();
        assert_eq!(
            o.status.code(),
            Some(3),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert_eq!(listing(&d), vec!["plain".to_string()]);
    }
    let _ = std::fs::remove_dir_all(&d);
}
