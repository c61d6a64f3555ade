//! The sheen rows of the DFG ledger end to end: `fastbrdf errors --model sheen-albedo-*` prints
//! the row (JSON: albedo and furnace errors, where, means) within the documented ledger bound
//! (`fastbrdf::microfacet::sheen_albedo::LEDGER`) and not far below it; bad input is exit 2
//! with nothing on stdout, before any quadrature.

mod common;

use common::fastbrdf;
use fastbrdf::microfacet::sheen_albedo::LEDGER;

#[test]
fn errors_prints_the_sheen_row_within_its_bound() {
    let o = fastbrdf(&["errors", "--model", "sheen-albedo-khronos", "--json"], "");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["reference"], "sheen-albedo");
    assert_eq!(j["v"], "charlie");
    let max = j["albedo"]["max_abs"].as_f64().unwrap();
    let bound = LEDGER
        .iter()
        .find(|(id, _, v, _)| *id == "sheen-albedo-khronos" && *v == "charlie")
        .unwrap()
        .3;
    assert!(max <= bound && max > 0.9 * bound, "{max} vs {bound}");
    // The worst point is at grazing and the smallest slope; the mean is far below the max.
    assert!(j["albedo"]["cos_v"].as_f64().unwrap() < 0.01);
    assert!(j["albedo"]["alpha"].as_f64().unwrap() < 0.08);
    let mean = j["albedo"]["mean_abs"].as_f64().unwrap();
    assert!(mean > 0.0 && mean < 0.2 * max);
    // The fit underestimates E at grazing, so the base there is too bright: the furnace's
    // largest albedo exceeds 1 (the exact scaling's is 1, reached at grazing).
    let (gain, loss) = (
        j["furnace_gain"].as_f64().unwrap(),
        j["furnace_loss"].as_f64().unwrap(),
    );
    assert!(gain.max(loss) <= j["furnace"]["max_abs"].as_f64().unwrap() + 1e-12);
    assert!(j["furnace_peak"].as_f64().unwrap() > 1.0);
    assert!((j["furnace_peak_exact"].as_f64().unwrap() - 1.0).abs() < 1e-6);
}

#[test]
fn bad_sheen_rows_are_input_errors() {
    for (args, needle) in [
        (
            &["--model", "sheen-albedo-table", "--param", "bits=7"][..],
            "bits",
        ),
        (
            &["--model", "sheen-albedo-khronos", "--param", "v=ashikhmin"][..],
            "v=ashikhmin",
        ),
        (
            &["--model", "sheen-albedo-tuned", "--reference", "env-brdf"][..],
            "--reference env-brdf",
        ),
        (
            &["--model", "sheen-albedo-tuned", "--param", "size=32"][..],
            "size",
        ),
    ] {
        let o = fastbrdf(&[&["errors"], args].concat(), "");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}
