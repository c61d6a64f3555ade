//! The built-in scene resources: the embedded face mesh (`--mesh face`) and the procedural
//! skin texture (`--texture skin`), by name through `setup::load`, and rendered together
//! under the built-in sky.

use fastbrdf::ModelSpec;
use fastbrdf_render::mesh::{FACE_OBJ, face, load_obj};
use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::Specular;
use fastbrdf_render::setup::{self, SceneSpec};
use glam::Vec3;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

#[test]
fn the_embedded_face_is_mediapipes_canonical_face() {
    let m = face();
    assert_eq!(m.triangles.len(), 898);
    let unique: HashSet<[u32; 3]> = m
        .positions
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect();
    assert_eq!(unique.len(), 468, "unique vertex positions");
    assert_eq!(
        FACE_OBJ.lines().filter(|l| l.starts_with("v ")).count(),
        468
    );
    assert!(!FACE_OBJ.contains("\nvn "), "the file has no normals");
    // Texture coordinates on every corner, inside the unit square; normals computed, unit.
    assert_eq!(m.uvs.len(), m.positions.len());
    assert!(
        m.uvs
            .iter()
            .all(|t| (0.0..=1.0).contains(&t.x) && (0.0..=1.0).contains(&t.y))
    );
    assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    // The same mesh as the file the repository carries (read from its path, not embedded).
    let file = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/canonical_face_model.obj"
    ));
    let s = load_obj(&file).unwrap();
    assert_eq!(s.positions, m.positions);
    assert_eq!(s.triangles, m.triangles);
    assert_eq!(s.uvs, m.uvs);
    // The licence notice travels with it.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let notice = std::fs::read_to_string(data.join("NOTICE.md")).unwrap();
    assert!(notice.contains("Apache License, Version 2.0") && notice.contains("mediapipe"));
    assert!(data.join("LICENSE-APACHE-2.0").exists());
}

#[test]
fn builtin_names_are_exact_words() {
    assert!(setup::is_builtin(Path::new("face"), setup::BUILTIN_MESH));
    assert!(!setup::is_builtin(Path::new("./face"), setup::BUILTIN_MESH));
    assert!(!setup::is_builtin(
        Path::new("face.obj"),
        setup::BUILTIN_MESH
    ));
    assert!(setup::is_builtin(Path::new("skin"), setup::BUILTIN_TEXTURE));
    assert!(!setup::is_builtin(
        Path::new("./skin"),
        setup::BUILTIN_TEXTURE
    ));
    // `./face` is a file: none here, so loading it fails with the file's error.
    let mut spec = SceneSpec::new();
    spec.mesh = Some(PathBuf::from("./face"));
    let e = setup::load(&spec)
        .err()
        .expect("no file ./face")
        .to_string();
    assert!(e.contains("./face") && e.contains("cannot read"), "{e}");
}

#[test]
fn the_face_with_the_skin_texture_renders_under_the_sky() {
    let mut spec = SceneSpec::new();
    spec.mesh = Some(PathBuf::from("face"));
    spec.texture = Some(PathBuf::from("skin"));
    spec.albedo = Vec3::ONE;
    spec.env = Some("sky".into());
    spec.env_samples = 2;
    let loaded = setup::load(&spec).unwrap();
    let specular = Specular::new(&ModelSpec::parse("ward", &[("alpha", "0.35")]).unwrap()).unwrap();
    let scene = setup::scene(&spec, &loaded, Arc::new(specular));
    let opts = Options {
        width: 64,
        height: 64,
        spp: 1,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    let film = render(&scene, &opts, &|_, _| {}).unwrap();
    // The centre (the nose) is lit skin: finite, warm (red over blue).
    let mut c = Vec3::ZERO;
    for y in 28..36 {
        for x in 28..36 {
            c += film.at(x, y);
        }
    }
    assert!(c.is_finite() && c.x > 0.0 && c.x > 1.2 * c.z, "centre {c}");
}
