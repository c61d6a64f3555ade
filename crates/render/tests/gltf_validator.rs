//! Every kind of glTF file the project writes passes the Khronos glTF-Validator (the
//! `gltf-validator` npm package, run by `tools/gltf_validate.mjs` under Node): the demo scene
//! `fastbrdf demo` writes (`scene.glb`, and the same document as `.gltf`), and documents that
//! use each material extension alone and all together, each kind of punctual light, a camera
//! with an aspect ratio and an infinite far plane, a node hierarchy, and 32-bit indices, each
//! as `.glb` and `.gltf`. Zero errors and zero warnings are required (each message is listed;
//! infos are counted only). A file with a known error must be reported as such, so the harness
//! itself can fail.
//!
//! Needs `node` and the validator: tools/test.sh installs the package into
//! target/gltf-validator and sets FASTBRDF_GLTF_VALIDATOR to its folder. Without them the
//! test is skipped with a message, except under CI (`CI` set), where it fails.

use fastbrdf_render::gltf_write::{
    Anisotropy, Camera, Clearcoat, Document, Light, LightKind, Material, Node, Sheen, Specular,
    demo_document, demo_scene, uv_sphere,
};
use glam::Vec3;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The validator's package folder, or why it cannot be used.
fn validator() -> Result<PathBuf, String> {
    let dir = match std::env::var_os("FASTBRDF_GLTF_VALIDATOR") {
        Some(d) => PathBuf::from(d),
        None => repo().join("target/gltf-validator/node_modules/gltf-validator"),
    };
    if !dir.join("package.json").is_file() {
        return Err(format!(
            "no gltf-validator at {} (tools/test.sh installs it; or set FASTBRDF_GLTF_VALIDATOR)",
            dir.display()
        ));
    }
    match Command::new("node").arg("--version").output() {
        Ok(o) if o.status.success() => Ok(dir),
        _ => Err("no `node` on PATH (the validator runs under Node.js)".into()),
    }
}

/// The validator, or `None` after saying why the test is skipped (a panic under CI).
fn need_validator() -> Option<PathBuf> {
    match validator() {
        Ok(d) => Some(d),
        Err(e) if std::env::var_os("CI").is_some() => panic!("CI is set: {e}"),
        Err(e) => {
            eprintln!("skipping the glTF-Validator test: {e}");
            None
        }
    }
}

/// Runs the validator on `files`: its exit status and one report per file.
fn validate(dir: &Path, files: &[PathBuf]) -> (i32, Vec<Value>) {
    let out = Command::new("node")
        .arg(repo().join("tools/gltf_validate.mjs"))
        .args(files)
        .env("FASTBRDF_GLTF_VALIDATOR", dir)
        .output()
        .expect("node runs");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let reports: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect();
    assert_eq!(
        reports.len(),
        files.len(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.code().unwrap_or(-1), reports)
}

/// A sphere of `material` (tangents and texture coordinates included), a camera, a light.
fn sphere_scene(material: Material, light: LightKind, rings: u32) -> Document {
    let mut d = Document::new();
    let g = d.add_geometry(uv_sphere(rings, 2 * rings));
    let m = d.add_material(material);
    let mesh = d.add_mesh("sphere", g, Some(m));
    let child = d.add_node(Node {
        name: "sphere".into(),
        mesh: Some(mesh),
        translation: Vec3::new(0.0, 0.5, 0.0),
        ..Node::default()
    });
    d.add_node(Node {
        name: "group".into(),
        scale: Vec3::new(2.0, 2.0, 2.0),
        children: vec![child],
        ..Node::default()
    });
    d.cameras.push(Camera {
        name: "camera".into(),
        yfov: 0.7,
        aspect_ratio: Some(16.0 / 9.0),
        znear: 0.05,
        zfar: None,
    });
    d.add_node(Node {
        camera: Some(0),
        ..Node::looking("camera", Vec3::new(0.0, 1.0, 6.0), Vec3::NEG_Z, Vec3::Y)
    });
    d.lights.push(Light {
        name: "light".into(),
        kind: light,
        color: [1.0, 0.9, 0.8],
        intensity: 5.0,
    });
    d.add_node(Node {
        light: Some(0),
        ..Node::looking(
            "light",
            Vec3::new(2.0, 3.0, 2.0),
            Vec3::new(-2.0, -3.0, -2.0),
            Vec3::Y,
        )
    });
    d
}

/// The documents: name and document.
fn documents() -> Vec<(String, Document)> {
    let base = Material {
        name: "base".into(),
        base_color: [0.8, 0.3, 0.1, 1.0],
        metallic: 0.0,
        roughness: 0.4,
        ..Material::default()
    };
    let ior = Some(1.45);
    let specular = Some(Specular {
        factor: 0.7,
        color: [1.0, 1.2, 0.9],
    });
    let clearcoat = Some(Clearcoat {
        factor: 1.0,
        roughness: 0.05,
    });
    let sheen = Some(Sheen {
        color: [0.9, 0.5, 0.7],
        roughness: 0.4,
    });
    let anisotropy = Some(Anisotropy {
        strength: 0.6,
        rotation: 0.8,
    });
    let every = Material {
        ior,
        specular,
        clearcoat,
        sheen,
        anisotropy,
        double_sided: true,
        ..base.clone()
    };
    let directional = LightKind::Directional;
    let mut docs = vec![
        ("demo".to_string(), demo_document()),
        ("plain".into(), sphere_scene(base.clone(), directional, 8)),
        (
            "ior".into(),
            sphere_scene(
                Material {
                    ior,
                    ..base.clone()
                },
                directional,
                8,
            ),
        ),
        (
            "specular".into(),
            sphere_scene(
                Material {
                    specular,
                    ..base.clone()
                },
                directional,
                8,
            ),
        ),
        (
            "clearcoat".into(),
            sphere_scene(
                Material {
                    clearcoat,
                    ..base.clone()
                },
                directional,
                8,
            ),
        ),
        (
            "sheen".into(),
            sphere_scene(
                Material {
                    sheen,
                    ..base.clone()
                },
                directional,
                8,
            ),
        ),
        (
            "anisotropy".into(),
            sphere_scene(
                Material {
                    anisotropy,
                    ..base.clone()
                },
                directional,
                8,
            ),
        ),
        (
            "every-extension-point-light".into(),
            sphere_scene(every.clone(), LightKind::Point { range: Some(20.0) }, 8),
        ),
        (
            "spot-light-u32-indices".into(),
            sphere_scene(
                every,
                LightKind::Spot {
                    range: None,
                    inner_cone: 0.3,
                    outer_cone: 0.6,
                },
                // 201 x 401 vertices: more than u16 indices hold.
                200,
            ),
        ),
    ];
    // A bare document: one mesh with the default material, no camera, no light.
    let mut bare = Document::new();
    let g = bare.add_geometry(uv_sphere(4, 6));
    let mesh = bare.add_mesh("", g, None);
    bare.add_node(Node {
        mesh: Some(mesh),
        ..Node::default()
    });
    docs.push(("bare".into(), bare));
    docs
}

#[test]
fn every_file_the_writer_makes_passes_the_khronos_validator() {
    let Some(dir) = need_validator() else { return };
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_validator");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let mut files = vec![];
    // The bytes `fastbrdf demo` writes as scene.glb.
    let scene = out.join("scene.glb");
    std::fs::write(&scene, demo_scene()).unwrap();
    files.push(scene);
    for (name, d) in documents() {
        let glb = out.join(format!("{name}.glb"));
        std::fs::write(&glb, d.to_glb().unwrap()).unwrap();
        let gltf = out.join(format!("{name}.gltf"));
        std::fs::write(&gltf, d.to_gltf().unwrap()).unwrap();
        files.extend([glb, gltf]);
    }
    let (status, reports) = validate(&dir, &files);
    let mut failures = vec![];
    for r in &reports {
        let (errors, warnings) = (
            r["errors"].as_u64().unwrap(),
            r["warnings"].as_u64().unwrap(),
        );
        eprintln!(
            "{}: {errors} errors, {warnings} warnings, {} infos (validator {})",
            r["file"].as_str().unwrap(),
            r["infos"],
            r["validator"].as_str().unwrap()
        );
        for m in r["messages"].as_array().unwrap() {
            eprintln!(
                "  {} {} at {}: {}",
                m["severity"], m["code"], m["pointer"], m["message"]
            );
        }
        if errors > 0 || warnings > 0 {
            failures.push(r["file"].as_str().unwrap().to_string());
        }
    }
    assert!(
        failures.is_empty(),
        "validator errors or warnings in {failures:?}"
    );
    assert_eq!(status, 0);
}

#[test]
fn the_validator_reports_a_file_with_an_error() {
    let Some(dir) = need_validator() else { return };
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_validator_bad");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    // The demo's JSON with the first POSITION accessor's max off by one: ACCESSOR_MAX_MISMATCH.
    let mut json: Value = serde_json::from_slice(&demo_document().to_gltf().unwrap()).unwrap();
    let pos = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .unwrap() as usize;
    let max = json["accessors"][pos]["max"][0].as_f64().unwrap();
    json["accessors"][pos]["max"][0] = (max + 1.0).into();
    let bad = out.join("bad.gltf");
    std::fs::write(&bad, serde_json::to_vec(&json).unwrap()).unwrap();
    let (status, reports) = validate(&dir, std::slice::from_ref(&bad));
    assert_eq!(status, 1, "{reports:?}");
    assert!(reports[0]["errors"].as_u64().unwrap() >= 1);
    let codes: Vec<&str> = reports[0]["messages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["code"].as_str().unwrap())
        .collect();
    assert!(codes.contains(&"ACCESSOR_MAX_MISMATCH"), "{codes:?}");
}
