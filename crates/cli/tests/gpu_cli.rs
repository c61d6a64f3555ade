//! The GPU-related commands end to end: `fastbrdf shader` (no GPU needed) and
//! `fastbrdf bench --gpu` (needs an adapter: skipped without one, a failure when `CI` is set).

mod common;
use common::have_gpu;

use common::{stderr, stdout, temp_dir};
use std::process::Output;

fn fastbrdf(args: &[&str]) -> Output {
    common::fastbrdf(args, "")
}

#[test]
fn shader_prints_every_language_and_matches_the_library() {
    for lang in ["wgsl", "glsl", "hlsl", "msl", "brdf-explorer"] {
        let o = fastbrdf(&[
            "shader",
            "--model",
            "flog-normalized",
            "--param",
            "n=100",
            "--lang",
            lang,
        ]);
        assert!(o.status.success(), "{lang}: {}", stderr(&o));
        let text = stdout(&o);
        let want = fastbrdf_gpu::export::export(
            &fastbrdf::ModelSpec::parse("flog-normalized", &[("n", "100")]).unwrap(),
            fastbrdf_gpu::export::Lang::parse(lang).unwrap(),
        )
        .unwrap();
        assert_eq!(text, want, "{lang}");
        assert!(text.contains("n = 100"), "{lang}");
    }
    // Default language is WGSL.
    let o = fastbrdf(&["shader", "--model", "pow"]);
    assert!(stdout(&o).contains("fn fb_pow(c: f32) -> f32"));
}

#[test]
fn shader_runtime_params_takes_the_parameters_as_arguments() {
    use fastbrdf_gpu::export::{Form, Lang, export_form};
    for lang in ["wgsl", "glsl", "hlsl", "msl"] {
        let o = fastbrdf(&[
            "shader",
            "--model",
            "cubic",
            "--lang",
            lang,
            "--runtime-params",
        ]);
        assert!(o.status.success(), "{lang}: {}", stderr(&o));
        let cubic = fastbrdf::ModelSpec::parse("cubic", &[]).unwrap();
        let want = export_form(&cubic, Lang::parse(lang).unwrap(), Form::Runtime).unwrap();
        assert_eq!(stdout(&o), want, "{lang}");
    }
    let o = fastbrdf(&["shader", "--model", "cubic", "--runtime-params"]);
    assert!(
        stdout(&o).contains("fn fb_cubic(c: f32, p_n: f32) -> f32"),
        "{}",
        stdout(&o)
    );
    // Every model, every file or none.
    let dir = temp_dir("runtime-all");
    let o = fastbrdf(&[
        "shader",
        "--all",
        "--runtime-params",
        "--lang",
        "glsl",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let n = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(n, fastbrdf::registry::all().len());
    let _ = std::fs::remove_dir_all(&dir);
    // Bad input in the runtime form: exit 2, nothing on stdout, no file left behind.
    let bad_dir = temp_dir("runtime-bad");
    let out = bad_dir.join("x.glsl");
    for bad in [
        vec!["--model", "cubic", "--param", "n=nan"],
        vec!["--model", "cubic", "--param", "n=1e9"],
        vec!["--model", "no-such-model"],
        vec!["--model", "cubic", "--param", "alpha=0.3"],
    ] {
        let mut args = vec!["shader", "--runtime-params", "--lang", "glsl"];
        args.extend(bad.iter().copied());
        args.extend(["--out", out.to_str().unwrap()]);
        let o = fastbrdf(&args);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{bad:?}");
        assert!(!out.exists(), "{bad:?}: a file was left");
    }
}

#[test]
fn shader_writes_files_and_rejects_bad_input_without_writing() {
    let dir = temp_dir("shader");
    let out = dir.join("ct.hlsl");
    let o = fastbrdf(&[
        "shader",
        "--model",
        "cook-torrance",
        "--param",
        "f=schlick",
        "--lang",
        "hlsl",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).is_empty());
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .contains("float fb_cook_torrance(")
    );

    let all = dir.join("all");
    let o = fastbrdf(&[
        "shader",
        "--all",
        "--lang",
        "glsl",
        "--out",
        all.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let n = std::fs::read_dir(&all).unwrap().count();
    assert_eq!(n, fastbrdf::registry::all().len());

    let bad = dir.join("bad.glsl");
    for args in [
        vec!["shader", "--model", "nope", "--lang", "glsl"],
        vec![
            "shader", "--model", "pow", "--param", "n=-3", "--lang", "glsl",
        ],
        vec!["shader", "--model", "pow", "--param", "n", "--lang", "glsl"],
        vec!["shader", "--model", "pow", "--lang", "cuda"],
        vec![
            "shader", "--model", "beckmann", "--param", "alpha=0", "--lang", "glsl",
        ],
        vec!["shader", "--all", "--param", "n=3", "--lang", "glsl"],
    ] {
        let mut a = args.clone();
        a.extend(["--out", bad.to_str().unwrap()]);
        let o = fastbrdf(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stdout(&o).is_empty(), "{args:?}");
        assert!(!bad.exists(), "{args:?} wrote a file");
        assert!(
            stderr(&o).starts_with("error:") || stderr(&o).contains("error"),
            "{args:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `fastbrdf bench --gpu --quick --json --models MODELS --large LARGE`, which must succeed,
/// and its JSON.
fn bench_gpu(models: &str, large: &str) -> (Output, serde_json::Value) {
    let o = fastbrdf(&[
        "bench", "--gpu", "--quick", "--json", "--models", models, "--large", large,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let j = serde_json::from_slice(&o.stdout).unwrap();
    (o, j)
}

#[test]
fn bench_gpu_adds_labelled_gpu_rows_to_the_cpu_run() {
    if !have_gpu() {
        return;
    }
    let (_, j) = bench_gpu("power16,ward", "65536");
    let label = j["gpu"].as_str().expect("the adapter is named");
    let rows = j["kernels"].as_array().unwrap();
    for m in ["power16", "ward"] {
        for v in ["gpu", "gpu+transfer", "simd"] {
            let r = rows
                .iter()
                .find(|r| r["model"] == m && r["variant"] == v)
                .unwrap_or_else(|| panic!("no {m} {v} row"));
            assert!(r["evals_per_s"].as_f64().unwrap() > 0.0);
        }
    }
    let names: Vec<&str> = j["speedups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"ward.gpu.over.cpu-threads"), "{names:?}");
    if label.contains("llvmpipe") || label.contains("lavapipe") {
        assert!(label.contains("CPU figures"), "{label}");
    }
    // --gpu and --from do not mix.
    let o = fastbrdf(&["bench", "--gpu", "--from", "x.json"]);
    assert_eq!(o.status.code(), Some(2));
}

/// A model whose GPU dispatch is projected (from 65536 elements) to take over 3 s gets
/// `skipped` entries instead of rows: the quadrature reference `sheen-albedo` on lavapipe
/// (about 20 s per 4M-element dispatch, and timing takes seven). Before, `bench --gpu` spent
/// minutes on it there. On a real GPU it is timed, and its rows must then be there.
#[test]
fn bench_gpu_leaves_out_a_model_too_slow_to_time() {
    if !have_gpu() {
        return;
    }
    let (o, j) = bench_gpu("sheen-albedo", "4194304");
    let label = j["gpu"].as_str().unwrap();
    let skipped = j["skipped"].as_array().unwrap();
    let rows = j["kernels"].as_array().unwrap();
    for v in ["gpu", "gpu+transfer"] {
        let s = skipped
            .iter()
            .find(|s| s["model"] == "sheen-albedo" && s["variant"] == v);
        let row = rows
            .iter()
            .find(|r| r["model"] == "sheen-albedo" && r["variant"] == v);
        // Exactly one of the two, for each variant.
        assert!(s.is_some() != row.is_some(), "{v}: {s:?} {row:?}");
        if let Some(s) = s {
            assert_eq!(s["batch"], 4194304);
            assert!(s["projected_s"].as_f64().unwrap() > 3.0, "{s}");
        }
        if label.contains("llvmpipe") {
            assert!(s.is_some(), "{label}: sheen-albedo {v} was timed");
        }
    }
    if label.contains("llvmpipe") {
        assert!(
            stderr(&o).contains("GPU figures are left out"),
            "{}",
            stderr(&o)
        );
    }
}

#[test]
fn render_gpu_matches_the_cpu_render_and_rejects_bad_input() {
    if !have_gpu() {
        return;
    }
    let dir = temp_dir("render");
    let (cpu, gpu) = (dir.join("cpu.png"), dir.join("gpu.png"));
    let args = [
        "--model", "flog", "--param", "n=50", "--size", "64x48", "--spp", "2", "--floor",
    ];
    // The CPU on the axis-aligned grid the GPU rasterises (adaptive antialiasing refines
    // outlines further, on a rotated grid).
    let o = fastbrdf(
        &[
            &["render", "--aa", "grid"],
            &args[..],
            &["--out", cpu.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = fastbrdf(
        &[
            &["render", "--gpu"],
            &args[..],
            &["--out", gpu.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("GPU: "),
        "the adapter is named: {}",
        stderr(&o)
    );
    // The set-up (device, pipelines) and the draws are timed apart: two numbers whose sum is
    // at most the render's time (tools/equal_error.py reads the draws').
    let err = stderr(&o);
    let number = |key: &str| -> f64 {
        let at = err
            .find(key)
            .unwrap_or_else(|| panic!("no '{key}' in: {err}"))
            + key.len();
        err[at..].split(' ').next().unwrap().parse().unwrap()
    };
    let (setup, draws, render) = (number("set-up "), number("draws "), number("render "));
    assert!(
        setup >= 0.0 && draws > 0.0 && setup + draws <= render + 0.002,
        "{err}"
    );
    // Shadows on both (the default, the floor catching the sphere's): no note any more.
    assert!(!stderr(&o).contains("shadows"), "{}", stderr(&o));
    // `--repeat 3` on one device: the later renders' draws in brackets after the first's, and
    // the same picture.
    let again = dir.join("gpu3.png");
    let o = fastbrdf(
        &[
            &["render", "--gpu", "--repeat", "3"],
            &args[..],
            &["--out", again.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    for key in ["render ", "draws "] {
        let (secs, tail) = common::then_times(&err, key)
            .unwrap_or_else(|| panic!("no '{key}X s (then ' in {err}"));
        assert_eq!(tail, "--repeat 3", "{err}");
        assert!(secs.len() == 2 && secs.iter().all(|&s| s > 0.0), "{err}");
    }
    assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&gpu).unwrap());
    let a = image::open(&cpu).unwrap().to_rgb8();
    let b = image::open(&gpu).unwrap().to_rgb8();
    assert_eq!(a.dimensions(), (64, 48));
    assert_eq!(a.dimensions(), b.dimensions());
    let max = a
        .as_raw()
        .iter()
        .zip(b.as_raw())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap();
    assert!(max <= 2, "GPU and CPU PNGs differ by {max}/255");

    let bad = dir.join("bad.png");
    for extra in [
        vec!["--size", "100000x100000"],
        vec!["--size", "0x10"],
        vec!["--model", "nope"],
        vec!["--spp", "17"],
        vec!["--texture", "/nonexistent/skin.png"],
    ] {
        let mut a = vec![
            "render",
            "--gpu",
            "--model",
            "pow",
            "--out",
            bad.to_str().unwrap(),
        ];
        a.extend(extra.iter());
        let o = fastbrdf(&a);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(!bad.exists(), "{extra:?} left a file");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn readme_gpu_table_is_the_saved_run() {
    let bench = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/bench/bench-gpu.json"
    );
    let o = fastbrdf(&["bench", "--from", bench, "--gpu-only", "--markdown"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let md = stdout(&o);
    assert!(
        md.contains("software adapter") || md.contains("GPU"),
        "{md}"
    );
    // The book's copy (docs/book/src/gpu.md): tests/docs.rs, generated_gpu_bench_tables_are_the_saved_run.
    // A run without GPU figures cannot print GPU tables.
    let cpu = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let o = fastbrdf(&["bench", "--from", cpu, "--gpu-only"]);
    assert_eq!(o.status.code(), Some(2));
}
