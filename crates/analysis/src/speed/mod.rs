//! Throughput measurement for `fastbrdf bench`: every model's scalar and SIMD evaluations per
//! second, the machine's FMA throughput, and the speedups the seeds claim, in one run.
//!
//! Method: each measurement runs its closure repeatedly for a time budget after one warm-up
//! call and keeps the fastest round (best-of-rounds is robust on shared, noisy machines).
//! Ratios are always taken between figures of the same run.
//!
//! Variants (the JSON's `variant`):
//! - `scalar`: the library's scalar f32 model (`Model<f32>`), element by element, through its
//!   trait object, as a renderer calling the model per sample would;
//! - `simd`: the batch kernel (`fastbrdf::batch::Kernel`) with the best instruction set, one
//!   thread;
//! - `simd-threads`: the batch kernel split across all threads (`Kernel::eval_par`);
//! - the baselines `powf-loop`, `expf-loop` and `beckmann-expf-loop` (ids of their own): the
//!   loops a user would write naively, `out[i] = c[i].powf(n)`, `out[i] = (-k x[i]).exp()`, and
//!   the Beckmann formula with one `expf` per element; scalar.
//!
//! C peers (the JSON's `peers`, issue 13): fastbrdf claims its approximations are cheap, so
//! each lobe's and Beckmann's batch kernel is raced against the C loop a performance-minded
//! user would write (`crates/analysis/c/peer.c`, compiled by `build.rs` with the system C
//! compiler at `-O3 -march=native -ffast-math`, powf/expf/exp2f vectorised through glibc's
//! libmvec where GCC does so). Same process, same inputs and parameters, interleaved round by
//! round (kernel, peer, kernel, peer, ...), each round a batch of 4096 repeated until it is far
//! above the clock's cost; the median and spread of both rates and of the per-round ratio are
//! reported, with both sides' maximum error against the f64 model and the FTZ/DAZ state.
//!
//! Files: [`report`] (a run's rows, loading a saved run, comparing two runs), [`limits`] (the
//! machine's FMA and divider rates, and the fraction of them a kernel uses), [`inputs`] (the
//! aligned benchmark inputs), [`speedups`] (the ratios taken from a run's rows), [`peers`] (the
//! C peers and their race); this file runs the benchmark.

mod inputs;
mod limits;
mod peers;
mod report;
mod speedups;

pub use inputs::{Aligned, Inputs};
pub use limits::{div_per_s, fma_per_s, fma_slots, fma_supported, limit_fraction};
pub use peers::{
    PEER_COMPILER, PEER_FLAGS, PEER_LIBMVEC, Peer, PeerOptions, PeerRow, Spread, accuracy_inputs,
    ftz_daz, ftz_note, max_mixed_error, peer_rows, peers,
};
pub use report::{
    CompareRow, Instructions, KernelRow, Report, SAVED_RUN_LIMIT, SLOWER_BELOW, Skipped,
    SpeedupRow, compare,
};
pub use speedups::speedups;

use fastbrdf::batch::{Input, Isa, Kernel};
use fastbrdf::{Given, Kind, Model, ModelSpec, registry};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// The CPU's model name (Linux /proc/cpuinfo), or "unknown".
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Seconds per call of `f`: the fastest of repeated rounds within `budget`, each round timing
/// enough calls to last at least 20 us.
pub fn time(mut f: impl FnMut(), budget: Duration) -> f64 {
    // Each sample times enough calls to last at least 20 us: a 4096-element call of a cheap
    // kernel takes ~200 ns, and a pair of clock reads 50-120 ns here (issue 13: timing one
    // call per pair understated the cheap kernels by up to a third).
    let repeats = repeats_for(20e-6, timed(1, &mut f));
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut rounds = 0;
    while rounds < 3 || start.elapsed() < budget {
        best = best.min(timed(repeats, &mut f) / repeats as f64);
        rounds += 1;
        if rounds >= 10_000 {
            break;
        }
    }
    best
}

/// Calls per timed sample so that a sample of calls taking `one` seconds each lasts at least
/// `target` seconds (1 to 2^20).
fn repeats_for(target: f64, one: f64) -> usize {
    ((target / one.max(1e-9)).ceil() as usize).clamp(1, 1 << 20)
}

/// Seconds for `repeats` calls of `f` (one clock read each side).
fn timed(repeats: usize, mut f: impl FnMut()) -> f64 {
    let t = Instant::now();
    for _ in 0..repeats {
        f();
    }
    t.elapsed().as_secs_f64()
}

/// Options of a run.
pub struct Options {
    pub quick: bool,
    /// The large batch (16M by default).
    pub large: usize,
    /// Restrict to these model ids (all when empty).
    pub models: Vec<String>,
}

fn scalar_eval(m: &Model<f32>, input: &Input, out: &mut [f32]) {
    match (m, input) {
        (Model::Lobe(l), Input::Cos(x)) => {
            for (o, &c) in out.iter_mut().zip(x.iter()) {
                *o = l.eval(c);
            }
        }
        (Model::Distribution(d), Input::Cos(x)) => {
            for (o, &c) in out.iter_mut().zip(x.iter()) {
                *o = d.eval(c);
            }
        }
        (Model::Fresnel(f), Input::Cos(x)) => {
            for (o, &c) in out.iter_mut().zip(x.iter()) {
                *o = f.f(c);
            }
        }
        (Model::Brdf(b), Input::Dirs(w)) => {
            for (i, o) in out.iter_mut().enumerate() {
                *o = b.eval([w[0][i], w[1][i], w[2][i]], [w[3][i], w[4][i], w[5][i]]);
            }
        }
        (Model::Env(e), Input::Env([v, a])) => {
            for (i, o) in out.iter_mut().enumerate() {
                *o = e.e(v[i], a[i]);
            }
        }
        _ => unreachable!("kinds match their inputs"),
    }
}

/// The configurations measured, each with its name (the rows' `model`): every model at its
/// defaults (lobes at n = 200), and the seed-000 Cook-Torrance (V-cavity, Schlick,
/// denominator (V.N)(L.N)) with each Beckmann form.
pub fn configurations() -> Vec<(String, ModelSpec)> {
    let spec = |id: &str, given: &[(&str, Given)]| {
        ModelSpec::new(id, given).unwrap_or_else(|e| panic!("a benchmark configuration: {e}"))
    };
    let mut v: Vec<(String, ModelSpec)> = registry::all()
        .iter()
        // Shadowing terms take several cosines (no batch kernel); `env-brdf` is a quadrature
        // reference (1152 points per value: 16M values would take minutes), not a shading
        // model: engines read it from a table (`fastbrdf lut`).
        .filter(|e| e.info.kind != Kind::Shadowing && e.info.id != "env-brdf")
        .map(|e| {
            // Lobes at n = 200 (defaults: n = 20 hides nothing, but a sharper lobe is the more
            // common specular case).
            let given: &[(&str, Given)] = if e.info.kind == Kind::Lobe {
                &[("n", Given::Num(200.0))]
            } else {
                &[]
            };
            (e.info.id.to_string(), spec(e.info.id, given))
        })
        .collect();
    let choice = |v: &str| Given::Choice(v.into());
    for d in ["beckmann-ct", "beckmann-pow", "beckmann-power16"] {
        v.push((
            format!("cook-torrance[seed-000,d={d}]"),
            spec(
                "cook-torrance",
                &[
                    ("d", choice(d)),
                    ("g", choice("v-cavity")),
                    ("f", choice("schlick")),
                    ("denominator", choice("seed-000")),
                ],
            ),
        ));
    }
    v
}

/// Longest projected call on the large batch, in seconds, that the run times: a model slower
/// than `large / LARGE_CALL_LIMIT_S` evaluations per second on one thread (a quadrature
/// reference: `sheen-albedo` evaluates 48 x 48 points per value, about 12 k values per second,
/// so 16M values would take 23 minutes per call) gets its 4096-element rows and a
/// [`Skipped`] entry for each large-batch row instead. The slowest shading kernel
/// (`gltf-pbr`, about 2e7 per second) projects well under it at the default batch.
pub const LARGE_CALL_LIMIT_S: f64 = 3.0;

/// The registry id of a configuration name (`cook-torrance[seed-000,d=...]` -> `cook-torrance`).
pub fn registry_id(name: &str) -> &str {
    name.split('[').next().unwrap_or(name)
}

/// Runs the benchmark. `progress(done, total)` is called as it goes.
pub fn run(opts: &Options, progress: &dyn Fn(usize, usize)) -> fastbrdf::Result<Report> {
    let budget = if opts.quick {
        Duration::from_millis(25)
    } else {
        Duration::from_millis(150)
    };
    let isa = Isa::best();
    let fma = fma_per_s(isa, budget * 2).expect("Isa::best() is an instruction set this CPU has");
    let div = div_per_s(isa, budget * 2);
    let small = 4096;
    let small_in = Inputs::new(small);
    let large_in = Inputs::new(opts.large);
    let mut out_small = Aligned::zeroed(small);
    let mut out_large = Aligned::zeroed(opts.large);
    let configs: Vec<_> = configurations()
        .into_iter()
        .filter(|(name, _)| {
            opts.models.is_empty()
                || opts
                    .models
                    .iter()
                    .any(|m| m == registry_id(name) || m == name)
        })
        .collect();
    // The baselines (2 steps), the configurations, then the C peers.
    let total = configs.len() + 3;
    let mut kernels = Vec::new();
    let mut skipped = Vec::new();
    // Naive baselines.
    let n = black_box(200.0f32);
    let t = time(
        || {
            for (o, &c) in out_small.iter_mut().zip(small_in.cos.iter()) {
                *o = c.powf(n);
            }
            black_box(&out_small);
        },
        budget,
    );
    kernels.push(speedups::baseline("powf-loop", t));
    progress(1, total);
    let k = black_box(3.0f32);
    let t = time(
        || {
            for (o, &c) in out_small.iter_mut().zip(small_in.cos.iter()) {
                *o = (-k * c).exp();
            }
            black_box(&out_small);
        },
        budget,
    );
    kernels.push(speedups::baseline("expf-loop", t));
    // The Beckmann formula as a user would write it, one expf per element.
    let (inv_a2, scale) = (
        black_box(1.0f32 / 0.09),
        black_box(1.0f32 / (std::f32::consts::PI * 0.09)),
    );
    let t = time(
        || {
            for (o, &c) in out_small.iter_mut().zip(small_in.cos.iter()) {
                let c2 = c * c;
                *o = if c > 0.0 {
                    scale * (-(1.0 - c2) / c2 * inv_a2).exp() / (c2 * c2)
                } else {
                    0.0
                };
            }
            black_box(&out_small);
        },
        budget,
    );
    kernels.push(speedups::baseline("beckmann-expf-loop", t));
    progress(2, total);
    for (i, (name, spec)) in configs.iter().enumerate() {
        let info = spec.info();
        let kernel = Kernel::new(spec)?;
        let model = spec.model::<f32>()?;
        let slots = fma_slots(info, kernel.isa());
        let frac = |evals: f64| slots.map(|f| evals * f / fma);
        let row = |variant: &str, batch: usize, evals: f64, isa: Isa, fraction: Option<f64>| {
            // The machine's limit is measured on one core: the rows of one thread only.
            let limit = (variant == "simd")
                .then(|| limit_fraction(info, isa, evals, fma, div, kernel.pipe_ops()))
                .flatten();
            KernelRow {
                model: name.clone(),
                variant: variant.into(),
                batch,
                evals_per_s: evals,
                isa: isa.name().into(),
                fma_fraction: fraction,
                limit: limit.map(|l| l.0.into()),
                limit_fraction: limit.map(|l| l.1),
                instructions: None,
            }
        };
        let input = small_in.input(info.kind, small);
        let t = time(|| scalar_eval(&model, &input, &mut out_small), budget);
        kernels.push(row("scalar", small, small as f64 / t, Isa::Scalar, None));
        let t = time(
            || kernel.eval(input, &mut out_small).expect("shapes match"),
            budget,
        );
        let e = small as f64 / t;
        kernels.push(row("simd", small, e, kernel.isa(), frac(e)));
        let projected_s = opts.large as f64 / e;
        if projected_s > LARGE_CALL_LIMIT_S {
            for (variant, s) in [
                ("simd", projected_s),
                (
                    "simd-threads",
                    projected_s / rayon::current_num_threads() as f64,
                ),
            ] {
                skipped.push(Skipped {
                    model: name.clone(),
                    variant: variant.into(),
                    batch: opts.large,
                    projected_s: s,
                });
            }
            progress(i + 3, total);
            continue;
        }
        let large = large_in.input(info.kind, opts.large);
        let big_budget = if opts.quick { Duration::ZERO } else { budget };
        let t = time(
            || kernel.eval(large, &mut out_large).expect("shapes match"),
            big_budget,
        );
        kernels.push(row(
            "simd",
            opts.large,
            opts.large as f64 / t,
            kernel.isa(),
            None,
        ));
        let t = time(
            || {
                kernel
                    .eval_par(large, &mut out_large)
                    .expect("shapes match")
            },
            big_budget,
        );
        kernels.push(row(
            "simd-threads",
            opts.large,
            opts.large as f64 / t,
            kernel.isa(),
            None,
        ));
        progress(i + 3, total);
    }
    let speedups = speedups(&kernels, small, opts.large);
    let peer_opts = PeerOptions {
        rounds: if opts.quick { 41 } else { 151 },
        round: if opts.quick {
            Duration::from_micros(400)
        } else {
            Duration::from_millis(2)
        },
    };
    let mut peers = peer_rows(&opts.models, &small_in.cos, &peer_opts)?;
    for p in &mut peers {
        let info = &registry::find(&p.model)?.info;
        let isa = Isa::available()
            .iter()
            .copied()
            .find(|i| i.name() == p.isa)
            .unwrap_or(Isa::Scalar);
        // The kernel's own count where its family gives one: the C loop calls libm's or
        // libmvec's exp2f/expf there, whose operations are not the kernel's, so it gets no
        // fraction (the formula's count would understate it).
        let pipe_ops = p.kernel_pipe_ops;
        let limit = limit_fraction(info, isa, p.kernel_evals_per_s.median, fma, div, pipe_ops);
        p.kernel_limit = limit.map(|l| l.0.into());
        p.kernel_limit_fraction = limit.map(|l| l.1);
        p.peer_limit_fraction = if pipe_ops.is_some() {
            None
        } else {
            limit_fraction(info, isa, p.peer_evals_per_s.median, fma, div, None).map(|l| l.1)
        };
    }
    progress(total, total);
    Ok(Report {
        cpu: cpu_name(),
        isa: isa.name().into(),
        threads: rayon::current_num_threads(),
        fma_per_s: fma,
        div_per_s: div,
        kernels,
        speedups,
        quick: opts.quick,
        gpu: None,
        peers,
        skipped,
    })
}
