//! A small glTF 2.0 writer: triangle meshes (positions, normals, optional texture coordinates
//! and tangents), nodes with transforms, metallic-roughness materials with their textures
//! (PNG images in the buffer: base colour, metallic-roughness, normal, occlusion, emissive) and
//! the KHR_materials_ior, _specular, _clearcoat, _sheen and _anisotropy extensions, perspective
//! cameras and KHR_lights_punctual lights, written as `.gltf` (JSON with the buffer as a
//! base64 data URI, [`Document::to_gltf`]) or `.glb` (binary container, [`Document::to_glb`]).
//!
//! The project's own files are made with it (the demo scene, [`demo::demo_scene`], and the
//! tests' files for the reader, `crate::gltf`); every kind of file it writes passes the
//! Khronos glTF-Validator (`crates/render/tests/gltf_validator.rs`,
//! `tools/gltf_validate.mjs`).
//!
//! The document is plain data: the caller fills the vectors and refers to other objects by
//! index. [`Document::to_json`] checks it first (lengths, index ranges, finite numbers, unit
//! normals and tangents, factor ranges) and fails with [`RenderError::Invalid`] naming the
//! object, so a file it writes is valid glTF. Layout: one buffer; per geometry one buffer view
//! per attribute and one for the indices (u16 when every index fits, else u32), each aligned
//! to 4 bytes; a geometry's accessors are written once and shared by every primitive that uses
//! it (spheres of several materials cost one sphere). Numbers in the JSON are the shortest
//! decimal that reads back as the same `f32`, except accessor bounds (`min`/`max`), written
//! exactly so that the validator's comparison with the data holds.

pub mod demo;
mod encode;

pub use demo::{
    demo_document, demo_materials, demo_scene, face_material, material_rows, uv_sphere,
};

use crate::error::{RenderError, Result};
use crate::geometry::TriMesh;
use glam::{Quat, Vec2, Vec3, Vec4};

/// Triangle geometry: one glTF set of attribute accessors plus an index accessor.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    pub positions: Vec<Vec3>,
    /// Unit vectors, one per position.
    pub normals: Vec<Vec3>,
    /// `TEXCOORD_0` in glTF's convention (origin at the image's top-left, v down); empty for
    /// none.
    pub uvs: Vec<Vec2>,
    /// `TANGENT`: unit xyz, w = +1 or -1 (bitangent = cross(normal, xyz) * w); empty for none.
    pub tangents: Vec<Vec4>,
    /// Counter-clockwise triangles (glTF's front faces), indices into the attributes.
    pub triangles: Vec<[u32; 3]>,
}

impl Geometry {
    /// A renderer mesh as glTF geometry: texture coordinates flipped from the OBJ convention
    /// (v up, what [`TriMesh`] and the renderer's textures use) to glTF's (v down).
    pub fn from_trimesh(mesh: &TriMesh) -> Self {
        Geometry {
            positions: mesh.positions.clone(),
            normals: mesh.normals.clone(),
            uvs: mesh.uvs.iter().map(|t| Vec2::new(t.x, 1.0 - t.y)).collect(),
            tangents: Vec::new(),
            triangles: mesh.triangles.clone(),
        }
    }
}

/// One draw of a geometry with a material (`None`: glTF's default material).
#[derive(Clone, Copy, Debug)]
pub struct Primitive {
    pub geometry: usize,
    pub material: Option<usize>,
}

/// A glTF mesh: one or more primitives.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub primitives: Vec<Primitive>,
}

/// KHR_materials_specular.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Specular {
    /// `specularFactor`, [0, 1].
    pub factor: f32,
    /// `specularColorFactor`, each channel >= 0.
    pub color: [f32; 3],
}

/// KHR_materials_clearcoat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearcoat {
    /// `clearcoatFactor`, [0, 1].
    pub factor: f32,
    /// `clearcoatRoughnessFactor`, [0, 1].
    pub roughness: f32,
}

/// KHR_materials_sheen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheen {
    /// `sheenColorFactor`, each channel in [0, 1].
    pub color: [f32; 3],
    /// `sheenRoughnessFactor`, [0, 1].
    pub roughness: f32,
}

/// KHR_materials_anisotropy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anisotropy {
    /// `anisotropyStrength`, [0, 1].
    pub strength: f32,
    /// `anisotropyRotation`, radians counter-clockwise from the tangent.
    pub rotation: f32,
}

/// A metallic-roughness material with the extensions the `gltf-pbr` model evaluates; an
/// extension is written only when its field is `Some`.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// `baseColorFactor` (linear RGBA), each in [0, 1].
    pub base_color: [f32; 4],
    /// `metallicFactor`, [0, 1].
    pub metallic: f32,
    /// `roughnessFactor`, [0, 1].
    pub roughness: f32,
    pub double_sided: bool,
    /// KHR_materials_ior: `ior`, 0 or >= 1.
    pub ior: Option<f32>,
    pub specular: Option<Specular>,
    pub clearcoat: Option<Clearcoat>,
    pub sheen: Option<Sheen>,
    pub anisotropy: Option<Anisotropy>,
    /// The textures, each an index into [`Document::images`] read on `TEXCOORD_0` (a mesh
    /// using the material needs texture coordinates): `baseColorTexture` (sRGB),
    pub base_color_texture: Option<usize>,
    /// `metallicRoughnessTexture` (linear; G roughness, B metallic),
    pub metallic_roughness_texture: Option<usize>,
    /// `normalTexture` (linear, tangent space) and its `scale`,
    pub normal_texture: Option<(usize, f32)>,
    /// `occlusionTexture` (linear, R) and its `strength` ([0, 1]),
    pub occlusion_texture: Option<(usize, f32)>,
    /// `emissiveTexture` (sRGB).
    pub emissive_texture: Option<usize>,
    /// `emissiveFactor` (linear RGB, each in [0, 1]).
    pub emissive: [f32; 3],
}

impl Material {
    /// The images the material refers to.
    pub fn images(&self) -> Vec<usize> {
        [
            self.base_color_texture,
            self.metallic_roughness_texture,
            self.normal_texture.map(|t| t.0),
            self.occlusion_texture.map(|t| t.0),
            self.emissive_texture,
        ]
        .into_iter()
        .flatten()
        .collect()
    }
}

/// A PNG image, stored in the buffer; each image is one texture (linear filtering, REPEAT).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub name: String,
    /// The PNG file's bytes.
    pub png: Vec<u8>,
}

impl Image {
    /// An RGB image of `w` x `h` 8-bit texels (row-major from the top), PNG-encoded.
    pub fn from_rgb8(name: &str, w: u32, h: u32, texels: &[[u8; 3]]) -> Result<Self> {
        if texels.len() as u64 != u64::from(w) * u64::from(h) || w == 0 || h == 0 {
            return Err(RenderError::Invalid(format!(
                "image '{name}': {} texels for {w} x {h}",
                texels.len()
            )));
        }
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            image::Rgb(texels[(y as usize) * (w as usize) + x as usize])
        });
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .map_err(|e| RenderError::Invalid(format!("image '{name}': {e}")))?;
        Ok(Image {
            name: name.into(),
            png: out.into_inner(),
        })
    }
}

impl Default for Material {
    /// glTF's defaults: white, metallic 1, roughness 1, no extension.
    fn default() -> Self {
        Material {
            name: String::new(),
            base_color: [1.0; 4],
            metallic: 1.0,
            roughness: 1.0,
            double_sided: false,
            ior: None,
            specular: None,
            clearcoat: None,
            sheen: None,
            anisotropy: None,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            emissive_texture: None,
            emissive: [0.0; 3],
        }
    }
}

/// A perspective camera; it looks down its node's -z axis, +y up.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub name: String,
    /// Vertical field of view, radians, in (0, pi).
    pub yfov: f32,
    /// Width over height; `None` lets the viewer use its picture's.
    pub aspect_ratio: Option<f32>,
    pub znear: f32,
    /// `None`: an infinite projection.
    pub zfar: Option<f32>,
}

/// The kind of a KHR_lights_punctual light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Shines down its node's -z axis; intensity in lux.
    Directional,
    /// Intensity in candela; `range` (metres) where it fades to zero, `None` for infinite.
    Point { range: Option<f32> },
    /// Down its node's -z axis; cone angles in radians, 0 <= inner < outer <= pi/2.
    Spot {
        range: Option<f32>,
        inner_cone: f32,
        outer_cone: f32,
    },
}

/// A KHR_lights_punctual light.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub name: String,
    pub kind: LightKind,
    /// Linear RGB, each in [0, 1].
    pub color: [f32; 3],
    /// >= 0: lux for directional lights, candela for the others.
    pub intensity: f32,
}

/// A node: a transform (translation, rotation, scale, applied as T * R * S) with optional
/// mesh, camera and light, and children.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub name: String,
    pub translation: Vec3,
    /// Unit quaternion.
    pub rotation: Quat,
    pub scale: Vec3,
    pub mesh: Option<usize>,
    pub camera: Option<usize>,
    pub light: Option<usize>,
    pub children: Vec<usize>,
}

impl Default for Node {
    fn default() -> Self {
        Node {
            name: String::new(),
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
            mesh: None,
            camera: None,
            light: None,
            children: Vec::new(),
        }
    }
}

impl Node {
    /// A node at `translation` whose -z axis (where cameras look and lights shine) points
    /// along `direction`, +y kept as close to `up` as the direction allows.
    pub fn looking(name: &str, translation: Vec3, direction: Vec3, up: Vec3) -> Self {
        let back = -direction.normalize();
        let right = up.cross(back).normalize();
        let true_up = back.cross(right);
        let rotation = Quat::from_mat3(&glam::Mat3::from_cols(right, true_up, back)).normalize();
        Node {
            name: name.into(),
            translation,
            rotation,
            ..Node::default()
        }
    }
}

/// A glTF document: one scene whose roots are the nodes that are no node's child.
#[derive(Clone, Debug, Default)]
pub struct Document {
    /// `asset.generator`.
    pub generator: String,
    pub geometries: Vec<Geometry>,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub cameras: Vec<Camera>,
    pub lights: Vec<Light>,
    pub nodes: Vec<Node>,
    pub images: Vec<Image>,
}

impl Document {
    /// An empty document whose `asset.generator` names this crate.
    pub fn new() -> Self {
        Document {
            generator: format!("fastbrdf-render {}", env!("CARGO_PKG_VERSION")),
            ..Document::default()
        }
    }

    /// Adds a geometry, returning its index.
    pub fn add_geometry(&mut self, g: Geometry) -> usize {
        self.geometries.push(g);
        self.geometries.len() - 1
    }

    /// Adds an image, returning its index.
    pub fn add_image(&mut self, i: Image) -> usize {
        self.images.push(i);
        self.images.len() - 1
    }

    /// Adds a material, returning its index.
    pub fn add_material(&mut self, m: Material) -> usize {
        self.materials.push(m);
        self.materials.len() - 1
    }

    /// Adds a one-primitive mesh of `geometry` with `material`, returning its index.
    pub fn add_mesh(&mut self, name: &str, geometry: usize, material: Option<usize>) -> usize {
        self.meshes.push(Mesh {
            name: name.into(),
            primitives: vec![Primitive { geometry, material }],
        });
        self.meshes.len() - 1
    }

    /// Adds a node, returning its index.
    pub fn add_node(&mut self, n: Node) -> usize {
        self.nodes.push(n);
        self.nodes.len() - 1
    }

    /// The glTF JSON and the binary buffer it refers to (buffer 0, without a `uri`; the
    /// `.gltf` form adds the data URI). Checks the document first.
    pub fn to_json(&self) -> Result<(serde_json::Value, Vec<u8>)> {
        encode::check(self)?;
        Ok(encode::json(self))
    }

    /// The `.gltf` form: JSON text, the buffer embedded as a base64 data URI.
    pub fn to_gltf(&self) -> Result<Vec<u8>> {
        let (mut json, bin) = self.to_json()?;
        if !bin.is_empty() {
            use base64::Engine;
            let uri = format!(
                "data:application/octet-stream;base64,{}",
                base64::engine::general_purpose::STANDARD.encode(&bin)
            );
            json["buffers"][0]["uri"] = uri.into();
        }
        let mut text = serde_json::to_vec_pretty(&json).expect("a JSON value serialises");
        text.push(b'\n');
        Ok(text)
    }

    /// The `.glb` form: the 12-byte header, the JSON chunk (padded with spaces) and the
    /// binary chunk (padded with zeros), each chunk's length a multiple of 4.
    pub fn to_glb(&self) -> Result<Vec<u8>> {
        let (json, bin) = self.to_json()?;
        let text = serde_json::to_vec(&json).expect("a JSON value serialises");
        encode::glb(&text, &bin)
    }
}

fn invalid(message: String) -> RenderError {
    RenderError::Invalid(format!("glTF writer: {message}"))
}

#[cfg(test)]
mod tests;
