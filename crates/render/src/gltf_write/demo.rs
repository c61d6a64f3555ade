//! The built-in demo scene (`fastbrdf demo` writes it as `scene.glb`): the embedded MediaPipe
//! face over a row of five spheres of real materials, each showing one extension of the
//! `gltf-pbr` model (gold, a clear-coated car paint, a velvet with sheen, brushed aluminium
//! with anisotropy, a plastic with KHR_materials_specular), a perspective camera, a directional
//! key light and a point fill light. Built at run time by the writer (the same bytes every
//! time: no clock, no randomness), so it needs no file in the repository beyond the face.
//! Units are metres: the face (in centimetres in its OBJ) is scaled by 0.01 by its node.

use super::{
    Anisotropy, Camera, Clearcoat, Document, Geometry, Light, LightKind, Material, Node, Sheen,
    Specular,
};
use glam::{Vec2, Vec3, Vec4};
use std::f32::consts::PI;

/// A unit sphere centred at the origin: `rings` bands from the north pole (+y) to the south
/// pole, `segments` around; texture coordinates u around (0 and 1 at the seam, +z at
/// u = 0), v from 0 at the north pole to 1 at the south; tangents along increasing u (the
/// lines of latitude, so an anisotropic material is brushed around the vertical axis),
/// w = +1 (bitangent towards decreasing v, as MikkTSpace gives for these coordinates). The
/// degenerate triangles at the poles are left out.
pub fn uv_sphere(rings: u32, segments: u32) -> Geometry {
    let (rings, segments) = (rings.max(2), segments.max(3));
    let mut g = Geometry::default();
    for i in 0..=rings {
        let theta = PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = 2.0 * PI * j as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                theta.sin() * phi.cos(),
            );
            // At the poles sin(theta) is exactly 0 only at i = 0; keep the normal exact there.
            let n = if i == 0 {
                Vec3::Y
            } else if i == rings {
                Vec3::NEG_Y
            } else {
                n.normalize()
            };
            g.positions.push(n);
            g.normals.push(n);
            g.uvs.push(Vec2::new(
                j as f32 / segments as f32,
                i as f32 / rings as f32,
            ));
            g.tangents.push(Vec4::new(phi.cos(), 0.0, -phi.sin(), 1.0));
        }
    }
    let at = |i: u32, j: u32| i * (segments + 1) + j;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if i + 1 < rings {
                g.triangles.push([a, b, c]);
            }
            if i > 0 {
                g.triangles.push([a, c, d]);
            }
        }
    }
    g
}

/// The demo's materials, in their order along the row of spheres (the face's is separate).
/// Factors in linear RGB; the book's page `gltf-demo.md` tabulates them.
pub fn demo_materials() -> Vec<Material> {
    let dielectric = |name: &str, base: [f32; 3], roughness: f32| Material {
        name: name.into(),
        base_color: [base[0], base[1], base[2], 1.0],
        metallic: 0.0,
        roughness,
        ..Material::default()
    };
    vec![
        Material {
            name: "gold".into(),
            base_color: [1.0, 0.766, 0.336, 1.0],
            metallic: 1.0,
            roughness: 0.25,
            ..Material::default()
        },
        Material {
            clearcoat: Some(Clearcoat {
                factor: 1.0,
                roughness: 0.03,
            }),
            ..dielectric("car paint", [0.55, 0.01, 0.02], 0.45)
        },
        Material {
            sheen: Some(Sheen {
                color: [0.95, 0.45, 0.75],
                roughness: 0.5,
            }),
            ..dielectric("velvet", [0.18, 0.02, 0.1], 1.0)
        },
        Material {
            name: "brushed aluminium".into(),
            base_color: [0.91, 0.92, 0.92, 1.0],
            metallic: 1.0,
            roughness: 0.4,
            anisotropy: Some(Anisotropy {
                strength: 0.8,
                rotation: 0.0,
            }),
            ..Material::default()
        },
        Material {
            ior: Some(1.5),
            specular: Some(Specular {
                factor: 0.5,
                color: [1.0, 0.9, 0.8],
            }),
            ..dielectric("plastic", [0.05, 0.25, 0.8], 0.25)
        },
    ]
}

/// The face's material: a skin-like dielectric (KHR_materials_ior 1.4).
pub fn face_material() -> Material {
    Material {
        name: "skin".into(),
        base_color: [0.8, 0.5, 0.38, 1.0],
        metallic: 0.0,
        roughness: 0.5,
        ior: Some(1.4),
        ..Material::default()
    }
}

/// The demo's materials as table rows (the face's first): name, base colour (linear RGB),
/// metallic, roughness, and the extensions with their factors; `fastbrdf demo`'s
/// `index.html` and the book's page `gltf-demo.md` show them (a test keeps the page's table
/// equal to these rows).
pub fn material_rows() -> Vec<[String; 5]> {
    let list = |c: &[f32]| {
        c.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut all = vec![face_material()];
    all.extend(demo_materials());
    all.iter()
        .map(|m| {
            let mut ext = vec![];
            if let Some(x) = m.ior {
                ext.push(format!("KHR_materials_ior: ior {x}"));
            }
            if let Some(x) = m.specular {
                ext.push(format!(
                    "KHR_materials_specular: factor {}, colour {}",
                    x.factor,
                    list(&x.color)
                ));
            }
            if let Some(x) = m.clearcoat {
                ext.push(format!(
                    "KHR_materials_clearcoat: factor {}, roughness {}",
                    x.factor, x.roughness
                ));
            }
            if let Some(x) = m.sheen {
                ext.push(format!(
                    "KHR_materials_sheen: colour {}, roughness {}",
                    list(&x.color),
                    x.roughness
                ));
            }
            if let Some(x) = m.anisotropy {
                ext.push(format!(
                    "KHR_materials_anisotropy: strength {}, rotation {}",
                    x.strength, x.rotation
                ));
            }
            if ext.is_empty() {
                ext.push("none".into());
            }
            [
                m.name.clone(),
                list(&m.base_color[..3]),
                m.metallic.to_string(),
                m.roughness.to_string(),
                ext.join("; "),
            ]
        })
        .collect()
}

/// Radius of the demo's spheres, metres.
pub const SPHERE_RADIUS: f32 = 0.038;

/// The demo scene as a document (see the module's documentation).
pub fn demo_document() -> Document {
    let mut d = Document::new();
    let face = d.add_geometry(Geometry::from_trimesh(&crate::mesh::face()));
    let skin = d.add_material(face_material());
    let face_mesh = d.add_mesh("face", face, Some(skin));
    d.add_node(Node {
        name: "face".into(),
        scale: Vec3::splat(0.01),
        mesh: Some(face_mesh),
        ..Node::default()
    });
    let sphere = d.add_geometry(uv_sphere(24, 48));
    let materials = demo_materials();
    let count = materials.len();
    for (k, m) in materials.into_iter().enumerate() {
        let x = 0.08 * (k as f32 - (count - 1) as f32 / 2.0);
        let name = m.name.clone();
        let mat = d.add_material(m);
        let mesh = d.add_mesh(&name, sphere, Some(mat));
        d.add_node(Node {
            name,
            translation: Vec3::new(x, -0.15, 0.03),
            scale: Vec3::splat(SPHERE_RADIUS),
            mesh: Some(mesh),
            ..Node::default()
        });
    }
    d.cameras.push(Camera {
        name: "camera".into(),
        yfov: 0.6,
        aspect_ratio: None,
        znear: 0.01,
        zfar: Some(100.0),
    });
    d.add_node(Node {
        camera: Some(0),
        ..Node::looking("camera", Vec3::new(0.0, -0.05, 0.78), Vec3::NEG_Z, Vec3::Y)
    });
    d.lights.push(Light {
        name: "key".into(),
        kind: LightKind::Directional,
        color: [1.0, 0.96, 0.9],
        intensity: 3.0,
    });
    d.add_node(Node {
        light: Some(0),
        ..Node::looking("key light", Vec3::ZERO, Vec3::new(0.5, -0.6, -0.6), Vec3::Y)
    });
    d.lights.push(Light {
        name: "fill".into(),
        kind: LightKind::Point { range: None },
        color: [0.8, 0.9, 1.0],
        intensity: 0.15,
    });
    d.add_node(Node {
        light: Some(1),
        translation: Vec3::new(0.35, 0.1, 0.4),
        ..Node::default()
    });
    d
}

/// The demo scene as `.glb` bytes.
pub fn demo_scene() -> Vec<u8> {
    demo_document()
        .to_glb()
        .expect("the built-in demo scene is a valid document")
}
