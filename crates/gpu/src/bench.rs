//! GPU throughput: evaluations per second of one model instance, with the data resident on
//! the GPU (repeated dispatches in one submission, timed by the wall clock after the queue
//! drains), and with the transfers (upload, dispatch, read back) for comparison.
//!
//! A software adapter (lavapipe) runs the shader on the CPU's cores: its figures are CPU
//! figures, and `context::label` says so wherever they are printed. Users' shaders are timed
//! by the same method (`user::bench`).

use crate::compute::{GpuInput, GpuKernel};
use crate::context::GpuError;
use std::time::{Duration, Instant};

/// Elements of the probe dispatch that projects a model's cost before its full batch is timed.
pub const PROBE: usize = 1 << 16;

/// Longest projected dispatch of the full batch, in seconds, that is timed: a quadrature
/// reference (`sheen-albedo`, 48 x 48 points per value) on a software adapter takes about 20 s
/// per 4M-element dispatch, and timing it needs at least seven; such a model gets
/// [`Timing::TooSlow`] instead (on a real GPU it is timed).
pub const CALL_LIMIT_S: f64 = 3.0;

/// A model's GPU figures, or why there are none.
#[derive(Clone, Copy, Debug)]
pub enum Timing {
    Measured(Measured),
    /// One dispatch of the full batch was projected (from a [`PROBE`]-element dispatch) to
    /// take `projected_s` seconds, over [`CALL_LIMIT_S`].
    TooSlow {
        projected_s: f64,
    },
}

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
) -> Result<Timing, GpuError> {
    let n = input.len();
    let k = GpuKernel::from_spec(device, spec)?;
    if n > PROBE {
        let p = k.upload(device, input.slice(0, PROBE))?;
        if let Some(projected_s) = too_slow(device, n, &|| k.dispatch(device, queue, &p, 1))? {
            return Ok(Timing::TooSlow { projected_s });
        }
    }
    let r = k.upload(device, input)?;
    let mut out = vec![0.0f32; n];
    time(
        device,
        n,
        budget,
        &|repeat| k.dispatch(device, queue, &r, repeat),
        &mut || k.eval(device, queue, input, &mut out),
    )
    .map(Timing::Measured)
}

/// The projected seconds of one dispatch of `n` elements when over [`CALL_LIMIT_S`], from
/// `probe`, one dispatch of [`PROBE`] elements (run twice: the first compiles the pipeline
/// on some drivers).
pub(crate) fn too_slow(
    device: &wgpu::Device,
    n: usize,
    probe: &dyn Fn(),
) -> Result<Option<f64>, GpuError> {
    probe();
    wait(device)?;
    let t = Instant::now();
    probe();
    wait(device)?;
    let projected_s = t.elapsed().as_secs_f64() * n as f64 / PROBE as f64;
    Ok((projected_s > CALL_LIMIT_S).then_some(projected_s))
}

/// The timing method of every GPU figure (built-in models and users' shaders alike, so their
/// numbers compare): `dispatch(repeat)` submits `repeat` dispatches over `n` resident elements
/// without waiting, `transfer()` uploads, dispatches and reads back the `n` elements.
pub(crate) fn time(
    device: &wgpu::Device,
    n: usize,
    budget: Duration,
    dispatch: &dyn Fn(u32),
    transfer: &mut dyn FnMut() -> Result<(), GpuError>,
) -> Result<Measured, GpuError> {
    // Warm-up (pipeline compilation happens at the first dispatch on some drivers).
    dispatch(1);
    wait(device)?;
    // Double the dispatches per submission until one submission takes a quarter of the budget,
    // then keep the best of the rounds that fit in the budget.
    let mut repeat = 1u32;
    let mut best = 0.0f64;
    let start = Instant::now();
    let mut rounds = 0;
    loop {
        let t = Instant::now();
        dispatch(repeat);
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
    let mut best_t = f64::INFINITY;
    let start = Instant::now();
    let mut rounds = 0;
    while rounds < 3 || (start.elapsed() < budget && rounds < 12) {
        let t = Instant::now();
        transfer()?;
        best_t = best_t.min(t.elapsed().as_secs_f64());
        rounds += 1;
    }
    Ok(Measured {
        kernel_evals_per_s: best,
        transfer_evals_per_s: n as f64 / best_t,
    })
}
