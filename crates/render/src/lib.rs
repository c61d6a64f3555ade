//! fastbrdf-render: a CPU renderer that shades spheres, planes and OBJ meshes with any model
//! of the fastbrdf registry, and compares renders of several models.
//!
//! Data flow: [`scene::Scene`] (camera, lights, objects with materials) -> [`render::render`]
//! (rayon over tiles, 16x16 with an environment, 64x32 without; primary rays, N x N supersampling; per tile, the hits' light and
//! view directions in each hit's local frame go through one batch kernel call per light,
//! `fastbrdf::batch::Kernel`) -> [`film::Film`] (linear HDR) -> PNG (sRGB, exposure) or EXR
//! (linear). [`compare`] renders several models, lays them out with labels and heat maps, and
//! measures RMSE, PSNR and FLIP (NVIDIA's metric, through the `nv-flip` crate).
//!
//! Shading: `kd * albedo * lambert + ks * specular`, per light, times `cos theta_i`, plus an
//! ambient term `ambient * kd * albedo`. Shadow rays per light (`Scene::shadows`). With an
//! environment map ([`env`]): no ambient term; per primary hit and progressive pass, one
//! map-sampled, one cosine-sampled and one BRDF-sampled direction, combined by MIS (see
//! `env` and `render::env_pass`). The specular model is any registry id: full BRDFs as
//! they are, lobes as the lobe of `n . h` (`blinn-phong` with `norm = none`, the seeds'
//! pictures), distributions inside `cook-torrance` with that `d`.

pub mod bump;
pub mod compare;
mod decode;
pub mod env;
pub mod error;
pub mod film;
pub mod geometry;
pub mod gltf;
pub mod gltf_write;
mod hash;
pub mod maps;
pub mod mesh;
pub mod render;
pub mod scene;
pub mod setup;
mod specular;
pub mod texture;
pub mod user;

pub use error::{RenderError, Result};
