//! The built-in demo scene (`fastbrdf demo` writes it as `scene.glb`): the embedded MediaPipe
//! face with textures (the built-in skin as its base colour, and a pore normal texture and an
//! occlusion-roughness-metallic texture made here from one height field, [`face_images`])
//! over a row of five spheres of real materials, each showing one extension of the
//! `gltf-pbr` model (gold, a clear-coated car paint, a velvet with sheen, brushed aluminium
//! with anisotropy, a plastic with KHR_materials_specular), a perspective camera, a directional
//! key light and a point fill light. Built at run time by the writer (the same bytes every
//! time: no clock, no randomness), so it needs no file in the repository beyond the face.
//! Units are metres: the face (in centimetres in its OBJ) is scaled by 0.01 by its node.

use super::{
    Anisotropy, Camera, Clearcoat, Document, Geometry, Image, Light, LightKind, Material, Node,
    Sheen, Specular,
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

/// The face's material: a skin-like dielectric (KHR_materials_ior 1.4) with the textures of
/// [`face_images`] (images 0, 1, 2 of the demo document): the base colour is the texture's,
/// the roughness its G channel (factor 1), the occlusion its R channel.
pub fn face_material() -> Material {
    Material {
        name: "skin".into(),
        base_color: [1.0, 1.0, 1.0, 1.0],
        metallic: 0.0,
        roughness: 1.0,
        ior: Some(1.4),
        base_color_texture: Some(0),
        normal_texture: Some((1, 1.0)),
        occlusion_texture: Some((2, 1.0)),
        metallic_roughness_texture: Some(2),
        ..Material::default()
    }
}

/// Side of the face's textures, texels.
pub const FACE_TEXTURE_SIDE: u32 = 256;

/// Periodic value noise on a `cells` x `cells` grid over the texture (PCG-hashed cell values,
/// smoothstep-interpolated), in [0, 1], at texel (x, y) of a `side`-texel texture.
fn noise(x: u32, y: u32, side: u32, cells: u32, seed: u32) -> f32 {
    let cell = side as f32 / cells as f32;
    let (fx, fy) = (x as f32 / cell, y as f32 / cell);
    let (ix, iy) = (fx.floor() as u32, fy.floor() as u32);
    let (tx, ty) = (fx - ix as f32, fy - iy as f32);
    let v = |i: u32, j: u32| {
        let h = crate::hash::pcg((i % cells) ^ crate::hash::pcg((j % cells) ^ seed));
        h as f32 / u32::MAX as f32
    };
    let s = |t: f32| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(tx), s(ty));
    let top = v(ix, iy) + (v(ix + 1, iy) - v(ix, iy)) * sx;
    let bottom = v(ix, iy + 1) + (v(ix + 1, iy + 1) - v(ix, iy + 1)) * sx;
    top + (bottom - top) * sy
}

/// The face's images: the built-in skin (`texture::skin`, averaged down to
/// [`FACE_TEXTURE_SIDE`]) as the base colour (sRGB); a tangent-space normal texture of pores
/// and fine wrinkles from a height field `h` (value noise at 128 and 32 cells); and an
/// occlusion-roughness-metallic texture from the same field: occlusion `0.7 + 0.3 h` (the pores
/// darker), roughness `0.35 + 0.35` of a broad noise (oily and dry areas), metallic 0.
/// Deterministic and periodic, as the skin.
pub fn face_images() -> [Image; 3] {
    let n = FACE_TEXTURE_SIDE;
    let skin = crate::texture::skin();
    let k = (skin.width / n) as usize;
    let srgb = |c: f32| (crate::texture::linear_to_srgb(c) * 255.0).round() as u8;
    let mut colour = Vec::with_capacity((n * n) as usize);
    for y in 0..n as usize {
        for x in 0..n as usize {
            let mut sum = Vec3::ZERO;
            for j in 0..k {
                for i in 0..k {
                    sum += skin.texels()[(y * k + j) * skin.width as usize + x * k + i];
                }
            }
            let c = sum / (k * k) as f32;
            colour.push([srgb(c.x), srgb(c.y), srgb(c.z)]);
        }
    }
    let h = |x: u32, y: u32| {
        let (x, y) = (x % n, y % n);
        0.7 * noise(x, y, n, 128, 17) + 0.3 * noise(x, y, n, 32, 29)
    };
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let mut normal = Vec::with_capacity((n * n) as usize);
    let mut orm = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            // Slopes per texel; +Y of the texture is up the image (rows grow downwards).
            let dx = 0.5 * (h(x + 1, y) - h(x + n - 1, y));
            let dy = 0.5 * (h(x, y + n - 1) - h(x, y + 1));
            let t = Vec3::new(-1.5 * dx, -1.5 * dy, 1.0).normalize();
            normal.push([t.x, t.y, t.z].map(|c| byte(0.5 + 0.5 * c)));
            let rough = 0.35 + 0.35 * noise(x, y, n, 4, 41);
            orm.push([byte(0.7 + 0.3 * h(x, y)), byte(rough), 0]);
        }
    }
    let img = |name: &str, t: &[[u8; 3]]| {
        Image::from_rgb8(name, n, n, t).expect("the texel count matches the size")
    };
    [
        img("skin base colour", &colour),
        img("skin normal", &normal),
        img("skin occlusion-roughness-metallic", &orm),
    ]
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
            let textures: Vec<&str> = [
                (m.base_color_texture.is_some(), "base colour"),
                (m.normal_texture.is_some(), "normal"),
                (m.occlusion_texture.is_some(), "occlusion"),
                (m.metallic_roughness_texture.is_some(), "metallic-roughness"),
                (m.emissive_texture.is_some(), "emissive"),
            ]
            .into_iter()
            .filter_map(|(on, name)| on.then_some(name))
            .collect();
            if !textures.is_empty() {
                ext.push(format!("textures: {}", textures.join(", ")));
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
    for i in face_images() {
        d.add_image(i);
    }
    // The face's TANGENTs (its normal texture needs them; the validator warns where a reader
    // would have to generate them): MikkTSpace, as the reader would, a unit vector
    // perpendicular to the normal where it finds none.
    let mut face = Geometry::from_trimesh(&crate::mesh::face());
    face.tangents = crate::gltf::tangents::mikktspace(
        &face.positions,
        &face.normals,
        &face.uvs,
        &face.triangles,
    )
    .iter()
    .zip(&face.normals)
    .map(|(t, n)| {
        let v = Vec3::new(t[0], t[1], t[2]);
        if (v.length() - 1.0).abs() < 1e-3 {
            Vec4::new(v.x, v.y, v.z, if t[3] < 0.0 { -1.0 } else { 1.0 })
        } else {
            n.any_orthonormal_vector().extend(1.0)
        }
    })
    .collect();
    let face = d.add_geometry(face);
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
