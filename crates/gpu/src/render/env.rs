//! Environment light on the GPU (issues 30, 32, 33): `scene.environment` sampled per primary
//! hit and pass by `shaders/env.wgsl`, spliced after `render.wgsl` only when the scene has an
//! environment, so the module and bind groups 0 to 2 of an environment-less scene are
//! unchanged.
//!
//! # The estimator
//!
//! Per primary hit and pass, one direction drawn from the map by its importance tables
//! (`EnvMap::sample`'s rows by their sin theta-weighted luminance, then columns; where the map
//! has a compact bright part, a sun, one from the rest, `EnvMap::sample_rest`, and one from
//! the bright texels, `EnvMap::sample_bright`, as the CPU's light strategies), one
//! cosine-weighted about the shading normal and, on an object with a specular term, one drawn
//! from a GGX lobe about the view's mirror direction (Heitz's visible normals, roughness
//! [`lobe_alpha`]: the model's `alpha`), combined by the balance heuristic over the whole
//! integrand: each adds `L (base cos / pi + ks f cos) / (pdf_map + cos / pi + pdf_lobe)`, with
//! the CPU's shadow rays (`environment.rs`, `visible`). The CPU renderer draws its third
//! direction from the specular BRDF's own sampler and weighs the specular term by the power
//! heuristic; the GPU has every model's value (its WGSL twin) but no sampling twins, so it
//! draws from a GGX lobe of the model's roughness whatever the model: any lobe keeps the
//! estimate unbiased (the weights use the densities of the strategies actually taken, and
//! the map and cosine strategies alone cover every direction the integrand is non-zero in),
//! one close to the model's lowers its noise (measured: as low as the CPU's on the tests'
//! scenes). So the GPU's picture converges to the CPU's; with no specular term the two
//! estimators are the same.
//!
//! Random numbers: the CPU's (`opts.sampler`): Owen-scrambled Sobol points (the default;
//! `sobol_burley`'s `sample_4d` ported with its first four dimensions' direction numbers) or
//! the independent sampler (`fastbrdf_render::env::Rng`, a PCG hash), seeded by the CPU's
//! sample id and pass, so that each sample and pass takes the very numbers the CPU's map,
//! cosine, BRDF and bright directions take: with no specular term (where neither draws a BRDF
//! direction) the pictures agree to rounding, with a sun apart or without
//! (`tests/render_env.rs`). A
//! render is deterministic, and a draw of passes `[first, first + count)` adds new samples to
//! the draws before it.
//!
//! # Bind group 3 (what a browser mirrors)
//!
//! | binding | type | content |
//! |---|---|---|
//! | 0 | `var<uniform>` 48 bytes | `EnvParams`: `size: vec4<u32>` (map width, height, first pass, pass count), `weights: vec4<f32>` (each pass's weight, the direct light's weight, the lobe strategy's roughness or the split-sum's alpha, the split-sum's f0), `options: vec4<u32>` (sampler: 0 Sobol, 1 independent; mode: 0 sampled, 1 split-sum; the prefiltered maps' level width and height): [`EnvData::params`], [`EnvData::split_sum_params`] |
//! | 1 | `texture_2d<f32>`, `Rgba32Float`, non-filterable (textureLoad) | [`EnvData::texels_rgba32f`] (A: the light strategies' mass) |
//! | 2 | `var<storage, read> array<f32>` | [`EnvData::tables`] (the map's, then [`sun_section`]) |
//! | 3 | `texture_2d<f32>`, `Rgba32Float`, non-filterable (textureLoad) | the split-sum's prefiltered maps ([`super::split_sum::Prefiltered`]); any 1 x 1 texture in the sampled mode |
//!
//! All in the fragment stage. The module ends with `rd_dfg(cos_v, alpha) -> vec2<f32>`:
//! [`super::split_sum::DFG_STUB`] in the sampled mode, the environment model's terms in the
//! split-sum mode ([`super::split_sum::dfg_glue`]); [`env_module_source`]
//! gives what follows `render.wgsl`.
//! The shading pass's pipelines use the entry points
//! `rd_fs_analytic_env` and `rd_fs_mesh_env` instead of `rd_fs_analytic` and `rd_fs_mesh`
//! (layout: groups 0, 1, 2 as before and this group 3); the background is drawn first in the
//! shading pass by `rd_vs_full` + `rd_fs_env_background` (groups 0, an empty group 1, 2 and 3;
//! no depth test or write), which writes the map's radiance where the visibility pass found
//! no object. The shading pass clears to black instead of the scene's background.
//! A progressive viewer draws with `params(frame, 1, [1, 1], sampler, lobe_alpha)` per frame
//! (each frame an unbiased picture) and averages frames; [`super::render`] draws `samples`
//! passes in chunks, the first with the direct light (`params(0, k, [1 / samples, 1], ...)`),
//! the rest without (`params(first, k, [1 / samples, 0], ...)`), and sums them. With the Sobol
//! sampler, frame k's points are stratified with those of frames 0 to k - 1 (per sample, pass
//! k is point k of its sequence).

use super::layouts::Layouts;
use super::scene_data::check_binding;
use super::split_sum::{DFG_STUB, Prefiltered, SplitSum, dfg_glue};
use super::{COLOR_FORMAT, DEPTH_FORMAT, SHADER};
use crate::context::{GpuError, validated};
use fastbrdf_render::env::EnvMap;
use fastbrdf_render::render::Sampler;
use wgpu::util::DeviceExt;

/// The environment's shader, appended to the render module (after `render.wgsl`, before the
/// `rd_brdf` glue) when the scene has an environment.
pub const ENV_SHADER: &str = include_str!("../shaders/env.wgsl");

/// Shaded sample-passes per GPU submission (chunks of passes keep each draw short: a
/// display driver's watchdog resets a GPU busy for a few seconds).
const SAMPLE_PASSES_PER_DRAW: u64 = 1 << 20;

/// Passes per draw at most, with shadow rays through a mesh's BVH and without. Why: Mesa's
/// llvmpipe (lavapipe, the software Vulkan driver CI uses) ends every loop of a shader
/// invocation once all of them together have run 65535 iterations
/// (`LP_MAX_TGSI_LOOP_ITERATIONS`, shared between every loop): a fragment that ran more was
/// silently cut short. A mesh's shadow ray takes tens to hundreds of traversal steps, three
/// per pass; measured on a glTF scene of three meshes (1,100 triangles), 32 x 32 at 1024
/// passes in one draw: a third of the light, 256: 1% low; 64 per draw: the CPU's picture
/// (RMSE 0.002, means within 1e-4). Without meshes a pass takes about 60 iterations (Sobol
/// points, the map's binary searches, the objects' shadow tests).
const PASSES_PER_DRAW: [u32; 2] = [4, 64];

/// What the environment light puts on the GPU (bind group 3), as plain data: what the native
/// renderer uploads, and what a browser (WebGPU) uploads likewise.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvData {
    /// Map size in texels (2:1).
    pub width: u32,
    pub height: u32,
    /// `width x height` texels, row-major, top row straight up (`fastbrdf_render::env`'s
    /// mapping): R, G, B radiance and A = the texel's probability mass under the light
    /// strategies x width x height (the numerator of the density `A / (2 pi^2 sin theta)`):
    /// the map's mass, times one over the bright texels' share on a bright texel and one over
    /// the rest's elsewhere where the map has a bright part (`EnvMap::light_pdf`). Upload as
    /// an `Rgba32Float` texture (`bytemuck::cast_slice` for the bytes; little-endian f32 in a
    /// browser).
    pub texels_rgba32f: Vec<f32>,
    /// The sampling tables, one storage buffer: the marginal CDF over rows (`height + 1`
    /// entries, 0 to 1), then per row the conditional CDF over its columns (`width + 1`
    /// entries each, 0 to 1; all 0 for a row of zero weight), then the bright strategy's
    /// section ([`sun_section`]: 8 entries, the first 0, where the map has no bright part).
    pub tables: Vec<f32>,
}

/// The bright strategy's part of [`EnvData::tables`] (after the map's rows), the twin of
/// `EnvMap::sample_bright` and `EnvMap::sample_rest` for `env.wgsl`: a header of 8 entries
/// (the number of bright texels `nb`, 0 for none; the rest's rows that differ from the
/// map's, `k`; the cone's axis x, y, z and `below`; two zeros), then the bright texels' CDF
/// (`nb + 1`), their rows (`nb`) and columns (`nb`), the rest's marginal CDF (`height + 1`),
/// per row its row of the conditional tables (`height`: the map's own below `height`, else
/// `height + j` = the `j`-th of the `k` rows that follow, `width + 1` entries each). Indices
/// are stored as f32 values (at most 8192: exact).
pub fn sun_section(map: &EnvMap) -> Vec<f32> {
    let Some(b) = map.bright_tables() else {
        return vec![0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0];
    };
    let (w, nb) = (map.width, b.texels.len());
    let k = b.rest_rows.len() / (w as usize + 1);
    let mut out = vec![
        nb as f32, k as f32, b.axis.x, b.axis.y, b.axis.z, b.below, 0.0, 0.0,
    ];
    out.extend_from_slice(b.cdf);
    out.extend(b.texels.iter().map(|&i| (i / w) as f32));
    out.extend(b.texels.iter().map(|&i| (i % w) as f32));
    out.extend_from_slice(b.rest_marginal);
    out.extend(b.rest_row.iter().map(|&r| r as f32));
    out.extend_from_slice(b.rest_rows);
    out
}

impl EnvData {
    /// The data of `map`: its texels and its sampling distribution, the very tables the CPU
    /// renderer draws from (`EnvMap::texels`, `EnvMap::tables`).
    pub fn new(map: &EnvMap) -> Self {
        let n = (map.width * map.height) as f32;
        let texels_rgba32f = map
            .texels()
            .flat_map(|(t, mass)| [t.x, t.y, t.z, map.light_pdf(t, mass) * n])
            .collect();
        let (marginal, conditional) = map.tables();
        Self {
            width: map.width,
            height: map.height,
            texels_rgba32f,
            tables: [marginal, conditional, &sun_section(map)].concat(),
        }
    }

    /// The `EnvParams` uniform (48 bytes: four u32, four f32 as their bits, four u32) of a
    /// sampled draw taking passes `first .. first + count`, each weighted `pass_weight`, with
    /// the direct light, ambient and background weighted `direct_weight` (1 or 0), its random
    /// numbers from `sampler`, and a third strategy drawing directions from a GGX lobe of
    /// roughness `lobe_alpha` about the mirror direction on objects with a specular term (0:
    /// none; [`lobe_alpha`] gives the scene's).
    pub fn params(
        &self,
        first: u32,
        count: u32,
        [pass_weight, direct_weight]: [f32; 2],
        sampler: Sampler,
        lobe_alpha: f32,
    ) -> [u32; 12] {
        params(
            (self.width, self.height),
            [first, count],
            [pass_weight, direct_weight],
            sampler,
            Mode::Sampled { lobe_alpha },
        )
    }

    /// The `EnvParams` uniform of a split-sum draw (one draw, with the direct light) of a
    /// GGX surface of roughness `alpha` and Schlick `f0`, its prefiltered maps `pre`.
    pub fn split_sum_params(&self, pre: &Prefiltered, alpha: f32, f0: f32) -> [u32; 12] {
        params(
            (self.width, self.height),
            [0, 0],
            [0.0, 1.0],
            Sampler::Sobol,
            Mode::SplitSum(alpha, f0, pre),
        )
    }
}

/// The roughness of the GGX lobe strategy for `scene` (see [`EnvData::params`]): the `alpha`
/// of the first object's specular model with a specular term that has one (a Phong-like
/// exponent `n` counts as `alpha = sqrt(2 / (n + 2))`, a `roughness` as `alpha = roughness^2`,
/// glTF's rule; a coloured model's first channel), clamped to 0.001 to 1; 0 (no lobe
/// strategy) when none has. Any value keeps the estimate unbiased (the balance heuristic
/// weighs the strategies by their densities); one near the model's lobe lowers its noise.
pub fn lobe_alpha(scene: &fastbrdf_render::scene::Scene) -> f32 {
    for o in scene.objects.iter().filter(|o| o.material.ks > 0.0) {
        let Some(p) = o
            .material
            .specular
            .channels
            .first()
            .and_then(|c| c.spec.params().ok())
        else {
            continue;
        };
        let a = match (p.opt_num("alpha"), p.opt_num("n"), p.opt_num("roughness")) {
            (Some(a), _, _) => a,
            (None, Some(n), _) if n > -2.0 => (2.0 / (n + 2.0)).sqrt(),
            (None, None, Some(r)) => r * r,
            _ => continue,
        };
        if a.is_finite() && a > 0.0 {
            return (a as f32).clamp(1e-3, 1.0);
        }
    }
    0.0
}

/// What a draw shades: sampled (with the lobe strategy's roughness) or the split-sum (alpha,
/// f0, the prefiltered maps).
enum Mode<'a> {
    Sampled { lobe_alpha: f32 },
    SplitSum(f32, f32, &'a Prefiltered),
}

/// The `EnvParams` words (see [`EnvData::params`]).
fn params(
    size: (u32, u32),
    passes: [u32; 2],
    weights: [f32; 2],
    sampler: Sampler,
    mode: Mode,
) -> [u32; 12] {
    let s = match sampler {
        Sampler::Sobol => 0,
        Sampler::Independent => 1,
    };
    let (a, f0, mode, pw, ph) = match mode {
        Mode::Sampled { lobe_alpha } => (lobe_alpha, 0.0, 0, 0, 0),
        Mode::SplitSum(a, f0, p) => (a, f0, 1, p.width, p.height),
    };
    [
        size.0,
        size.1,
        passes[0],
        passes[1],
        weights[0].to_bits(),
        weights[1].to_bits(),
        a.to_bits(),
        f0.to_bits(),
        s,
        mode,
        pw,
        ph,
    ]
}

/// What follows `render.wgsl` in the module of a scene with an environment (for a browser
/// building the module itself): `env.wgsl` ([`ENV_SHADER`]) and `rd_dfg`, the
/// split-sum terms of `dfg` (an environment model) or, with none, the stub
/// ([`DFG_STUB`]); `module` is the module's other code (the model library's items and the
/// model's function, or a user's shader). The module is then
/// `module + render.wgsl + this + the rd_brdf glue`, as `render::render` compiles it.
pub fn env_module_source(
    module: &str,
    dfg: Option<&fastbrdf::ModelSpec>,
) -> Result<String, GpuError> {
    let glue = match dfg {
        Some(d) => dfg_glue(d, module)?,
        None => DFG_STUB.to_string(),
    };
    Ok(format!("{}\n{glue}\n", ENV_SHADER))
}

/// The environment's GPU resources: group 3, its layouts, the background pipeline.
pub(super) struct GpuEnv {
    pub(super) data_size: (u32, u32),
    pub(super) sampler: Sampler,
    pub(super) params: wgpu::Buffer,
    pub(super) bind: wgpu::BindGroup,
    /// The shading pass's layout under an environment: frame, object, ids, env.
    pub(super) pipeline: wgpu::PipelineLayout,
    /// An empty group 1 for the background draw.
    pub(super) empty: wgpu::BindGroup,
    pub(super) background: wgpu::RenderPipeline,
    /// Passes per primary sample (`Environment::samples`).
    pub(super) samples: u32,
    /// Passes per draw at most ([`PASSES_PER_DRAW`]).
    pub(super) per_draw: u32,
    /// The lobe strategy's roughness ([`lobe_alpha`]).
    pub(super) lobe_alpha: f32,
    /// The split-sum mode, with its prefiltered maps.
    pub(super) split: Option<(SplitSum, Prefiltered)>,
}

impl GpuEnv {
    pub(super) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &Layouts,
        limits: &wgpu::Limits,
        scene: &fastbrdf_render::scene::Scene,
        sampler: Sampler,
        split: Option<&SplitSum>,
    ) -> Result<Self, GpuError> {
        let Some(env) = &scene.environment else {
            return Err(GpuError::Input("the scene has no environment".into()));
        };
        let data = EnvData::new(&env.map);
        let split = split.map(|s| (s.clone(), Prefiltered::new(&env.map)));
        if data.width > limits.max_texture_dimension_2d {
            return Err(GpuError::Input(format!(
                "the environment map is {}x{}: wider than the GPU's largest texture ({}); \
                 render it on the CPU (drop --gpu) or downscale the map",
                data.width, data.height, limits.max_texture_dimension_2d
            )));
        }
        check_binding(
            limits,
            data.tables.len() * 4,
            "the environment map's sampling tables",
        )?;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render env"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: frag,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: frag,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: frag,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: frag,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let empty_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render empty"),
            entries: &[],
        });
        let empty = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("fastbrdf render empty"),
            layout: &empty_layout,
            entries: &[],
        });
        let pipeline = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fastbrdf render env"),
            bind_group_layouts: &[
                Some(&layouts.frame),
                Some(&layouts.object),
                Some(&layouts.ids),
                Some(&layout),
            ],
            immediate_size: 0,
        });
        let bg_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fastbrdf render env background"),
            bind_group_layouts: &[
                Some(&layouts.frame),
                Some(&empty_layout),
                Some(&layouts.ids),
                Some(&layout),
            ],
            immediate_size: 0,
        });
        let texture = |label, (width, height), texels: &[f32]| {
            device
                .create_texture_with_data(
                    queue,
                    &wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d {
                            width,
                            height,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: wgpu::TextureFormat::Rgba32Float,
                        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                        view_formats: &[],
                    },
                    wgpu::util::TextureDataOrder::LayerMajor,
                    bytemuck::cast_slice(texels),
                )
                .create_view(&Default::default())
        };
        let view = texture(
            "fastbrdf render env map",
            (data.width, data.height),
            &data.texels_rgba32f,
        );
        let pre_view = match &split {
            Some((_, p)) => texture(
                "fastbrdf render env prefiltered",
                (p.width, p.height * p.levels),
                &p.texels_rgba32f,
            ),
            None => texture("fastbrdf render env prefiltered", (1, 1), &[0.0; 4]),
        };
        let tables = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf render env tables"),
            contents: bytemuck::cast_slice(&data.tables),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf render env params"),
            contents: bytemuck::cast_slice(&data.params(0, 1, [1.0, 1.0], sampler, 0.0)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("fastbrdf render env"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: tables.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&pre_view),
                },
            ],
        });
        let background = background_pipeline(device, &bg_layout)?;
        Ok(Self {
            data_size: (data.width, data.height),
            sampler,
            params,
            bind,
            pipeline,
            empty,
            background,
            samples: env.samples.max(1),
            per_draw: PASSES_PER_DRAW[usize::from(
                !(scene.shadows
                    && scene
                        .objects
                        .iter()
                        .any(|o| matches!(o.shape, fastbrdf_render::scene::Shape::Mesh(_)))),
            )],
            lobe_alpha: lobe_alpha(scene),
            split,
        })
    }

    /// The chunks of passes of a tile of `tile_samples` primary samples: (first, count).
    /// The split-sum mode draws once.
    pub(super) fn chunks(&self, tile_samples: u64) -> Vec<(u32, u32)> {
        if self.split.is_some() {
            return vec![(0, 1)];
        }
        chunks(self.samples, tile_samples, self.per_draw)
    }

    /// Sets the parameters of the draw of passes `first .. first + count` of the render: each
    /// weighted 1 / samples, the direct light in the draw of pass 0 only.
    pub(super) fn set_chunk(&self, queue: &wgpu::Queue, first: u32, count: u32) {
        let direct = if first == 0 { 1.0 } else { 0.0 };
        let p = params(
            self.data_size,
            [first, count],
            [1.0 / self.samples as f32, direct],
            self.sampler,
            match &self.split {
                Some((s, p)) => Mode::SplitSum(s.alpha, s.f0, p),
                None => Mode::Sampled {
                    lobe_alpha: self.lobe_alpha,
                },
            },
        );
        queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&p));
    }
}

/// `samples` passes in draws of at most [`SAMPLE_PASSES_PER_DRAW`] sample-passes and at most
/// `max` passes (at least one pass each): (first pass, count).
fn chunks(samples: u32, tile_samples: u64, max: u32) -> Vec<(u32, u32)> {
    let per = (SAMPLE_PASSES_PER_DRAW / tile_samples.max(1)).clamp(1, u64::from(max.max(1))) as u32;
    (0..samples)
        .step_by(per as usize)
        .map(|first| (first, per.min(samples - first)))
        .collect()
}

/// An `rd_brdf` that is black: for a module that shades no object with it (the background's,
/// the features' tests).
pub(super) const BLACK_BRDF: &str = "fn rd_brdf(wi: vec3<f32>, wo: vec3<f32>, h: u32) -> RdSpec {\n    \
    return RdSpec(vec3<f32>(0.0), vec3<f32>(0.0));\n}\n";

/// The background pipeline (`rd_fs_env_background`): the render module with the
/// environment and a black `rd_brdf` (no object is shaded by it).
fn background_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
) -> Result<wgpu::RenderPipeline, GpuError> {
    let src = format!("{SHADER}\n{ENV_SHADER}\n{DFG_STUB}\n{BLACK_BRDF}");
    validated(device, "the environment's background shader", || {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("fastbrdf render env background"),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("fastbrdf render env background"),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("rd_vs_full"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("rd_fs_env_background"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf_render::env::Rng;
    use glam::Vec3;
    use std::f32::consts::PI;

    /// The data's texels, densities and draws are the CPU map's: the radiance and density at
    /// the texel of each drawn direction, and the direction a draw of the tables gives.
    #[test]
    fn the_data_is_the_cpu_maps() {
        let mut rng = Rng::new(5, 0);
        let random: Vec<Vec3> = (0..64 * 32)
            .map(|i| {
                let x = rng.uniform();
                if i / 64 % 7 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::new(x, x * x, 0.5) * 10.0
                }
            })
            .collect();
        for map in [EnvMap::sky(), EnvMap::from_texels(64, 32, random).unwrap()] {
            let d = EnvData::new(&map);
            let (w, h) = (d.width as usize, d.height as usize);
            assert_eq!(d.texels_rgba32f.len(), 4 * w * h);
            let sun = sun_section(&map);
            assert_eq!(d.tables.len(), h + 1 + h * (w + 1) + sun.len());
            assert_eq!(d.tables[h], 1.0);
            assert_eq!(sun[0] as usize, map.bright().map_or(0, |b| b.0));
            for _ in 0..2000 {
                let (dir, le, pdf) = map.sample(rng.uniform(), rng.uniform());
                let (u, v) = fastbrdf_render::env::dir_to_uv(dir);
                let c = ((u * w as f32) as usize).min(w - 1);
                let r = ((v * h as f32) as usize).min(h - 1);
                let t = &d.texels_rgba32f[4 * (r * w + c)..][..4];
                assert_eq!(Vec3::new(t[0], t[1], t[2]), le);
                let st = (1.0 - dir.y * dir.y).max(0.0).sqrt();
                if pdf > 0.0 && st > 1e-3 {
                    // The light strategies' density (the map's own without a sun).
                    let (mine, pdf) = (t[3] / (2.0 * PI * PI * st), map.light_pdf(le, pdf));
                    assert!((mine - pdf).abs() <= 1e-3 * pdf, "{mine} vs {pdf}");
                }
            }
        }
    }

    /// `env.wgsl`'s draws, as it reads the flat tables (`rd_env_sample_rest`,
    /// `rd_env_sample_bright`): the bin found in each table and where in it.
    fn bin(t: &[f32], off: usize, n: usize, u: f32) -> (usize, f32) {
        let p = t[off..=off + n].partition_point(|&c| c <= u);
        let i = p.max(1).min(n) - 1;
        let width = t[off + i + 1] - t[off + i];
        let frac = if width > 0.0 {
            ((u - t[off + i]) / width).clamp(0.0, 1.0 - f32::EPSILON)
        } else {
            0.5
        };
        (i, frac)
    }

    fn scaled(t: &[f32], off: usize, n: usize, u: f32) -> (usize, f32) {
        bin(t, off, n, u.clamp(0.0, 1.0 - f32::EPSILON) * t[off + n])
    }

    /// (row, place, column, place) of the shader's draw from the rest, or from the bright
    /// texels.
    fn shader_draw(d: &EnvData, bright: bool, u1: f32, u2: f32) -> (usize, f32, usize, f32) {
        let (w, h, t) = (d.width as usize, d.height as usize, &d.tables);
        let b = h + 1 + h * (w + 1);
        let nb = t[b] as usize;
        if bright {
            let (k, fr) = bin(t, b + 8, nb, u1.clamp(0.0, 1.0 - f32::EPSILON));
            let (r, c) = (t[b + 9 + nb + k] as usize, t[b + 9 + 2 * nb + k] as usize);
            return (r, fr, c, u2.clamp(0.0, 1.0 - f32::EPSILON));
        }
        let marginal = b + 9 + 3 * nb;
        let rows = marginal + h + 1;
        let (r, fr) = scaled(t, marginal, h, u1);
        let row = t[rows + r] as usize;
        let off = if row < h {
            h + 1 + row * (w + 1)
        } else {
            rows + h + (row - h) * (w + 1)
        };
        let (c, fc) = scaled(t, off, w, u2);
        (r, fr, c, fc)
    }

    /// The shader's reading of the sun section draws the CPU's directions: from the rest and
    /// from the bright texels, on the sky (a 2-degree sun) and on a map with two bright
    /// texels in different rows, the texel of each draw and its density the CPU's.
    #[test]
    fn the_sun_section_draws_the_cpus_directions() {
        let mut texels = vec![Vec3::splat(0.5); 64 * 32];
        texels[5 * 64 + 40] = Vec3::splat(2000.0);
        texels[9 * 64 + 12] = Vec3::new(900.0, 1200.0, 3000.0);
        let two = EnvMap::from_texels(64, 32, texels).unwrap();
        let mut rng = Rng::new(9, 1);
        for map in [EnvMap::sky(), two] {
            assert!(map.bright().is_some());
            let d = EnvData::new(&map);
            let (w, h) = (d.width as f32, d.height as f32);
            for j in 0..4000 {
                let (u1, u2) = (rng.uniform(), rng.uniform());
                let bright = j % 2 == 1;
                let (dir, le, pdf) = if bright {
                    map.sample_bright(u1, u2).unwrap()
                } else {
                    map.sample_rest(u1, u2)
                };
                let (r, fr, c, fc) = shader_draw(&d, bright, u1, u2);
                let (mine, st) =
                    fastbrdf_render::env::uv_to_dir((c as f32 + fc) / w, (r as f32 + fr) / h);
                assert_eq!(mine, dir, "bright {bright}, u = ({u1}, {u2})");
                let t = &d.texels_rgba32f[4 * (r * d.width as usize + c)..][..4];
                assert_eq!(Vec3::new(t[0], t[1], t[2]), le);
                if st > 1e-3 {
                    let density = t[3] / (2.0 * PI * PI * st);
                    assert!((density - pdf).abs() <= 1e-5 * pdf, "{density} vs {pdf}");
                }
            }
        }
    }

    #[test]
    fn params_and_chunks() {
        assert_eq!(chunks(16, 64 * 64, 64), vec![(0, 16)]);
        assert_eq!(chunks(5, 1 << 19, 64), vec![(0, 2), (2, 2), (4, 1)]);
        assert_eq!(chunks(3, 1 << 24, 64), vec![(0, 1), (1, 1), (2, 1)]);
        assert_eq!(chunks(10, 64 * 64, 4), vec![(0, 4), (4, 4), (8, 2)]);
        let d = EnvData::new(&EnvMap::constant(Vec3::ONE));
        let p = d.params(3, 2, [0.25, 1.0], Sampler::Independent, 0.3);
        assert_eq!(&p[..4], &[16, 8, 3, 2]);
        assert_eq!(f32::from_bits(p[4]), 0.25);
        assert_eq!(f32::from_bits(p[5]), 1.0);
        assert_eq!(f32::from_bits(p[6]), 0.3);
        assert_eq!(&p[8..], &[1, 0, 0, 0]);
        assert_eq!(d.params(0, 1, [1.0, 1.0], Sampler::Sobol, 0.0)[8], 0);
    }
}
