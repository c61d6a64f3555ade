//! What the page needs to draw its pictures itself with WebGPU (issue 32): the scene as the
//! GPU renderer's buffers (`/api/gpu/scene`) and one render module per model and choice set
//! (`/api/gpu/shader`), from `fastbrdf_gpu::render::web`. The page then redraws on every
//! slider move without asking the server; `/api/render` stays for browsers without WebGPU.

use super::query::{MAX_SIZE, Query, Response, base64, checked_id, parse_u32};
use crate::CliError;
use crate::commands::view::state::State;
use crate::model_args::{self, Use};
use fastbrdf_gpu::render::web;
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::{Light, Specular};
use fastbrdf_render::setup::{self, Loaded, SceneSpec};
use serde_json::{Value, json};
use std::sync::{Arc, Mutex, OnceLock};

/// An environment's data by its name in the query.
type Cached = (String, Arc<web::WebEnv>);

/// The environments' data for the page, computed once each (`sky`, `file`): the split-sum's
/// prefiltered maps take a moment.
fn web_env(state: &State, which: &str) -> Result<Option<Arc<web::WebEnv>>, CliError> {
    static CACHE: OnceLock<Mutex<Vec<Cached>>> = OnceLock::new();
    let map = match which {
        "none" => return Ok(None),
        "sky" => None,
        "file" => match &state.env_file {
            Some((_, m)) => Some(m.clone()),
            None => {
                return Err(CliError::input(
                    "env=file: the server was started without --env FILE",
                ));
            }
        },
        e => {
            return Err(CliError::input(format!(
                "env '{}': expected none, sky or file",
                fastbrdf_io::shorten(e, 64)
            )));
        }
    };
    let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
    if let Some((_, e)) = cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .iter()
        .find(|(k, _)| k == which)
    {
        return Ok(Some(e.clone()));
    }
    let map = map.unwrap_or_else(|| Arc::new(fastbrdf_render::env::EnvMap::sky()));
    let env = Arc::new(web::WebEnv::new(&map));
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push((which.to_string(), env.clone()));
    Ok(Some(env))
}

/// The scene a query names (`mesh=sphere|mesh`, `light=X,Y,Z`), for `/api/render` and the page:
/// its spec and the loaded geometry.
pub fn scene_choice<'a>(state: &'a State, q: &Query) -> Result<(SceneSpec, &'a Loaded), CliError> {
    let mut spec = SceneSpec::new();
    let loaded = match q.get("mesh").unwrap_or("sphere") {
        "sphere" => &state.loaded_sphere,
        "mesh" => {
            let Some(m) = state.loaded_mesh.as_ref() else {
                return Err(CliError::input(
                    "mesh=mesh: the server was started without --mesh",
                ));
            };
            spec.mesh = state.mesh_path.clone();
            m
        }
        m => {
            return Err(CliError::input(format!(
                "mesh '{}': expected sphere or mesh",
                fastbrdf_io::shorten(m, 64)
            )));
        }
    };
    if let Some(l) = q.get("light") {
        spec.lights = vec![Light::parse(&format!("dir:{l}"))?];
    }
    Ok((spec, loaded))
}

/// Little-endian words (u32 or f32), base64.
trait Words {
    fn le(&self) -> [u8; 4];
}
impl Words for u32 {
    fn le(&self) -> [u8; 4] {
        self.to_le_bytes()
    }
}
impl Words for f32 {
    fn le(&self) -> [u8; 4] {
        self.to_le_bytes()
    }
}
fn b64<T: Words>(data: &[T]) -> String {
    let bytes: Vec<u8> = data.iter().flat_map(Words::le).collect();
    base64(&bytes)
}

/// `GET /api/gpu/scene?mesh=sphere|mesh&light=X,Y,Z&size=N&spp=S&env=none|sky|file`: the scene as the GPU
/// renderer's buffers, each little-endian base64 (`fastbrdf_gpu::render::web::WebScene`):
/// `{width, height, spp, frame (u32), lights (f32), occluders (u32), nodes (u32),
/// shadow_triangles (f32), background [r,g,b], objects: [{uniform (u32), whole (u32: kd 0,
/// ks 1), texture: {width, height, texels (f32 RGBA)}, vertices (f32), triangles (u32),
/// corners (f32) | null, count}], magma (768 bytes: the difference maps' colours, FLIP's
/// magma as `compare::heat_map`), env: null | {width, height, texels (f32 RGBA: radiance and
/// the texel's probability mass), tables (f32: the sampling CDFs), prefiltered: {width,
/// height, levels, texels}} (group 3, `fastbrdf_gpu::render::env`)}`. With an environment
/// the ambient term is 0, as `--env` makes it.
pub fn scene_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let size = parse_u32(q, "size", 512, 16, MAX_SIZE)?;
    let spp = parse_u32(q, "spp", 1, 1, 4)?;
    let (spec, loaded) = scene_choice(state, q)?;
    // The specular term is the module's (the page's); the scene only carries the material.
    let any = fastbrdf::ModelSpec::parse("blinn-phong", &[])?;
    let mut scene = setup::scene(&spec, loaded, Arc::new(Specular::new(&any)?));
    let env = web_env(state, q.get("env").unwrap_or("none"))?;
    if env.is_some() {
        // As `setup::scene` with --env: the environment is the ambient light.
        scene.ambient = glam::Vec3::ZERO;
    }
    let opts = Options {
        width: size,
        height: size,
        spp,
        shading: fastbrdf_render::render::Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    let s = web::scene(&scene, &opts).map_err(|e| CliError::input(e.to_string()))?;
    let objects: Vec<Value> = s
        .objects
        .iter()
        .map(|o| {
            json!({
                "uniform": b64(&o.uniform), "whole": b64(&o.whole),
                "texture": {"width": o.texture.0, "height": o.texture.1, "texels": b64(&o.texture.2)},
                "vertices": b64(&o.vertices), "triangles": b64(&o.triangles),
                "corners": o.corners.as_ref().map(|(c, _)| b64(c)),
                "count": o.corners.as_ref().map_or(0, |(_, n)| *n),
            })
        })
        .collect();
    let magma: Vec<u8> = fastbrdf_render::compare::heat_map(
        &(0..256).map(|i| i as f32 / 255.0).collect::<Vec<_>>(),
        1.0,
    );
    let env = env.map(|e| {
        let (d, p) = (&e.data, &e.prefiltered);
        json!({
            "width": d.width, "height": d.height,
            "texels": b64(&d.texels_rgba32f), "tables": b64(&d.tables),
            "prefiltered": {"width": p.width, "height": p.height, "levels": p.levels,
                            "texels": b64(&p.texels_rgba32f)},
        })
    });
    Ok(Response::json(&json!({
        "env": env,
        "width": s.width, "height": s.height, "spp": s.spp,
        "frame": b64(&s.frame), "lights": b64(&s.lights),
        "occluders": b64(&s.occluders), "nodes": b64(&s.nodes),
        "shadow_triangles": b64(&s.shadow_triangles),
        "background": s.background, "objects": objects,
        "magma": base64(&magma),
    })))
}

/// `GET /api/gpu/shader?model=ID&mesh=sphere|mesh&env=none|sky|file&dfg=ENV_MODEL&CHOICE=VALUE...`:
/// the render module of one model for a scene with or without meshes and an environment (with
/// `dfg`'s split-sum terms, default `env-brdf`), for the
/// page's WebGPU renderer: `{model, wgsl, block, params: [{name, default}], whole}`. A
/// registry model is its shaded BRDF's runtime-parameter instance with the query's choices
/// (numbers are the page's, one `vec4` each in the block at group 1, binding 5, in `params`
/// order); a user's model (`file:...`) its shader with its own block (`block: "user"`, the
/// layout of its `params` in `/api/models`), shaded as a whole BRDF (`whole`: kd 0, ks 1).
pub fn shader_endpoint(state: &State, q: &Query) -> Result<Response, CliError> {
    let id = q.need("model")?;
    let meshes = match q.get("mesh").unwrap_or("sphere") {
        "sphere" => false,
        "mesh" => true,
        m => {
            return Err(CliError::input(format!(
                "mesh '{}': expected sphere or mesh",
                fastbrdf_io::shorten(m, 64)
            )));
        }
    };
    let dfg_spec;
    let env = match q.get("env").unwrap_or("none") {
        "none" => web::Env::None,
        "sky" | "file" => {
            let dfg = q.get("dfg").unwrap_or("env-brdf");
            dfg_spec = fastbrdf::ModelSpec::parse(dfg, &[])?;
            if dfg_spec.kind() != fastbrdf::Kind::Env {
                return Err(CliError::input(format!(
                    "dfg '{dfg}': not an environment model (see `fastbrdf models --kind env`)"
                )));
            }
            web::Env::Lit(Some(&dfg_spec))
        }
        e => {
            return Err(CliError::input(format!(
                "env '{}': expected none, sky or file",
                fastbrdf_io::shorten(e, 64)
            )));
        }
    };
    if let Some(u) = state.user(id) {
        let wgsl =
            web::user_module(&u.shader, meshes, env).map_err(|e| CliError::input(e.to_string()))?;
        return Ok(Response::json(&json!({
            "model": u.name, "wgsl": wgsl, "block": "user", "params": u.params_json(),
            "whole": true,
        })));
    }
    let id = checked_id(id)?;
    let spec = model_args::spec(
        id,
        &model_args::own_pairs(id, &q.params())?,
        None,
        None,
        Use::AsIs,
    )?;
    let m = web::model_module(&spec, meshes, env).map_err(|e| CliError::input(e.to_string()))?;
    let params: Vec<Value> = m
        .params
        .iter()
        .map(|(n, v)| json!({"name": n, "default": v}))
        .collect();
    Ok(Response::json(&json!({
        "model": id, "wgsl": m.wgsl, "block": "model", "params": params, "whole": false,
    })))
}
