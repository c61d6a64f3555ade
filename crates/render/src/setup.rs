//! Building scenes from options: the built-in sphere (or a mesh), lights, material. Shared by
//! `fastbrdf render`, `compare` and `demo`.

use crate::bump::Bump;
use crate::env::{EnvMap, Environment};
use crate::error::Result;
use crate::geometry::{Plane, Sphere};
use crate::mesh::load_obj;
use crate::scene::{Camera, Light, LightKind, Material, Object, Scene, Shape, Specular};
use crate::texture::Texture;
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Scene options (everything except the specular model).
#[derive(Clone, Debug, Default)]
pub struct SceneSpec {
    /// An OBJ mesh instead of the built-in sphere; exactly `face` ([`BUILTIN_MESH`]) is the
    /// embedded face ([`crate::mesh::face`]), `./face` a file of that name.
    pub mesh: Option<PathBuf>,
    /// An albedo texture file; exactly `skin` ([`BUILTIN_TEXTURE`]) is the procedural skin
    /// ([`crate::texture::skin`]), `./skin` a file of that name.
    pub texture: Option<PathBuf>,
    /// Lights; none means the default key light.
    pub lights: Vec<Light>,
    pub bump: Option<Bump>,
    /// Add a ground plane under the object.
    pub floor: bool,
    pub kd: f32,
    pub ks: f32,
    pub albedo: Vec3,
    /// Shadow rays (see [`crate::scene::Scene::shadows`]); on in [`SceneSpec::new`].
    pub shadows: bool,
    /// An environment light: `sky`, `white` or a file (`crate::env::EnvMap::from_spec`).
    /// With one, no ambient term, and no default key light when `lights` is empty.
    pub env: Option<String>,
    /// Environment samples per primary hit (progressive passes); 16 in [`SceneSpec::new`].
    pub env_samples: u32,
    /// How the environment's light directions are drawn: a sun apart from the rest of the map
    /// (the default) or every direction from the whole map.
    pub env_sun: SunDraw,
}

/// How a map's light directions are drawn ([`EnvMap::without_bright`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SunDraw {
    /// A sun's texels (`crate::env::BRIGHT_FACTOR`, `BRIGHT_MIN_SHARE`, `BRIGHT_MAX_TEXELS`)
    /// and the rest of the map as two strategies, one direction of each per pass.
    #[default]
    Apart,
    /// Every light direction from the whole map: the estimator before the sun strategy (the
    /// same expected picture, more noise under a sun), and what the GPU renderer draws.
    WithMap,
}

impl SunDraw {
    /// The map as this choice draws it.
    pub fn apply(self, map: EnvMap) -> EnvMap {
        match self {
            Self::Apart => map,
            Self::WithMap => map.without_bright(),
        }
    }
}

impl SceneSpec {
    /// The defaults: kd 0.6, ks 0.4, albedo 0.8 grey, shadows on.
    pub fn new() -> Self {
        Self {
            kd: 0.6,
            ks: 0.4,
            albedo: Vec3::splat(0.8),
            shadows: true,
            env_samples: 16,
            ..Default::default()
        }
    }
}

/// The `--mesh` value that names the embedded face rather than a file.
pub const BUILTIN_MESH: &str = "face";
/// The `--texture` value that names the procedural skin rather than a file.
pub const BUILTIN_TEXTURE: &str = "skin";

/// Whether `path` is exactly the built-in name `name` (`./face` is a file, `face` is not).
pub fn is_builtin(path: &Path, name: &str) -> bool {
    path.as_os_str() == name
}

/// Notes for the user when a built-in name is also a file in the working directory: the
/// built-in wins, `./NAME` reads the file.
pub fn builtin_notes(spec: &SceneSpec) -> Vec<String> {
    let mut notes = Vec::new();
    for (opt, path, name, what) in [
        ("--mesh", &spec.mesh, BUILTIN_MESH, "the embedded face"),
        (
            "--texture",
            &spec.texture,
            BUILTIN_TEXTURE,
            "the procedural skin",
        ),
    ] {
        if path.as_deref().is_some_and(|p| is_builtin(p, name)) && Path::new(name).exists() {
            notes.push(format!(
                "note: {opt} {name} is {what}, not the file {name} here: write {opt} ./{name} to read the file"
            ));
        }
    }
    notes
}

/// Loaded resources shared by several renders (mesh, texture).
pub struct Loaded {
    mesh: Option<Arc<crate::geometry::TriMesh>>,
    texture: Option<Arc<Texture>>,
    env: Option<Arc<EnvMap>>,
}

/// Loads the mesh, texture and environment map once (the built-in face and skin by name).
pub fn load(spec: &SceneSpec) -> Result<Loaded> {
    Ok(Loaded {
        mesh: spec
            .mesh
            .as_deref()
            .map(|p| {
                if is_builtin(p, BUILTIN_MESH) {
                    Ok(crate::mesh::face())
                } else {
                    load_obj(p)
                }
            })
            .transpose()?
            .map(Arc::new),
        texture: spec
            .texture
            .as_deref()
            .map(|p| {
                if is_builtin(p, BUILTIN_TEXTURE) {
                    Ok(crate::texture::skin())
                } else {
                    Texture::load(p)
                }
            })
            .transpose()?
            .map(Arc::new),
        env: spec
            .env
            .as_deref()
            .map(EnvMap::from_spec)
            .transpose()?
            .map(|m| Arc::new(spec.env_sun.apply(m))),
    })
}

/// The scene for one specular model.
pub fn scene(spec: &SceneSpec, loaded: &Loaded, specular: Arc<Specular>) -> Scene {
    let material = || Material {
        kd: spec.kd,
        ks: spec.ks,
        albedo: spec.albedo,
        texture: loaded.texture.clone(),
        bump: spec.bump,
        specular: specular.clone(),
        maps: None,
    };
    let (shape, camera) = match &loaded.mesh {
        Some(m) => {
            let (lo, hi) = m.bounds();
            (
                Shape::Mesh(m.clone()),
                Camera::framing(lo, hi, -Vec3::Z, 30.0),
            )
        }
        None => (
            Shape::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            }),
            Camera {
                eye: Vec3::new(0.0, 0.0, 4.6),
                target: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 30.0,
            },
        ),
    };
    let mut objects = vec![Object {
        shape,
        material: material(),
    }];
    if spec.floor {
        let y = match &loaded.mesh {
            Some(m) => m.bounds().0.y,
            None => -1.0,
        };
        objects.push(Object {
            shape: Shape::Plane(Plane {
                point: Vec3::new(0.0, y, 0.0),
                normal: Vec3::Y,
            }),
            material: Material {
                kd: 0.8,
                ks: 0.0,
                albedo: Vec3::splat(0.5),
                texture: None,
                bump: None,
                specular: specular.clone(),
                maps: None,
            },
        });
    }
    let lights = if spec.lights.is_empty() && loaded.env.is_none() {
        vec![Light {
            kind: LightKind::Directional {
                to_light: Vec3::new(-0.45, 0.55, 0.7).normalize(),
            },
            color: Vec3::ONE,
            intensity: 3.0,
        }]
    } else {
        spec.lights.clone()
    };
    Scene {
        camera,
        lights,
        // The environment is the ambient light when there is one.
        ambient: if loaded.env.is_some() {
            Vec3::ZERO
        } else {
            Vec3::splat(0.04)
        },
        background: Vec3::splat(0.015),
        objects,
        shadows: spec.shadows,
        environment: loaded.env.clone().map(|map| Environment {
            map,
            samples: spec.env_samples.max(1),
        }),
    }
}
