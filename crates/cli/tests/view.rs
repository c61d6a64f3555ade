//! `fastbrdf view`: the JSON API over real HTTP (the binary on port 0), every endpoint and the
//! bad requests, with numbers compared against the CLI commands that compute the same things.
//! The page end to end in headless Chromium is in `view_page.rs`, the measured reference in
//! `view_measured.rs`, the server's limits in `view_server.rs`; shared helpers in
//! `explorer/mod.rs`.

mod common;
mod explorer;
mod served;

use common::{fastbrdf, stderr, temp_dir};
use explorer::{cdp, cli_errors, cli_message, get_json, ok_json, request};
use serde_json::Value;
use served::serve;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

#[test]
fn page_is_embedded_and_self_contained() {
    let s = serve(&[]);
    for target in ["/", "/index.html"] {
        let (status, ctype, body) = request(&s.addr, "GET", target);
        assert_eq!(status, 200);
        assert!(ctype.starts_with("text/html"));
        let page = String::from_utf8(body).unwrap();
        assert!(page.contains("<canvas") && page.contains("/api/plots"));
        // Offline: nothing is fetched from anywhere but this server.
        for bad in ["http://", "https://", "//cdn", "<link "] {
            assert!(!page.contains(bad), "the page refers to {bad}");
        }
        // No string is ever parsed as HTML (issue 27: ids from the link ran as script).
        for bad in [
            "innerHTML",
            "outerHTML",
            "insertAdjacentHTML",
            "document.write",
        ] {
            assert!(!page.contains(bad), "the page uses {bad}");
        }
    }
}

#[test]
fn models_lists_every_shadeable_model_with_its_parameters() {
    let s = serve(&[]);
    let v = ok_json(&s.addr, "/api/models");
    let o = fastbrdf(&["models", "--json"], "");
    let all: Value = serde_json::from_slice(&o.stdout).unwrap();
    let expected: Vec<&str> = all["models"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["kind"].is_string()) // every kind: terms too (view_kinds.rs)
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    let got: Vec<&str> = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    assert_eq!(got, expected);
    let flog = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["id"] == "flog")
        .unwrap();
    let n = &flog["params"][0];
    assert_eq!(
        (
            n["name"].as_str(),
            n["min"].as_f64(),
            n["max"].as_f64(),
            n["log"].as_bool()
        ),
        (Some("n"), Some(1.0), Some(100000.0), Some(true))
    );
    let ct = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["id"] == "cook-torrance")
        .unwrap();
    let d = ct["params"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "d")
        .unwrap();
    assert_eq!(d["type"], "choice");
    assert!(d["options"].as_array().unwrap().iter().any(|o| o == "ggx"));
    assert_eq!(v["materials"].as_array().unwrap().len(), 86);
    assert!(flog["cost"].is_null(), "no --bench run: unavailable");
    // With a bench run: the best SIMD row of the saved file.
    let s = serve(&["--bench", "../../docs/bench/bench.json"]);
    let v = ok_json(&s.addr, "/api/models");
    let flog = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["id"] == "flog")
        .unwrap();
    let saved: Value =
        serde_json::from_str(&std::fs::read_to_string("../../docs/bench/bench.json").unwrap())
            .unwrap();
    let best = saved["kernels"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|k| k["model"] == "flog" && k["variant"] == "simd")
        .map(|k| k["evals_per_s"].as_f64().unwrap())
        .fold(0.0, f64::max);
    assert_eq!(flog["cost"]["simd"].as_f64(), Some(best));
}

#[test]
fn errors_endpoint_equals_fastbrdf_errors() {
    let s = serve(&[]);
    for (model, reference, key, flag, value) in [
        ("flog", "pow", "n", "--n", "100"),
        ("schlick", "pow", "n", "--n", "7.5"),
        ("beckmann-power16", "beckmann-ct", "alpha", "--m", "0.2"),
        ("ward-pow", "ward", "alpha", "--m", "0.35"),
    ] {
        let v = ok_json(
            &s.addr,
            &format!("/api/errors?model={model}&ref={reference}&{key}={value}"),
        );
        let c = cli_errors(model, reference, flag, value);
        for f in [
            "max_abs",
            "max_abs_at",
            "max_rel",
            "max_rel_at",
            "rms",
            "samples",
        ] {
            assert_eq!(v[f], c[f], "{model} {f}");
        }
    }
}

#[test]
fn plots_carry_every_curve_and_the_cli_numbers() {
    let s = serve(&[]);
    let v = ok_json(
        &s.addr,
        "/api/plots?models=flog,schlick&ref=pow&n=60&theta=35",
    );
    assert_eq!(v["theta_i_deg"], 35.0);
    let np = v["polar_theta_deg"].as_array().unwrap().len();
    let nc = v["curve_theta_deg"].as_array().unwrap().len();
    let side = v["slice_size"].as_u64().unwrap() as usize;
    let models = v["models"].as_array().unwrap();
    assert_eq!(
        models
            .iter()
            .map(|m| m["id"].as_str().unwrap())
            .collect::<Vec<_>>(),
        ["pow", "flog", "schlick"]
    );
    for m in models {
        assert_eq!(m["polar"].as_array().unwrap().len(), np);
        assert_eq!(m["lobe"].as_array().unwrap().len(), nc);
        assert_eq!(m["slice"].as_array().unwrap().len(), side * side);
        // The polar plot peaks near the mirror direction (+35 degrees: the incident direction
        // is at -35 on the plot's axis).
        let polar: Vec<f64> = m["polar"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let peak = polar
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap()
            .0;
        let at = v["polar_theta_deg"][peak].as_f64().unwrap();
        assert!((at - 35.0).abs() <= 3.0, "{} peaks at {at}", m["id"]);
    }
    assert!(
        models[0]["error"].is_null(),
        "the reference has no error against itself"
    );
    for m in &models[1..] {
        let e = &m["error"];
        let c = cli_errors(m["id"].as_str().unwrap(), "pow", "--n", "60");
        assert_eq!(e["max_abs"], c["max_abs"]);
        assert_eq!(e["max_rel"], c["max_rel"]);
        let abs: Vec<f64> = e["abs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        // The plotted curve never exceeds the located (refined) maximum.
        assert!(
            abs.iter()
                .all(|a| a.abs() <= c["max_abs"].as_f64().unwrap() + 1e-12)
        );
    }
    // Albedo against `fastbrdf albedo` (its default: lobes as energy-normalised phong).
    let o = fastbrdf(
        &[
            "albedo",
            "--model",
            "flog",
            "--param",
            "n=60",
            "--angles",
            "0,10,20,30,40,50,60,70,80,85",
            "--json",
        ],
        "",
    );
    let cli: Value = serde_json::from_slice(&o.stdout).unwrap();
    let alb = ok_json(&s.addr, "/api/albedo?models=flog,schlick&ref=pow&n=60");
    let ids: Vec<&str> = alb["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["pow", "flog", "schlick"]);
    let a = &alb["models"][1]["albedo"];
    for (k, row) in cli["rows"].as_array().unwrap().iter().enumerate() {
        let (x, y) = (
            a["albedo"][k].as_f64().unwrap(),
            row["albedo"].as_f64().unwrap(),
        );
        assert!(
            (x - y).abs() <= 2e-3 * y.max(1e-3),
            "albedo at {}: {x} vs {y}",
            row["theta_deg"]
        );
    }
    assert_eq!(a["conserves"], cli["conserves"]);
    assert_eq!(a["claims_energy"], cli["claims_energy"]);
}

/// How far the quick albedo estimate (`quick=1`) may be from the precise curve, relative to
/// max(precise, 1e-3) at each angle. Measured worst over the queries below (the test prints
/// it with `-- --nocapture`): 1.5e-3; the bound leaves a factor of about 3.
const QUICK_ALBEDO_TOL: f64 = 5e-3;

#[test]
fn quick_albedo_is_close_to_the_precise_one_and_carries_no_verdict() {
    let s = serve(&[]);
    let mut worst: f64 = 0.0;
    for q in [
        "models=flog,schlick&ref=pow&n=60",
        "models=flog,schlick&ref=pow&n=2",
        "models=flog&ref=pow&n=1000",
        "models=beckmann-power16&ref=cook-torrance&alpha=0.05",
        "models=beckmann-power16&ref=cook-torrance&alpha=0.5",
        "models=ward,blinn-phong&alpha=0.2",
        // The ends of the sliders: the sharpest lobes.
        "models=flog&ref=pow&n=100000",
        "models=ward&ref=cook-torrance&alpha=0.005",
        "models=cook-torrance&alpha=1",
        // The non-reciprocal BRDF, integrated over wi (`Target::view`).
        "models=cook-torrance&ms=filament&d=ggx&g=smith-ggx-correlated&alpha=0.3",
    ] {
        let precise = ok_json(&s.addr, &format!("/api/albedo?{q}"));
        let quick = ok_json(&s.addr, &format!("/api/albedo?{q}&quick=1"));
        assert_eq!(precise["estimate"], false);
        assert_eq!(quick["estimate"], true);
        let (pm, qm) = (
            precise["models"].as_array().unwrap(),
            quick["models"].as_array().unwrap(),
        );
        assert_eq!(pm.len(), qm.len());
        for (p, k) in pm.iter().zip(qm) {
            assert_eq!(p["id"], k["id"]);
            let id = p["id"].as_str().unwrap();
            let (p, k) = (&p["albedo"], &k["albedo"]);
            if p.is_null() {
                assert!(k.is_null(), "{q}");
                continue;
            }
            // The verdict only from the precise computation.
            assert!(p["conserves"].is_boolean(), "{q}: {p}");
            assert!(k["conserves"].is_null(), "{q}: {k}");
            assert!(k["worst_albedo"].is_null(), "{q}: {k}");
            assert_eq!(p["theta_deg"], k["theta_deg"]);
            for (x, y) in p["albedo"]
                .as_array()
                .unwrap()
                .iter()
                .zip(k["albedo"].as_array().unwrap())
            {
                let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
                let d = (x - y).abs() / x.max(1e-3);
                worst = worst.max(d);
                assert!(d <= QUICK_ALBEDO_TOL, "{q}: {id}: quick {y} vs precise {x}");
            }
        }
        eprintln!(
            "{q}: precise {:.1} ms, quick {:.1} ms (server, debug build)",
            precise["ms"], quick["ms"]
        );
    }
    eprintln!("worst relative difference quick vs precise: {worst:.2e}");
    let (status, v) = get_json(&s.addr, "/api/albedo?models=flog&n=60&quick=2");
    assert_eq!(status, 400);
    assert!(v["error"].as_str().unwrap().contains("quick"), "{v}");
}

#[test]
fn renders_and_their_metrics_equal_fastbrdf_compare() {
    let s = serve(&["--mesh", "face"]);
    let v = ok_json(
        &s.addr,
        "/api/render?models=flog&ref=pow&n=100&size=64&spp=1",
    );
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(64), Some(64))
    );
    let ids: Vec<&str> = v["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["pow", "flog"]);
    for i in v["images"]
        .as_array()
        .unwrap()
        .iter()
        .chain(v["diffs"].as_array().unwrap())
    {
        let png = cdp::base64_decode(i["png"].as_str().unwrap()).unwrap();
        let img = image::load_from_memory(&png).unwrap();
        assert_eq!((img.width(), img.height()), (64, 64));
    }
    let dir = temp_dir("view-compare");
    let out = dir.join("c.png");
    let o = fastbrdf(
        &[
            "compare",
            "--models",
            "flog",
            "--reference",
            "pow",
            "--param",
            "n=100",
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
    assert!(o.status.success(), "{}", stderr(&o));
    let c: Value = serde_json::from_slice(&o.stdout).unwrap();
    for f in ["rmse", "psnr", "flip"] {
        assert_eq!(v["metrics"][0][f], c["metrics"][0][f], "{f}");
    }
    // The page's way: the pictures with RMSE and PSNR at once, FLIP from the pool after.
    let later = ok_json(
        &s.addr,
        "/api/render?models=flog&ref=pow&n=100&size=64&spp=1&flip=later",
    );
    assert_eq!(later["images"], v["images"]);
    assert!(
        later["metrics"][0]["flip"].is_null(),
        "{}",
        later["metrics"]
    );
    let job = later["flip_job"].as_u64().expect("flip_job");
    let f = ok_json(&s.addr, &format!("/api/flip?job={job}"));
    for f_ in ["rmse", "psnr"] {
        assert_eq!(later["metrics"][0][f_], c["metrics"][0][f_], "{f_}");
    }
    assert_eq!(f["metrics"][0]["model"], "flog");
    for f_ in ["rmse", "psnr", "flip"] {
        assert_eq!(f["metrics"][0][f_], c["metrics"][0][f_], "{f_}");
    }
    // The light and the object change the picture.
    let moved = ok_json(
        &s.addr,
        "/api/render?models=flog&n=100&size=64&spp=1&light=-1,0.2,0.5",
    );
    assert_ne!(moved["images"][0]["png"], v["images"][1]["png"]);
    let face = ok_json(
        &s.addr,
        "/api/render?models=flog&n=100&size=64&spp=1&mesh=mesh",
    );
    assert_ne!(face["images"][0]["png"], v["images"][1]["png"]);
    assert!(face["metrics"].as_array().unwrap().is_empty() && face["reference"].is_null());
}

#[test]
fn shader_and_material_equal_the_cli() {
    let s = serve(&[]);
    for lang in ["wgsl", "glsl", "hlsl", "msl", "brdf-explorer"] {
        let (status, ctype, body) = request(
            &s.addr,
            "GET",
            &format!("/api/shader?model=cook-torrance&alpha=0.2&f=schlick&lang={lang}"),
        );
        assert_eq!(status, 200);
        assert!(ctype.starts_with("text/plain"));
        let o = fastbrdf(
            &[
                "shader",
                "--model",
                "cook-torrance",
                "--param",
                "alpha=0.2",
                "--param",
                "f=schlick",
                "--lang",
                lang,
            ],
            "",
        );
        assert_eq!(
            String::from_utf8(body).unwrap(),
            String::from_utf8(o.stdout).unwrap(),
            "{lang}"
        );
    }
    let v = ok_json(&s.addr, "/api/material?name=gold-paint&model=flog");
    let o = fastbrdf(&["materials", "--json"], "");
    let m: Value = serde_json::from_slice(&o.stdout).unwrap();
    let gold = m
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["name"] == "gold-paint")
        .unwrap()
        .clone();
    assert_eq!(v["params"]["n"].as_f64(), gold["blinn_phong"]["n"].as_f64());
}

#[test]
fn bad_requests_get_4xx_with_the_cli_message_and_the_server_survives() {
    let s = serve(&[]);
    let unknown = cli_message(&[
        "errors",
        "--model",
        "nope",
        "--reference",
        "pow",
        "--n",
        "10",
    ]);
    let not_number = cli_message(&["eval", "--model", "flog", "--param", "n=abc"]);
    let out_of_range = cli_message(&["eval", "--model", "flog", "--param", "n=1e9"]);
    for (target, status, message) in [
        ("/api/plots?models=nope", 400, Some(unknown.as_str())),
        (
            "/api/errors?model=nope&ref=pow&n=10",
            400,
            Some(unknown.as_str()),
        ),
        (
            "/api/plots?models=flog&n=abc",
            400,
            Some(not_number.as_str()),
        ),
        (
            "/api/render?models=flog&n=1e9",
            400,
            Some(out_of_range.as_str()),
        ),
        ("/api/shader?model=flog&n=abc", 400, None),
        (
            "/api/plots?models=flog&bogus=1",
            400,
            Some("model 'flog' has no parameter 'bogus'"),
        ),
        ("/api/plots?models=flog&theta=95", 400, None),
        ("/api/plots?models=a,b,c,d,e,f,g", 400, None),
        ("/api/plots?models=fresnel-schlick&f0=2", 400, None),
        ("/api/plots", 400, Some("missing query parameter 'models'")),
        ("/api/render?models=flog&size=100000", 400, None),
        ("/api/render?models=flog&size=-1", 400, None),
        ("/api/render?models=flog&spp=99", 400, None),
        ("/api/render?models=flog&light=nan,1,1", 400, None),
        (
            "/api/render?models=flog&mesh=mesh",
            400,
            Some("mesh=mesh: the server was started without --mesh"),
        ),
        ("/api/render?models=flog&mesh=/etc/passwd", 400, None),
        (
            "/api/render?models=flog&flip=soon",
            400,
            Some("flip 'soon': expected wait, later or none"),
        ),
        ("/api/flip", 400, Some("missing query parameter 'job'")),
        (
            "/api/flip?job=-1",
            400,
            Some("job '-1': not a whole number"),
        ),
        ("/api/flip?job=987654321", 404, None),
        ("/api/shader?model=flog&lang=cobol", 400, None),
        ("/api/material?name=unobtainium&model=flog", 400, None),
        ("/api/plots?models=%ff%fe&n=%zz", 400, None),
        ("/../../etc/passwd", 404, None),
        ("/%2e%2e/%2e%2e/etc/passwd", 404, None),
        ("/api/../../../etc/passwd", 404, None),
        ("/page.html", 404, None),
    ] {
        let (got, v) = get_json(&s.addr, target);
        assert_eq!(got, status, "{target}: {v}");
        let e = v["error"].as_str().unwrap();
        assert!(!e.contains("root:"), "{target}");
        if let Some(m) = message {
            assert_eq!(e, m, "{target}");
        }
    }
    let (status, _, _) = request(&s.addr, "POST", "/api/models");
    assert_eq!(status, 405);
    let long = format!("/api/plots?models=flog&x={}", "a".repeat(10000));
    let (status, _, _) = request(&s.addr, "GET", &long);
    assert!((400..500).contains(&status), "{status}");
    ok_json(&s.addr, "/api/models");
}

#[test]
fn stale_renders_are_dropped() {
    let s = serve(&[]);
    ok_json(&s.addr, "/api/render?models=flog&size=16&client=c1&gen=5");
    let (status, v) = get_json(&s.addr, "/api/render?models=flog&size=16&client=c1&gen=3");
    assert_eq!(status, 409, "{v}");
    // A FLIP job's answer after its client's newer request is a 409 too, whether its FLIP was
    // computed by then or not.
    let later = ok_json(
        &s.addr,
        "/api/render?models=flog&ref=pow&size=32&client=c1&gen=6&flip=later",
    );
    let job = later["flip_job"].as_u64().unwrap();
    ok_json(
        &s.addr,
        "/api/render?models=flog&size=16&client=c1&gen=7&flip=none",
    );
    let (status, v) = get_json(&s.addr, &format!("/api/flip?job={job}"));
    assert_eq!(status, 409, "{v}");
    // Another client is not affected; many at once get an answer each (200, or 503 when the
    // queue is full), never a dead server.
    ok_json(&s.addr, "/api/render?models=flog&size=16&client=c2&gen=1");
    let handles: Vec<_> = (0..12)
        .map(|k| {
            let addr = s.addr.clone();
            std::thread::spawn(move || {
                get_json(
                    &addr,
                    &format!("/api/render?models=flog,pow&size=128&client=p{k}&gen=1"),
                )
                .0
            })
        })
        .collect();
    for h in handles {
        assert!([200, 503].contains(&h.join().unwrap()));
    }
    ok_json(&s.addr, "/api/models");
}

#[test]
fn non_loopback_needs_allow_remote_and_warns() {
    let o = fastbrdf(&["view", "--host", "0.0.0.0", "--port", "0"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--allow-remote"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_fastbrdf"))
        .args(["view", "--host", "0.0.0.0", "--port", "0", "--allow-remote"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let _ = child.kill();
    let _ = child.wait();
    assert!(line.starts_with("warning:"), "{line}");
}
