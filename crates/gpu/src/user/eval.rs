//! A user's shader compiled on a device: batches of direction pairs in storage buffers, one
//! dispatch per chunk of at most [`CHUNK`] rows (every binding under wgpu's default 128 MiB
//! cap), workgroups spread over two dimensions past the 65,535 a dimension allows; f32 on the
//! GPU, inputs passed as given.

use super::{ParamValue, UserError, UserShader};
use crate::compute::read_buffer;
use crate::context::validated;
use fastbrdf::user::{SampleBatch, UserBrdf, check_rows};
use wgpu::util::DeviceExt;

/// Rows per dispatch: the widest row (a sample's 8 outputs) is 32 bytes, 64 MiB a chunk.
pub const CHUNK: usize = 1 << 21;
const WORKGROUP: u32 = 64;

/// The compute entry points around the `fb_user_*` functions: row `i` of a batch is
/// invocation `gid.x + gid.y * width`; inputs and outputs are rows of f32.
const ENTRIES: &str = "
struct FbDims {
    n: u32,
    width: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<storage, read> fb_in: array<f32>;
@group(0) @binding(1) var<storage, read_write> fb_out: array<f32>;
@group(0) @binding(2) var<uniform> fb_dims: FbDims;

fn fb_in3(b: u32) -> vec3<f32> {
    return vec3<f32>(fb_in[b], fb_in[b + 1u], fb_in[b + 2u]);
}

@compute @workgroup_size(64)
fn fb_eval(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x + gid.y * fb_dims.width;
    if i >= fb_dims.n {
        return;
    }
    let f = fb_user_brdf(fb_in3(6u * i), fb_in3(6u * i + 3u));
    fb_out[3u * i] = f.x;
    fb_out[3u * i + 1u] = f.y;
    fb_out[3u * i + 2u] = f.z;
}
";

const SAMPLE_ENTRIES: &str = "
@compute @workgroup_size(64)
fn fb_sample(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x + gid.y * fb_dims.width;
    if i >= fb_dims.n {
        return;
    }
    let wo = fb_in3(5u * i);
    let s = fb_user_sample(wo, vec2<f32>(fb_in[5u * i + 3u], fb_in[5u * i + 4u]));
    var w = vec3<f32>(0.0);
    if s.w != 0.0 {
        w = fb_user_weight(wo, s.xyz, s.w);
    }
    let b = 8u * i;
    fb_out[b] = s.x;
    fb_out[b + 1u] = s.y;
    fb_out[b + 2u] = s.z;
    fb_out[b + 3u] = s.w;
    fb_out[b + 4u] = w.x;
    fb_out[b + 5u] = w.y;
    fb_out[b + 6u] = w.z;
    fb_out[b + 7u] = 0.0;
}

@compute @workgroup_size(64)
fn fb_pdf(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x + gid.y * fb_dims.width;
    if i >= fb_dims.n {
        return;
    }
    fb_out[i] = fb_user_pdf(fb_in3(6u * i), fb_in3(6u * i + 3u));
}
";

/// A user's shader compiled into compute pipelines on one device, with its parameter values.
pub struct GpuBrdf {
    shader: UserShader,
    values: Vec<ParamValue>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    batch_layout: wgpu::BindGroupLayout,
    params: wgpu::BindGroup,
    eval: wgpu::ComputePipeline,
    sample: Option<(wgpu::ComputePipeline, wgpu::ComputePipeline)>,
    max_groups_x: u32,
    chunk_rows: usize,
}

impl GpuBrdf {
    /// Compiles `shader` on `device` with its defaults replaced by `given` (see
    /// [`UserShader::values`]).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        shader: UserShader,
        given: &[(String, String)],
    ) -> Result<Self, UserError> {
        let values = shader.values(given)?;
        let src = format!(
            "{}\n{ENTRIES}{}",
            shader.wgsl()?,
            if shader.samples() { SAMPLE_ENTRIES } else { "" }
        );
        let what = format!("compute shader of {}", shader.name());
        let buffer = |ty| wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: buffer(ty),
            count: None,
        };
        let storage = |read_only| wgpu::BufferBindingType::Storage { read_only };
        let made = validated(device, &what, || {
            let batch_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("fastbrdf user batch"),
                entries: &[
                    entry(0, storage(true)),
                    entry(1, storage(false)),
                    entry(2, wgpu::BufferBindingType::Uniform),
                ],
            });
            let param_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("fastbrdf user parameters"),
                entries: &[entry(0, wgpu::BufferBindingType::Uniform)],
            });
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&what),
                bind_group_layouts: &[Some(&batch_layout), Some(&param_layout)],
                immediate_size: 0,
            });
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&what),
                source: wgpu::ShaderSource::Wgsl(src.as_str().into()),
            });
            let pipeline = |entry: &str| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(&what),
                    layout: Some(&layout),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let eval = pipeline("fb_eval");
            let sample = shader
                .samples()
                .then(|| (pipeline("fb_sample"), pipeline("fb_pdf")));
            let block = shader.param_block(&values);
            let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf user parameters"),
                contents: bytemuck::cast_slice(&block),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let params = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fastbrdf user parameters"),
                layout: &param_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buf.as_entire_binding(),
                }],
            });
            (batch_layout, params, eval, sample)
        })
        .map_err(|e| {
            UserError::gpu(format!(
                "{}: the GPU refused the shader: {e}",
                shader.origin()
            ))
        })?;
        let (batch_layout, params, eval, sample) = made;
        Ok(Self {
            values,
            device: device.clone(),
            queue: queue.clone(),
            batch_layout,
            params,
            eval,
            sample,
            max_groups_x: device.limits().max_compute_workgroups_per_dimension,
            chunk_rows: CHUNK,
            shader,
        })
    }

    /// The shader it runs.
    pub fn shader(&self) -> &UserShader {
        &self.shader
    }

    /// The parameter values it runs with, in [`UserShader::params`] order.
    pub fn values(&self) -> &[ParamValue] {
        &self.values
    }

    /// Caps the workgroups of a dispatch's x dimension and the rows of a chunk (tests: small
    /// caps exercise the 2-D dispatch and the chunking on small batches).
    #[doc(hidden)]
    pub fn set_limits(&mut self, max_groups_x: u32, chunk_rows: usize) {
        let most = self.device.limits().max_compute_workgroups_per_dimension;
        self.max_groups_x = max_groups_x.clamp(1, most);
        self.chunk_rows = chunk_rows.clamp(1, CHUNK);
    }

    /// Runs `pipeline` over `rows` rows of `stride_in` inputs, `stride_out` outputs each.
    fn run(
        &self,
        pipeline: &wgpu::ComputePipeline,
        input: &[f32],
        stride_in: usize,
        stride_out: usize,
    ) -> Result<Vec<f32>, String> {
        let rows = input.len() / stride_in;
        let mut out = vec![0.0f32; rows * stride_out];
        let mut lo = 0;
        while lo < rows {
            let hi = (lo + self.chunk_rows).min(rows);
            self.chunk(
                pipeline,
                &input[lo * stride_in..hi * stride_in],
                &mut out[lo * stride_out..hi * stride_out],
                hi - lo,
            )?;
            lo = hi;
        }
        Ok(out)
    }

    fn chunk(
        &self,
        pipeline: &wgpu::ComputePipeline,
        input: &[f32],
        out: &mut [f32],
        n: usize,
    ) -> Result<(), String> {
        let d = &self.device;
        let groups = (n as u32).div_ceil(WORKGROUP);
        let gx = groups.min(self.max_groups_x);
        let gy = groups.div_ceil(gx);
        if gy > self.device.limits().max_compute_workgroups_per_dimension {
            return Err(format!(
                "{n} rows need more workgroups than the device allows"
            ));
        }
        let output = validated(d, "a user shader's batch", || {
            let input_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf user input"),
                contents: bytemuck::cast_slice(input),
                usage: wgpu::BufferUsages::STORAGE,
            });
            let output = d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("fastbrdf user output"),
                size: (out.len() * 4) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let dims = [n as u32, gx * WORKGROUP, 0, 0];
            let dims_buf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fastbrdf user dims"),
                contents: bytemuck::cast_slice(&dims),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fastbrdf user batch"),
                layout: &self.batch_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: input_buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: output.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: dims_buf.as_entire_binding(),
                    },
                ],
            });
            let mut enc = d.create_command_encoder(&Default::default());
            {
                let mut pass = enc.begin_compute_pass(&Default::default());
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.set_bind_group(1, &self.params, &[]);
                pass.dispatch_workgroups(gx, gy, 1);
            }
            self.queue.submit([enc.finish()]);
            output
        })
        .map_err(|e| e.to_string())?;
        read_buffer(d, &self.queue, &output, out).map_err(|e| e.to_string())
    }

    fn fail(&self, e: String) -> String {
        format!("{} on the GPU: {e}", self.shader.name())
    }
}

/// Rows of `a` then `b` (three numbers each) as f32, six per row.
fn pack6(a: &[[f64; 3]], b: &[[f64; 3]]) -> Vec<f32> {
    let mut v = Vec::with_capacity(6 * a.len());
    for (x, y) in a.iter().zip(b) {
        v.extend(x.iter().chain(y).map(|&c| c as f32));
    }
    v
}

impl UserBrdf for GpuBrdf {
    fn name(&self) -> String {
        self.shader.name()
    }

    fn channels(&self) -> usize {
        self.shader.channels()
    }

    fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        let c = self.channels();
        check_rows(wi.len(), wo.len(), out.len(), c)?;
        if wi.is_empty() {
            return Ok(());
        }
        let f = self
            .run(&self.eval, &pack6(wi, wo), 6, 3)
            .map_err(|e| self.fail(e))?;
        for (k, o) in out.chunks_exact_mut(c).enumerate() {
            for (j, v) in o.iter_mut().enumerate() {
                *v = f64::from(f[3 * k + j]);
            }
        }
        Ok(())
    }

    fn samples(&self) -> bool {
        self.sample.is_some()
    }

    fn sample(&self, wo: &[[f64; 3]], u: &[[f64; 2]]) -> Result<SampleBatch, String> {
        let Some((pipeline, _)) = &self.sample else {
            return Err(format!("{} does not sample (no brdf_sample)", self.name()));
        };
        if wo.len() != u.len() {
            return Err(format!("{} wo rows but {} u rows", wo.len(), u.len()));
        }
        let c = self.channels();
        let n = wo.len();
        let mut b = SampleBatch {
            valid: vec![false; n],
            wi: vec![[0.0; 3]; n],
            weight: vec![0.0; n * c],
            pdf: vec![0.0; n],
        };
        if n == 0 {
            return Ok(b);
        }
        let mut input = Vec::with_capacity(5 * n);
        for (o, uu) in wo.iter().zip(u) {
            input.extend(o.iter().chain(uu).map(|&x| x as f32));
        }
        let r = self.run(pipeline, &input, 5, 8).map_err(|e| self.fail(e))?;
        for k in 0..n {
            let row = &r[8 * k..8 * k + 8];
            let pdf = f64::from(row[3]);
            // pdf 0: no sample; anything else (NaN, negative) is reported for checks to see.
            if pdf != 0.0 {
                b.valid[k] = true;
                b.wi[k] = [row[0], row[1], row[2]].map(f64::from);
                b.pdf[k] = pdf;
                for j in 0..c {
                    b.weight[k * c + j] = f64::from(row[4 + j]);
                }
            }
        }
        Ok(b)
    }

    fn pdf(&self, wo: &[[f64; 3]], wi: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        let Some((_, pipeline)) = &self.sample else {
            return Err(format!("{} does not sample (no brdf_pdf)", self.name()));
        };
        check_rows(wo.len(), wi.len(), out.len(), 1)?;
        if wo.is_empty() {
            return Ok(());
        }
        let p = self
            .run(pipeline, &pack6(wo, wi), 6, 1)
            .map_err(|e| self.fail(e))?;
        for (o, v) in out.iter_mut().zip(p) {
            *o = f64::from(v);
        }
        Ok(())
    }
}
