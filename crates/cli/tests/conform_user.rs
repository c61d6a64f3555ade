//! `fastbrdf conform file:PATH` on users' shaders (issue 31): each deliberately broken model of
//! `crates/gpu/tests/data/user/` (three as BRDF Explorer files, three as WGSL functions that
//! sample, one more of each) fails exactly the check it breaks; a correct sampled WGSL model
//! passes every check; every BRDF Explorer sample file runs through every check. On the GPU
//! (lavapipe in CI): skipped without an adapter, a failure when `CI` is set.

mod common;
use common::gpu_data as data;
use common::have_gpu;

use common::stderr;

/// The record of `fastbrdf conform file:PATH --json` and its exit code.
fn conform(rel: &str) -> (serde_json::Value, Option<i32>) {
    let model = format!("file:{}", data(rel));
    let o = common::fastbrdf(&["conform", &model, "--json"], "");
    let j =
        serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{rel}: {e}: {}", stderr(&o)));
    (j, o.status.code())
}

fn failed(j: &serde_json::Value) -> Vec<String> {
    j["checks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["status"] == "fail")
        .map(|c| c["check"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn each_broken_shader_fails_exactly_the_check_it_breaks() {
    if !have_gpu() {
        return;
    }
    for (file, check) in [
        ("user/broken_pdf_scaled.wgsl", "pdf-integral"),
        ("user/broken_weight_no_cosine.wgsl", "weight"),
        ("user/broken_nonreciprocal.brdf", "reciprocity"),
        ("user/broken_energy_gain.brdf", "energy"),
        ("user/broken_nan_grazing.brdf", "finite"),
        ("user/broken_negative_lobe.brdf", "non-negative"),
        ("user/broken_pdf_zero.wgsl", "pdf-coverage"),
    ] {
        let (j, code) = conform(file);
        assert_eq!(failed(&j), [check], "{file}: {j}");
        assert_eq!(code, Some(1), "{file}");
        assert_eq!(j["passed"], false);
    }
}

#[test]
fn a_correct_sampled_shader_passes_every_check() {
    if !have_gpu() {
        return;
    }
    let (j, code) = conform("user/ggx_sampled.wgsl");
    assert_eq!(code, Some(0), "{j}");
    let run: Vec<&str> = j["checks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["status"] == "pass")
        .map(|c| c["check"].as_str().unwrap())
        .collect();
    // Everything but `reference` ran (none was given), the sampling checks included.
    assert_eq!(run.len(), 10, "{j}");
    assert!(run.contains(&"chi2") && run.contains(&"pdf-sample"), "{j}");
}

#[test]
fn every_brdf_explorer_sample_runs_through_every_check() {
    if !have_gpu() {
        return;
    }
    let dir = data("brdf-explorer");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".brdf"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 31);
    for f in &files {
        let (j, code) = conform(&format!("brdf-explorer/{f}"));
        // A verdict (0 or 1) with every value-based check run, never an evaluator failure.
        assert!(matches!(code, Some(0 | 1)), "{f}: {code:?}");
        for c in j["checks"].as_array().unwrap().iter().take(5) {
            assert_ne!(c["status"], "skip", "{f}: {c}");
        }
    }
    // What the checks find in two of them: walter.brdf divides 0 by 0 on the horizon.
    let (j, _) = conform("brdf-explorer/walter.brdf");
    assert!(failed(&j).contains(&"finite".to_string()), "{j}");
    let (j, _) = conform("brdf-explorer/lambert.brdf");
    assert!(!failed(&j).contains(&"energy".to_string()), "{j}");
}
