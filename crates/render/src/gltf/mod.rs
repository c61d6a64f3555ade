//! glTF 2.0 scenes (`.gltf` with external or data-URI buffers, `.glb`) for the CPU renderer:
//! the default scene's meshes with their node transforms, normals (flat when absent, as the
//! specification asks), texture coordinates, tangents (MikkTSpace when absent and a material
//! is anisotropic), the first camera, punctual lights (`KHR_lights_punctual`), and each
//! material as the `gltf-pbr` model with its `KHR_materials_*` factors ([`material`]).
//!
//! The `gltf` crate parses and validates the JSON (its file import and image decoding are
//! off); the bytes are read here, bounded ([`MAX_SCENE_BYTES`], [`MAX_BUFFER_BYTES`],
//! [`MAX_TOTAL_BUFFER_BYTES`], [`crate::mesh::MAX_TRIANGLES`]), every accessor's range checked
//! before it is read. A broken file is a [`RenderError::Input`] naming the file and the JSON
//! pointer of what is wrong (`scene.gltf: /meshes/0/primitives/0/attributes/POSITION:
//! accessor 7 does not exist (2 accessors)`). The base colour texture is rendered exactly
//! (`Specular::tint`: the model is affine in its base colour); the metallic-roughness, normal,
//! occlusion and emissive textures and the emission as [`crate::maps`] says (metallic exactly,
//! roughness to 1/512, the normal in the mesh's tangent frame). What the renderer does not
//! use (the extensions' textures, animations, skins, morph targets, alpha modes, other
//! extensions...) is named in [`GltfScene::warnings`], never dropped silently.

mod buffers;
mod images;
pub mod material;
mod meshes;
mod pointer;
pub(crate) mod tangents;
mod view;

use crate::env::{EnvMap, Environment};
use crate::error::{RenderError, Result};
use crate::geometry::TriMesh;
use crate::maps::{self, Emissive, MetallicRoughness, NormalMap, Occlusion, SurfaceMaps};
use crate::scene::{Camera, Light, LightKind, Material, Object, Scene, Shape, Specular};
use crate::setup::SceneSpec;
use crate::texture::Texture;
use fastbrdf::ModelSpec;
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;

pub use material::{GltfMaterial, MODEL_ID};

/// Largest `.gltf` or `.glb` file read: 256 MiB, as an OBJ mesh.
pub const MAX_SCENE_BYTES: u64 = 256 << 20;
/// Largest buffer (a file, a data URI or the BIN chunk): 1 GiB.
pub const MAX_BUFFER_BYTES: u64 = 1 << 30;
/// Largest sum of a scene's buffers: 1 GiB.
pub const MAX_TOTAL_BUFFER_BYTES: u64 = 1 << 30;
/// Most node visits while walking the default scene (a node may be instanced many times).
pub const MAX_NODE_VISITS: usize = 1 << 20;

/// The extensions read (or named in a warning when only partly used); any other in
/// `extensionsRequired` is an error.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_anisotropy",
    "KHR_materials_emissive_strength",
];

/// The file named in errors.
pub(crate) struct Ctx {
    pub file: String,
}

impl Ctx {
    /// An input error at JSON pointer `ptr` ("" for the file as a whole).
    pub fn err(&self, ptr: &str, message: impl Into<String>) -> RenderError {
        let message = message.into();
        RenderError::Input {
            file: self.file.clone(),
            line: None,
            message: if ptr.is_empty() {
                message
            } else {
                format!("{ptr}: {message}")
            },
        }
    }
}

/// One mesh of the scene: every triangle of one material, in world space.
pub struct GltfObject {
    pub mesh: Arc<TriMesh>,
    /// Per-vertex tangents (xyz, w the bitangent's sign) where a material needs them
    /// (anisotropy, a normal texture): the file's, or MikkTSpace's; the mesh carries them too
    /// (`TriMesh::tangents`), for the CPU renderer's shading frame.
    pub tangents: Option<Vec<[f32; 4]>>,
    /// Index into [`GltfScene::materials`].
    pub material: usize,
}

/// A glTF scene as read: what the renderer needs, and what it does not use named.
pub struct GltfScene {
    /// The file as named in messages.
    pub file: String,
    pub objects: Vec<GltfObject>,
    pub materials: Vec<GltfMaterial>,
    /// Per material, its base colour texture (linear texels) when it is rendered.
    pub textures: Vec<Option<Arc<Texture>>>,
    /// Per material, its other textures when they are rendered.
    pub maps: Vec<MapTextures>,
    /// The first camera of the default scene (perspective), if any.
    pub camera: Option<Camera>,
    pub lights: Vec<Light>,
    /// Bounds of every triangle.
    pub bounds: (Vec3, Vec3),
    /// What is not rendered, one line each (`warning: ` is the printer's).
    pub warnings: Vec<String>,
}

/// A material's decoded textures beyond its base colour (each when rendered), with their
/// scalars: the normal texture's `scale`, the occlusion texture's `strength`.
#[derive(Clone, Default)]
pub struct MapTextures {
    pub metallic_roughness: Option<Arc<Texture>>,
    pub normal: Option<(Arc<Texture>, f32)>,
    pub occlusion: Option<(Arc<Texture>, f32)>,
    pub emissive: Option<Arc<Texture>>,
}

/// Reads a `.gltf` or `.glb` file (bounded by [`MAX_SCENE_BYTES`]; buffers resolved beside it).
pub fn load(path: &Path) -> Result<GltfScene> {
    let ctx = Ctx {
        file: path.display().to_string(),
    };
    let f = std::fs::File::open(path).map_err(|e| ctx.err("", format!("cannot read: {e}")))?;
    let bytes = fastbrdf_io::read_reader_bounded(f, path, MAX_SCENE_BYTES, "a glTF scene")?;
    let dir = path.parent().unwrap_or(Path::new("."));
    from_bytes(&ctx.file, &bytes, dir)
}

/// Reads a scene from its bytes: `file` names it in messages, `dir` is where its buffer
/// files are.
pub fn from_bytes(file: &str, bytes: &[u8], dir: &Path) -> Result<GltfScene> {
    let ctx = Ctx { file: file.into() };
    let (json_bytes, bin) = if bytes.starts_with(b"glTF") {
        buffers::split_glb(&ctx, bytes)?
    } else {
        (bytes, None)
    };
    let raw: serde_json::Value = serde_json::from_slice(json_bytes)
        .map_err(|e| ctx.err("", format!("not glTF JSON: {e}")))?;
    if !raw.is_object() {
        return Err(ctx.err("", "not glTF JSON: the top level must be an object"));
    }
    let version = raw.pointer("/asset/version").and_then(|v| v.as_str());
    if version.is_none_or(|v| v.split('.').next() != Some("2")) {
        return Err(ctx.err(
            "/asset/version",
            format!(
                "{}: only glTF 2.x is read",
                version.map_or("missing".to_string(), |v| format!(
                    "'{}'",
                    fastbrdf_io::shorten(v, 20)
                ))
            ),
        ));
    }
    let mut warnings = Vec::new();
    pointer::check_extensions(&ctx, &raw, &mut warnings)?;
    let root: gltf::json::Root = gltf::json::deserialize::from_slice(json_bytes)
        .map_err(|e| ctx.err("", format!("not valid glTF: {e}")))?;
    pointer::validate(&ctx, &root, &raw)?;
    let doc = gltf::Document::from_json_without_validation(root);
    let buffers = buffers::load_buffers(&ctx, &doc, bin, dir)?;
    let mut materials = material::read_all(&ctx, &raw, &mut warnings)?;
    let walked = meshes::walk(&ctx, &doc, &raw, &buffers, &mut materials, &mut warnings)?;
    meshes::unused_features(&doc, &mut warnings);
    let mut images = images::Images::default();
    let mut textures = Vec::new();
    let mut maps = Vec::new();
    for (mi, m) in materials.iter().enumerate() {
        let used: Vec<&GltfObject> = walked.objects.iter().filter(|o| o.material == mi).collect();
        let no_uvs = used.iter().any(|o| o.mesh.uvs.is_empty());
        let mut get = |t: Option<usize>, what: &str, srgb: bool| -> Result<Option<Arc<Texture>>> {
            match t {
                Some(_) if no_uvs => {
                    warnings.push(format!(
                        "material {}: its {what} is not rendered: not every primitive has TEXCOORD_0",
                        m.label()
                    ));
                    Ok(None)
                }
                Some(t) if !used.is_empty() => Ok(Some(images.get(
                    &ctx,
                    &doc,
                    &buffers,
                    dir,
                    (t, srgb),
                    &mut warnings,
                )?)),
                _ => Ok(None),
            }
        };
        textures.push(get(m.base_color_texture, "baseColorTexture", true)?);
        let scaled = |t: Option<(usize, f64)>| t.map(|(i, _)| i);
        let normal = get(scaled(m.normal_texture), "normalTexture", false)?;
        let occlusion = get(scaled(m.occlusion_texture), "occlusionTexture", false)?;
        maps.push(MapTextures {
            metallic_roughness: get(
                m.metallic_roughness_texture,
                "metallicRoughnessTexture",
                false,
            )?,
            normal: normal.zip(m.normal_texture.map(|(_, s)| s as f32)),
            occlusion: occlusion.zip(m.occlusion_texture.map(|(_, s)| s as f32)),
            emissive: get(m.emissive_texture, "emissiveTexture", true)?,
        });
    }
    Ok(GltfScene {
        file: file.into(),
        objects: walked.objects,
        materials,
        textures,
        maps,
        camera: walked.camera,
        lights: walked.lights,
        bounds: walked.bounds,
        warnings,
    })
}

impl GltfScene {
    /// The camera the scene is rendered from: the file's first, else one framing the scene
    /// from +z (as an OBJ mesh, [`Camera::framing`]).
    pub fn view(&self) -> Camera {
        self.camera
            .unwrap_or_else(|| Camera::framing(self.bounds.0, self.bounds.1, -Vec3::Z, 30.0))
    }

    /// Each material's `gltf-pbr` spec with `overrides` (the shortcut choices of an
    /// approximation set, the values of `--param`) after the file's values, so they win. A
    /// material the model refuses names the file and the material's pointer; an override the
    /// model refuses names the override.
    pub fn specs(&self, overrides: &[(String, String)]) -> Result<Vec<ModelSpec>> {
        self.materials
            .iter()
            .map(|m| m.spec(&self.file, overrides))
            .collect()
    }

    /// The scene to render with `specs` (one per material, [`GltfScene::specs`]): the file's
    /// camera; `spec.lights` if given, else none under the environment `env`, else the file's
    /// lights, else the default key light; `env`, `spec`'s shadows and environment samples.
    /// Each material is the whole BRDF: weights kd 0, ks 1. A material with a base colour
    /// texture is tinted by it ([`Tint`]): the model at base colour 0 as well, mixed by the
    /// texel per channel, exact since `gltf-pbr` is affine in its base colour.
    pub fn scene(
        &self,
        spec: &SceneSpec,
        env: Option<Arc<EnvMap>>,
        specs: &[ModelSpec],
    ) -> Result<Scene> {
        // A textured base colour: the value is affine in it, f(0) + t (f(factor) - f(0)).
        let speculars: Vec<Arc<Specular>> = specs
            .iter()
            .zip(&self.textures)
            .map(|(s, tex)| Ok(Arc::new(maps::tinted_specular(s, tex.as_ref())?)))
            .collect::<Result<_>>()?;
        let surface_maps: Vec<Option<Arc<SurfaceMaps>>> = (0..self.materials.len())
            .map(|i| self.surface_maps(i, &specs[i]))
            .collect::<Result<_>>()?;
        let objects = self
            .objects
            .iter()
            .map(|o| Object {
                shape: Shape::Mesh(o.mesh.clone()),
                material: Material {
                    kd: 0.0,
                    ks: 1.0,
                    albedo: Vec3::ONE,
                    texture: None,
                    bump: None,
                    specular: speculars[o.material].clone(),
                    maps: surface_maps[o.material].clone(),
                },
            })
            .collect();
        let lights = if !spec.lights.is_empty() {
            spec.lights.clone()
        } else if env.is_some() {
            Vec::new()
        } else if !self.lights.is_empty() {
            self.lights.clone()
        } else {
            vec![Light {
                kind: LightKind::Directional {
                    to_light: Vec3::new(-0.45, 0.55, 0.7).normalize(),
                },
                color: Vec3::ONE,
                intensity: 3.0,
            }]
        };
        Ok(Scene {
            camera: self.view(),
            lights,
            ambient: Vec3::ZERO,
            background: Vec3::splat(0.015),
            objects,
            shadows: spec.shadows,
            environment: env.map(|map| Environment {
                map,
                samples: spec.env_samples.max(1),
            }),
        })
    }

    /// Material `i`'s textures beyond its base colour and its emission, with its spec `spec`;
    /// `None` when it has neither.
    fn surface_maps(&self, i: usize, spec: &ModelSpec) -> Result<Option<Arc<SurfaceMaps>>> {
        let (m, t) = (&self.materials[i], &self.maps[i]);
        let emission = Vec3::from_array(m.emission.map(|x| x as f32));
        let out = SurfaceMaps {
            metallic_roughness: t
                .metallic_roughness
                .clone()
                .map(|tex| MetallicRoughness::new(tex, spec, self.textures[i].clone()))
                .transpose()?,
            normal: t
                .normal
                .clone()
                .map(|(texture, scale)| NormalMap { texture, scale }),
            occlusion: t
                .occlusion
                .clone()
                .map(|(texture, strength)| Occlusion { texture, strength }),
            emissive: (emission != Vec3::ZERO).then(|| Emissive {
                factor: emission,
                texture: t.emissive.clone(),
            }),
        };
        let any = out.metallic_roughness.is_some()
            || out.normal.is_some()
            || out.occlusion.is_some()
            || out.emissive.is_some();
        Ok(any.then(|| Arc::new(out)))
    }

    /// Triangles in the scene (every instance counted).
    pub fn triangles(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangles.len()).sum()
    }
}
