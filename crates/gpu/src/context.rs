//! GPU set-up: one call finds an adapter and opens a device. Everything else in this crate
//! takes `&wgpu::Device, &wgpu::Queue`, so tests and applications can bring their own.

use std::fmt;

/// What can go wrong on the GPU side.
#[derive(Debug)]
pub enum GpuError {
    /// No adapter: no GPU driver and no software one (Mesa's lavapipe).
    NoAdapter(String),
    /// The adapter would not open a device.
    Device(String),
    /// A shader or pipeline failed validation (a bug: the message says where).
    Shader { what: String, message: String },
    /// Bad model id or parameters.
    Model(fastbrdf::Error),
    /// Bad input (lengths, shapes, sizes).
    Input(String),
    /// A buffer could not be read back.
    Readback(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter(why) => write!(
                f,
                "no GPU adapter found ({why}); on Debian without a GPU install Mesa's software \
                 Vulkan driver: apt-get install mesa-vulkan-drivers"
            ),
            GpuError::Device(m) => write!(f, "the GPU adapter would not open a device: {m}"),
            GpuError::Shader { what, message } => write!(f, "{what}: {message}"),
            GpuError::Model(e) => write!(f, "{e}"),
            GpuError::Input(m) => write!(f, "{m}"),
            GpuError::Readback(m) => write!(f, "reading GPU results back failed: {m}"),
        }
    }
}

impl std::error::Error for GpuError {}

impl From<fastbrdf::Error> for GpuError {
    fn from(e: fastbrdf::Error) -> Self {
        GpuError::Model(e)
    }
}

/// An open GPU device and what it is.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
}

impl Gpu {
    /// Opens the first adapter wgpu offers (high performance preferred), honouring wgpu's
    /// environment variables (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME`, ...). Headless: no surface.
    pub fn new() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("fastbrdf"),
            required_limits: wgpu::Limits::default(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Self {
            device,
            queue,
            info,
        })
    }

    /// Whether the adapter is a CPU in disguise (lavapipe, llvmpipe, WARP, SwiftShader).
    pub fn is_software(&self) -> bool {
        is_software(&self.info)
    }

    /// A one-line label: name, backend and, for software adapters, a warning that its
    /// figures are CPU figures.
    pub fn label(&self) -> String {
        label(&self.info)
    }
}

/// Whether an adapter is a software rasteriser running on the CPU.
pub fn is_software(info: &wgpu::AdapterInfo) -> bool {
    info.device_type == wgpu::DeviceType::Cpu
}

/// `name (backend, type)`, plus the software warning.
pub fn label(info: &wgpu::AdapterInfo) -> String {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => "discrete GPU",
        wgpu::DeviceType::IntegratedGpu => "integrated GPU",
        wgpu::DeviceType::VirtualGpu => "virtual GPU",
        wgpu::DeviceType::Cpu => "software adapter on the CPU: its figures are CPU figures",
        wgpu::DeviceType::Other => "unknown device type",
    };
    format!("{} ({:?}, {kind})", info.name, info.backend)
}

/// Runs `f` inside a validation error scope and turns a validation error into
/// `GpuError::Shader` naming `what`.
pub fn validated<T>(
    device: &wgpu::Device,
    what: &str,
    f: impl FnOnce() -> T,
) -> Result<T, GpuError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    match pollster::block_on(scope.pop()) {
        None => Ok(out),
        Some(e) => Err(GpuError::Shader {
            what: what.into(),
            message: e.to_string(),
        }),
    }
}
