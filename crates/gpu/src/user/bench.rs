//! A user's shader in `fastbrdf bench --gpu` (issue 31): its instruction count
//! ([`UserShader::instructions`], the figure `fastbrdf_gpu::cost` gives the built-ins) and its
//! throughput ([`measure`]), timed as the built-in models are (`crate::bench::time`: the same
//! rounds, the same batch of direction pairs packed column after column, one invocation per
//! pair, workgroups of 256), so the figures stand beside theirs.
//!
//! The one difference: a user's BRDF returns RGB, so each invocation stores three floats (a
//! built-in model stores one). All three are stored so that no channel's work is optimised
//! away; the timed work is the whole of `fb_user_brdf`, as the instruction count is.

use super::{UserError, UserShader};
use crate::bench::{PROBE, Timing, time, too_slow};
use crate::compute::{CHUNK, read_buffer};
use crate::context::{GpuError, validated};
use crate::cost::{self, Counts};
use std::time::Duration;
use wgpu::util::DeviceExt;

const WORKGROUP: u32 = 256;

/// The compute entry point around `fb_user_brdf`, as `compute`'s entry point around a
/// built-in BRDF: element `i` reads column `k` at `inp[k * n + i]`, writes `outp[3i..3i+3]`.
const ENTRY: &str = "
struct FbDims {
    n: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<storage, read> fb_inp: array<f32>;
@group(0) @binding(1) var<storage, read_write> fb_outp: array<f32>;
@group(0) @binding(2) var<uniform> fb_dims: FbDims;

@compute @workgroup_size(256)
fn fb_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    let n = fb_dims.n;
    if i >= n {
        return;
    }
    let f = fb_user_brdf(
        vec3<f32>(fb_inp[i], fb_inp[n + i], fb_inp[2u * n + i]),
        vec3<f32>(fb_inp[3u * n + i], fb_inp[4u * n + i], fb_inp[5u * n + i]),
    );
    fb_outp[3u * i] = f.x;
    fb_outp[3u * i + 1u] = f.y;
    fb_outp[3u * i + 2u] = f.z;
}
";

impl UserShader {
    /// The SPIR-V instructions of the user's BRDF after `spirv-opt -O`, by class: `cost::of_wgsl`
    /// of [`Self::wgsl`]'s `fb_user_brdf` (the parameters' uniform loads are the wrapper's
    /// input, not counted). The same on every machine; an error (naming the file) when
    /// `spirv-opt` is missing (the message says how to install it).
    pub fn instructions(&self) -> Result<Counts, String> {
        let src = self.wgsl().map_err(|e| e.message)?;
        cost::of_wgsl(&src, "fb_user_brdf").map_err(|e| format!("{}: {e}", self.origin()))
    }
}

/// A user's shader with its parameter values in one compute pipeline, for timing.
pub struct UserKernel {
    name: String,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::BindGroup,
}

/// One batch of direction pairs resident on the GPU, for repeated dispatches.
pub struct UserResident {
    n: usize,
    bind: wgpu::BindGroup,
    output: wgpu::Buffer,
}

impl UserKernel {
    /// Compiles `shader` with its defaults replaced by `given` (see [`UserShader::values`]).
    pub fn new(
        device: &wgpu::Device,
        shader: &UserShader,
        given: &[(String, String)],
    ) -> Result<Self, UserError> {
        let values = shader.values(given)?;
        let src = format!("{}\n{ENTRY}", shader.wgsl_at(1, 0)?);
        let what = format!("benchmark shader of {}", shader.name());
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let storage = |read_only| wgpu::BufferBindingType::Storage { read_only };
        let made = validated(device, &what, || {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("fastbrdf user bench batch"),
                entries: &[
                    entry(0, storage(true)),
                    entry(1, storage(false)),
                    entry(2, wgpu::BufferBindingType::Uniform),
                ],
            });
            let param_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("fastbrdf user bench parameters"),
                entries: &[entry(0, wgpu::BufferBindingType::Uniform)],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&what),
                bind_group_layouts: &[Some(&layout), Some(&param_layout)],
                immediate_size: 0,
            });
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&what),
                source: wgpu::ShaderSource::Wgsl(src.as_str().into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&what),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some("fb_main"),
                compilation_options: Default::default(),
                cache: None,
            });
            let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf user bench parameters"),
                contents: bytemuck::cast_slice(&shader.param_block(&values)),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let params = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fastbrdf user bench parameters"),
                layout: &param_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buf.as_entire_binding(),
                }],
            });
            (pipeline, layout, params)
        })
        .map_err(|e| {
            UserError::gpu(format!(
                "{}: the GPU refused the shader: {e}",
                shader.origin()
            ))
        })?;
        let (pipeline, layout, params) = made;
        Ok(Self {
            name: shader.name(),
            pipeline,
            layout,
            params,
        })
    }

    /// Uploads `dirs` (`wi_x, wi_y, wi_z, wo_x, wo_y, wo_z`, 1 to `compute::CHUNK` pairs).
    pub fn upload(
        &self,
        device: &wgpu::Device,
        dirs: [&[f32]; 6],
    ) -> Result<UserResident, GpuError> {
        let n = dirs[0].len();
        if dirs.iter().any(|c| c.len() != n) {
            return Err(GpuError::Input(format!(
                "{}: the six direction columns differ in length",
                self.name
            )));
        }
        if n == 0 || n > CHUNK {
            return Err(GpuError::Input(format!(
                "a resident batch holds 1 to {CHUNK} pairs, not {n}"
            )));
        }
        let packed: Vec<f32> = dirs.concat();
        let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf user bench input"),
            contents: bytemuck::cast_slice(&packed),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fastbrdf user bench output"),
            size: (3 * n * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let dims = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf user bench dims"),
            contents: bytemuck::cast_slice(&[n as u32, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("fastbrdf user bench batch"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: dims.as_entire_binding(),
                },
            ],
        });
        Ok(UserResident { n, bind, output })
    }

    /// Records `repeat` dispatches over a resident batch and submits them (no wait).
    pub fn dispatch(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        r: &UserResident,
        repeat: u32,
    ) {
        let mut enc = device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &r.bind, &[]);
            pass.set_bind_group(1, &self.params, &[]);
            let groups = (r.n as u32).div_ceil(WORKGROUP);
            for _ in 0..repeat {
                pass.dispatch_workgroups(groups, 1, 1);
            }
        }
        queue.submit([enc.finish()]);
    }

    /// Uploads `dirs`, evaluates and reads back: `out` holds R, G, B per pair (`3 n` floats).
    pub fn eval(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        dirs: [&[f32]; 6],
        out: &mut [f32],
    ) -> Result<(), GpuError> {
        if out.len() != 3 * dirs[0].len() {
            return Err(GpuError::Input(format!(
                "{} pairs need {} outputs (R, G, B), not {}",
                dirs[0].len(),
                3 * dirs[0].len(),
                out.len()
            )));
        }
        let r = self.upload(device, dirs)?;
        self.dispatch(device, queue, &r, 1);
        read_buffer(device, queue, &r.output, out)
    }
}

/// Measures `shader` with the `given` parameter values over the direction pairs `dirs`
/// (`wi_x, wi_y, wi_z, wo_x, wo_y, wo_z`, 1 to `compute::CHUNK` pairs), spending about
/// `budget` on each figure, as `crate::bench::measure` measures a built-in model.
pub fn measure(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    shader: &UserShader,
    given: &[(String, String)],
    dirs: [&[f32]; 6],
    budget: Duration,
) -> Result<Timing, UserError> {
    let k = UserKernel::new(device, shader, given)?;
    let gpu = |e: GpuError| UserError::gpu(format!("{} on the GPU: {e}", shader.name()));
    let n = dirs[0].len();
    if n > PROBE {
        let p = k.upload(device, dirs.map(|d| &d[..PROBE])).map_err(gpu)?;
        let probe = || k.dispatch(device, queue, &p, 1);
        if let Some(projected_s) = too_slow(device, n, &probe).map_err(gpu)? {
            return Ok(Timing::TooSlow { projected_s });
        }
    }
    let r = k.upload(device, dirs).map_err(gpu)?;
    let mut out = vec![0.0f32; 3 * r.n];
    time(
        device,
        r.n,
        budget,
        &|repeat| k.dispatch(device, queue, &r, repeat),
        &mut || k.eval(device, queue, dirs, &mut out),
    )
    .map(Timing::Measured)
    .map_err(gpu)
}
