//! `fastbrdf view --model file:PATH` (issue 31): a user's BRDF Explorer file and WGSL function
//! listed by `/api/models` with their declared parameters, plotted with the numbers a direct
//! GPU evaluation gives, compared with a registry reference (walter.brdf is cook-torrance with
//! GGX and Smith-GGX), rendered, their values checked per request (400 naming the parameter),
//! and a broken file refused at start-up (exit 2 naming file:line:col). The GPU tests skip
//! without a GPU unless CI is set (then a missing adapter fails); lavapipe serves in CI.

mod common;
use common::gpu_data as data;
use common::have_gpu;
mod explorer;
mod served;

use common::{fastbrdf, stderr};
use explorer::{get_json, ok_json};
use fastbrdf::user::UserBrdf;
use serde_json::Value;
use served::serve;

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("not a number: {x}")))
        .collect()
}

/// What the plots show of a model's values: the value, or the Rec. 709 luminance of RGB.
fn shown(b: &dyn UserBrdf, wi: &[[f64; 3]], wo: &[[f64; 3]]) -> Vec<f64> {
    let c = b.channels();
    let mut out = vec![0.0; wi.len() * c];
    b.eval(wi, wo, &mut out).unwrap();
    out.chunks(c)
        .map(|v| {
            if c == 3 {
                0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]
            } else {
                v[0]
            }
        })
        .collect()
}

fn pairs(v: &[(&str, &str)]) -> Vec<(String, String)> {
    v.iter()
        .map(|(k, x)| (k.to_string(), x.to_string()))
        .collect()
}

#[test]
fn a_user_model_is_listed_plotted_compared_and_rendered() {
    if !have_gpu() {
        return;
    }
    let (walter, ggx) = (
        data("brdf-explorer/walter.brdf"),
        data("user/ggx_sampled.wgsl"),
    );
    let s = serve(&[
        "--model",
        &format!("file:{walter}"),
        "--model",
        &format!("file:{ggx}"),
        "--param",
        "alphaG=0.2",
    ]);

    // Listed beside the registry's models, with the declared ranges; --param's value is the
    // default a request runs with, the file's is `declared`.
    let info = ok_json(&s.addr, "/api/models");
    assert_eq!(
        info["users"],
        serde_json::json!(["walter.brdf", "ggx_sampled.wgsl"])
    );
    let models = info["models"].as_array().unwrap();
    assert!(models.iter().any(|m| m["id"] == "cook-torrance"));
    let w = models.iter().find(|m| m["id"] == "walter.brdf").unwrap();
    assert_eq!(w["kind"], "user");
    assert_eq!(w["channels"], 3);
    // The deterministic cost beside the built-ins': SPIR-V instructions after spirv-opt -O
    // (spirv-opt is installed by tools/test.sh; without it the count is null).
    let ct = models.iter().find(|m| m["id"] == "cook-torrance").unwrap();
    assert!(ct["instructions"]["total"].as_u64().unwrap() > 0, "{ct}");
    let shader = fastbrdf_gpu::user::UserShader::load(std::path::Path::new(&data(
        "brdf-explorer/walter.brdf",
    )))
    .unwrap();
    match shader.instructions() {
        Ok(want) => assert_eq!(w["instructions"]["total"], want.total, "{w}"),
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI is set and no spirv-opt: {e}"),
        Err(_) => assert!(w["instructions"].is_null(), "{w}"),
    }
    let p = |name: &str| {
        w["params"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == name)
            .unwrap_or_else(|| panic!("no {name}: {w}"))
            .clone()
    };
    let a = p("alphaG");
    assert_eq!(
        (a["type"].as_str(), a["min"].as_f64(), a["max"].as_f64()),
        (Some("number"), Some(0.001), Some(1.0))
    );
    assert_eq!(
        (a["default"].as_f64(), a["declared"].as_f64()),
        (Some(0.2), Some(0.1))
    );
    let f = p("useFresnel");
    assert_eq!(f["type"], "choice");
    assert_eq!(f["default"], "0");
    let g = models
        .iter()
        .find(|m| m["id"] == "ggx_sampled.wgsl")
        .unwrap();
    assert_eq!(g["channels"], 1);
    assert_eq!(g["params"][0]["name"], "alpha");

    // Plots: the numbers a direct evaluation of the same shader gives at the plotted
    // directions (walter with the request's Ks and the start-up alphaG; ggx_sampled with the
    // request's alpha, which cook-torrance takes too).
    let q = "models=walter.brdf,ggx_sampled.wgsl,cook-torrance&ref=cook-torrance&d=ggx&g=smith-ggx&alpha=0.2&Ks=1&theta=30";
    let v = ok_json(&s.addr, &format!("/api/plots?{q}"));
    let ids: Vec<&str> = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["cook-torrance", "walter.brdf", "ggx_sampled.wgsl"]);
    let ti = 30f64.to_radians();
    let thetas = numbers(&v["polar_theta_deg"]);
    let wi = vec![[ti.sin(), 0.0, ti.cos()]; thetas.len()];
    let wo: Vec<[f64; 3]> = thetas
        .iter()
        .map(|t| {
            let r = t.to_radians();
            [-r.sin(), 0.0, r.cos()]
        })
        .collect();
    let direct_w = fastbrdf_gpu::user::load(
        std::path::Path::new(&walter),
        &pairs(&[("alphaG", "0.2"), ("Ks", "1")]),
    )
    .unwrap();
    let direct_g =
        fastbrdf_gpu::user::load(std::path::Path::new(&ggx), &pairs(&[("alpha", "0.2")])).unwrap();
    for (k, direct) in [(1, &direct_w), (2, &direct_g)] {
        let m = &v["models"][k];
        assert_eq!(m["kind"], "user");
        let got = numbers(&m["polar"]);
        let want = shown(direct, &wi, &wo);
        assert_eq!(got.len(), want.len());
        assert!(got.iter().all(|x| x.is_finite()));
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g - w).abs() <= 1e-9 * w.abs().max(1e-12),
                "{}: {g} vs {w}",
                m["id"]
            );
        }
        let side = v["slice_size"].as_u64().unwrap() as usize;
        assert_eq!(numbers(&m["slice"]).len(), side * side);
        assert_eq!(
            numbers(&m["lobe"]).len(),
            v["curve_theta_deg"].as_array().unwrap().len()
        );
    }
    assert_eq!(v["models"][1]["channel"], "luminance");
    assert_eq!(v["models"][2]["channel"], "value");
    // The peak of a GGX lobe at alpha 0.2 is near the mirror direction.
    let polar = numbers(&v["models"][1]["polar"]);
    let peak = (0..polar.len())
        .max_by(|&a, &b| polar[a].total_cmp(&polar[b]))
        .unwrap();
    assert!(
        (thetas[peak] - 30.0).abs() <= 3.0,
        "peak at {}",
        thetas[peak]
    );

    // Errors against the registry reference: walter.brdf (Ks 1, no Fresnel) is cook-torrance
    // with GGX and Smith-GGX to f32's precision; against Beckmann (cook-torrance's default d)
    // it is not.
    let e = &v["models"][1]["against"];
    assert_eq!(e["reference"], "cook-torrance");
    let (max_abs, peak_ref) = (
        e["max_abs"].as_f64().unwrap(),
        e["reference_peak"].as_f64().unwrap(),
    );
    assert!(max_abs <= 1e-5 * peak_ref, "{e}");
    assert!(e["rms"].as_f64().unwrap() <= max_abs);
    assert!(e["samples"].as_u64().unwrap() >= 1000);
    let row = ok_json(
        &s.addr,
        "/api/errors?model=walter.brdf&ref=cook-torrance&d=ggx&g=smith-ggx&alpha=0.2&Ks=1",
    );
    assert_eq!(row["model"], "walter.brdf");
    for k in ["max_abs", "max_rel", "rms", "samples"] {
        assert_eq!(row[k], e[k], "{k}");
    }
    let beckmann = ok_json(
        &s.addr,
        "/api/errors?model=walter.brdf&ref=cook-torrance&d=beckmann&alpha=0.2&Ks=1",
    );
    assert!(
        beckmann["max_abs"].as_f64().unwrap() > 100.0 * max_abs,
        "{beckmann}"
    );
    // A user's model as the reference: the registry model's errors against it.
    let r = ok_json(
        &s.addr,
        "/api/plots?models=cook-torrance&ref=walter.brdf&d=ggx&g=smith-ggx&alpha=0.2&Ks=1",
    );
    assert_eq!(r["reference_kind"], "user");
    assert_eq!(r["models"][0]["id"], "walter.brdf");
    let back = &r["models"][1]["against"];
    assert_eq!(back["reference"], "walter.brdf");
    assert!(
        back["max_abs"].as_f64().unwrap() <= 1e-5 * peak_ref,
        "{back}"
    );

    // Each set of values is its own compiled instance, past the ones kept: a value seen
    // before gives the same numbers again, another value other numbers.
    let polar_at = |a: &str| {
        let v = ok_json(
            &s.addr,
            &format!("/api/plots?models=walter.brdf&alphaG={a}&Ks=1"),
        );
        numbers(&v["models"][0]["polar"])
    };
    let first = polar_at("0.3");
    let mut seen = vec![];
    for k in 0..10 {
        let p = polar_at(&format!("0.{}", 40 + k));
        assert_ne!(p, first);
        assert!(!seen.contains(&p));
        seen.push(p);
    }
    assert_eq!(polar_at("0.3"), first);

    // A user's model as the reference of the pictures: rendered first.
    let pic = ok_json(
        &s.addr,
        "/api/render?models=cook-torrance,walter.brdf&ref=walter.brdf&size=16&flip=none",
    );
    assert_eq!(pic["reference"], "walter.brdf");
    assert_eq!(pic["images"][0]["id"], "walter.brdf");
    assert_eq!(pic["diffs"][0]["id"], "cook-torrance");

    // Pictures: the user's model rendered beside the registry reference.
    let pic = ok_json(&s.addr, &format!("/api/render?{q}&size=32&spp=1&flip=none"));
    let imgs: Vec<&str> = pic["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["id"].as_str().unwrap())
        .collect();
    assert_eq!(imgs, ["cook-torrance", "walter.brdf", "ggx_sampled.wgsl"]);
    let png = explorer::cdp::base64_decode(pic["images"][1]["png"].as_str().unwrap()).unwrap();
    let px = image::load_from_memory(&png).unwrap().to_rgb8();
    assert!(
        px.pixels().any(|p| p.0.iter().any(|&c| c > 0)),
        "a black picture"
    );
    for m in pic["metrics"].as_array().unwrap() {
        assert!(m["rmse"].as_f64().unwrap().is_finite(), "{m}");
    }

    // The white furnace of a user's model: `fastbrdf albedo --model file:PATH`'s numbers.
    let al = ok_json(&s.addr, &format!("/api/albedo?{q}"));
    let w = al["models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["id"] == "walter.brdf")
        .unwrap();
    let a = numbers(&w["albedo"]["albedo"]);
    assert_eq!(a.len(), 10, "{w}");
    assert!(a.iter().all(|x| *x > 0.5 && *x <= 1.0), "{w}");
    assert_eq!(w["albedo"]["conserves"], true, "{w}");
}

#[test]
fn bad_values_are_400_naming_the_parameter_and_the_server_goes_on() {
    if !have_gpu() {
        return;
    }
    let s = serve(&[
        "--model",
        &format!("file:{}", data("brdf-explorer/walter.brdf")),
    ]);
    for (q, names) in [
        ("models=walter.brdf&alphaG=5", ["alphaG", "[0.001, 1]"]),
        ("models=walter.brdf&alphaG=abc", ["alphaG", "abc"]),
        (
            "models=walter.brdf&useFresnel=maybe",
            ["useFresnel", "maybe"],
        ),
        ("models=walter.brdf&nonesuch=1", ["nonesuch", "walter.brdf"]),
        ("models=walter.brdf,flog&n=-3", ["n", "-3"]),
        ("models=walter.brdf&ref=nonesuch", ["nonesuch", "nonesuch"]),
    ] {
        for api in ["plots", "render", "albedo"] {
            let (status, v) = get_json(&s.addr, &format!("/api/{api}?{q}&size=16"));
            assert_eq!(status, 400, "{api}?{q}: {v}");
            let m = v["error"].as_str().unwrap();
            for n in names {
                assert!(m.contains(n), "{api}?{q}: {m}");
            }
        }
    }
    let (status, v) = get_json(&s.addr, "/api/errors?model=walter.brdf&ref=flog&alphaG=2");
    assert_eq!(status, 400, "{v}");
    // Still serving, and a good value after the bad ones is answered.
    ok_json(&s.addr, "/api/plots?models=walter.brdf&alphaG=0.5");
}

#[test]
fn a_broken_file_or_value_is_exit_2_at_start_up_naming_it() {
    let broken = data("user/compile_error.glsl");
    let o = fastbrdf(
        &["view", "--port", "0", "--model", &format!("file:{broken}")],
        "",
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    assert!(
        stderr(&o).contains(&format!("{broken}:7:23")),
        "{}",
        stderr(&o)
    );
    // Values are checked before a GPU is opened: these need none.
    let walter = format!("file:{}", data("brdf-explorer/walter.brdf"));
    for (args, says) in [
        (vec!["--model", &walter, "--param", "alphaG=7"], "alphaG"),
        (
            vec!["--model", &walter, "--param", "nonesuch=1"],
            "nonesuch",
        ),
        (vec!["--param", "alpha=0.3"], "--param alpha"),
        (vec!["--model", "cook-torrance"], "cook-torrance"),
        (
            vec!["--model", "file:/nonexistent/x.brdf"],
            "/nonexistent/x.brdf",
        ),
    ] {
        let mut a = vec!["view", "--port", "0"];
        a.extend(args);
        let o = fastbrdf(&a, "");
        assert_eq!(o.status.code(), Some(2), "{a:?}: {}", stderr(&o));
        assert!(o.stdout.is_empty());
        assert!(stderr(&o).contains(says), "{a:?}: {}", stderr(&o));
    }
}
