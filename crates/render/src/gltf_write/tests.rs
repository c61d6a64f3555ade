//! The writer's own checks: the GLB container's layout, the JSON read back by the `gltf`
//! crate (a second, independent parser), the document checks, the sphere's geometry and the
//! demo scene's determinism. That the files are valid glTF is the Khronos validator's job
//! (`tests/gltf_validator.rs`).

use super::*;
use serde_json::Value;

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// One sphere with one material, a camera and a light of `kind`.
fn one_sphere(material: Material, kind: LightKind) -> Document {
    let mut d = Document::new();
    let g = d.add_geometry(uv_sphere(6, 8));
    let m = d.add_material(material);
    let mesh = d.add_mesh("sphere", g, Some(m));
    d.add_node(Node {
        mesh: Some(mesh),
        ..Node::default()
    });
    d.cameras.push(Camera {
        name: "cam".into(),
        yfov: 0.5,
        aspect_ratio: Some(1.5),
        znear: 0.1,
        zfar: None,
    });
    d.add_node(Node {
        camera: Some(0),
        ..Node::looking("cam", Vec3::new(0.0, 0.0, 4.0), Vec3::NEG_Z, Vec3::Y)
    });
    d.lights.push(Light {
        name: "l".into(),
        kind,
        color: [1.0, 0.5, 0.25],
        intensity: 2.0,
    });
    d.add_node(Node {
        light: Some(0),
        ..Node::looking(
            "l",
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-1.0, -2.0, -3.0),
            Vec3::Y,
        )
    });
    d
}

#[test]
fn glb_layout_and_gltf_data_uri_hold_the_same_document() {
    let d = demo_document();
    let glb = d.to_glb().unwrap();
    assert_eq!(&glb[0..4], b"glTF");
    assert_eq!(u32_at(&glb, 4), 2);
    assert_eq!(u32_at(&glb, 8) as usize, glb.len());
    let json_len = u32_at(&glb, 12) as usize;
    assert_eq!(&glb[16..20], b"JSON");
    assert_eq!(json_len % 4, 0);
    let json: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = u32_at(&glb, bin_at) as usize;
    assert_eq!(&glb[bin_at + 4..bin_at + 8], b"BIN\0");
    assert_eq!(bin_len % 4, 0);
    assert_eq!(bin_at + 8 + bin_len, glb.len());
    let byte_length = json["buffers"][0]["byteLength"].as_u64().unwrap() as usize;
    assert!(byte_length <= bin_len && bin_len - byte_length < 4);
    assert!(json["buffers"][0].get("uri").is_none());
    // The .gltf form: the same JSON plus the buffer as a data URI.
    let text: Value = serde_json::from_slice(&d.to_gltf().unwrap()).unwrap();
    let uri = text["buffers"][0]["uri"].as_str().unwrap();
    let b64 = uri
        .strip_prefix("data:application/octet-stream;base64,")
        .unwrap();
    use base64::Engine;
    let bin = base64::engine::general_purpose::STANDARD
        .decode(b64)
        .unwrap();
    assert_eq!(bin, &glb[bin_at + 8..bin_at + 8 + byte_length]);
    let mut without = text.clone();
    without["buffers"][0].as_object_mut().unwrap().remove("uri");
    assert_eq!(without, json);
}

#[test]
fn the_gltf_crate_reads_back_what_was_written() {
    let mut m = Material {
        name: "all".into(),
        base_color: [0.9, 0.6, 0.2, 1.0],
        metallic: 0.25,
        roughness: 0.7,
        ior: Some(1.33),
        specular: Some(Specular {
            factor: 0.5,
            color: [1.0, 0.8, 2.0],
        }),
        clearcoat: Some(Clearcoat {
            factor: 0.75,
            roughness: 0.1,
        }),
        sheen: Some(Sheen {
            color: [0.2, 0.3, 0.4],
            roughness: 0.6,
        }),
        anisotropy: Some(Anisotropy {
            strength: 0.4,
            rotation: 1.2,
        }),
        ..Material::default()
    };
    m.double_sided = true;
    let spot = LightKind::Spot {
        range: Some(10.0),
        inner_cone: 0.2,
        outer_cone: 0.5,
    };
    let d = one_sphere(m, spot);
    let glb = d.to_glb().unwrap();
    let g = gltf::Gltf::from_slice(&glb).unwrap();
    let mat = g.materials().next().unwrap();
    let pbr = mat.pbr_metallic_roughness();
    assert_eq!(pbr.base_color_factor(), [0.9, 0.6, 0.2, 1.0]);
    assert_eq!(pbr.metallic_factor(), 0.25);
    assert_eq!(pbr.roughness_factor(), 0.7);
    assert!(mat.double_sided());
    assert_eq!(mat.ior(), Some(1.33));
    let s = mat.specular().unwrap();
    assert_eq!(s.specular_factor(), 0.5);
    assert_eq!(s.specular_color_factor(), [1.0, 0.8, 2.0]);
    // The extensions the gltf crate has no type for, from the raw JSON.
    let json: Value = serde_json::from_slice(&d.to_gltf().unwrap()).unwrap();
    let ext = &json["materials"][0]["extensions"];
    assert_eq!(ext["KHR_materials_clearcoat"]["clearcoatFactor"], 0.75);
    assert_eq!(
        ext["KHR_materials_clearcoat"]["clearcoatRoughnessFactor"],
        0.1
    );
    assert_eq!(
        ext["KHR_materials_sheen"]["sheenColorFactor"],
        serde_json::json!([0.2, 0.3, 0.4])
    );
    assert_eq!(ext["KHR_materials_sheen"]["sheenRoughnessFactor"], 0.6);
    assert_eq!(ext["KHR_materials_anisotropy"]["anisotropyStrength"], 0.4);
    assert_eq!(ext["KHR_materials_anisotropy"]["anisotropyRotation"], 1.2);
    let mut used: Vec<&str> = json["extensionsUsed"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    used.sort();
    assert_eq!(
        used,
        [
            "KHR_lights_punctual",
            "KHR_materials_anisotropy",
            "KHR_materials_clearcoat",
            "KHR_materials_ior",
            "KHR_materials_sheen",
            "KHR_materials_specular"
        ]
    );
    // Geometry: the accessors hold the sphere's data.
    let prim = g.meshes().next().unwrap().primitives().next().unwrap();
    let sphere = uv_sphere(6, 8);
    let pos = prim.get(&gltf::Semantic::Positions).unwrap();
    assert_eq!(pos.count(), sphere.positions.len());
    assert_eq!(pos.min().unwrap(), serde_json::json!([-1.0, -1.0, -1.0]));
    assert_eq!(prim.indices().unwrap().count(), sphere.triangles.len() * 3);
    assert!(prim.get(&gltf::Semantic::Tangents).is_some());
    assert!(prim.get(&gltf::Semantic::TexCoords(0)).is_some());
    // Camera, light and transforms.
    let cam = g.cameras().next().unwrap();
    let gltf::camera::Projection::Perspective(p) = cam.projection() else {
        panic!("not perspective")
    };
    assert_eq!(
        (p.yfov(), p.aspect_ratio(), p.zfar()),
        (0.5, Some(1.5), None)
    );
    let light = g.lights().unwrap().next().unwrap();
    assert!(matches!(
        light.kind(),
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle: 0.2,
            outer_cone_angle: 0.5
        }
    ));
    assert_eq!(light.range(), Some(10.0));
    assert_eq!(light.color(), [1.0, 0.5, 0.25]);
    let node = g.nodes().find(|n| n.light().is_some()).unwrap();
    let (t, r, _) = node.transform().decomposed();
    assert_eq!(t, [1.0, 2.0, 3.0]);
    // Its -z axis points along the direction it was given.
    let minus_z = Quat::from_array(r) * Vec3::NEG_Z;
    let want = Vec3::new(-1.0, -2.0, -3.0).normalize();
    assert!(minus_z.distance(want) < 1e-5, "{minus_z} != {want}");
}

#[test]
fn indices_are_u16_until_the_vertices_need_u32() {
    for (rings, u32_wanted) in [(100u32, false), (200, true)] {
        let mut d = Document::new();
        let g = d.add_geometry(uv_sphere(rings, 2 * rings));
        let mesh = d.add_mesh("s", g, None);
        d.add_node(Node {
            mesh: Some(mesh),
            ..Node::default()
        });
        let (json, bin) = d.to_json().unwrap();
        let idx = json["meshes"][0]["primitives"][0]["indices"]
            .as_u64()
            .unwrap() as usize;
        let ty = json["accessors"][idx]["componentType"].as_u64().unwrap();
        assert_eq!(ty, if u32_wanted { 5125 } else { 5123 }, "{rings} rings");
        assert_eq!(bin.len() % 4, 0);
    }
}

#[test]
fn bad_documents_are_refused_naming_the_object() {
    let good = || one_sphere(Material::default(), LightKind::Directional);
    let cases: Vec<(Document, &str)> = vec![
        (
            {
                let mut d = good();
                d.geometries[0].normals[3] *= 2.0;
                d
            },
            "geometry 0 normal 3",
        ),
        (
            {
                let mut d = good();
                d.geometries[0].triangles[1][2] = 9999;
                d
            },
            "geometry 0 triangle 1 vertex = 9999",
        ),
        (
            {
                let mut d = good();
                d.geometries[0].uvs.pop();
                d
            },
            "uvs for",
        ),
        (
            {
                let mut d = good();
                d.materials[0].roughness = 1.5;
                d
            },
            "roughnessFactor = 1.5",
        ),
        (
            {
                let mut d = good();
                d.materials[0].sheen = Some(Sheen {
                    color: [0.5, f32::NAN, 0.5],
                    roughness: 0.5,
                });
                d
            },
            "sheenColorFactor",
        ),
        (
            {
                let mut d = good();
                d.nodes[0].mesh = Some(4);
                d
            },
            "node 0 () mesh = 4: the document has 1 meshes",
        ),
        (
            {
                let mut d = good();
                d.nodes[0].children = vec![1];
                d.nodes[1].children = vec![0];
                d
            },
            "cycle",
        ),
        (
            {
                let mut d = good();
                d.cameras[0].yfov = 4.0;
                d
            },
            "yfov = 4",
        ),
        (
            {
                let mut d = good();
                d.lights[0].kind = LightKind::Spot {
                    range: None,
                    inner_cone: 0.5,
                    outer_cone: 0.5,
                };
                d
            },
            "spot cone",
        ),
    ];
    for (d, want) in cases {
        let e = d.to_glb().unwrap_err().to_string();
        assert!(
            e.starts_with("glTF writer: ") && e.contains(want),
            "{e:?} lacks {want:?}"
        );
        assert!(d.to_gltf().is_err());
    }
    assert!(good().to_glb().is_ok());
}

#[test]
fn sphere_is_closed_outward_and_its_tangents_follow_u() {
    let g = uv_sphere(12, 24);
    for t in &g.triangles {
        let p = t.map(|i| g.positions[i as usize]);
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        assert!(cross.length() > 1e-4, "degenerate triangle {t:?}");
        let centre = (p[0] + p[1] + p[2]) / 3.0;
        assert!(cross.dot(centre) > 0.0, "triangle {t:?} faces inwards");
    }
    for (i, (n, t)) in g.normals.iter().zip(&g.tangents).enumerate() {
        assert!(n.dot(t.truncate()).abs() < 1e-6, "vertex {i}");
    }
    // Along a row (constant v), u grows in the tangent's direction.
    let (a, b) = (12 * 25 / 2 + 3, 12 * 25 / 2 + 4);
    let (pa, pb) = (g.positions[a], g.positions[b]);
    assert!(g.uvs[b].x > g.uvs[a].x && (pb - pa).dot(g.tangents[a].truncate()) > 0.0);
    // Euler: a closed sphere of V vertices (seam and pole copies merged) has 2V - 4 faces.
    let merged = 2 + 11 * 24;
    assert_eq!(g.triangles.len(), 2 * merged - 4);
}

#[test]
fn demo_scene_is_the_same_bytes_every_time_and_holds_every_extension() {
    let a = demo_scene();
    assert_eq!(a, demo_scene());
    let g = gltf::Gltf::from_slice(&a).unwrap();
    assert_eq!(g.meshes().count(), 6);
    assert_eq!(g.cameras().count(), 1);
    assert_eq!(g.lights().unwrap().count(), 2);
    let used: Vec<&str> = g.extensions_used().collect();
    for e in [
        "KHR_materials_ior",
        "KHR_materials_specular",
        "KHR_materials_clearcoat",
        "KHR_materials_sheen",
        "KHR_materials_anisotropy",
        "KHR_lights_punctual",
    ] {
        assert!(used.contains(&e), "{e} not in {used:?}");
    }
    // The face's texture coordinates are flipped to glTF's v-down convention.
    let face = crate::mesh::face();
    let geo = Geometry::from_trimesh(&face);
    assert_eq!(geo.uvs[0].y, 1.0 - face.uvs[0].y);
}

#[test]
fn the_books_table_lists_the_demo_materials() {
    let page = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/book/src/gltf-demo.md"
    );
    let text = std::fs::read_to_string(page).unwrap();
    let rows: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("| material | base colour"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .collect();
    let want: Vec<String> = material_rows()
        .iter()
        .map(|r| format!("| {} |", r.join(" | ")))
        .collect();
    assert_eq!(rows, want, "docs/book/src/gltf-demo.md's material table");
}
