//! The GPU renderer: the CPU renderer's scenes (`fastbrdf_render::scene::Scene`: camera,
//! lights, spheres, planes, OBJ meshes, textures, micro-relief) rasterised with wgpu and shaded
//! per sample by any model's WGSL twin (`spec::Instance`) or a user's shader
//! ([`render_user`], `crate::user`), into the CPU's `Film`.
//!
//! # Design
//!
//! The CPU renderer (`fastbrdf_render::render`) traces one primary ray per stratified sample:
//! N x N samples per pixel at `(x + (sx + 0.5) / N, y + (sy + 0.5) / N)`. Here the image is
//! rasterised at (W N) x (H N) into an `Rgba32Float` target with a `Depth32Float` depth
//! buffer, so that every fragment centre is exactly one of the CPU's sample positions; the
//! N x N blocks are read back and averaged on the CPU in the CPU's order.
//!
//! - Spheres and planes: one triangle covering the tile; the fragment shader intersects the
//!   sample's primary ray analytically (the formulas of `geometry.rs`) and discards misses.
//! - Meshes: real triangles (three corners per triangle, so the fragment shader knows its
//!   triangle through a flat-interpolated index), projected by a matrix built from the
//!   camera. The rasteriser only decides which triangle covers a sample; the fragment shader
//!   then runs the CPU's Moller-Trumbore test on that triangle with the sample's primary ray,
//!   so `t`, the barycentrics, the interpolated normal and uv are the CPU's, not the
//!   rasteriser's interpolants. Where the two disagree about a sample within rounding of an
//!   edge, a sample outside a boundary edge (one no other triangle shares: the outline of an
//!   open mesh like the face) is discarded, as the CPU's ray misses it; a sample outside a
//!   shared edge is shaded from its barycentrics as they are (the CPU's ray hits the
//!   neighbour, and shading is continuous across the edge).
//!   Boundary edges are pushed a quarter sample outward for the rasteriser only
//!   (`dilate_boundaries`), so that a sample exactly on one (which the CPU's inclusive test
//!   draws and the top-left rule may skip) still gets a fragment for the exact test to keep.
//! - Depth: every fragment writes `t * 2^-40` as its depth. The scaling is exact, so the
//!   depth test (`Less`, objects drawn in scene order) picks the nearest hit exactly as
//!   `Scene::intersect` does (strictly nearer wins, ties keep the earlier object).
//! - Shading (`shaders/render.wgsl`): the primary ray rebuilt from the fragment position
//!   (`Camera::ray`'s arithmetic, with the camera frame computed by glam here), two-sided
//!   normal, micro-relief (`bump.rs` ported, wrapping u32 hash included), albedo texture
//!   (linear texels uploaded as `Rgba32Float` and filtered by `texture.rs`'s bilinear rule with
//!   `textureLoad`),
//!   sphere uvs with `atan2`/`asin` written out (WGSL's built-ins are too loose: lavapipe's
//!   moved texels by 6e-4), ambient, and per light `li base cos/pi + li ks brdf(wi, wo) cos`
//!   in the local frame of glam's `any_orthonormal_pair`, accumulated in the CPU's order.
//! - Specular models (`models.rs`, issue 33): `rd_brdf` gives the object's model per colour
//!   channel: a grey model's one instance in R, G and B, a coloured model's three channel
//!   instances (`Specular::channels`, as the CPU evaluates them), each weighting its own
//!   channel with the grey path's operations (`li (ks f cos)`), so channel c of a coloured
//!   render is the grey render of channel c's model, on both renderers. A tinted term
//!   (`Specular::tint`, a glTF base colour texture) also evaluates the zero model and mixes
//!   the two weighted terms per channel as `f0 + t (f1 - f0)`, `t` the texel of the tint's
//!   texture (uploaded below the albedo texture's rows in the object's texture, filtered by
//!   the same bilinear rule). The channels and the zero model are slots of one loop over
//!   coefficient offsets in `fb_k`, so each distinct model function is compiled once.
//!   A glTF material's other textures (`maps.rs`) are stacked there too: the normal texture
//!   tilts the shading normal in the tangent frame (below), the occlusion scales the ambient
//!   and environment light, the emission is added once per sample, each with the CPU's
//!   arithmetic; a metallic-roughness texture selects per sample the blocks of coefficients
//!   of its roughness level's models at metallic 0 and 1 (uploaded for every level its
//!   texels can select) and mixes the two by the metallic, as `mapped.rs` does.
//! - Tangent frames: a mesh with tangents (a glTF mesh of an anisotropic material) carries
//!   them per vertex (`mesh_v`, 12 floats instead of 8); the shader interpolates them as
//!   `TriMesh::hit_tangent` and builds `maps::frame`'s local frame from them, so an
//!   anisotropic model turns with the file's tangents as on the CPU. Elsewhere the frame is
//!   `any_orthonormal_pair` of the shading normal.
//! - Shadows (`scene.shadows`, the CPU's rule and arithmetic): every object goes up once
//!   more, for the shadow rays (`Occluders`): spheres and planes as records, each mesh as its
//!   CPU BVH (`TriMesh::bvh`, nodes flattened into one array with rebased indices) and its
//!   triangles' corners in the BVH's leaf order. Per light the fragment shader casts the CPU's
//!   shadow ray (`Scene::shadowed`: origin offset along the unbumped normal by
//!   `SHADOW_EPS (1 + max |p|)`, no ray where only the bumped normal faces the light, a point
//!   light's ray stopping short of it) and tests it like `Scene::occluded`: the sphere's and
//!   plane's formulas, and for meshes the walk of `TriMesh::occluded_binary`: the CPU's slab
//!   test (`geometry::slab`, its far bounds widened by `SLAB_WIDEN`, its comparisons written
//!   out so NaN from an axis-parallel ray, e.g. a light straight above, goes the same way),
//!   children tested at their parent, its stack (64 entries, children skipped when full, as
//!   on the CPU; sized for the scene's deepest BVH, which never fills it, `features.rs`) and
//!   Moller-Trumbore test, ending at the first hit: a hit is found wherever a leaf whose slab
//!   tests pass holds one, whatever the order. The f32 constants
//!   (`SHADOW_EPS`, `1 - 1e-5`, `f32::MAX` standing for the infinite reach of a directional
//!   light: the same decisions under `t < t_max`) come from the CPU in the frame uniform, so no
//!   WGSL literal rounds differently. Memory: 36 bytes per triangle and 32 per node, checked
//!   against the device's storage binding limit like the other mesh buffers (128 MiB by
//!   default: about 3.5 million triangles); a larger mesh is refused with the sizes and the
//!   hint `--shadows off` (no such buffers then).
//! - Environment light (`scene.environment`): `env.rs` and `shaders/env.wgsl`, spliced in
//!   only then; per sample and pass a map direction and a cosine direction (balance
//!   heuristic), with the CPU's shadow rays; `samples` passes in a few draws per tile, summed
//!   (at most 4 passes per draw with shadow rays through meshes, 64 without: lavapipe cuts a
//!   shader invocation's loops short after 65535 iterations in all, `env.rs`).
//!   Under the environment the CPU's own BRDF sampling is the one estimator the GPU lacks.
//! - The scene's features (`features.rs`): the shader's optional parts (micro-relief,
//!   textures, glTF maps, tangents, shadow rays and each occluder kind) sit behind WGSL
//!   constants, set false for the parts no object of the scene uses, so their code is dead.
//!   Adapters that run both sides of every branch (lavapipe) no longer pay for
//!   them in every fragment (the default sphere 3.98x faster on lavapipe under the key light,
//!   4.20x under the sky); the picture is the same to the bit.
//! - Large images are cut into tiles of at most 2048 x 2048 samples (and at most the device's
//!   largest texture side), whole pixels each, so the image size is only limited by
//!   `film::check_size`, like the CPU's.
//!
//! # Why rasterise
//!
//! Primary visibility is what rasterisers do; only the shadow rays need the scene's BVH on the
//! GPU. With the ray-triangle test in the fragment shader the
//! rasteriser adds no interpolation error of its own: it only chooses the triangle. The
//! shading is where models differ, and that is one fragment per sample.
//!
//! # The parity rule
//!
//! Every shader function is the twin of the CPU code it names, with the same arrangement of f32
//! operations. GPU and CPU renders may still differ by what WGSL lets a GPU do differently
//! (fused multiply-adds; division and `sqrt` within a few ulp), by the model functions' own
//! differences (`tests/parity.rs`), and, on mesh silhouettes, where a sample lies within
//! rounding of an edge (measured on lavapipe: about 1 sample in 300,000 of a face render),
//! and likewise where a shadow ray passes within rounding of an occluder's edge (a shadow's
//! edge: lit on one side, in shadow on the other).
//! `tests/render.rs` holds GPU renders of the sphere and the face mesh to their CPU renders
//! within stated tolerances: 8-bit on any adapter, and 1e-4 linear on software adapters;
//! `tests/render_gltf.rs` a glTF scene's coloured and textured `gltf-pbr` materials likewise
//! (and, under the environment light, in the limit, as `tests/render_env.rs`).

pub mod env;
pub mod features;
mod layouts;
mod models;
mod objects;
mod passes;
mod resolve;
mod scene_data;
pub mod split_sum;
pub mod web;

use crate::context::{GpuError, validated};
use crate::user::{ParamValue, UserShader};
use fastbrdf_render::film::{Film, check_size};
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::Scene;
use features::Features;
use glam::Vec3;
use layouts::Layouts;
use objects::{MR_WORD, Reach, object_data, upload_object};
use passes::{Pipelines, ScenePass};
use scene_data::{OccluderData, Occluders, frame_data, lights_buffer};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// The shaders (see the file's header); completed by the model library and `rd_brdf`.
pub const SHADER: &str = include_str!("../shaders/render.wgsl");

/// Largest tile side, in samples: a 2048 x 2048 `Rgba32Float` tile is 64 MiB.
pub const TILE_SAMPLES: u32 = 2048;

/// The near clipping distance along the view axis for mesh triangles, below the CPU's
/// smallest ray parameter (1e-4), so that clipping never removes a hit the CPU would find.
const NEAR: f64 = 1e-5;

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The visibility pass's target: object index + 1 (0: none), triangle.
const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

/// Renders `scene` on the GPU: the same image as `fastbrdf_render::render::render` (within
/// the tolerances of `tests/render.rs`), shadow rays included when `scene.shadows`, as a
/// linear `Film`.
///
/// `opts.shading` is ignored (the GPU evaluates the model per sample); `scene.environment`
/// is sampled as [`env`] says, with the CPU's random numbers (`opts.sampler`): the same
/// picture as the CPU's in the limit of many samples (`tests/render_env.rs`). Errors: sizes
/// outside `film::check_size` or `opts.spp` outside 1..=16 (as on the CPU), a mesh (its vertices,
/// corners, or with shadows its BVH and triangles) or texture larger than the device's limits,
/// a model that is not a BRDF instance, an RGB BRDF (see [`render_user`]), what [`check`]
/// refuses, and GPU failures.
pub fn render(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    opts: &Options,
) -> Result<Film, GpuError> {
    render_with_progress(device, queue, scene, opts, &|_, _| {})
}

/// [`render`], calling `progress(done, total)` after each tile (tiles of at most
/// 2048 x 2048 samples, each finished on the GPU before the next is drawn), as
/// `fastbrdf_render::render::render` does with its tiles: the CLI draws its progress bar
/// from it.
pub fn render_with_progress(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    opts: &Options,
    progress: &dyn Fn(usize, usize),
) -> Result<Film, GpuError> {
    render_scene(device, queue, scene, opts, None, None, progress)
}

/// [`render_with_progress`] with a user's shader (issue 31): every object whose specular term
/// is an RGB BRDF (`Specular::rgb`, e.g. `fastbrdf_render::user::UserRgb` of this shader's
/// [`crate::user::GpuBrdf`], as the CPU renderer shades it) is shaded with `shader` at
/// `values` ([`UserShader::values`]) instead: its `fb_user_brdf` spliced in place of a model
/// instance's function, R, G and B, weighted like the CPU's RGB BRDFs (`li ks f cos` per
/// channel; a scene gives a whole BRDF the weights kd 0, ks 1). The RGB BRDF the scene
/// carries is not called. Objects with a model spec shade as in [`render`].
///
/// Errors: those of [`render`], values that are not one per parameter of `shader`, and the
/// user's module failing to translate.
#[allow(clippy::too_many_arguments)]
pub fn render_user(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    opts: &Options,
    shader: &UserShader,
    values: &[ParamValue],
    progress: &dyn Fn(usize, usize),
) -> Result<Film, GpuError> {
    if values.len() != shader.params().len() {
        return Err(GpuError::Input(format!(
            "{}: {} parameter values for its {} parameters (UserShader::values gives them all)",
            shader.name(),
            values.len(),
            shader.params().len()
        )));
    }
    let user = User {
        shader,
        block: shader.param_block(values),
    };
    render_scene(device, queue, scene, opts, Some(&user), None, progress)
}

/// A user's shader and its parameter block, for the objects with an RGB specular term.
struct User<'a> {
    shader: &'a UserShader,
    block: Vec<f32>,
}

/// The pipelines' key of the user's shader (a model's key is WGSL text, never this).
const USER_KEY: &str = "file:";

/// Refuses what only the CPU renderer draws, before any device is needed (a command line
/// checks its scene with it before looking for an adapter): a tinted RGB BRDF. [`render`] and
/// its siblings check it too.
pub fn check(scene: &Scene) -> Result<(), GpuError> {
    for obj in &scene.objects {
        let spec = &obj.material.specular;
        if spec.rgb.is_some() && spec.tint.is_some() {
            return Err(GpuError::Input(format!(
                "'{}': a textured RGB BRDF is CPU-only: drop --gpu",
                spec.id
            )));
        }
    }
    Ok(())
}

fn render_scene(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    opts: &Options,
    user: Option<&User>,
    split: Option<&split_sum::SplitSum>,
    progress: &dyn Fn(usize, usize),
) -> Result<Film, GpuError> {
    check_size(opts.width, opts.height).map_err(|e| GpuError::Input(e.to_string()))?;
    if !(1..=16).contains(&opts.spp) {
        return Err(GpuError::Input(format!(
            "--spp {}: must be 1 to 16 (N x N samples per pixel)",
            opts.spp
        )));
    }
    check(scene)?;
    let limits = device.limits();
    let (w, h, n) = (opts.width, opts.height, opts.spp);
    // Tile side in whole pixels.
    let tile_px = TILE_SAMPLES.min(limits.max_texture_dimension_2d) / n;
    if tile_px == 0 {
        return Err(GpuError::Input(format!(
            "the GPU's largest texture side ({}) is smaller than {n} samples",
            limits.max_texture_dimension_2d
        )));
    }

    let layouts = Layouts::new(device);
    let env = scene
        .environment
        .as_ref()
        .map(|_| env::GpuEnv::new(device, queue, &layouts, &limits, scene, opts.sampler, split))
        .transpose()?;
    // World length of one sample per unit of distance from the eye (see `dilate_boundaries`).
    let (_, _, _, th) = scene.camera.frame();
    let reach = Reach {
        eye: scene.camera.eye,
        sample_per_distance: 2.0 * th / (h * n) as f32,
    };
    // Each object's data goes up first (its metallic-roughness words set), keeping its
    // uniform's words: the scene's features (which parts of the shader any object uses,
    // `features.rs`) decide every pipeline's module.
    let mut uniforms = Vec::with_capacity(scene.objects.len());
    let mut shaders = Vec::with_capacity(scene.objects.len());
    let mut objects = Vec::with_capacity(scene.objects.len());
    for (i, obj) in scene.objects.iter().enumerate() {
        let p = prepare(&limits, obj, i, &reach, user)?;
        let key = p
            .shader
            .as_ref()
            .map_or(USER_KEY, |m| m.key.as_str())
            .to_string();
        uniforms.push(p.data.uniform.clone());
        objects.push(upload_object(
            device,
            queue,
            &layouts,
            p.data,
            (&p.coefs, &p.params),
            key,
        )?);
        shaders.push(p.shader);
    }
    let (features, occluders) = {
        let d = OccluderData::new(&limits, scene)?;
        let f = Features::new(scene, uniforms.iter().map(Vec::as_slice), &d.objects);
        (f, Occluders::new(device, &d))
    };
    let mut pipelines: HashMap<String, Pipelines> = HashMap::new();
    for shader in &shaders {
        match (shader, user) {
            (Some(model), _) if !pipelines.contains_key(&model.key) => {
                let p = Pipelines::new(device, &layouts, &features, model, env.as_ref())?;
                pipelines.insert(model.key.clone(), p);
            }
            (None, Some(u)) if !pipelines.contains_key(USER_KEY) => {
                let p = Pipelines::user(device, &layouts, &features, u.shader, env.as_ref())?;
                pipelines.insert(USER_KEY.to_string(), p);
            }
            _ => {}
        }
    }
    let lights = lights_buffer(device, scene);

    let (tw_max, th_max) = (w.min(tile_px) * n, h.min(tile_px) * n);
    let target = |format, label, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: tw_max,
                height: th_max,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
    let color = target(
        COLOR_FORMAT,
        "fastbrdf render colour",
        attachment | wgpu::TextureUsages::TEXTURE_BINDING,
    );
    let depth = target(DEPTH_FORMAT, "fastbrdf render depth", attachment);
    let ids = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("fastbrdf render ids"),
        size: wgpu::Extent3d {
            width: tw_max,
            height: th_max,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: ID_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let ids_view = ids.create_view(&Default::default());
    let ids_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fastbrdf render ids"),
        layout: &layouts.ids,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::TextureView(&ids_view),
        }],
    });
    let (color_view, depth_view) = (
        color.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    let resolver = resolve::Resolver::new(device, u64::from(tw_max / n) * u64::from(th_max / n));

    let mut film = Film::try_new(w, h).map_err(|e| GpuError::Input(e.to_string()))?;
    let tiles = (w.div_ceil(tile_px) * h.div_ceil(tile_px)) as usize;
    // Under an environment, each tile takes its passes in a few draws (the first with the
    // direct light and the background), summed (`env::GpuEnv::chunks`).
    let chunks_of = |tile: &Tile| {
        env.as_ref().map_or(vec![(0, 1)], |e| {
            e.chunks(u64::from(tile.w) * u64::from(tile.h))
        })
    };
    let total = {
        let full = Tile {
            x0: 0,
            y0: 0,
            w: w.min(tile_px) * n,
            h: h.min(tile_px) * n,
        };
        tiles * chunks_of(&full).len()
    };
    let mut done = 0;
    progress(done, total);
    for py0 in (0..h).step_by(tile_px as usize) {
        for px0 in (0..w).step_by(tile_px as usize) {
            let (pw, ph) = (tile_px.min(w - px0), tile_px.min(h - py0));
            let tile = Tile {
                x0: px0 * n,
                y0: py0 * n,
                w: pw * n,
                h: ph * n,
            };
            let chunks = chunks_of(&tile);
            let resolve = resolver.tile(device, &color_view, (pw, ph, n));
            // A smaller tile at an edge may take fewer draws: the progress still ends at
            // `total`.
            let extra = total / tiles - chunks.len();
            let frame = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf render frame"),
                contents: bytemuck::cast_slice(&frame_data(scene, opts, &tile)),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let frame_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fastbrdf render frame"),
                layout: &layouts.frame,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: frame.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: lights.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: occluders.objects.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: occluders.nodes.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: occluders.triangles.as_entire_binding(),
                    },
                ],
            });
            for (ci, &(first, count)) in chunks.iter().enumerate() {
                if let Some(e) = &env {
                    e.set_chunk(queue, first, count);
                }
                validated(device, "the GPU render pass", || {
                    let mut enc = device.create_command_encoder(&Default::default());
                    // Visibility: per sample the nearest hit's object and triangle (each fragment
                    // only intersects its primary ray), so that the shading pass below shades one
                    // fragment per sample however many surfaces overlap there: shading every
                    // fragment that passed the depth test so far (it writes its depth, so the test
                    // comes after the shader) cost a shadow ray per overlapping layer, thousands
                    // per sample on a mesh of stacked copies.
                    // Under an environment the background is drawn (`env.wgsl`) on black.
                    let bg = if env.is_some() {
                        Vec3::ZERO
                    } else {
                        scene.background
                    };
                    let passes = [
                        // The visibility pass: ids into `ids_view`.
                        ScenePass {
                            label: "fastbrdf render visibility",
                            target: &ids_view,
                            clear: wgpu::Color::TRANSPARENT,
                            ids: None,
                            env: None,
                            pick: |p: &Pipelines| (&p.analytic_id, &p.mesh_id),
                        },
                        // The shading pass. Scene order: with the `Less` depth test, ties keep the
                        // earlier object (decided by the visibility pass; here only its winner
                        // passes).
                        ScenePass {
                            label: "fastbrdf render",
                            target: &color_view,
                            clear: wgpu::Color {
                                r: f64::from(bg.x),
                                g: f64::from(bg.y),
                                b: f64::from(bg.z),
                                a: 1.0,
                            },
                            ids: Some(&ids_bind),
                            env: env.as_ref(),
                            pick: |p: &Pipelines| (&p.analytic, &p.mesh),
                        },
                    ];
                    for p in &passes {
                        p.draw(
                            &mut enc,
                            &depth_view,
                            &tile,
                            &frame_bind,
                            &objects,
                            &pipelines,
                        );
                    }
                    // The draw's samples into the tile's pixels, on the GPU.
                    resolver.record(&mut enc, &resolve, ci == 0);
                    queue.submit([enc.finish()]);
                })?;
                done += 1;
                progress(done, total);
            }
            // One read-back per tile, after its last draw.
            resolver.read(device, queue, &resolve, |px| {
                for py in 0..ph {
                    for qx in 0..pw {
                        let i = 3 * (py * pw + qx) as usize;
                        film.pixels[((py0 + py) * w + px0 + qx) as usize] =
                            Vec3::new(px[i], px[i + 1], px[i + 2]);
                    }
                }
            })?;
            if extra > 0 {
                done += extra;
                progress(done, total);
            }
        }
    }
    Ok(film)
}

/// An object ready to go up: its model's shader (`None`: the user's), the model's
/// coefficients or the user's parameter block, and its data with the metallic-roughness words
/// set (`render_scene`; the features' tests read the same).
struct Prepared {
    shader: Option<models::ModelShader>,
    coefs: Vec<f32>,
    params: Vec<f32>,
    data: objects::ObjectData,
}

/// [`Prepared`] of object `i`. Errors: an RGB BRDF without a user's shader, a model the GPU
/// cannot shade, and what `object_data` refuses.
fn prepare(
    limits: &wgpu::Limits,
    obj: &fastbrdf_render::scene::Object,
    i: usize,
    reach: &Reach,
    user: Option<&User>,
) -> Result<Prepared, GpuError> {
    let spec = &obj.material.specular;
    let (shader, coefs, params, mr) = match (&spec.rgb, user) {
        // An RGB BRDF: the user's shader (its pipelines made once, in `render_scene`).
        (Some(_), Some(u)) => (None, Vec::new(), u.block.clone(), [0; 4]),
        (Some(_), None) => {
            return Err(GpuError::Input(format!(
                "'{}' is an RGB BRDF (measured data, a fitted model): CPU-only; the GPU \
                 renderer shades with model instances and users' shaders",
                spec.id
            )));
        }
        // The model the CPU renderer shades with (its channels, and a tint's zero model), its
        // plans built once with the scene; one pipeline per distinct shader text.
        (None, _) => {
            let mr = obj
                .material
                .maps
                .as_ref()
                .and_then(|x| x.metallic_roughness.as_ref());
            let mut model = models::model_shader(spec, mr)?;
            let coefs = std::mem::take(&mut model.coefs);
            let mr = model.mr;
            (Some(model), coefs, Vec::new(), mr)
        }
    };
    let mut data = object_data(limits, obj, i, reach)?;
    data.uniform[MR_WORD..MR_WORD + 4].copy_from_slice(&mr);
    Ok(Prepared {
        shader,
        coefs,
        params,
        data,
    })
}

/// `src` parsed and validated by naga, as a browser's or wgpu's WGSL compiler would take it
/// (the render modules' tests); panics with naga's message.
#[cfg(test)]
fn naga_module(src: &str) -> naga::Module {
    let module =
        naga::front::wgsl::parse_str(src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(src)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{e:?}"));
    module
}

/// One tile of the sample grid: first sample column and row, size in samples.
struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}
