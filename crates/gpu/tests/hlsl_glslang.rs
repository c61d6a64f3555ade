//! Every HLSL export compiles with glslang's HLSL front end (`glslangValidator -D -V`), the
//! usual HLSL-to-SPIR-V path besides DXC (issue 27): every model, every combination of its
//! choice parameters that `fastbrdf::accuracy::domain_configs` covers (cook-torrance's `ms`
//! tables, env-brdf's quadrature tables), coefficients as literals and at run time, and a
//! coloured export. naga writes constant arrays as calls of a constructor function, which
//! glslang rejects in a static initialiser ("Recursion detected", glslang issue 1216):
//! `export::initialiser_lists` rewrites them.
//!
//! glslang is Debian's `glslang-tools` (`tools/test.sh` installs it). Without it the test
//! skips with a message, except when `CI` is set: there it fails.

mod common;

use fastbrdf::model::Kind;
use fastbrdf::params::ParamKind;
use fastbrdf::registry;
use fastbrdf_gpu::export::{Form, Lang, export_form, exported_name, initialiser_lists};
use fastbrdf_gpu::spec::{Instance, function_name};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `glslangValidator`, or `None` (skip) without it; under `CI` a missing one panics.
fn glslang() -> Option<&'static str> {
    let found = Command::new("glslangValidator")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some("glslangValidator");
    }
    if std::env::var_os("CI").is_some() {
        panic!("CI is set and glslangValidator is missing (Debian's glslang-tools)");
    }
    eprintln!("skipping the glslang HLSL test: no glslangValidator (Debian's glslang-tools)");
    None
}

/// An HLSL call of `f` for a model of `kind` with `extra` runtime parameters (each 0.5).
fn hlsl_call(f: &str, kind: Kind, extra: usize) -> String {
    let extra = ", 0.5".repeat(extra);
    match kind {
        Kind::Brdf => format!("{f}(float3(0.0, 0.6, 0.8), float3(0.0, -0.6, 0.8){extra})"),
        Kind::Shadowing => format!("{f}(0.8, 0.8, 0.9, 0.9{extra})"),
        Kind::Env => format!("{f}(0.9, 0.3{extra})"),
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => format!("{f}(0.9{extra})"),
    }
}

/// Compiles `hlsl` with a compute entry point that stores `call` (an expression of type
/// `ty`); returns glslang's complaint on failure.
fn compile(
    tool: &str,
    dir: &Path,
    name: &str,
    hlsl: &str,
    call: &str,
    ty: &str,
) -> Result<(), String> {
    let path = dir.join(format!("{name}.hlsl"));
    let src = format!(
        "{hlsl}\nRWStructuredBuffer<{ty}> fb_test_out : register(u0);\n\
         [numthreads(1, 1, 1)]\nvoid fb_test_main() {{\n    fb_test_out[0] = {call};\n}}\n"
    );
    std::fs::write(&path, &src).unwrap();
    let out = Command::new(tool)
        .args(["-D", "-V", "-S", "comp", "-e", "fb_test_main", "-o"])
        .arg(dir.join(format!("{name}.spv")))
        .arg(&path)
        .output()
        .unwrap();
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fastbrdf-hlsl-glslang-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Parameter lists that together give every option of every choice parameter of a model
/// (the configurations of `domain_configs`, which honour the options' requirements, kept
/// while each brings an option not seen yet): the shader text of a model depends on its
/// choices, and each option's code is compiled at least once.
fn choice_configs(info: &fastbrdf::ModelInfo) -> Vec<Vec<(String, String)>> {
    let choices: Vec<&str> = info
        .params
        .iter()
        .filter(|p| matches!(p.kind, ParamKind::Choice { .. }))
        .map(|p| p.name)
        .collect();
    let mut seen = BTreeSet::new();
    let mut kept = vec![];
    for c in fastbrdf::accuracy::domain_configs(info, true)
        .iter()
        .map(|s| s.pairs())
    {
        let mut new = kept.is_empty();
        for (k, v) in &c {
            if choices.contains(&k.as_str()) {
                new |= seen.insert((k.clone(), v.clone()));
            }
        }
        if new {
            kept.push(c);
        }
    }
    kept
}

#[test]
fn every_hlsl_export_compiles_with_glslang() {
    let Some(tool) = glslang() else { return };
    let dir = scratch();
    // The exports first, then glslang on every core (one process per export: 2x on CI's
    // two cores, where the test took minutes).
    let mut jobs: Vec<(String, String, String)> = vec![];
    let mut tables = 0;
    for e in registry::all() {
        let id = e.info.id;
        let f = exported_name(&function_name(id), Lang::Hlsl);
        for config in choice_configs(&e.info) {
            let given: Vec<(&str, &str)> = config
                .iter()
                .map(|(a, b)| (a.as_str(), b.as_str()))
                .collect();
            for form in [Form::Literals, Form::Runtime] {
                let extra = match form {
                    Form::Literals => 0,
                    Form::Runtime => Instance::runtime(&common::spec(id, &given))
                        .unwrap()
                        .sliders
                        .len(),
                };
                let text = export_form(&common::spec(id, &given), Lang::Hlsl, form)
                    .unwrap_or_else(|err| panic!("{id} {given:?}: {err}"));
                tables += usize::from(text.contains("] = { "));
                jobs.push((
                    format!("{id} {given:?} {form:?}"),
                    text,
                    hlsl_call(&f, e.info.kind, extra),
                ));
            }
        }
    }
    let count = jobs.len();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let mut failures: Vec<(usize, String)> = std::thread::scope(|sc| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                sc.spawn(|| {
                    let mut failed = vec![];
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some((what, text, call)) = jobs.get(k) else {
                            return failed;
                        };
                        let name = format!("export-{k}");
                        if let Err(msg) = compile(tool, &dir, &name, text, call, "float") {
                            failed.push((k, format!("{what}: {msg}")));
                        }
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    failures.sort();
    let mut failures: Vec<String> = failures.into_iter().map(|(_, m)| m).collect();
    // A coloured export: three grey instances and the vector function.
    let text = export_form(
        &common::spec(
            "cook-torrance",
            &[
                ("d", "ggx"),
                ("g", "smith-ggx-correlated"),
                ("ms", "kulla-conty"),
                ("f", "schlick"),
                ("f0", "0.9,0.6,0.3"),
            ],
        ),
        Lang::Hlsl,
        Form::Literals,
    )
    .unwrap();
    let f = exported_name("fb_cook_torrance_rgb", Lang::Hlsl);
    if let Err(msg) = compile(
        tool,
        &dir,
        "colour",
        &text,
        &hlsl_call(&f, Kind::Brdf, 0),
        "float3",
    ) {
        failures.push(format!("coloured cook-torrance: {msg}"));
    }
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("{count} HLSL exports compiled by glslang, {tables} with constant tables");
    // The tables are there to be tested: env-brdf and both energy compensations.
    assert!(tables >= 4, "only {tables} exports with constant tables");
    assert!(
        failures.is_empty(),
        "{} of {count} HLSL exports fail in glslang:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn constant_arrays_become_initialiser_lists_and_unused_constructors_go() {
    let naga_text = "typedef float ret_Constructarray2_float_[2];\n\
        ret_Constructarray2_float_ Constructarray2_float_(float arg0, float arg1) {\n    \
        float ret[2] = { arg0, arg1 };\n    return ret;\n}\n\n\
        static const float T[2] = Constructarray2_float_(0.5, -1.0);\n\
        float f(int i) {\n    return T[i];\n}\n";
    let out = initialiser_lists(naga_text);
    assert_eq!(
        out,
        "static const float T[2] = { 0.5, -1.0 };\nfloat f(int i) {\n    return T[i];\n}\n"
    );
    // A constructor still called in a function body stays.
    let used =
        format!("{naga_text}float g() {{\n    return Constructarray2_float_(1.0, 2.0)[0];\n}}\n");
    let out = initialiser_lists(&used);
    assert!(out.contains("static const float T[2] = { 0.5, -1.0 };"));
    assert!(out.contains("ret_Constructarray2_float_ Constructarray2_float_("));
    assert!(out.contains("typedef float ret_Constructarray2_float_[2];"));
}
