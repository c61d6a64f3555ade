//! The GPU renderer: the CPU renderer's scenes (`fastbrdf_render::scene::Scene`: camera,
//! lights, spheres, planes, OBJ meshes, textures, micro-relief) rasterised with wgpu and shaded
//! per sample by any model's WGSL twin (`spec::Instance`), into the CPU's `Film`.
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
//! - Shadows (`scene.shadows`, the CPU's rule and arithmetic): every object goes up once
//!   more, for the shadow rays (`Occluders`): spheres and planes as records, each mesh as its
//!   CPU BVH (`TriMesh::bvh`, nodes flattened into one array with rebased indices) and its
//!   triangles' corners in the BVH's leaf order. Per light the fragment shader casts the CPU's
//!   shadow ray (`Scene::shadowed`: origin offset along the unbumped normal by
//!   `SHADOW_EPS (1 + max |p|)`, no ray where only the bumped normal faces the light, a point
//!   light's ray stopping short of it) and tests it like `Scene::occluded`: the sphere's and
//!   plane's formulas, and for meshes the CPU's slab test, 64-entry stack (children skipped
//!   when full, as on the CPU) and Moller-Trumbore test, ending at the first hit. Before its
//!   first hit the CPU's nearest-hit traversal culls the same nodes with the same `t_max`, so
//!   any-hit gives the same answer; glam's NaN behaviour of `min`/`max` in the slab test (an
//!   axis-parallel ray, e.g. a light straight above) is written out. The f32 constants
//!   (`SHADOW_EPS`, `1 - 1e-5`, `f32::MAX` standing for the infinite reach of a directional
//!   light: the same decisions under `t < t_max`) come from the CPU in the frame uniform, so no
//!   WGSL literal rounds differently. Memory: 36 bytes per triangle and 32 per node, checked
//!   against the device's storage binding limit like the other mesh buffers (128 MiB by
//!   default: about 3.5 million triangles); a larger mesh is refused with the sizes and the
//!   hint `--shadows off` (no such buffers then).
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
//! within stated tolerances: 8-bit on any adapter, and 1e-4 linear on software adapters.

use crate::context::{GpuError, validated};
use crate::spec::Instance;
use fastbrdf_render::film::{Film, check_size};
use fastbrdf_render::render::Options;
use fastbrdf_render::scene::{LightKind, Object, SHADOW_EPS, Scene, Shape};
use fastbrdf_render::texture::Texture;
use glam::{DVec3, Vec2, Vec3};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// The shaders (see the file's header); completed by the model library and `rd_brdf`.
pub const SHADER: &str = include_str!("shaders/render.wgsl");

/// Largest tile side, in samples: a 2048 x 2048 `Rgba32Float` tile is 64 MiB.
pub const TILE_SAMPLES: u32 = 2048;

/// The near clipping distance along the view axis for mesh triangles, below the CPU's
/// smallest ray parameter (1e-4), so that clipping never removes a hit the CPU would find.
const NEAR: f64 = 1e-5;

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The visibility pass's target: object index + 1 (0: none), triangle.
const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

/// The pipelines of one specular model: the visibility pass (`_id`: depth and the nearest
/// hit's object and triangle) and the shading pass (radiance of the visible hit only).
struct Pipelines {
    analytic_id: wgpu::RenderPipeline,
    mesh_id: wgpu::RenderPipeline,
    analytic: wgpu::RenderPipeline,
    mesh: wgpu::RenderPipeline,
}

/// What one object needs on the GPU.
struct GpuObject {
    bind: wgpu::BindGroup,
    /// The key of its model's pipelines.
    model: String,
    /// Mesh corners (three per triangle) and their count; none for spheres and planes.
    corners: Option<(wgpu::Buffer, u32)>,
}

/// One pass over the scene's objects into `target` (cleared to `clear`, depth cleared and
/// discarded): `pick` chooses each model's analytic and mesh pipelines; `ids` (the visibility
/// pass's result) is bound at group 2 when given.
struct ScenePass<'a> {
    label: &'static str,
    target: &'a wgpu::TextureView,
    clear: wgpu::Color,
    ids: Option<&'a wgpu::BindGroup>,
    pick: fn(&Pipelines) -> (&wgpu::RenderPipeline, &wgpu::RenderPipeline),
}

impl ScenePass<'_> {
    fn draw(
        &self,
        enc: &mut wgpu::CommandEncoder,
        depth_view: &wgpu::TextureView,
        tile: &Tile,
        frame_bind: &wgpu::BindGroup,
        objects: &[GpuObject],
        pipelines: &HashMap<String, Pipelines>,
    ) {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(self.label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: self.target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(self.clear),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_viewport(0.0, 0.0, tile.w as f32, tile.h as f32, 0.0, 1.0);
        pass.set_scissor_rect(0, 0, tile.w, tile.h);
        pass.set_bind_group(0, frame_bind, &[]);
        if let Some(ids) = self.ids {
            pass.set_bind_group(2, ids, &[]);
        }
        for o in objects {
            let (analytic, mesh) = (self.pick)(&pipelines[&o.model]);
            pass.set_bind_group(1, &o.bind, &[]);
            match &o.corners {
                None => {
                    pass.set_pipeline(analytic);
                    pass.draw(0..3, 0..1);
                }
                Some((buf, count)) => {
                    pass.set_pipeline(mesh);
                    pass.set_vertex_buffer(0, buf.slice(..));
                    pass.draw(0..*count, 0..1);
                }
            }
        }
    }
}

/// Renders `scene` on the GPU: the same image as `fastbrdf_render::render::render` (within
/// the tolerances of `tests/render.rs`), shadow rays included when `scene.shadows`, as a
/// linear `Film`.
///
/// `opts.shading` is ignored (the GPU evaluates the model per sample); `scene.environment`
/// is not rendered (the CLI refuses `--env` with `--gpu`). Errors: sizes outside
/// `film::check_size` or `opts.spp` outside 1..=16 (as on the CPU), a mesh (its vertices,
/// corners, or with shadows its BVH and triangles) or texture larger than the device's limits, a model that is not a BRDF instance, and GPU failures.
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
    check_size(opts.width, opts.height).map_err(|e| GpuError::Input(e.to_string()))?;
    if !(1..=16).contains(&opts.spp) {
        return Err(GpuError::Input(format!(
            "--spp {}: must be 1 to 16 (N x N samples per pixel)",
            opts.spp
        )));
    }
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
    let mut pipelines: HashMap<String, Pipelines> = HashMap::new();
    let mut objects = Vec::with_capacity(scene.objects.len());
    // World length of one sample per unit of distance from the eye (see `dilate_boundaries`).
    let (_, _, _, th) = scene.camera.frame();
    let reach = Reach {
        eye: scene.camera.eye,
        sample_per_distance: 2.0 * th / (h * n) as f32,
    };
    for (i, obj) in scene.objects.iter().enumerate() {
        let spec = &obj.material.specular;
        if spec.is_coloured() {
            return Err(GpuError::Input(format!(
                "coloured specular ({}: a parameter given as R,G,B, e.g. --metal) is CPU-only for now: drop --gpu",
                spec.id
            )));
        }
        let given: Vec<(&str, &str)> = spec
            .brdf
            .1
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect();
        let instance = Instance::with_storage(&spec.brdf.0, &given)?;
        let key = format!("{} {:?}", spec.brdf.0, instance.params);
        if !pipelines.contains_key(&key) {
            pipelines.insert(key.clone(), Pipelines::new(device, &layouts, &instance)?);
        }
        objects.push(upload_object(
            device, queue, &layouts, &limits, obj, i, &instance, key, &reach,
        )?);
    }
    let lights = lights_buffer(device, scene);
    let occluders = Occluders::new(device, &limits, scene)?;

    let (tw_max, th_max) = (w.min(tile_px) * n, h.min(tile_px) * n);
    let target = |format, label| {
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
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    let color = target(COLOR_FORMAT, "fastbrdf render colour");
    let depth = target(DEPTH_FORMAT, "fastbrdf render depth");
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
    let row_bytes = (tw_max * 16).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("fastbrdf render readback"),
        size: u64::from(row_bytes) * u64::from(th_max),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });

    let mut film = Film::try_new(w, h).map_err(|e| GpuError::Input(e.to_string()))?;
    let inv = 1.0 / (n * n) as f32;
    let tiles = (w.div_ceil(tile_px) * h.div_ceil(tile_px)) as usize;
    let mut done = 0;
    progress(done, tiles);
    for py0 in (0..h).step_by(tile_px as usize) {
        for px0 in (0..w).step_by(tile_px as usize) {
            let (pw, ph) = (tile_px.min(w - px0), tile_px.min(h - py0));
            let tile = Tile {
                x0: px0 * n,
                y0: py0 * n,
                w: pw * n,
                h: ph * n,
            };
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
            validated(device, "the GPU render pass", || {
                let mut enc = device.create_command_encoder(&Default::default());
                // Visibility: per sample the nearest hit's object and triangle (each fragment
                // only intersects its primary ray), so that the shading pass below shades one
                // fragment per sample however many surfaces overlap there: shading every
                // fragment that passed the depth test so far (it writes its depth, so the test
                // comes after the shader) cost a shadow ray per overlapping layer, thousands
                // per sample on a mesh of stacked copies.
                let bg = scene.background;
                let passes = [
                    // The visibility pass: ids into `ids_view`.
                    ScenePass {
                        label: "fastbrdf render visibility",
                        target: &ids_view,
                        clear: wgpu::Color::TRANSPARENT,
                        ids: None,
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
                enc.copy_texture_to_buffer(
                    wgpu::TexelCopyTextureInfo {
                        texture: &color,
                        mip_level: 0,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::TexelCopyBufferInfo {
                        buffer: &readback,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(row_bytes),
                            rows_per_image: None,
                        },
                    },
                    wgpu::Extent3d {
                        width: tile.w,
                        height: tile.h,
                        depth_or_array_layers: 1,
                    },
                );
                queue.submit([enc.finish()]);
            })?;
            crate::compute::map_read(device, &readback, |bytes| {
                let texels: &[f32] = bytemuck::cast_slice(bytes);
                let stride = (row_bytes / 4) as usize;
                for py in 0..ph {
                    for px in 0..pw {
                        // The CPU's order: samples row by row within the pixel, then scaled.
                        let mut sum = Vec3::ZERO;
                        for sy in 0..n {
                            for sx in 0..n {
                                let (x, y) = ((px * n + sx) as usize, (py * n + sy) as usize);
                                let t = &texels[y * stride + 4 * x..][..3];
                                sum += Vec3::new(t[0], t[1], t[2]);
                            }
                        }
                        sum *= inv;
                        film.pixels[((py0 + py) * w + px0 + px) as usize] = sum;
                    }
                }
            })?;
            done += 1;
            progress(done, tiles);
        }
    }
    Ok(film)
}

/// One tile of the sample grid: first sample column and row, size in samples.
struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

/// The bind group layouts shared by every pipeline.
struct Layouts {
    frame: wgpu::BindGroupLayout,
    object: wgpu::BindGroupLayout,
    /// The visibility pass's ids, read by the shading pass.
    ids: wgpu::BindGroupLayout,
    /// The shading pass: frame, object, ids.
    pipeline: wgpu::PipelineLayout,
    /// The visibility pass: frame, object.
    visibility: wgpu::PipelineLayout,
}

impl Layouts {
    fn new(device: &wgpu::Device) -> Self {
        let entry = |binding, visibility, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty,
            count: None,
        };
        let uniform = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let storage = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let frame = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render frame"),
            entries: &[
                entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, uniform),
                entry(1, fragment, storage),
                entry(2, fragment, storage),
                entry(3, fragment, storage),
                entry(4, fragment, storage),
            ],
        });
        let object = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render object"),
            entries: &[
                entry(0, fragment, uniform),
                entry(
                    1,
                    fragment,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                entry(2, fragment, storage),
                entry(3, fragment, storage),
                entry(4, fragment, storage),
            ],
        });
        let ids = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fastbrdf render ids"),
            entries: &[entry(
                0,
                fragment,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
            )],
        });
        let pipeline = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fastbrdf render"),
            bind_group_layouts: &[Some(&frame), Some(&object), Some(&ids)],
            immediate_size: 0,
        });
        let visibility = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fastbrdf render visibility"),
            bind_group_layouts: &[Some(&frame), Some(&object)],
            immediate_size: 0,
        });
        Self {
            frame,
            object,
            ids,
            pipeline,
            visibility,
        }
    }
}

impl Pipelines {
    /// Compiles the render shader with the model `instance` (a BRDF) as `rd_brdf`.
    fn new(
        device: &wgpu::Device,
        layouts: &Layouts,
        instance: &Instance,
    ) -> Result<Self, GpuError> {
        if instance.info.kind != fastbrdf::Kind::Brdf {
            return Err(GpuError::Input(format!(
                "'{}' is not a BRDF: the renderer shades with BRDF instances",
                instance.info.id
            )));
        }
        let glue = format!(
            "fn rd_brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {{\n    return {}(wi, wo);\n}}\n",
            instance.function
        );
        let src = format!("{}\n{SHADER}\n{glue}", instance.module_source());
        let what = format!("render shader of {}", instance.info.id);
        validated(device, &what, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&what),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
            let pipeline = |vs: &str, fs: &str, buffers: &[Option<wgpu::VertexBufferLayout>]| {
                let visibility = fs.ends_with("_id");
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(&what),
                    layout: Some(if visibility {
                        &layouts.visibility
                    } else {
                        &layouts.pipeline
                    }),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers,
                    },
                    primitive: wgpu::PrimitiveState {
                        topology: wgpu::PrimitiveTopology::TriangleList,
                        // Two-sided, like the CPU's ray tests.
                        cull_mode: None,
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[Some(wgpu::ColorTargetState {
                            format: if visibility { ID_FORMAT } else { COLOR_FORMAT },
                            blend: None,
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
            let corners = wgpu::VertexBufferLayout {
                array_stride: 12,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            };
            Self {
                analytic_id: pipeline("rd_vs_full", "rd_fs_analytic_id", &[]),
                mesh_id: pipeline("rd_vs_mesh", "rd_fs_mesh_id", &[Some(corners.clone())]),
                analytic: pipeline("rd_vs_full", "rd_fs_analytic", &[]),
                mesh: pipeline("rd_vs_mesh", "rd_fs_mesh", &[Some(corners)]),
            }
        })
    }
}

/// The camera frame exactly as `Camera::ray` computes it: (f, r, u, tan(fov/2), aspect).
fn camera_frame(scene: &Scene, w: u32, h: u32) -> (Vec3, Vec3, Vec3, f32, f32) {
    let (f, r, u, th) = scene.camera.frame();
    (f, r, u, th, w as f32 / h as f32)
}

/// The frame uniform of one tile (layout: `struct Frame` in the shader).
fn frame_data(scene: &Scene, opts: &Options, tile: &Tile) -> Vec<u32> {
    let (w, h, n) = (opts.width, opts.height, opts.spp);
    let (f, r, u, th, aspect) = camera_frame(scene, w, h);
    let eye = scene.camera.eye;
    let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w].map(f32::to_bits);
    // Clip coordinates of world point p, as linear forms in p - eye (f64, then f32): the
    // sample-grid position X = x N of `Camera::project`'s x (and Y likewise), local to the tile.
    let (fd, rd, ud) = (f.as_dvec3(), r.as_dvec3(), u.as_dvec3());
    let (thd, ad) = (f64::from(th), f64::from(aspect));
    let (sw, sh) = (f64::from(w * n), f64::from(h * n));
    let (x0, y0) = (f64::from(tile.x0), f64::from(tile.y0));
    let (tw, tht) = (f64::from(tile.w), f64::from(tile.h));
    // X z = (0.5 sw / (th aspect)) (r . d) + 0.5 sw z; clip_x = 2 (X - x0) z / tw - z.
    let xz = rd * (0.5 * sw / (thd * ad)) + fd * (0.5 * sw - x0);
    let clip_x = xz * (2.0 / tw) - fd;
    // Y z = 0.5 sh z - (0.5 sh / th) (u . d); clip_y = z - 2 (Y - y0) z / th.
    let yz = fd * (0.5 * sh - y0) - ud * (0.5 * sh / thd);
    let clip_y = fd - yz * (2.0 / tht);
    let eyed = eye.as_dvec3();
    let row = |a: DVec3, c: f64| [a.x, a.y, a.z, c - a.dot(eyed)].map(|x| (x as f32).to_bits());
    let mut out = Vec::with_capacity(48);
    out.extend(v4(eye, 0.0));
    out.extend(v4(f, 0.0));
    out.extend(v4(r, 0.0));
    out.extend(v4(u, 0.0));
    out.extend([th, aspect, w as f32, h as f32].map(f32::to_bits));
    out.extend(v4(scene.ambient, 0.0));
    out.extend([w, h, n, scene.lights.len() as u32]);
    out.extend([tile.x0, tile.y0, tile.w, tile.h]);
    out.extend(row(clip_x, 0.0));
    out.extend(row(clip_y, 0.0));
    out.extend(row(fd, -NEAR));
    out.extend(row(fd, 0.0));
    out.extend(
        [
            if scene.shadows { 1.0 } else { 0.0 },
            SHADOW_EPS,
            1.0 - 1e-5,
            f32::MAX,
        ]
        .map(f32::to_bits),
    );
    out
}

/// The lights as `struct Light` records (one zero record when there are none).
fn lights_buffer(device: &wgpu::Device, scene: &Scene) -> wgpu::Buffer {
    let mut data: Vec<f32> = Vec::with_capacity(8 * scene.lights.len().max(1));
    for l in &scene.lights {
        let (p, kind) = match l.kind {
            LightKind::Directional { to_light } => (to_light, 0.0),
            LightKind::Point { position } => (position, 1.0),
        };
        data.extend([
            p.x,
            p.y,
            p.z,
            kind,
            l.color.x,
            l.color.y,
            l.color.z,
            l.intensity,
        ]);
    }
    if data.is_empty() {
        data.resize(8, 0.0);
    }
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fastbrdf render lights"),
        contents: bytemuck::cast_slice(&data),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// The scene's objects for the shadow rays (`struct Occluder`, `BvhNode` and `sh_tris` in
/// the shader): every object in scene order; every mesh's BVH nodes, rebased into one array
/// (inner nodes' children by the mesh's first node, leaves' triangles by its first
/// triangle); every mesh's triangle corners in its BVH's leaf order, so a leaf's triangles
/// are consecutive. With shadows off, only the (small) object records go up.
struct Occluders {
    objects: wgpu::Buffer,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
}

impl Occluders {
    fn new(device: &wgpu::Device, limits: &wgpu::Limits, scene: &Scene) -> Result<Self, GpuError> {
        let mut objects: Vec<[u32; 12]> = Vec::with_capacity(scene.objects.len());
        let mut nodes: Vec<[u32; 8]> = Vec::new();
        let mut triangles: Vec<f32> = Vec::new();
        let bits = |v: [f32; 4]| v.map(f32::to_bits);
        for obj in &scene.objects {
            let (a, b, kind) = match &obj.shape {
                Shape::Sphere(s) => (
                    [s.center.x, s.center.y, s.center.z, s.radius],
                    [0.0; 4],
                    [0, 0, 0, 0],
                ),
                Shape::Plane(p) => (
                    [p.point.x, p.point.y, p.point.z, 0.0],
                    [p.normal.x, p.normal.y, p.normal.z, 0.0],
                    [1, 0, 0, 0],
                ),
                Shape::Mesh(m) if scene.shadows && !m.triangles.is_empty() => {
                    let (tree, order) = m.bvh();
                    let root = u32::try_from(nodes.len()).map_err(|_| too_many())?;
                    let first = u32::try_from(triangles.len() / 9).map_err(|_| too_many())?;
                    for node in tree {
                        let start = if node.count > 0 {
                            node.start.checked_add(first)
                        } else {
                            node.start.checked_add(root)
                        }
                        .ok_or_else(too_many)?;
                        let (lo, hi) = (node.lo, node.hi);
                        nodes.push([
                            lo.x.to_bits(),
                            lo.y.to_bits(),
                            lo.z.to_bits(),
                            start,
                            hi.x.to_bits(),
                            hi.y.to_bits(),
                            hi.z.to_bits(),
                            node.count,
                        ]);
                    }
                    check_binding(
                        limits,
                        nodes.len() * 32,
                        "the meshes' BVH nodes for the shadow rays (--shadows off needs none)",
                    )?;
                    check_binding(
                        limits,
                        (triangles.len() + 9 * order.len()) * 4,
                        "the meshes' triangles for the shadow rays (--shadows off needs none)",
                    )?;
                    triangles.reserve(9 * order.len());
                    for &t in order {
                        let tri = m.triangles.get(t as usize).ok_or_else(too_many)?;
                        for &i in tri {
                            let p = m.positions.get(i as usize).ok_or_else(|| {
                                GpuError::Input(format!(
                                    "a triangle vertex index {i} is out of range ({} vertices)",
                                    m.positions.len()
                                ))
                            })?;
                            triangles.extend(p.to_array());
                        }
                    }
                    ([0.0; 4], [0.0; 4], [2, root, 0, 0])
                }
                // No shadow rays, or no triangles: nothing to hit.
                Shape::Mesh(_) => ([0.0; 4], [0.0; 4], [3, 0, 0, 0]),
            };
            let mut rec = [0u32; 12];
            rec[..4].copy_from_slice(&bits(a));
            rec[4..8].copy_from_slice(&bits(b));
            rec[8..].copy_from_slice(&kind);
            objects.push(rec);
        }
        if objects.is_empty() {
            // No objects: one record that hits nothing (a zeroed one would be a sphere).
            objects.push([0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0]);
        }
        Ok(Self {
            objects: storage(device, "fastbrdf render occluders", &objects),
            nodes: storage(device, "fastbrdf render bvh nodes", &nodes),
            triangles: storage(device, "fastbrdf render shadow triangles", &triangles),
        })
    }
}

fn too_many() -> GpuError {
    GpuError::Input("the meshes have too many triangles for the GPU's shadow rays".into())
}

/// A storage buffer of `data`, or of one zero when `data` is empty.
fn storage<T: bytemuck::Pod + bytemuck::Zeroable>(
    device: &wgpu::Device,
    label: &str,
    data: &[T],
) -> wgpu::Buffer {
    let one = [T::zeroed()];
    let data = if data.is_empty() { &one[..] } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(data),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// Checks a storage binding's size against the device's limit.
fn check_binding(limits: &wgpu::Limits, bytes: usize, what: &str) -> Result<(), GpuError> {
    let cap = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    if bytes as u64 > cap {
        return Err(GpuError::Input(format!(
            "{what} takes {} MiB, more than the GPU's largest storage binding ({} MiB)",
            bytes >> 20,
            cap >> 20
        )));
    }
    Ok(())
}

/// The object uniform, its texture, mesh buffers and model coefficients, bound together.
#[allow(clippy::too_many_arguments)]
fn upload_object(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layouts: &Layouts,
    limits: &wgpu::Limits,
    obj: &Object,
    index: usize,
    instance: &Instance,
    model: String,
    reach: &Reach,
) -> Result<GpuObject, GpuError> {
    let m = &obj.material;
    let zero4 = [0.0f32; 4];
    let (mut a, mut normal, mut tu, mut tv) = (zero4, zero4, zero4, zero4);
    let mut vertices: Vec<f32> = Vec::new();
    let mut triangles: Vec<u32> = Vec::new();
    let mut corners = None;
    let mut has_uvs = 0;
    let kind = match &obj.shape {
        Shape::Sphere(s) => {
            a = [s.center.x, s.center.y, s.center.z, s.radius];
            0
        }
        Shape::Plane(p) => {
            let (t, b) = p.normal.any_orthonormal_pair();
            a = [p.point.x, p.point.y, p.point.z, 0.0];
            normal = [p.normal.x, p.normal.y, p.normal.z, 0.0];
            tu = [t.x, t.y, t.z, 0.0];
            tv = [b.x, b.y, b.z, 0.0];
            1
        }
        Shape::Mesh(mesh) => {
            let nv = mesh.positions.len();
            if mesh.normals.len() != nv || !(mesh.uvs.is_empty() || mesh.uvs.len() == nv) {
                return Err(GpuError::Input(format!(
                    "object {index}: the mesh has {nv} positions, {} normals and {} uvs \
                     (normals must match the positions; uvs too, or be absent)",
                    mesh.normals.len(),
                    mesh.uvs.len()
                )));
            }
            if let Some(bad) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= nv) {
                return Err(GpuError::Input(format!(
                    "object {index}: triangle vertex index {bad} is out of range ({nv} vertices)"
                )));
            }
            has_uvs = u32::from(!mesh.uvs.is_empty());
            vertices.reserve(8 * nv);
            for i in 0..nv {
                let (p, nn) = (mesh.positions[i], mesh.normals[i]);
                let uv = mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO);
                vertices.extend([p.x, p.y, p.z, nn.x, nn.y, nn.z, uv.x, uv.y]);
            }
            triangles = with_boundary_edges(&mesh.positions, &mesh.triangles);
            let count = u32::try_from(3 * mesh.triangles.len())
                .map_err(|_| GpuError::Input(format!("object {index}: too many triangles")))?;
            let pos = dilate_boundaries(&mesh.positions, &triangles, reach);
            check_binding(limits, vertices.len() * 4, "the mesh's vertices")?;
            check_binding(limits, pos.len() * 4, "the mesh's triangle corners")?;
            let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf render corners"),
                contents: bytemuck::cast_slice(&pos),
                usage: wgpu::BufferUsages::VERTEX,
            });
            corners = Some((buf, count));
            2
        }
    };
    let (tex_w, tex_h, texels) = match &m.texture {
        Some(t) => {
            let max = limits.max_texture_dimension_2d;
            if t.width > max || t.height > max {
                return Err(GpuError::Input(format!(
                    "the texture is {}x{}, larger than the GPU's largest texture side ({max})",
                    t.width, t.height
                )));
            }
            (t.width, t.height, linear_texels(t))
        }
        None => (1, 1, vec![0.0; 4]),
    };
    let texture = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("fastbrdf render albedo"),
            size: wgpu::Extent3d {
                width: tex_w,
                height: tex_h,
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
        bytemuck::cast_slice(&texels),
    );
    let (bump_scale, bump_depth) = m.bump.map_or((0.0, 0.0), |b| (b.scale, b.depth));
    let mut uniform: Vec<u32> = Vec::with_capacity(36);
    for v in [
        a,
        normal,
        tu,
        tv,
        [m.albedo.x, m.albedo.y, m.albedo.z, m.kd],
        [m.ks, bump_scale, bump_depth, 0.0],
        [tex_w as f32, tex_h as f32, 0.0, 0.0],
    ] {
        uniform.extend(v.map(f32::to_bits));
    }
    uniform.extend([
        kind,
        u32::from(m.texture.is_some()),
        u32::from(m.bump.is_some()),
        has_uvs,
    ]);
    // The object's id in the visibility pass: its index plus one (0 is no hit).
    let id = u32::try_from(index + 1)
        .map_err(|_| GpuError::Input(format!("object {index}: too many objects")))?;
    uniform.extend([tex_w, tex_h, id, 0]);
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("fastbrdf render object"),
        contents: bytemuck::cast_slice(&uniform),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let view = texture.create_view(&Default::default());
    let vertices = storage(device, "fastbrdf render vertices", &vertices);
    let triangles = storage(device, "fastbrdf render triangles", &triangles);
    let coefs = storage(device, "fastbrdf render coefficients", &instance.coefs);
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fastbrdf render object"),
        layout: &layouts.object,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: vertices.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: triangles.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: coefs.as_entire_binding(),
            },
        ],
    });
    Ok(GpuObject {
        bind,
        model,
        corners,
    })
}

/// Where the camera is and how long one sample is at unit distance from it (world units).
struct Reach {
    eye: Vec3,
    sample_per_distance: f32,
}

/// The triangle corners the rasteriser draws (three per triangle, world positions), with every
/// boundary edge pushed outward in its triangle's plane by a quarter of a sample.
///
/// Why: a sample exactly on a boundary edge (an axis-aligned triangle with corners on the
/// sample grid) is a hit for the CPU's inclusive ray-triangle test, but the rasteriser's
/// top-left rule may give no fragment there, and the GPU showed the background (up to 188/255
/// at 1 sample per pixel). Dilated, the rasteriser proposes those samples too; the fragment
/// shader's exact test (`rd_triangle`) still discards every sample outside a boundary edge, so
/// only the CPU's hits are drawn. Shared edges are not moved: across them the neighbour covers
/// the sample, as before. Each corner moves to the meeting point of its two (shifted or not)
/// edge lines, at most 8 shifts away (a needle's corner is not pushed to infinity).
fn dilate_boundaries(positions: &[Vec3], triangles: &[u32], reach: &Reach) -> Vec<f32> {
    let mut out = Vec::with_capacity(9 * triangles.len() / 4);
    for t in triangles.chunks_exact(4) {
        let p = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let mask = t[3];
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        let area2 = normal.length_squared();
        let corners = if mask == 0 || area2.is_nan() || area2 <= 0.0 {
            p
        } else {
            // Edge k runs from p[k] to p[k + 1]; bit 1 << k marks it as a boundary edge.
            let far = p
                .iter()
                .map(|q| q.distance(reach.eye))
                .fold(0.0f32, f32::max);
            let shift = 0.25 * reach.sample_per_distance * far;
            let edge = |k: usize| {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                let mut o = (b - a).cross(normal).normalize_or_zero();
                if o.dot(c - a) > 0.0 {
                    o = -o;
                }
                let s = if mask & (1 << k) != 0 { shift } else { 0.0 };
                (o, s)
            };
            let e = [edge(0), edge(1), edge(2)];
            [0, 1, 2].map(|j| {
                // Corner j joins edge j - 1 (ending at p[j]) and edge j (starting there).
                let ((o1, s1), (o2, s2)) = (e[(j + 2) % 3], e[j]);
                let c = o1.dot(o2);
                let det = 1.0 - c * c;
                let d = if det > 1e-6 {
                    o1 * ((s1 - c * s2) / det) + o2 * ((s2 - c * s1) / det)
                } else {
                    o1 * s1 + o2 * s2
                };
                let cap = 8.0 * shift;
                let d = if d.length() > cap {
                    d * (cap / d.length())
                } else {
                    d
                };
                if d.is_finite() { p[j] + d } else { p[j] }
            })
        };
        out.extend(corners.iter().flat_map(|q| q.to_array()));
    }
    out
}

/// The triangles as `[a, b, c, mask]`, where the mask marks the edges no other triangle
/// shares (1: a-b, 2: b-c, 4: c-a). Edges are compared by their end points' positions, so
/// vertices duplicated at texture seams still join.
fn with_boundary_edges(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<u32> {
    let key = |i: u32, j: u32| {
        let (p, q) = (
            positions[i as usize].to_array().map(f32::to_bits),
            positions[j as usize].to_array().map(f32::to_bits),
        );
        if p <= q { (p, q) } else { (q, p) }
    };
    let mut count: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    for &[a, b, c] in triangles {
        for (i, j) in [(a, b), (b, c), (c, a)] {
            *count.entry(key(i, j)).or_default() += 1;
        }
    }
    let mut out = Vec::with_capacity(4 * triangles.len());
    for &[a, b, c] in triangles {
        let mut mask = 0;
        for (bit, (i, j)) in [(1, (a, b)), (2, (b, c)), (4, (c, a))] {
            if count[&key(i, j)] == 1 {
                mask |= bit;
            }
        }
        out.extend([a, b, c, mask]);
    }
    out
}

/// `t`'s linear texels as RGBA rows, top row first (the CPU's storage order).
fn linear_texels(t: &Texture) -> Vec<f32> {
    t.texels()
        .iter()
        .flat_map(|c| [c.x, c.y, c.z, 1.0])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Texels go up in the CPU's order, as RGBA.
    #[test]
    fn texels_are_uploaded_in_order() {
        let texels: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f32, 0.5, 0.25)).collect();
        let got = linear_texels(&Texture::from_linear(3, 2, texels));
        assert_eq!(&got[..8], &[0.0, 0.5, 0.25, 1.0, 1.0, 0.5, 0.25, 1.0]);
        assert_eq!(got.len(), 24);
    }

    /// Boundary edges: a quad of two triangles has four, its diagonal is shared.
    #[test]
    fn boundary_edges_of_a_quad() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let t = with_boundary_edges(&p, &[[0, 1, 2], [0, 2, 3]]);
        // a-b and b-c of the first, b-c and c-a of the second; c-a / a-b (0-2) shared.
        assert_eq!(t, vec![0, 1, 2, 1 | 2, 0, 2, 3, 2 | 4]);
    }
}
