//! Issue 28's review of the parse-once refactor, as tests: the explorer's R,G,B contract (a
//! render and a shader take a value per colour channel; the plots, the albedo and the errors
//! compute one model and refuse it quoting the value, 400, never a silent null), messages that
//! name the model the user chose, `albedo`'s kind checked before its values, and the Made-by
//! line of a metal's BRDF Explorer export that re-runs to the same file.

mod common;
mod explorer;
mod served;

use common::{fastbrdf, stderr, stdout};
use explorer::{cdp, get_json, ok_json, request};
use served::serve;

/// What the core says of a value given per channel where one model is needed.
fn coloured(model: &str, param: &str, value: &str) -> String {
    format!("model '{model}': parameter {param} = {value} is invalid: expected a number in ")
}

#[test]
fn plots_albedo_and_errors_refuse_rgb_naming_the_model_chosen() {
    let s = serve(&[]);
    for (target, model, param, value) in [
        (
            "/api/albedo?models=cook-torrance&alpha=0.1,0.2,0.3",
            "cook-torrance",
            "alpha",
            "0.1,0.2,0.3",
        ),
        ("/api/albedo?models=flog&n=1,2,3", "flog", "n", "1,2,3"),
        (
            "/api/albedo?models=ggx&alpha=0.1,0.2,0.3",
            "ggx",
            "alpha",
            "0.1,0.2,0.3",
        ),
        (
            "/api/albedo?models=flog&n=1,2,3&quick=1",
            "flog",
            "n",
            "1,2,3",
        ),
        // A value of the BRDF a distribution is shaded as still names the distribution.
        (
            "/api/albedo?models=ggx&f0=0.1,0.2,0.3&quick=1",
            "ggx",
            "f0",
            "0.1,0.2,0.3",
        ),
        (
            "/api/plots?models=cook-torrance&f0=0.1,0.2,0.3",
            "cook-torrance",
            "f0",
            "0.1,0.2,0.3",
        ),
        // Named after the lobe chosen, not the blinn-phong it is shaded as.
        ("/api/plots?models=flog,ggx&n=1,2,3", "flog", "n", "1,2,3"),
        (
            "/api/plots?models=ggx&alpha=0.1,0.2,0.3",
            "ggx",
            "alpha",
            "0.1,0.2,0.3",
        ),
    ] {
        let (status, v) = get_json(&s.addr, target);
        assert_eq!(status, 400, "{target}: {v}");
        let e = v["error"].as_str().unwrap();
        assert!(
            e.starts_with(&coloured(model, param, value)),
            "{target}: {e}"
        );
        assert!(e.contains("not one per colour channel"), "{target}: {e}");
    }
    // The lobe's own range, not that of the BRDF it is shaded as.
    let (_, v) = get_json(&s.addr, "/api/plots?models=flog&n=1,2,3");
    let flog_range = fastbrdf(&["eval", "--model", "flog", "--param", "n=0"], "");
    let range = stderr(&flog_range);
    let range = &range[range.find("expected a number in ").unwrap()..];
    assert!(
        v["error"].as_str().unwrap().contains(range.trim()),
        "{v} / {range}"
    );
    // The errors row takes one number.
    let (status, v) = get_json(&s.addr, "/api/errors?model=flog&ref=pow&n=1,2,3");
    assert_eq!(status, 400, "{v}");
    assert!(v["error"].as_str().unwrap().contains("'1,2,3'"), "{v}");
    // A distribution's albedo is still null (not a BRDF on its own), the others computed.
    let v = ok_json(
        &s.addr,
        "/api/albedo?models=ggx,flog&alpha=0.2&n=20&quick=1",
    );
    let models = v["models"].as_array().unwrap();
    assert_eq!(models[0]["id"], "ggx");
    assert!(models[0]["albedo"].is_null(), "{v}");
    assert_eq!(models[1]["id"], "flog");
    assert!(models[1]["albedo"]["albedo"].is_array(), "{v}");
}

/// The largest |R - B| of a rendered picture (0-255).
fn colour_spread(v: &serde_json::Value) -> u8 {
    let png = cdp::base64_decode(v["images"][0]["png"].as_str().unwrap()).unwrap();
    let img = image::load_from_memory(&png).unwrap().to_rgb8();
    img.pixels().map(|p| p[0].abs_diff(p[2])).max().unwrap()
}

#[test]
fn render_and_shader_take_rgb_and_give_colour() {
    let s = serve(&[]);
    let grey = ok_json(
        &s.addr,
        "/api/render?models=cook-torrance&f=schlick&f0=0.5&size=32",
    );
    let rgb = ok_json(
        &s.addr,
        "/api/render?models=cook-torrance&f=schlick&f0=0.9,0.5,0.1&size=32",
    );
    assert_eq!(colour_spread(&grey), 0, "a grey model renders grey");
    assert!(
        colour_spread(&rgb) > 20,
        "f0 = 0.9,0.5,0.1 renders red: spread {}",
        colour_spread(&rgb)
    );
    // The shader: the CLI's coloured export, in every language.
    for lang in ["wgsl", "glsl", "brdf-explorer"] {
        let (status, _, body) = request(
            &s.addr,
            "GET",
            &format!("/api/shader?model=cook-torrance&f=schlick&f0=0.9,0.5,0.1&lang={lang}"),
        );
        assert_eq!(status, 200, "{lang}");
        let text = String::from_utf8(body).unwrap();
        assert!(text.contains("fb_cook_torrance_rgb"), "{lang}");
        let o = fastbrdf(
            &[
                "shader",
                "--model",
                "cook-torrance",
                "--param",
                "f=schlick",
                "--param",
                "f0=0.9,0.5,0.1",
                "--lang",
                lang,
            ],
            "",
        );
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(text, stdout(&o), "{lang}");
    }
}

#[test]
fn albedo_checks_the_kind_before_the_values() {
    for args in [
        &["albedo", "--model", "ggx", "--param", "m=0.2"][..],
        &["albedo", "--model", "ggx", "--param", "alpha=7"],
        &["albedo", "--model", "ggx"],
    ] {
        let o = fastbrdf(args, "");
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&o).contains("model 'ggx' is a distribution, but a brdf or lobe is needed"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // A BRDF's bad value is still named as such.
    let o = fastbrdf(&["albedo", "--model", "ward", "--param", "m=0.2"], "");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("model 'ward' has no parameter 'm'"),
        "{}",
        stderr(&o)
    );
}

/// A metal colours the BRDF a distribution is shaded as, so a BRDF Explorer export of
/// `--model ggx --metal gold` is cook-torrance's: its header says so and its Made-by line
/// re-runs to the same file.
#[test]
fn a_shaded_metal_export_names_what_it_exports_and_re_runs() {
    for extra in [&[][..], &["--param", "alpha=0.2", "--param", "g=smith-ggx"]] {
        let mut args = vec![
            "shader",
            "--model",
            "ggx",
            "--metal",
            "gold",
            "--lang",
            "brdf-explorer",
        ];
        args.extend_from_slice(extra);
        let o = fastbrdf(&args, "");
        assert!(o.status.success(), "{}", stderr(&o));
        let text = stdout(&o);
        assert!(
            text.contains("(brdf): cook-torrance"),
            "{}",
            &text[..300.min(text.len())]
        );
        let made = text
            .lines()
            .find_map(|l| l.strip_prefix("# Made by: fastbrdf "))
            .expect("a Made-by line");
        assert!(made.contains("--param d=ggx"), "{made}");
        let again: Vec<&str> = made.split_whitespace().collect();
        let o2 = fastbrdf(&again, "");
        assert!(o2.status.success(), "{made}: {}", stderr(&o2));
        assert_eq!(stdout(&o2), text, "{made}");
    }
}
