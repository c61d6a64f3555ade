//! fastbrdf on the GPU (wgpu 30, headless).
//!
//! - [`library`]: the WGSL twins of every model's core formula (in the core crate, each
//!   family's `.wgsl` file beside its Rust file: `fastbrdf::plan::library_sources`).
//! - [`spec`]: a model spec (`fastbrdf::ModelSpec`) as one WGSL function `fb_<id>`.
//! - [`context`]: instance, adapter and device set-up; everything else takes `&Device, &Queue`.
//! - [`compute`]: evaluate any model over a batch (the CPU batch API's inputs).
//! - [`bench`]: evaluations per second on the GPU (kernel alone, and with transfers).
//! - [`render`]: the CPU renderer's scenes, rasterised on the GPU, shaded by any model.
//! - [`export`]: a model as a self-contained function in WGSL, GLSL, HLSL, MSL (through
//!   naga) or a BRDF Explorer `.brdf` file.
//! - [`cost`]: a shader's instruction count after `spirv-opt -O`, by class of operation
//!   (committed for the built-ins: `src/shader_costs.csv`).

pub mod bench;
pub mod compute;
pub mod context;
pub mod cost;
pub mod export;
pub mod library;
pub mod render;
pub mod runtime_fits;
pub mod spec;
pub mod user;

pub use compute::GpuKernel;
pub use context::{Gpu, GpuError};
