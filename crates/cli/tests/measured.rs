//! `fastbrdf measured info|eval` end to end on a synthetic MERL file (a constant per channel,
//! missing where theta_d > 45 degrees), and bad files: exit 2 naming the file, nothing on
//! stdout.

mod common;

use common::{fastbrdf, stderr, stdout, temp_dir};
use fastbrdf::measured;
use std::path::{Path, PathBuf};

fn synthetic(dir: &Path) -> PathBuf {
    let p = dir.join("flat.binary");
    measured::write_merl(&p, |_, td, _| {
        if td > std::f64::consts::FRAC_PI_4 {
            [-1.0; 3]
        } else {
            [0.5, 0.25, 0.125]
        }
    })
    .unwrap();
    p
}

#[test]
fn info_and_eval() {
    let dir = temp_dir("measured");
    let p = synthetic(&dir);
    let f = p.to_str().unwrap();

    let o = fastbrdf(&["measured", "info", f], "");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(s.contains("90 x 90 x 180") && s.contains("729000"), "{s}");

    let o = fastbrdf(&["measured", "info", f, "--json"], "");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["dims"], serde_json::json!([90, 90, 180]));
    let ch = &v["channels"];
    assert_eq!(ch[0]["channel"], "red");
    assert_eq!(ch[1]["missing"], 729000);
    assert!((ch[2]["mean"].as_f64().unwrap() - 0.125).abs() < 1e-12);
    assert!((ch[0]["max"].as_f64().unwrap() - 0.5).abs() < 1e-12);

    // Normal incidence and a 60-degree pair (theta_d = 30 degrees: valid), one with
    // theta_d = 60 degrees (missing: 0), one below the horizon (0); the extra column passes.
    let input = "id,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n\
                 a,0,0,1,0,0,1\n\
                 b,0,0,2,0.866025,0,0.5\n\
                 c,0.866025,0,0.5,-0.866025,0,0.5\n\
                 d,0,0,1,0,0,-1\n";
    for precision in ["f32", "f64"] {
        let o = fastbrdf(&["measured", "eval", f, "--precision", precision], input);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let s = stdout(&o);
        let rows: Vec<&str> = s.lines().collect();
        assert_eq!(
            rows[0],
            "id,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,value_r,value_g,value_b"
        );
        assert_eq!(rows[1], "a,0,0,1,0,0,1,0.5,0.25,0.125");
        assert!(rows[2].ends_with(",0.5,0.25,0.125"), "{}", rows[2]);
        assert!(rows[3].ends_with(",0,0,0"), "{}", rows[3]);
        assert!(rows[4].ends_with(",0,0,0"), "{}", rows[4]);
    }
    // --input FILE reads the same.
    let csv = dir.join("in.csv");
    std::fs::write(&csv, input).unwrap();
    let o = fastbrdf(
        &["measured", "eval", f, "--input", csv.to_str().unwrap()],
        "",
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));

    // Bad CSV: missing column, a non-number, an output column already there.
    for (bad, want) in [
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y\n0,0,1,0,0\n",
            "missing column 'wo_z'",
        ),
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,zz,1\n",
            "line 2, field 5 ('wo_y')",
        ),
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,NaN,0,0,1\n",
            "not a finite number",
        ),
        (
            "value_r,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n1,0,0,1,0,0,1\n",
            "already has a 'value_r'",
        ),
    ] {
        let o = fastbrdf(&["measured", "eval", f], bad);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(o.stdout.is_empty());
        assert!(stderr(&o).contains(want), "{}", stderr(&o));
        assert!(stderr(&o).contains("<stdin>"), "{}", stderr(&o));
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_files_exit_2_naming_the_file() {
    let dir = temp_dir("measured-bad");
    let header = |d: [i32; 3]| -> Vec<u8> { d.iter().flat_map(|x| x.to_le_bytes()).collect() };
    let good = measured::merl_bytes(|_, _, _| [1.0; 3]);
    let mut nan = good.clone();
    nan[12 + 8 * 7..12 + 8 * 8].copy_from_slice(&f64::NAN.to_le_bytes());
    let mut long = good.clone();
    long.push(0);
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty.binary", vec![], "only 0 bytes"),
        ("short.binary", good[..1000].to_vec(), "1000 bytes"),
        ("long.binary", long, "more than that"),
        (
            "dims.binary",
            header([90, 90, 360]),
            "dimensions 90 x 90 x 360",
        ),
        ("neg.binary", header([-1, 90, 180]), "negative dimension"),
        (
            "huge.binary",
            header([2048, 1024, 128]),
            "dimensions 2048 x 1024 x 128",
        ),
        ("nan.binary", nan, "red channel, sample 7 "),
    ];
    for (name, bytes, want) in cases {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        for args in [
            vec!["measured", "info", p.to_str().unwrap()],
            vec!["measured", "eval", p.to_str().unwrap()],
        ] {
            let o = fastbrdf(&args, "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,1\n");
            assert_eq!(o.status.code(), Some(2), "{name}");
            assert!(o.stdout.is_empty(), "{name}");
            let e = stderr(&o);
            assert!(
                e.contains(p.to_str().unwrap()) && e.contains(want),
                "{name}: {e}"
            );
        }
    }
    let o = fastbrdf(
        &[
            "measured",
            "info",
            dir.join("none.binary").to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("none.binary"));
    let _ = std::fs::remove_dir_all(dir);
}
