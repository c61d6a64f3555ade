//! The tile's pixels summed on the GPU: each draw of a tile (under an environment, one per
//! chunk of passes) leaves its samples in the colour target, and a compute pass adds each
//! pixel's N x N samples, times 1 / N^2, into a per-tile buffer of RGB pixels (the first draw
//! writes it); the tile is read back once, after its last draw.
//!
//! Before, every draw was read back whole (16 bytes per sample: 16 MB for a 512 x 512 tile at
//! 2 x 2 samples) and summed on the CPU, with a wait for the GPU each time. On an NVIDIA H200
//! (tools/gpu_figures.sh) a pass of the built-in sky took about 8 ms, linear in the passes,
//! and the 16-thread CPU renderer was 1.5-2.4x faster than the GPU there; how much of that was
//! the read-back is not measured yet.
//!
//! The order of the additions is the CPU's (`Film` from the read-back, as before): samples row
//! by row within the pixel from 0, the sum scaled by 1 / N^2, then added to the earlier
//! draws' sum.

use crate::context::GpuError;
use wgpu::util::DeviceExt;

const SHADER: &str = r#"
struct Resolve { n: u32, pw: u32, ph: u32, add: u32, inv: f32, p0: f32, p1: f32, p2: f32 };
@group(0) @binding(0) var samples: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> acc: array<f32>;
@group(0) @binding(2) var<uniform> r: Resolve;

@compute @workgroup_size(8, 8)
fn resolve(@builtin(global_invocation_id) g: vec3<u32>) {
    if (g.x >= r.pw || g.y >= r.ph) {
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var sy = 0u; sy < r.n; sy++) {
        for (var sx = 0u; sx < r.n; sx++) {
            sum += textureLoad(samples, vec2<u32>(g.x * r.n + sx, g.y * r.n + sy), 0).xyz;
        }
    }
    sum *= r.inv;
    let i = 3u * (g.y * r.pw + g.x);
    if (r.add != 0u) {
        acc[i] += sum.x;
        acc[i + 1u] += sum.y;
        acc[i + 2u] += sum.z;
    } else {
        acc[i] = sum.x;
        acc[i + 1u] = sum.y;
        acc[i + 2u] = sum.z;
    }
}
"#;

/// The pipeline and the buffers of the largest tile.
pub(super) struct Resolver {
    pipeline: wgpu::ComputePipeline,
    acc: wgpu::Buffer,
    readback: wgpu::Buffer,
}

/// One tile's bind groups: the first draw's (writes) and the later draws' (adds).
pub(super) struct TileResolve {
    write: wgpu::BindGroup,
    add: wgpu::BindGroup,
    groups: (u32, u32),
    bytes: u64,
    pixels: usize,
}

impl Resolver {
    /// For tiles of at most `max_pixels` pixels.
    pub(super) fn new(device: &wgpu::Device, max_pixels: u64) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("fastbrdf render resolve"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("fastbrdf render resolve"),
            layout: None,
            module: &module,
            entry_point: Some("resolve"),
            compilation_options: Default::default(),
            cache: None,
        });
        let size = (max_pixels * 12).max(4);
        let acc = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fastbrdf render pixels"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fastbrdf render pixels readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Resolver {
            pipeline,
            acc,
            readback,
        }
    }

    /// The bind groups of a tile of `pw` x `ph` pixels of `n` x `n` samples in `samples`.
    pub(super) fn tile(
        &self,
        device: &wgpu::Device,
        samples: &wgpu::TextureView,
        (pw, ph, n): (u32, u32, u32),
    ) -> TileResolve {
        let bind = |add: u32| {
            let inv = 1.0 / (n * n) as f32;
            let words: [u32; 8] = [n, pw, ph, add, inv.to_bits(), 0, 0, 0];
            let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf render resolve"),
                contents: bytemuck::cast_slice(&words),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fastbrdf render resolve"),
                layout: &self.pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(samples),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: self.acc.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: params.as_entire_binding(),
                    },
                ],
            })
        };
        TileResolve {
            write: bind(0),
            add: bind(1),
            groups: (pw.div_ceil(8), ph.div_ceil(8)),
            bytes: u64::from(pw) * u64::from(ph) * 12,
            pixels: (pw * ph) as usize,
        }
    }

    /// Records the sum of the draw just recorded into the tile's pixels (`first`: the tile's
    /// first draw, which writes them).
    pub(super) fn record(&self, enc: &mut wgpu::CommandEncoder, t: &TileResolve, first: bool) {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, if first { &t.write } else { &t.add }, &[]);
        pass.dispatch_workgroups(t.groups.0, t.groups.1, 1);
    }

    /// Reads the tile's pixels back (waits for the GPU): RGB, row by row.
    pub(super) fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        t: &TileResolve,
        f: impl FnOnce(&[f32]),
    ) -> Result<(), GpuError> {
        let mut enc = device.create_command_encoder(&Default::default());
        enc.copy_buffer_to_buffer(&self.acc, 0, &self.readback, 0, t.bytes);
        queue.submit([enc.finish()]);
        crate::compute::map_read(device, &self.readback, |bytes| {
            let px: &[f32] = bytemuck::cast_slice(bytes);
            f(&px[..3 * t.pixels]);
        })
    }
}
