//! Shader export: every model in every language against the golden files in
//! `tests/golden/shaders/` (default parameters), each validated by naga: WGSL parsed and
//! validated as it is; GLSL and the `.brdf` shader block parsed back with naga's GLSL front
//! end (inside a test entry point) and validated; HLSL and MSL come from a module naga
//! validated before translating, and must define the model's function.
//!
//! `FASTBRDF_BLESS=1 cargo test -p fastbrdf-gpu --test export` rewrites the golden files
//! (review the diff: the files are what users paste).

mod common;

use fastbrdf::model::Kind;
use fastbrdf::{params, registry};
use fastbrdf_gpu::export::{Form, Lang, export, export_form, exported_name, validate};
use fastbrdf_gpu::spec::function_name;
use std::path::PathBuf;

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/shaders")
}

/// A GLSL call of `f` for a model of `kind` (the same arguments as the WGSL entry point),
/// with `extra` runtime parameters (each 0.5).
fn glsl_call(f: &str, kind: Kind, extra: usize) -> String {
    let extra = ", 0.5".repeat(extra);
    match kind {
        Kind::Brdf => format!("{f}(vec3(0.0, 0.6, 0.8), vec3(0.0, -0.6, 0.8){extra})"),
        Kind::Shadowing => format!("{f}(0.8, 0.8, 0.9, 0.9{extra})"),
        Kind::Env => format!("{f}(0.9, 0.3{extra})"),
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => format!("{f}(0.9{extra})"),
    }
}

/// Parses GLSL functions back with naga's GLSL front end, inside a compute entry point that
/// calls `call`, and validates the result.
fn parse_glsl(functions: &str, call: &str, what: &str) {
    let src = format!(
        "#version 450\nlayout(local_size_x = 1) in;\n{functions}\nvoid main() {{\n    float r = {call};\n}}\n"
    );
    let mut front = naga::front::glsl::Frontend::default();
    let module = front
        .parse(
            &naga::front::glsl::Options::from(naga::ShaderStage::Compute),
            &src,
        )
        .unwrap_or_else(|e| panic!("{what}: naga cannot parse the GLSL back: {e:?}\n{src}"));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{what}: GLSL parsed back does not validate: {e:?}"));
}

fn check_one(id: &str, kind: Kind, lang: Lang, text: &str) {
    check_form(id, kind, lang, text, 0);
}

/// As `check_one`, for a function with `extra` runtime parameters after its inputs.
fn check_form(id: &str, kind: Kind, lang: Lang, text: &str, extra: usize) {
    let what = format!("{id} ({})", lang.name());
    let f = exported_name(&function_name(id), lang);
    assert!(text.contains("Formula: "), "{what}: no header");
    assert!(
        text.contains("Made by: fastbrdf shader --model"),
        "{what}: no command"
    );
    match lang {
        Lang::Wgsl => {
            validate(text, &what).unwrap();
            assert!(text.contains(&format!("fn {f}(")), "{what}: no {f}");
        }
        Lang::Glsl => {
            assert!(!text.contains("void main"), "{what}: entry point left in");
            assert!(!text.contains("#version"), "{what}: #version left in");
            parse_glsl(text, &glsl_call(&f, kind, extra), &what);
        }
        Lang::Hlsl | Lang::Msl => {
            assert!(text.contains(&format!("float {f}(")), "{what}: no {f}");
            assert!(
                !text.contains("[numthreads") && !text.contains("kernel void"),
                "{what}"
            );
        }
        Lang::BrdfExplorer => {
            assert!(text.starts_with("analytic\n"), "{what}: not a .brdf file");
            assert!(text.contains("::begin parameters\n") && text.contains("::end parameters\n"));
            let body = text
                .split("::begin shader\n")
                .nth(1)
                .and_then(|s| s.split("::end shader").next())
                .unwrap_or_else(|| panic!("{what}: no shader block"));
            assert!(body.contains("vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"));
            // BRDF Explorer declares a uniform per slider; here a global at its default.
            let params = text
                .split("::begin parameters\n")
                .nth(1)
                .and_then(|s| s.split("::end parameters").next())
                .unwrap();
            let mut globals = String::new();
            for line in params.lines() {
                let f: Vec<&str> = line.split_whitespace().collect();
                assert_eq!(f.len(), 5, "{what}: slider line '{line}'");
                assert_eq!(f[0], "float", "{what}");
                let (lo, hi, v): (f64, f64, f64) = (
                    f[2].parse().unwrap(),
                    f[3].parse().unwrap(),
                    f[4].parse().unwrap(),
                );
                assert!(lo <= v && v <= hi, "{what}: {line}");
                globals.push_str(&format!("float {} = {:?};\n", f[1], v));
            }
            let body = format!("{globals}{body}");
            parse_glsl(
                &body,
                "BRDF(vec3(0.0, 0.6, 0.8), vec3(0.0, -0.6, 0.8), vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)).x",
                &what,
            );
        }
    }
}

#[test]
fn every_model_in_every_language_matches_its_golden_file_and_validates() {
    let bless = std::env::var_os("FASTBRDF_BLESS").is_some();
    let dir = golden_dir();
    if bless {
        std::fs::create_dir_all(&dir).unwrap();
    }
    let mut stale = vec![];
    let mut count = 0;
    for e in registry::all() {
        for lang in Lang::ALL {
            let text = export(&common::spec(e.info.id, &[]), lang)
                .unwrap_or_else(|err| panic!("{} ({}): {err}", e.info.id, lang.name()));
            check_one(e.info.id, e.info.kind, lang, &text);
            let path = dir.join(format!("{}.{}", e.info.id, lang.extension()));
            if bless {
                std::fs::write(&path, &text).unwrap();
            } else {
                let want = std::fs::read_to_string(&path).unwrap_or_default();
                if want != text {
                    stale.push(path.display().to_string());
                }
            }
            count += 1;
        }
    }
    assert_eq!(count, registry::all().len() * Lang::ALL.len());
    assert!(count >= 200, "only {count} exports");
    assert!(
        stale.is_empty(),
        "{} exports differ from their golden files (FASTBRDF_BLESS=1 rewrites them):\n{}",
        stale.len(),
        stale.join("\n")
    );
    // No stray golden files for models that no longer exist.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names.len(),
        count,
        "golden folder has extra files: {names:?}"
    );
}

#[test]
fn parameters_reach_the_code_and_bad_ones_are_errors() {
    let a = export(&common::spec("pow", &[("n", "50")]), Lang::Wgsl).unwrap();
    assert!(a.contains("fb_lobe_pow(c, 50.0f)"), "{a}");
    assert!(a.contains("this export: n = 50"));
    let b = export(
        &common::spec(
            "cook-torrance",
            &[
                ("d", "beckmann-power16"),
                ("g", "v-cavity"),
                ("f", "schlick"),
                ("f0", "0.5"),
            ],
        ),
        Lang::Glsl,
    )
    .unwrap();
    assert!(b.contains("fb_d_beckmann_power16") && b.contains("fb_g_v_cavity"));
    assert!(b.contains("fb_f_schlick") && b.contains("0.5"));
    assert!(!b.contains("fb_g1_smith"), "unused library code exported");
    for (id, given) in [
        ("no-such-model", vec![]),
        ("pow", vec![("n", "0")]),
        ("pow", vec![("n", "NaN")]),
        ("pow", vec![("alpha", "0.3")]),
        ("beckmann", vec![("alpha", "0")]),
    ] {
        assert!(
            // Refused where text becomes a model (the CLI's --param, the explorer's query).
            fastbrdf::ModelSpec::parse(id, &given).is_err(),
            "{id} {given:?} accepted"
        );
    }
}

/// BRDF Explorer's value at slider position `x` (0..=1000), as its `FloatVarWidget` computes
/// it: `min + (x / 1000) (max - min)` in f32, shown in a text field with 6 significant digits
/// (`QString::setNum`) and read back from that text (`getValue`). Written here from BRDF
/// Explorer's source, independently of the exporter.
fn explorer_value(lo: f32, hi: f32, x: u32) -> f32 {
    let raw = lo + (x as f32 / 1000.0) * (hi - lo);
    explorer_text(raw)
}

/// A float through BRDF Explorer's text field (6 significant digits).
fn explorer_text(v: f32) -> f32 {
    format!("{:.5e}", v as f64).parse().unwrap()
}

/// Evaluates the exporter's slider-to-parameter line `clamp(V * exp2((U -/+ S) * K), A, B)`
/// or `clamp(V + (U -/+ S), A, B)` at `u`, in f32 as a GPU would.
fn mapped(expr: &str, u: f32) -> f32 {
    let t: Vec<&str> = expr
        .split(|c: char| "(),*".contains(c) || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .collect();
    let num = |s: &str| -> f32 { s.parse().unwrap_or_else(|_| panic!("'{s}' in {expr}")) };
    if t[2] == "exp2" {
        // clamp V exp2 U op S K A B
        let s = if t[4] == "-" { -num(t[5]) } else { num(t[5]) };
        let v = num(t[1]) * ((u + s) * num(t[6])).exp2();
        v.clamp(num(t[7]), num(t[8]))
    } else {
        // clamp V + U op S A B
        let s = if t[4] == "-" { -num(t[5]) } else { num(t[5]) };
        (num(t[1]) + (u + s)).clamp(num(t[6]), num(t[7]))
    }
}

#[test]
fn brdf_explorer_sliders_reach_their_defaults_and_wide_ranges_are_logarithmic() {
    use fastbrdf::params::ParamKind;
    let mut cases: Vec<(String, Vec<(&str, &str)>)> = registry::all()
        .iter()
        .map(|e| (e.info.id.to_string(), vec![]))
        .collect();
    for (id, given) in [
        ("pow", vec![("n", "37.3")]),
        ("pow", vec![("n", "1")]),
        ("pow", vec![("n", "10000")]),
        ("sg", vec![("n", "1.01")]),
        ("beckmann", vec![("alpha", "0.01")]),
        ("beckmann", vec![("alpha", "1")]),
        ("beckmann", vec![("alpha", "0.137")]),
        (
            "cook-torrance",
            vec![("f", "schlick"), ("f0", "0.0437"), ("alpha", "0.0123")],
        ),
        ("ward", vec![("alpha_x", "0.1"), ("alpha_y", "0.4")]),
        (
            "cook-torrance",
            vec![
                ("d", "ggx"),
                ("g", "smith-ggx-correlated"),
                ("alpha_x", "0.05"),
                ("alpha_y", "0.4"),
            ],
        ),
        ("fresnel-dielectric", vec![("eta", "1.0001")]),
        ("fresnel-conductor", vec![("eta", "0.2"), ("k", "3.3")]),
        ("lambert", vec![("albedo", "0.7")]),
    ] {
        cases.push((id.to_string(), given));
    }
    let mut sliders = 0;
    let mut logs = 0;
    for (id, given) in &cases {
        let text = export(&common::spec(id, given), Lang::BrdfExplorer).unwrap();
        let what = format!("{id} {given:?}");
        let info = &registry::find(id).unwrap().info;
        // The model BRDF Explorer evaluates: lobes through blinn-phong, distributions through
        // cook-torrance (the export's header says so).
        let shaded = match info.kind {
            Kind::Lobe => "blinn-phong",
            Kind::Distribution => "cook-torrance",
            _ => id.as_str(),
        };
        let specs = registry::find(shaded).unwrap().info.params;
        let params = text
            .split("::begin parameters\n")
            .nth(1)
            .and_then(|s| s.split("::end parameters").next())
            .unwrap();
        for line in params.lines() {
            let f: Vec<&str> = line.split_whitespace().collect();
            let (uniform, lo, hi, default): (&str, f32, f32, f32) = (
                f[1],
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
                f[4].parse().unwrap(),
            );
            sliders += 1;
            // What BRDF Explorer starts with: the default through its text field.
            let start = explorer_text(default);
            assert!(lo <= start && start <= hi, "{what}: {line}");
            let reachable = (0..=1000).find(|&x| explorer_value(lo, hi, x) == start);
            assert!(
                reachable.is_some(),
                "{what}: default {start} of '{line}' is no slider position"
            );
            let name = uniform
                .strip_prefix("log10_")
                .or_else(|| uniform.strip_suffix("_slider"))
                .unwrap_or(uniform);
            // A split-sum term's alpha is an input with ALPHA's range (its own slider).
            let env_alpha = (info.kind == Kind::Env && name == "alpha").then_some(&params::ALPHA);
            let spec = specs
                .iter()
                .find(|p| p.name == name)
                .or(env_alpha)
                .unwrap_or_else(|| panic!("{what}: slider {uniform} of no parameter"));
            let ParamKind::Number { min, max, .. } = spec.kind else {
                panic!("{what}: {name} is not numeric")
            };
            let value: f64 = given
                .iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.parse().unwrap())
                .or(match spec.kind {
                    ParamKind::Number { default, .. } => default,
                    _ => None,
                })
                .unwrap_or_else(|| {
                    // An optional slope (ward's alpha_y): the export's header has the value.
                    let shown = text.split("this export: ").nth(1).unwrap();
                    let item = shown
                        .split([',', ')'])
                        .find(|s| s.trim().starts_with(&format!("{name} = ")))
                        .unwrap();
                    item.trim()[name.len() + 3..].parse().unwrap()
                });
            let wide = min > 0.0 && max / min >= 100.0;
            assert_eq!(
                uniform.starts_with("log10_"),
                wide,
                "{what}: {name} in [{min}, {max}] must be log-mapped exactly when it spans 2 decades"
            );
            if uniform == name {
                // A plain slider over the documented range, the parameter itself.
                assert_eq!((lo as f64, hi as f64), (min, max), "{what}: {line}");
                assert_eq!(start, value as f32, "{what}: {line}");
                continue;
            }
            if wide {
                logs += 1;
            }
            let decl = format!("float p_{name} = ");
            let expr = text
                .lines()
                .find_map(|l| l.trim().strip_prefix(&decl))
                .unwrap_or_else(|| panic!("{what}: no '{decl}' in the shader"))
                .trim_end_matches(';');
            // At the default (and its slider position), exactly the export's value; at the ends
            // of the slider, the ends of the documented range.
            assert_eq!(mapped(expr, start), value as f32, "{what}: {expr}");
            assert_eq!(
                mapped(expr, explorer_value(lo, hi, reachable.unwrap())),
                value as f32
            );
            assert_eq!(
                mapped(expr, explorer_value(lo, hi, 0)),
                min as f32,
                "{what}"
            );
            // The top of a lobe's n slider may stop below the documented maximum (the
            // export's comment says where; `lobe_n_max`).
            let top = text
                .lines()
                .find_map(|l| l.strip_prefix(&format!("# The {name} slider stops at ")))
                .map_or(max, |r| {
                    r.split_whitespace().next().unwrap().parse().unwrap()
                });
            assert!(top <= max, "{what}: {name} stops at {top} > {max}");
            assert_eq!(
                mapped(expr, explorer_value(lo, hi, 1000)),
                top as f32,
                "{what}"
            );
        }
    }
    assert!(
        sliders >= 40 && logs >= 30,
        "{sliders} sliders, {logs} logarithmic"
    );
}

/// The runtime parameters of model `id`'s default export (`p_<name>` arguments, in order).
fn runtime_params(id: &str) -> Vec<String> {
    fastbrdf_gpu::spec::Instance::runtime(&common::spec(id, &[]))
        .unwrap()
        .sliders
        .into_iter()
        .map(|(n, _)| n)
        .collect()
}

#[test]
fn every_model_exports_with_runtime_parameters_in_every_language() {
    let bless = std::env::var_os("FASTBRDF_BLESS").is_some();
    let dir = golden_dir().join("runtime");
    if bless {
        std::fs::create_dir_all(&dir).unwrap();
    }
    let mut stale = vec![];
    let mut count = 0;
    for e in registry::all() {
        let params = runtime_params(e.info.id);
        // Every numeric parameter of a lobe or a distribution shapes it: all are arguments.
        if matches!(e.info.kind, Kind::Lobe | Kind::Distribution) {
            assert!(!params.is_empty(), "{}: no runtime parameter", e.info.id);
        }
        for lang in [Lang::Wgsl, Lang::Glsl, Lang::Hlsl, Lang::Msl] {
            let text = export_form(&common::spec(e.info.id, &[]), lang, Form::Runtime)
                .unwrap_or_else(|err| panic!("{} ({}): {err}", e.info.id, lang.name()));
            check_form(e.info.id, e.info.kind, lang, &text, params.len());
            assert!(
                text.contains("--runtime-params"),
                "{}: no flag in the header",
                e.info.id
            );
            for p in &params {
                assert!(
                    text.contains(&format!("p_{p}")),
                    "{} ({}): no argument p_{p}",
                    e.info.id,
                    lang.name()
                );
            }
            // No coefficient was baked in: a literal export of other parameters differs, a
            // runtime export does not.
            let path = dir.join(format!("{}.{}", e.info.id, lang.extension()));
            if bless {
                std::fs::write(&path, &text).unwrap();
            } else if std::fs::read_to_string(&path).unwrap_or_default() != text {
                stale.push(path.display().to_string());
            }
            count += 1;
        }
    }
    assert_eq!(count, registry::all().len() * 4);
    let files = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(files, count, "stray files in {}", dir.display());
    assert!(
        stale.is_empty(),
        "{} runtime exports differ from their golden files (FASTBRDF_BLESS=1 rewrites them):\n{}",
        stale.len(),
        stale.join("\n")
    );
}

#[test]
fn a_runtime_export_does_not_depend_on_the_parameters_it_takes() {
    // The function body is the same whatever the exported parameter values: they only change
    // the header's defaults. Compare the code after the header.
    let code = |n: &str| {
        let t = export_form(
            &common::spec("cubic", &[("n", n)]),
            Lang::Wgsl,
            Form::Runtime,
        )
        .unwrap();
        t.lines()
            .skip_while(|l| l.starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(code("20"), code("700"));
    let lit = |n: &str| export(&common::spec("cubic", &[("n", n)]), Lang::Wgsl).unwrap();
    assert_ne!(lit("20"), lit("700"));
}

/// A coloured model (issue 14): gold Cook-Torrance (GGX) in every language against the golden
/// files in `tests/golden/shaders/colour/`, validated like the grey ones; each channel
/// function is the grey export of that channel's parameters, renamed; the runtime form is
/// refused.
#[test]
fn a_coloured_model_exports_three_channels_and_a_vector() {
    let bless = std::env::var_os("FASTBRDF_BLESS").is_some();
    let dir = golden_dir().join("colour");
    if bless {
        std::fs::create_dir_all(&dir).unwrap();
    }
    let gold = fastbrdf::colour::metal("gold").unwrap();
    let three = |v: [f64; 3]| format!("{},{},{}", v[0], v[1], v[2]);
    let (eta, k) = (three(gold.eta), three(gold.k));
    let given = [
        ("d", "ggx"),
        ("alpha", "0.2"),
        ("f", "conductor"),
        ("eta", eta.as_str()),
        ("k", k.as_str()),
    ];
    let call = "fb_cook_torrance_rgb(vec3(0.0, 0.6, 0.8), vec3(0.0, -0.6, 0.8)).x";
    let mut stale = vec![];
    for lang in Lang::ALL {
        let what = format!("gold cook-torrance ({})", lang.name());
        let text = export(&common::spec("cook-torrance", &given), lang)
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(text.contains("Colour: per-channel parameters"), "{what}");
        match lang {
            Lang::Wgsl => {
                validate(&text, &what).unwrap();
                for c in ["r", "g", "b"] {
                    assert!(
                        text.contains(&format!("fn fb_cook_torrance_{c}(")),
                        "{what}"
                    );
                }
                assert!(text.contains("-> vec3<f32>"), "{what}");
            }
            Lang::Glsl => parse_glsl(&text, call, &what),
            Lang::Hlsl => assert!(text.contains("float3 fb_cook_torrance_rgb("), "{what}"),
            Lang::Msl => assert!(
                text.contains("metal::float3 fb_cook_torrance_rgb("),
                "{what}"
            ),
            Lang::BrdfExplorer => {
                let body = text
                    .split("::begin shader\n")
                    .nth(1)
                    .and_then(|s| s.split("::end shader").next())
                    .unwrap();
                assert!(
                    body.contains("return fb_cook_torrance_rgb(wi, wo);"),
                    "{what}"
                );
                parse_glsl(
                    body,
                    "BRDF(vec3(0.0, 0.6, 0.8), vec3(0.0, -0.6, 0.8), vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0)).x",
                    &what,
                );
            }
        }
        let path = dir.join(format!("cook-torrance-gold.{}", lang.extension()));
        if bless {
            std::fs::write(&path, &text).unwrap();
        } else if std::fs::read_to_string(&path).unwrap_or_default() != text {
            stale.push(path.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "coloured exports differ from their golden files (FASTBRDF_BLESS=1 rewrites them):\n{}",
        stale.join("\n")
    );
    // Each channel is the grey export of its parameters.
    let wgsl = export(&common::spec("cook-torrance", &given), Lang::Wgsl).unwrap();
    for (c, name) in ["r", "g", "b"].iter().enumerate() {
        let (e, kk) = (gold.eta[c].to_string(), gold.k[c].to_string());
        let grey = export(
            &common::spec(
                "cook-torrance",
                &[
                    ("d", "ggx"),
                    ("alpha", "0.2"),
                    ("f", "conductor"),
                    ("eta", &e),
                    ("k", &kk),
                ],
            ),
            Lang::Wgsl,
        )
        .unwrap();
        let start = grey.find("fn fb_cook_torrance(").unwrap();
        let body = &grey[start..];
        let body = &body[..body.find("\n}\n").unwrap()];
        let renamed = body.replacen("fb_cook_torrance(", &format!("fb_cook_torrance_{name}("), 1);
        assert!(wgsl.contains(&renamed), "channel {name}: {renamed}");
    }
    let err = export_form(
        &common::spec("cook-torrance", &given),
        Lang::Glsl,
        Form::Runtime,
    )
    .unwrap_err();
    assert!(err.to_string().contains("--runtime-params"), "{err}");
}

/// issue 14: anisotropic `cook-torrance` exports in every language and form; its runtime form
/// takes `p_alpha_x`, `p_alpha_y` (its parts read `sqrt(p_alpha_x * p_alpha_y)` where an
/// isotropic one reads `p_alpha`), not `p_alpha`, and the literal form calls the stretch.
#[test]
fn anisotropic_cook_torrance_exports_with_both_slopes() {
    for (d, g) in [("ggx", "smith-ggx-correlated"), ("beckmann", "smith")] {
        let given = [("d", d), ("g", g), ("alpha_x", "0.05"), ("alpha_y", "0.4")];
        let params = fastbrdf_gpu::spec::Instance::runtime(&common::spec("cook-torrance", &given))
            .unwrap()
            .sliders
            .into_iter()
            .map(|(n, _)| n)
            .collect::<Vec<_>>();
        assert_eq!(params, ["alpha_x", "alpha_y"], "{d} {g}");
        for lang in [Lang::Wgsl, Lang::Glsl, Lang::Hlsl, Lang::Msl] {
            let text = export(&common::spec("cook-torrance", &given), lang).unwrap();
            check_one("cook-torrance", Kind::Brdf, lang, &text);
            let rt =
                export_form(&common::spec("cook-torrance", &given), lang, Form::Runtime).unwrap();
            check_form("cook-torrance", Kind::Brdf, lang, &rt, 2);
            assert!(
                rt.contains("p_alpha_x") && rt.contains("p_alpha_y"),
                "{d} {g}"
            );
            let code: String = rt
                .lines()
                .filter(|l| !l.starts_with("//"))
                .collect::<Vec<_>>()
                .join("\n");
            assert!(
                !code.contains("p_alpha)")
                    && !code.contains("p_alpha,")
                    && !code.contains("p_alpha *"),
                "{d} {g} {}: {code}",
                lang.name()
            );
        }
        let wgsl = export(&common::spec("cook-torrance", &given), Lang::Wgsl).unwrap();
        assert!(wgsl.contains("fb_aniso_cos(") && wgsl.contains("fb_aniso_sin2("));
    }
}

/// BRDF Explorer's `n` slider of every lobe (shaded through Blinn-Phong) and of Phong and
/// Blinn-Phong with every lobe stops where the f32 shader's lobe still holds the lobe's
/// documented error: at the slider's top, the lobe moved by the shader's rounding of its
/// cosine (`LOBE_ARG_ULPS`) stays within `lobe_tolerance`; and the slider does reach that top
/// (issue 27: the slider reached n = 1e5, where `power4-tuned` was off by 0.82 of its peak).
#[test]
fn brdf_explorer_n_sliders_stop_where_the_f32_lobe_holds_its_bound() {
    use fastbrdf_gpu::export::{lobe_argument_error, lobe_tolerance};
    let mut cases = vec![];
    for lobe in registry::ids_of(Kind::Lobe) {
        cases.push((lobe.to_string(), vec![], lobe));
        for brdf in ["phong", "blinn-phong"] {
            cases.push((brdf.to_string(), vec![("lobe", lobe)], lobe));
        }
    }
    let mut capped = 0;
    for (id, given, lobe) in &cases {
        let text = export(&common::spec(id, given), Lang::BrdfExplorer).unwrap();
        let line = text
            .lines()
            .find(|l| l.starts_with("float log10_n "))
            .unwrap_or_else(|| panic!("{id} {given:?}: no log10_n slider"));
        let f: Vec<&str> = line.split_whitespace().collect();
        let (lo, hi): (f32, f32) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        let expr = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("float p_n = "))
            .unwrap()
            .trim_end_matches(';');
        let top = mapped(expr, explorer_value(lo, hi, 1000)) as f64;
        let (err, tol) = (
            lobe_argument_error(lobe, top).unwrap(),
            lobe_tolerance(lobe, top).unwrap(),
        );
        eprintln!("{id} {given:?}: n up to {top}, error {err:.3e} (bound {tol})");
        assert!(
            err <= tol,
            "{id} {given:?}: at the slider's top n = {top} the lobe errs {err:.3e} > {tol}"
        );
        capped += usize::from(top < params::N_MAX);
    }
    assert!(capped > 0, "no slider capped");
}
