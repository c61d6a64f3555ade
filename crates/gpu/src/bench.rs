//! GPU throughput: evaluations per second of one model instance, with the data resident on
//! the GPU (repeated dispatches in one submission, timed by the wall clock after the queue
//! drains), and with the transfers (upload, dispatch, read back) for comparison.
//!
//! A software adapter (lavapipe) runs the shader on the CPU's cores: its figures are CPU
//! figures, and `context::label` says so wherever they are printed.

use crate::compute::{GpuInput, GpuKernel};
use crate::context::GpuError;
use std::time::{Duration, Instant};

/// One measurement.
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    /// Data resident on the GPU: evaluations per second of the kernel alone.
    pub kernel_evals_per_s: f64,
    /// Upload, dispatch and read back, per element.
    pub transfer_evals_per_s: f64,
}

fn wait(device: &wgpu::Device) -> Result<(), GpuError> {
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| GpuError::Readback(e.to_string()))
}

/// Measures the model of `spec` over `input` (1 to `compute::CHUNK` elements),
/// spending about `budget` on each figure.
pub fn measure(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    spec: &fastbrdf::ModelSpec,
    input: GpuInput,
    budget: Duration,
) -> Result<Measured, GpuError> {
    let n = input.len();
    let k = GpuKernel::from_spec(device, spec)?;
    let r = k.upload(device, input)?;
    // Warm-up (pipeline compilation happens at the first dispatch on some drivers).
    k.dispatch(device, queue, &r, 1);
    wait(device)?;
    // Double the dispatches per submission until one submission takes a quarter of the budget,
    // then keep the best of the rounds that fit in the budget.
    let mut repeat = 1u32;
    let mut best = 0.0f64;
    let start = Instant::now();
    let mut rounds = 0;
    loop {
        let t = Instant::now();
        k.dispatch(device, queue, &r, repeat);
        wait(device)?;
        let dt = t.elapsed().as_secs_f64();
        best = best.max(n as f64 * repeat as f64 / dt);
        if dt < budget.as_secs_f64() / 4.0 && repeat < 1 << 14 {
            repeat *= 2;
            continue;
        }
        rounds += 1;
        if rounds >= 3 && start.elapsed() >= budget {
            break;
        }
        if rounds >= 12 {
            break;
        }
    }
    let mut out = vec![0.0f32; n];
    let mut best_t = f64::INFINITY;
    let start = Instant::now();
    let mut rounds = 0;
    while rounds < 3 || (start.elapsed() < budget && rounds < 12) {
        let t = Instant::now();
        k.eval(device, queue, input, &mut out)?;
        best_t = best_t.min(t.elapsed().as_secs_f64());
        rounds += 1;
    }
    Ok(Measured {
        kernel_evals_per_s: best,
        transfer_evals_per_s: n as f64 / best_t,
    })
}
