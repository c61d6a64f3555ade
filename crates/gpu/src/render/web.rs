//! The GPU renderer for a browser (issue 32): everything `fastbrdf view`'s page needs to draw
//! a scene with WebGPU from the same module as [`super::render`], as plain data.
//!
//! The page runs the renderer's two passes (visibility, then shading: `shaders/render.wgsl`)
//! with the bind group layouts of `layouts.rs` (groups 0 to 2; WebGPU's default limits hold
//! them: 7 storage buffers in the fragment stage, 3 groups), so its picture is this
//! renderer's: the CPU's, within the tolerances of `tests/render.rs`. What differs is only
//! where the model's parameters live: in the page they change on every slider move, so a
//! registry model is the runtime-parameter instance (`Instance::runtime`, the code
//! `fastbrdf shader --runtime-params` exports), its numeric parameters read from a uniform at
//! group 1, binding 5, one `vec4` per parameter (`.x`; the layout of a user's parameter
//! block, `UserShader::param_block`); choices are fixed in the module (one module per model
//! and choice set). A user's shader takes its own block there already ([`user_module`]).
//!
//! One tile: the page draws at most [`MAX_SAMPLES`] samples per side.

use super::env::EnvData;
use super::env::env_module_source;
use super::features::Features;
use super::layouts::USER_PARAMS_BINDING;
use super::objects::{KD_WORD, KS_WORD, Reach, object_data};
use super::scene_data::{OccluderData, frame_data, lights_data};
use super::split_sum::Prefiltered;
use super::{SHADER, Tile};
use crate::context::GpuError;
use crate::spec::Instance;
use crate::user::UserShader;
use fastbrdf::ModelSpec;
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::Scene;

/// The largest side of the page's sample grid (W N and H N): one tile of the native renderer.
pub const MAX_SAMPLES: u32 = super::TILE_SAMPLES;

/// The name of a registry model's parameter block in a [`model_module`].
pub const PARAMS_NAME: &str = "fb_web_params";

/// The renderer's shaders for a page's scene, with or without meshes: the page refuses glTF
/// materials' textures and tints ([`scene`]), so their parts are off (`features.rs`; on
/// SwiftShader not measurably faster), and without meshes the mesh occluders' (SwiftShader
/// zero-initialises the traversal's stack in every fragment otherwise: about half of a frame,
/// measured).
fn renderer(meshes: bool) -> String {
    let mut f = Features::all();
    for part in [
        "RD_USE_TINT",
        "RD_USE_NORMAL_MAP",
        "RD_USE_OCCLUSION",
        "RD_USE_EMISSIVE",
        "RD_USE_MR",
    ] {
        f.set(part, false);
    }
    f.set("RD_OCC_MESHES", meshes);
    f.apply(SHADER)
}

/// One object of a [`WebScene`]: its uniform (`struct Object`; [`WebObject::whole`] is the
/// same with kd 0 and ks 1, how the explorer shades a whole BRDF: a user's model), linear
/// albedo texels (RGBA f32, row-major), mesh vertices (8 f32 each) and triangles (4 u32
/// each), and for a mesh the rasteriser's corners (3 x f32 per corner, `count` corners).
pub struct WebObject {
    pub uniform: Vec<u32>,
    pub whole: Vec<u32>,
    pub texture: (u32, u32, Vec<f32>),
    pub vertices: Vec<f32>,
    pub triangles: Vec<u32>,
    pub corners: Option<(Vec<f32>, u32)>,
}

/// A scene as the page's WebGPU renderer takes it: group 0's frame uniform (one tile: the
/// whole (W N) x (H N) sample grid), lights, occluder records, BVH nodes and shadow-ray
/// triangles; group 1's data per object; the background colour that clears the shading pass.
pub struct WebScene {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub frame: Vec<u32>,
    pub lights: Vec<f32>,
    pub occluders: Vec<u32>,
    pub nodes: Vec<u32>,
    pub shadow_triangles: Vec<f32>,
    pub background: [f32; 3],
    pub objects: Vec<WebObject>,
}

/// The scene's data for the page, checked against WebGPU's default limits
/// (`wgpu::Limits::default()`: what every browser grants without asking). Errors: sizes
/// whose sample grid exceeds [`MAX_SAMPLES`] per side, `spp` outside 1..=16, an environment
/// (not drawn by the page yet), and what [`super::render`] refuses about meshes and textures.
pub fn scene(scene: &Scene, opts: &Options) -> Result<WebScene, GpuError> {
    let (w, h, n) = (opts.width, opts.height, opts.spp);
    if !(1..=16).contains(&n) {
        return Err(GpuError::Input(format!(
            "spp {n}: must be 1 to 16 (N x N samples per pixel)"
        )));
    }
    if w == 0 || h == 0 || w * n > MAX_SAMPLES || h * n > MAX_SAMPLES {
        return Err(GpuError::Input(format!(
            "{w}x{h} at {n}x{n} samples: the page draws at most {MAX_SAMPLES} samples per side"
        )));
    }
    let limits = wgpu::Limits::default();
    let (_, _, _, th) = scene.camera.frame();
    let reach = Reach {
        eye: scene.camera.eye,
        sample_per_distance: 2.0 * th / (h * n) as f32,
    };
    let tile = Tile {
        x0: 0,
        y0: 0,
        w: w * n,
        h: h * n,
    };
    let mut objects = Vec::with_capacity(scene.objects.len());
    for (i, obj) in scene.objects.iter().enumerate() {
        if obj.material.specular.tint.is_some() || obj.material.maps.is_some() {
            return Err(GpuError::Input(format!(
                "object {i}: a textured glTF material: the page does not draw it (the server \
                 does)"
            )));
        }
        let d = object_data(&limits, obj, i, &reach)?;
        let mut whole = d.uniform.clone();
        whole[KD_WORD] = 0f32.to_bits();
        whole[KS_WORD] = 1f32.to_bits();
        objects.push(WebObject {
            uniform: d.uniform,
            whole,
            texture: d.texture,
            vertices: d.vertices,
            triangles: d.triangles,
            corners: d.corners,
        });
    }
    let occ = OccluderData::new(&limits, scene)?;
    let bg = scene.background;
    Ok(WebScene {
        width: w,
        height: h,
        spp: n,
        frame: frame_data(scene, opts, &tile),
        lights: lights_data(scene),
        occluders: occ.objects.concat(),
        nodes: occ.nodes.concat(),
        shadow_triangles: occ.triangles,
        background: [bg.x, bg.y, bg.z],
        objects,
    })
}

/// Environment light in a page's module: none, or `env.wgsl` with the split-sum terms of an
/// environment model (`rd_dfg`; the stub without one), so that one module draws both the
/// sampled picture and the split-sum shortcut (`EnvParams`' mode is a uniform).
#[derive(Clone, Copy)]
pub enum Env<'a> {
    None,
    Lit(Option<&'a ModelSpec>),
}

/// An environment's data for the page (group 3): the map and its sampling tables, and the
/// split-sum's prefiltered maps (`split_sum::Prefiltered`).
pub struct WebEnv {
    pub data: EnvData,
    pub prefiltered: Prefiltered,
}

impl WebEnv {
    pub fn new(map: &fastbrdf_render::env::EnvMap) -> Self {
        let data = EnvData::new(map);
        let prefiltered = Prefiltered::new(map);
        Self { data, prefiltered }
    }
}

/// `code` + the renderer + (with an environment) its part + `glue`: a page's module.
fn assemble(code: &str, meshes: bool, env: Env, glue: &str) -> Result<String, GpuError> {
    let env_part = match env {
        Env::None => String::new(),
        Env::Lit(dfg) => env_module_source(code, dfg)?,
    };
    Ok(format!("{code}\n{}\n{env_part}\n{glue}", renderer(meshes)))
}

/// A module for the page: the renderer's shaders with `rd_brdf`, and the numeric parameters
/// it reads from its block, in order, with their values in `spec` (one `vec4` each, `.x`).
pub struct WebModule {
    pub wgsl: String,
    pub params: Vec<(String, f64)>,
}

/// The module of a registry model (`meshes`: whether the scene has meshes): its shaded BRDF (a lobe or a distribution as the renderer
/// shades it, `ModelSpec::shaded`) as the runtime-parameter instance, every numeric parameter
/// read from `fb_web_params` at group 1, binding 5. Errors: a coloured spec (the runtime form
/// takes one value per parameter) and a model the renderer cannot shade.
pub fn model_module(spec: &ModelSpec, meshes: bool, env: Env) -> Result<WebModule, GpuError> {
    let shaded = spec.shaded().map_err(|e| GpuError::Input(e.to_string()))?;
    if shaded.is_coloured() {
        return Err(GpuError::Input(format!(
            "{}: a parameter given as R,G,B: the page draws grey models (the server draws \
             this one)",
            spec.id()
        )));
    }
    let inst = Instance::runtime(&shaded).map_err(|e| GpuError::Input(e.to_string()))?;
    if inst.info.kind != fastbrdf::Kind::Brdf {
        return Err(GpuError::Input(format!(
            "'{}' is not a BRDF: the renderer shades with BRDF instances",
            inst.info.id
        )));
    }
    let k = inst.sliders.len().max(1);
    let args: String = (0..inst.sliders.len())
        .map(|i| format!(", {PARAMS_NAME}[{i}].x"))
        .collect();
    let glue = format!(
        "@group(1) @binding({USER_PARAMS_BINDING}) var<uniform> {PARAMS_NAME}: array<vec4<f32>, {k}>;\n\
         fn rd_brdf(wi: vec3<f32>, wo: vec3<f32>, h: u32) -> RdSpec {{\n    return RdSpec(vec3<f32>({}(wi, wo{args})), vec3<f32>(0.0));\n}}\n",
        inst.function
    );
    Ok(WebModule {
        wgsl: assemble(&inst.module_source(), meshes, env, &glue)?,
        params: inst.sliders.clone(),
    })
}

/// The module of a user's shader: as `render_user` builds it (its parameters at group 1,
/// binding 5, in `UserShader::param_block`'s layout).
pub fn user_module(shader: &UserShader, meshes: bool, env: Env) -> Result<String, GpuError> {
    let user = shader
        .wgsl_at(1, USER_PARAMS_BINDING)
        .map_err(|e| GpuError::Input(e.message))?;
    assemble(&user, meshes, env, super::passes::USER_GLUE)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The page's module of a registry model validates (naga, as a browser's WGSL compiler
    /// would parse it): with and without meshes and an environment.
    #[test]
    fn model_modules_validate() {
        let spec = ModelSpec::parse("cook-torrance", &[("alpha", "0.3")]).unwrap();
        for (meshes, env) in [(true, Env::None), (false, Env::Lit(None))] {
            let m = model_module(&spec, meshes, env).unwrap();
            super::super::naga_module(&m.wgsl);
        }
    }
}
