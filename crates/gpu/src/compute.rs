//! The compute path: evaluate one model instance over a batch on the GPU.
//!
//! Inputs are the CPU batch API's (`fastbrdf::batch::Input`): one slice of cosines for lobes,
//! distributions and Fresnel terms, six direction slices for BRDFs; shadowing terms, which the
//! CPU batch API does not take, get four slices `cos_v, cos_l, cos_h, cos_vh` (two-sided).
//! The slices are packed column after column into one storage buffer; one invocation computes
//! one element. Batches are split into dispatches of at most `CHUNK` elements, which keeps
//! every binding under wgpu's default 128 MiB cap and the workgroup count under 65,535.

use crate::context::{GpuError, validated};
use crate::spec::Instance;
use fastbrdf::model::Kind;
use wgpu::util::DeviceExt;

/// Elements per dispatch: 6 columns of 2^22 f32 are 96 MiB; 2^22 / 256 = 16384 workgroups.
pub const CHUNK: usize = 1 << 22;
const WORKGROUP: u32 = 256;

/// The inputs of one GPU batch.
#[derive(Clone, Copy, Debug)]
pub enum GpuInput<'a> {
    /// Cosines (lobes: `cos`; distributions: `cos_h`; Fresnel: `cos_vh`).
    Cos(&'a [f32]),
    /// Shadowing: `cos_v, cos_l, cos_h, cos_vh`.
    Shadow([&'a [f32]; 4]),
    /// Directions `wi_x, wi_y, wi_z, wo_x, wo_y, wo_z` (BRDFs).
    Dirs([&'a [f32]; 6]),
    /// Split-sum terms: `cos_v, alpha`.
    Env([&'a [f32]; 2]),
}

impl<'a> GpuInput<'a> {
    /// The number of elements (of the first column; `GpuKernel` checks the others).
    pub fn len(&self) -> usize {
        self.columns()[0].len()
    }

    /// Whether there are no elements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Elements `lo..hi` of every column.
    pub(crate) fn slice(&self, lo: usize, hi: usize) -> Self {
        match *self {
            GpuInput::Cos(x) => GpuInput::Cos(&x[lo..hi]),
            GpuInput::Shadow(c) => GpuInput::Shadow(c.map(|s| &s[lo..hi])),
            GpuInput::Dirs(c) => GpuInput::Dirs(c.map(|s| &s[lo..hi])),
            GpuInput::Env(c) => GpuInput::Env(c.map(|s| &s[lo..hi])),
        }
    }

    fn columns(&self) -> Vec<&'a [f32]> {
        match *self {
            GpuInput::Cos(x) => vec![x],
            GpuInput::Shadow(c) => c.to_vec(),
            GpuInput::Dirs(c) => c.to_vec(),
            GpuInput::Env(c) => c.to_vec(),
        }
    }
}

impl<'a> From<fastbrdf::batch::Input<'a>> for GpuInput<'a> {
    fn from(i: fastbrdf::batch::Input<'a>) -> Self {
        match i {
            fastbrdf::batch::Input::Cos(x) => GpuInput::Cos(x),
            fastbrdf::batch::Input::Dirs(w) => GpuInput::Dirs(w),
            fastbrdf::batch::Input::Env(x) => GpuInput::Env(x),
        }
    }
}

/// How many input columns a kind takes.
pub fn columns_of(kind: Kind) -> usize {
    match kind {
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => 1,
        Kind::Env => 2,
        Kind::Shadowing => 4,
        Kind::Brdf => 6,
    }
}

/// The compute entry point calling `function` on element `i` of the packed columns.
fn entry_point(kind: Kind, function: &str) -> String {
    let col = |k: usize| format!("inp[{k}u * dims.n + i]");
    let call = match kind {
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => format!("{function}({})", col(0)),
        Kind::Env => format!("{function}({}, {})", col(0), col(1)),
        Kind::Shadowing => format!("{function}({}, {}, {}, {})", col(0), col(1), col(2), col(3)),
        Kind::Brdf => format!(
            "{function}(vec3<f32>({}, {}, {}), vec3<f32>({}, {}, {}))",
            col(0),
            col(1),
            col(2),
            col(3),
            col(4),
            col(5)
        ),
    };
    format!(
        "
struct FbDims {{
    n: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}}

@group(0) @binding(0) var<storage, read> inp: array<f32>;
@group(0) @binding(1) var<storage, read_write> outp: array<f32>;
@group(0) @binding(2) var<uniform> dims: FbDims;
@group(0) @binding(3) var<storage, read> fb_k: array<f32>;

@compute @workgroup_size({WORKGROUP})
fn fb_main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    let i = gid.x;
    if i >= dims.n {{
        return;
    }}
    // Keeps binding 3 in the layout when the instance has no coefficients.
    _ = arrayLength(&fb_k);
    outp[i] = {call};
}}
"
    )
}

/// One model instance compiled into a compute pipeline.
pub struct GpuKernel {
    instance: Instance,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// Buffers holding one chunk on the GPU, for repeated dispatches (benchmarks).
pub struct Resident {
    n: usize,
    bind: wgpu::BindGroup,
    output: wgpu::Buffer,
}

impl GpuKernel {
    /// Compiles the compute shader of `instance` (validated by naga inside wgpu).
    pub fn new(device: &wgpu::Device, instance: Instance) -> Result<Self, GpuError> {
        let src = format!(
            "{}\n{}",
            instance.module_source(),
            entry_point(instance.info.kind, &instance.function)
        );
        let what = format!("compute shader of {}", instance.info.id);
        let (pipeline, layout) = validated(device, &what, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&what),
                source: wgpu::ShaderSource::Wgsl(src.into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&what),
                layout: None,
                module: &module,
                entry_point: Some("fb_main"),
                compilation_options: Default::default(),
                cache: None,
            });
            let layout = pipeline.get_bind_group_layout(0);
            (pipeline, layout)
        })?;
        Ok(Self {
            instance,
            pipeline,
            layout,
        })
    }

    /// Shorthand: the instance of `spec` (coefficients in storage), compiled.
    pub fn from_spec(device: &wgpu::Device, spec: &fastbrdf::ModelSpec) -> Result<Self, GpuError> {
        Self::new(device, Instance::with_storage(spec)?)
    }

    /// The model instance.
    pub fn instance(&self) -> &Instance {
        &self.instance
    }

    fn check(&self, input: &GpuInput, n: usize) -> Result<(), GpuError> {
        let cols = input.columns();
        let want = columns_of(self.instance.info.kind);
        if cols.len() != want {
            return Err(GpuError::Input(format!(
                "{} takes {want} input column(s), got {}",
                self.instance.info.id,
                cols.len()
            )));
        }
        if cols.iter().any(|c| c.len() != n) {
            return Err(GpuError::Input(format!(
                "input and output lengths differ (output {n})"
            )));
        }
        Ok(())
    }

    /// Uploads one chunk (at most `CHUNK` elements) and prepares its bind group.
    pub fn upload(&self, device: &wgpu::Device, input: GpuInput) -> Result<Resident, GpuError> {
        let n = input.len();
        self.check(&input, n)?;
        if n == 0 || n > CHUNK {
            return Err(GpuError::Input(format!(
                "a resident chunk holds 1 to {CHUNK} elements, not {n}"
            )));
        }
        let mut packed: Vec<f32> = Vec::with_capacity(n * input.columns().len());
        for c in input.columns() {
            packed.extend_from_slice(&c[..n]);
        }
        let input_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf input"),
            contents: bytemuck::cast_slice(&packed),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("fastbrdf output"),
            size: (n * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let dims = [n as u32, 0, 0, 0];
        let dims_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf dims"),
            contents: bytemuck::cast_slice(&dims),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // Instances with literal coefficients read none: one zero keeps the binding valid.
        let coefs: Vec<f32> = if self.instance.coefs.is_empty() {
            vec![0.0]
        } else {
            self.instance.coefs.clone()
        };
        let coef_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fastbrdf coefficients"),
            contents: bytemuck::cast_slice(&coefs),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("fastbrdf batch"),
            layout: &self.layout,
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
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: coef_buf.as_entire_binding(),
                },
            ],
        });
        Ok(Resident { n, bind, output })
    }

    /// Records `repeat` dispatches over a resident chunk and submits them (no wait).
    pub fn dispatch(&self, device: &wgpu::Device, queue: &wgpu::Queue, r: &Resident, repeat: u32) {
        let mut enc = device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &r.bind, &[]);
            let groups = (r.n as u32).div_ceil(WORKGROUP);
            for _ in 0..repeat {
                pass.dispatch_workgroups(groups, 1, 1);
            }
        }
        queue.submit([enc.finish()]);
    }

    /// Copies a resident chunk's results into `out` (waits for the GPU).
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        r: &Resident,
        out: &mut [f32],
    ) -> Result<(), GpuError> {
        read_buffer(device, queue, &r.output, out)
    }

    /// Evaluates the model over the whole batch: `out[i]` is the model at element `i`.
    pub fn eval(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        input: GpuInput,
        out: &mut [f32],
    ) -> Result<(), GpuError> {
        let n = out.len();
        self.check(&input, n)?;
        let mut lo = 0;
        while lo < n {
            let hi = (lo + CHUNK).min(n);
            let r = self.upload(device, input.slice(lo, hi))?;
            self.dispatch(device, queue, &r, 1);
            self.read(device, queue, &r, &mut out[lo..hi])?;
            lo = hi;
        }
        Ok(())
    }
}

/// Waits for the queue and copies a storage buffer of f32 into `out`.
pub fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buf: &wgpu::Buffer,
    out: &mut [f32],
) -> Result<(), GpuError> {
    let size = (out.len() * 4) as u64;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("fastbrdf readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(buf, 0, &staging, 0, size);
    queue.submit([enc.finish()]);
    map_read(device, &staging, |bytes| {
        out.copy_from_slice(bytemuck::cast_slice(bytes));
    })
}

/// Maps a MAP_READ buffer, waits, and hands its bytes to `f`.
pub fn map_read(
    device: &wgpu::Device,
    buf: &wgpu::Buffer,
    f: impl FnOnce(&[u8]),
) -> Result<(), GpuError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buf.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| GpuError::Readback(e.to_string()))?
        .map_err(|e| GpuError::Readback(e.to_string()))?;
    {
        let view = buf
            .get_mapped_range(..)
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        f(&view);
    }
    buf.unmap();
    Ok(())
}
