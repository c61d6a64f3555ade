//! fastbrdf on the GPU (wgpu 30, headless).
//!
//! - [`library`]: the WGSL twins of every model's core formula (`src/wgsl/*.wgsl`).
//! - [`spec`]: a model id and parameters as one WGSL function `fb_<id>`.
//! - [`context`]: instance, adapter and device set-up; everything else takes `&Device, &Queue`.
//! - [`compute`]: evaluate any model over a batch (the CPU batch API's inputs).

pub mod compute;
pub mod context;
pub mod library;
pub mod spec;

pub use compute::GpuKernel;
pub use context::{Gpu, GpuError};
