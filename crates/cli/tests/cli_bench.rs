//! `bench` end to end: the saved run's JSON shape, `--compare`, the peers (the book's tables: docs.rs)
//! from the saved run, and saved runs read with a bound and refused when impossible.

mod common;

use common::{fastbrdf, stderr, stdout, temp_dir};

#[test]
fn bench_json_has_the_documented_shape_and_round_trips() {
    let o = fastbrdf(
        &[
            "bench",
            "--quick",
            "--models",
            "pow,power16,schlick,ward,ward-power16,cook-torrance",
            "--large",
            "4096",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for key in ["cpu", "isa", "fma_per_s", "kernels", "speedups"] {
        assert!(!v[key].is_null(), "no {key}");
    }
    assert!(v["fma_per_s"].as_f64().unwrap() > 0.0);
    assert!(v["div_per_s"].as_f64().unwrap() > 0.0);
    let kernels = v["kernels"].as_array().unwrap();
    // Each one-thread SIMD row names the limit it is held against, as a number.
    let limit = |m: &str| {
        let k = kernels
            .iter()
            .find(|k| k["model"] == m && k["variant"] == "simd" && k["batch"] == 4096)
            .unwrap();
        (k["limit"].as_str(), k["limit_fraction"].as_f64())
    };
    assert_eq!(limit("power16").0, Some("fma"));
    assert_eq!(limit("schlick").0, Some("divider"));
    assert!(limit("schlick").1.unwrap() > 0.0);
    assert_eq!(limit("pow"), (None, None));
    for k in kernels {
        for key in ["model", "variant", "batch", "evals_per_s"] {
            assert!(!k[key].is_null(), "{k} lacks {key}");
        }
        assert!(["scalar", "simd", "simd-threads"].contains(&k["variant"].as_str().unwrap()));
        assert!(k["evals_per_s"].as_f64().unwrap() > 0.0);
    }
    assert!(
        kernels.iter().any(|k| k["model"] == "power16"
            && k["variant"] == "simd-threads"
            && k["batch"] == 4096)
    );
    let names: Vec<&str> = v["speedups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"ward.speedup"), "{names:?}");
    let ward = v["speedups"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["name"] == "ward.speedup")
        .unwrap();
    assert_eq!(ward["claimed"], 2.0);
    // Render the saved run.
    let path = std::env::temp_dir().join(format!("fastbrdf-bench-{}.json", std::process::id()));
    std::fs::write(&path, &o.stdout).unwrap();
    let md = fastbrdf(
        &["bench", "--from", path.to_str().unwrap(), "--markdown"],
        "",
    );
    assert!(
        md.status.success() && stdout(&md).contains("| `power16` |"),
        "{}",
        stderr(&md)
    );
    std::fs::remove_file(&path).unwrap();
    // Bad input.
    let o = fastbrdf(&["bench", "--models", "nope"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("unknown model id 'nope'"));
    let o = fastbrdf(&["bench", "--from", "/nonexistent.json"], "");
    assert_eq!(o.status.code(), Some(2));
}

/// `bench --compare`: a run against itself gives ratio 1 everywhere and marks nothing; a row
/// made 3x slower is marked; a missing file is a clear error (exit 2, nothing on stdout).
/// No timing is asserted (both sides are saved runs).
#[test]
fn bench_compare_marks_slower_rows() {
    let saved = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let o = fastbrdf(
        &["bench", "--from", saved, "--compare", saved, "--json"],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = v["rows"].as_array().unwrap();
    assert!(rows.len() > 100, "{}", rows.len());
    assert!(
        rows.iter()
            .all(|r| r["ratio"] == 1.0 && r["slower"] == false)
    );
    assert_eq!(v["slower_below"], 0.8);
    // The old run three times faster on one row: that row, and only it, is slower.
    let mut old: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(saved).unwrap()).unwrap();
    let k = &mut old["kernels"][0];
    let (model, variant) = (k["model"].clone(), k["variant"].clone());
    k["evals_per_s"] = serde_json::json!(k["evals_per_s"].as_f64().unwrap() * 3.0);
    let d = temp_dir("bench-compare");
    let path = d.join("old.json");
    std::fs::write(&path, serde_json::to_string(&old).unwrap()).unwrap();
    let o = fastbrdf(
        &[
            "bench",
            "--from",
            saved,
            "--compare",
            path.to_str().unwrap(),
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let slower: Vec<&str> = text.lines().filter(|l| l.ends_with("slower")).collect();
    assert_eq!(slower.len(), 1, "{text}");
    assert!(
        slower[0].starts_with(model.as_str().unwrap())
            && slower[0].contains(variant.as_str().unwrap()),
        "{text}"
    );
    assert!(text.contains("1 below 0.8"), "{text}");
    std::fs::remove_dir_all(&d).unwrap();
    let o = fastbrdf(
        &["bench", "--from", saved, "--compare", "/nonexistent.json"],
        "",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        o.stdout.is_empty() && stderr(&o).contains("/nonexistent.json"),
        "{}",
        stderr(&o)
    );
    // Without --from the saved run is read before any timing: the same refusal.
    let o = fastbrdf(&["bench", "--quick", "--compare", "/nonexistent.json"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        o.stdout.is_empty() && stderr(&o).contains("/nonexistent.json"),
        "{}",
        stderr(&o)
    );
}

/// Issue 13: every run races the batch kernels against their C peers; the "peers" rows have
/// the shape `bench --help` documents, render from a saved run, and runs saved before them
/// still load and print as they did. Shapes only: no timing is asserted.
#[test]
fn bench_peers_have_the_documented_shape_and_old_runs_still_load() {
    let o = fastbrdf(
        &[
            "bench",
            "--quick",
            "--models",
            "pow,power16,beckmann,ward",
            "--large",
            "4096",
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let peers = v["peers"].as_array().expect("a peers array");
    let models: Vec<&str> = peers.iter().map(|p| p["model"].as_str().unwrap()).collect();
    assert_eq!(models, ["pow", "power16", "beckmann"], "ward has no C peer");
    for p in peers {
        for key in [
            "model",
            "params",
            "batch",
            "repeats",
            "rounds",
            "isa",
            "kernel_evals_per_s",
            "peer_evals_per_s",
            "ratio",
            "kernel_max_error",
            "peer_max_error",
            "peer",
            "compiler",
            "flags",
            "libmvec",
            "ftz",
            "daz",
        ] {
            assert!(p.get(key).is_some(), "{p} lacks {key}");
        }
        for spread in ["kernel_evals_per_s", "peer_evals_per_s", "ratio"] {
            for stat in ["median", "q1", "q3", "min", "max"] {
                let x = p[spread][stat].as_f64().unwrap_or(-1.0);
                assert!(x.is_finite() && x > 0.0, "{spread}.{stat} = {x}");
            }
        }
        assert_eq!(p["batch"], 4096);
        assert!(p["peer_max_error"].as_f64().unwrap() <= 1e-5, "{p}");
        assert!(p["kernel_max_error"].as_f64().unwrap() <= 1e-5, "{p}");
        assert!(p["flags"].as_str().unwrap().starts_with("-O3"));
        assert!(!p["compiler"].as_str().unwrap().is_empty());
        assert_eq!(p["ftz"].is_boolean(), cfg!(target_arch = "x86_64"), "{p}");
        assert_eq!(p["peer"], format!("peer_{}", p["model"].as_str().unwrap()));
    }
    assert_eq!(peers[2]["params"], "alpha=0.3");
    // power16 is held against the FMA pipes, and so is its C loop (same operation count);
    // pow's transcendental is uncounted: no fraction on either side; beckmann counts its
    // kernel (its exp2's polynomial, on FMA instruction sets), while its C loop, which calls
    // libm's expf, gets none.
    assert_eq!(peers[1]["kernel_limit"], "fma");
    let (k, c) = (
        peers[1]["kernel_limit_fraction"].as_f64().unwrap(),
        peers[1]["peer_limit_fraction"].as_f64().unwrap(),
    );
    let ratio = peers[1]["kernel_evals_per_s"]["median"].as_f64().unwrap()
        / peers[1]["peer_evals_per_s"]["median"].as_f64().unwrap();
    assert!(
        c > 0.0 && ((k / c) / ratio - 1.0).abs() < 1e-9,
        "{k} {c} {ratio}"
    );
    assert!(peers[0]["peer_limit_fraction"].is_null() && peers[2]["peer_limit_fraction"].is_null());
    assert!(peers[0]["kernel_limit_fraction"].is_null());
    let fma_isa = matches!(peers[2]["isa"].as_str(), Some("avx512" | "avx2+fma"));
    let b = peers[2]["kernel_limit_fraction"].as_f64();
    assert_eq!(b.is_some(), fma_isa, "{}", peers[2]);
    if fma_isa {
        assert!(b.unwrap() > 0.0 && b.unwrap() < 2.0, "{}", peers[2]);
        let unit = peers[2]["kernel_limit"].as_str().unwrap();
        assert!(unit == "fma" || unit == "divider", "{unit}");
    }
    // The saved run renders its peer table (Markdown and text).
    let d = temp_dir("bench-peers");
    let path = d.join("run.json");
    std::fs::write(&path, &o.stdout).unwrap();
    let f = path.to_str().unwrap();
    let md = fastbrdf(&["bench", "--from", f, "--markdown"], "");
    assert!(md.status.success(), "{}", stderr(&md));
    let md = stdout(&md);
    assert!(
        md.contains("| model | kernel | C peer | kernel / C |") && md.contains("| C % of limit |"),
        "{md}"
    );
    assert!(
        md.contains("| `power16` n=200 |") && md.contains("FTZ"),
        "{md}"
    );
    let text = stdout(&fastbrdf(&["bench", "--from", f], ""));
    assert!(
        text.contains("C peers") && text.contains("beckmann alpha=0.3"),
        "{text}"
    );
    // An impossible peer figure is refused like any other.
    let mut bad = v.clone();
    bad["peers"][0]["ratio"]["median"] = serde_json::json!(-1.0);
    std::fs::write(&path, serde_json::to_string(&bad).unwrap()).unwrap();
    let o = fastbrdf(&["bench", "--from", f], "");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("peers[0]"), "{}", stderr(&o));
    std::fs::remove_dir_all(&d).unwrap();
    // Runs saved before issue 13 have no "peers" (the saved GPU run is one): they load, print
    // without a peer table, and re-export with an empty array.
    let old = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/bench/bench-gpu.json"
    );
    assert!(!std::fs::read_to_string(old).unwrap().contains("\"peers\""));
    for flags in [&["--markdown"][..], &[][..]] {
        let o = fastbrdf(&[&["bench", "--from", old][..], flags].concat(), "");
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!stdout(&o).contains("C peer"), "{flags:?}");
    }
    let o = fastbrdf(&["bench", "--from", old, "--json"], "");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["peers"], serde_json::json!([]));
    assert!(!v["kernels"].as_array().unwrap().is_empty());
    // --help documents the shape.
    let help = stdout(&fastbrdf(&["bench", "--help"], ""));
    for word in [
        "\"peers\"",
        "peer_evals_per_s",
        "ratio",
        "ftz",
        "-march=native",
    ] {
        assert!(help.contains(word), "--help lacks {word}");
    }
}

// The book's copy of the tables (docs/book/src/speed.md) is the saved run's: tests/docs.rs,
// generated_bench_tables_are_the_saved_run.

/// Issue 11: saved runs were read with `read_to_string`, without a limit (`/dev/zero` grew
/// until memory ran out). Every one is read once, at most 64 MiB.
#[cfg(unix)]
#[test]
fn saved_runs_are_read_with_a_bound() {
    for args in [
        vec!["bench", "--from", "/dev/zero", "--markdown"],
        vec!["pareto", "--bench", "/dev/zero"],
        vec!["reproduce", "--speedups", "/dev/zero"],
    ] {
        let o = fastbrdf(&args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty(), "{args:?}");
        assert!(
            stderr(&o).contains("/dev/zero: larger than the 64 MiB"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// Issue 11 (review): saved runs with impossible figures were printed as if measured
/// ("FMA peak -0", "-1.00x", 300-digit throughputs).
#[test]
fn saved_runs_with_impossible_figures_are_refused() {
    let d = temp_dir("impossible-bench");
    let saved = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/bench/bench.json");
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(saved).unwrap()).unwrap();
    type Edit = fn(&mut serde_json::Value);
    let edits: [(&str, Edit); 3] = [
        ("fma", |v| v["fma_per_s"] = serde_json::json!(-5.0)),
        ("speedup", |v| {
            v["speedups"][0]["measured"] = serde_json::json!(-1.0)
        }),
        ("evals", |v| {
            v["kernels"][3]["evals_per_s"] = serde_json::json!(1e308)
        }),
    ];
    for (name, edit) in edits {
        let mut v = good.clone();
        edit(&mut v);
        let f = d.join(format!("{name}.json"));
        std::fs::write(&f, serde_json::to_string(&v).unwrap()).unwrap();
        let f = f.to_str().unwrap();
        for args in [
            &["bench", "--from", f][..],
            &["reproduce", "--speedups", f, "--json"][..],
            &["pareto", "--bench", f, "--json"][..],
        ] {
            let o = fastbrdf(args, "");
            assert_eq!(o.status.code(), Some(2), "{name} {args:?}: {}", stderr(&o));
            assert!(o.stdout.is_empty(), "{name} {args:?}");
            assert!(stderr(&o).contains(f), "{}", stderr(&o));
        }
    }
    // The saved run itself is accepted.
    assert!(fastbrdf(&["bench", "--from", saved], "").status.success());
    std::fs::remove_dir_all(&d).unwrap();
}

/// A quadrature reference (`sheen-albedo`, about 12 k evaluations per second) gets its
/// 4096-element rows and, instead of large-batch rows that would take minutes per call, a
/// `skipped` entry with the projected seconds, and a note on stderr; a cheap model beside it
/// keeps its large-batch rows. Before, `fastbrdf bench` without --models ran for hours.
#[test]
fn bench_leaves_out_the_large_batch_of_a_model_too_slow_for_it() {
    let large = 1 << 20;
    let o = fastbrdf(
        &[
            "bench",
            "--quick",
            "--models",
            "sheen-albedo,power16",
            "--large",
            &large.to_string(),
            "--json",
        ],
        "",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let kernels = v["kernels"].as_array().unwrap();
    let has = |m: &str, variant: &str, batch: u64| {
        kernels
            .iter()
            .any(|k| k["model"] == m && k["variant"] == variant && k["batch"] == batch)
    };
    for variant in ["scalar", "simd"] {
        assert!(
            has("sheen-albedo", variant, 4096),
            "no sheen-albedo {variant} row"
        );
    }
    for variant in ["simd", "simd-threads"] {
        assert!(
            !has("sheen-albedo", variant, large),
            "sheen-albedo {variant} was timed"
        );
        assert!(has("power16", variant, large), "no power16 {variant} row");
    }
    let skipped = v["skipped"].as_array().unwrap();
    let simd = skipped
        .iter()
        .find(|s| s["model"] == "sheen-albedo" && s["variant"] == "simd")
        .unwrap_or_else(|| panic!("no skipped entry: {skipped:?}"));
    assert_eq!(simd["batch"], large);
    // Projected from the measured 4096-element rate: large / rate.
    let rate = kernels
        .iter()
        .find(|k| k["model"] == "sheen-albedo" && k["variant"] == "simd" && k["batch"] == 4096)
        .unwrap()["evals_per_s"]
        .as_f64()
        .unwrap();
    let projected = simd["projected_s"].as_f64().unwrap();
    assert!(projected > 3.0, "{projected}");
    assert!((projected * rate / large as f64 - 1.0).abs() < 1e-9);
    assert!(!skipped.iter().any(|s| s["model"] == "power16"));
    let err = stderr(&o);
    assert!(
        err.contains("sheen-albedo") && err.contains("left out"),
        "{err}"
    );
    // The saved run renders, the missing figures as "-".
    let dir = temp_dir("bench-skipped");
    let path = dir.join("run.json");
    std::fs::write(&path, &o.stdout).unwrap();
    let md = fastbrdf(
        &["bench", "--from", path.to_str().unwrap(), "--markdown"],
        "",
    );
    assert!(md.status.success(), "{}", stderr(&md));
    let row = stdout(&md)
        .lines()
        .find(|l| l.starts_with("| `sheen-albedo` |"))
        .map(str::to_string)
        .unwrap_or_else(|| panic!("{}", stdout(&md)));
    assert!(row.contains("| - |"), "{row}");
    let _ = std::fs::remove_dir_all(&dir);
}
