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

use fastbrdf::accuracy::splitmix;
use fastbrdf::batch::{Input, Isa, Kernel};
use fastbrdf::{Kind, Model, registry};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// One throughput figure.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KernelRow {
    pub model: String,
    pub variant: String,
    pub batch: usize,
    pub evals_per_s: f64,
    /// The instruction set used.
    pub isa: String,
    /// Fraction of the measured FMA-pipe throughput used by the kernel's own multiplies and
    /// adds (registry op counts; Rust does not fuse them, so each takes one FMA-pipe slot).
    pub fma_fraction: Option<f64>,
}

/// One speedup.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SpeedupRow {
    pub name: String,
    pub measured: f64,
    /// The seed's number, when it states one.
    pub claimed: Option<f64>,
    /// How it was measured.
    pub how: String,
}

/// The whole run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub cpu: String,
    pub isa: String,
    pub threads: usize,
    /// Lane FMAs per second on one core with `isa` (independent FMA chains).
    pub fma_per_s: f64,
    pub kernels: Vec<KernelRow>,
    pub speedups: Vec<SpeedupRow>,
    pub quick: bool,
    /// The GPU adapter of `--gpu` rows (variants `gpu`, `gpu+transfer`), with a warning when it
    /// is a software adapter (its figures are CPU figures); absent without `--gpu`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu: Option<String>,
}

/// Largest saved run read (`fastbrdf bench --from`, `pareto --bench`, `reproduce --speedups`).
pub const SAVED_RUN_LIMIT: u64 = 64 << 20;

/// Largest plausible throughput figure (evaluations or lane-FMAs per second): 10^15, far above
/// any machine, so that only impossible numbers are refused.
const MAX_RATE: f64 = 1e15;

impl Report {
    /// Reads a saved `fastbrdf bench --json` run (once, at most [`SAVED_RUN_LIMIT`] bytes) and
    /// checks that every figure is a possible measurement: rates finite, positive and at most
    /// 10^15 per second, speedups finite and positive, at least one thread, batches of at least
    /// one element. The error names the file and the first impossible field.
    pub fn load(path: &std::path::Path) -> Result<Self, fastbrdf_io::IoError> {
        let bad = |message: String| fastbrdf_io::IoError::Input {
            path: path.display().to_string(),
            message,
        };
        let text = fastbrdf_io::read_text_bounded(path, SAVED_RUN_LIMIT, "a bench run")?;
        let r: Report = serde_json::from_str(&text)
            .map_err(|e| bad(format!("not a `fastbrdf bench --json` run: {e}")))?;
        let rate = |x: f64| x.is_finite() && x > 0.0 && x <= MAX_RATE;
        if !rate(r.fma_per_s) {
            return Err(bad(format!(
                "fma_per_s = {} is not a possible rate (finite, positive, at most 1e15)",
                r.fma_per_s
            )));
        }
        if r.threads == 0 {
            return Err(bad("threads = 0: a run has at least one thread".into()));
        }
        for (i, k) in r.kernels.iter().enumerate() {
            if !rate(k.evals_per_s) || k.batch == 0 {
                return Err(bad(format!(
                    "kernels[{i}] ({} {}): evals_per_s = {} with batch {} is not a possible measurement",
                    k.model, k.variant, k.evals_per_s, k.batch
                )));
            }
            if let Some(f) = k.fma_fraction.filter(|f| !(f.is_finite() && *f >= 0.0)) {
                return Err(bad(format!(
                    "kernels[{i}] ({}): fma_fraction = {f} is not a fraction",
                    k.model
                )));
            }
        }
        for (i, s) in r.speedups.iter().enumerate() {
            let ok = |x: f64| x.is_finite() && x > 0.0;
            if !ok(s.measured) || s.claimed.is_some_and(|c| !ok(c)) {
                return Err(bad(format!(
                    "speedups[{i}] ({}): a speedup is a finite positive ratio",
                    s.name
                )));
            }
        }
        Ok(r)
    }

    /// Every speedup of the run as `(name, measured)`, as [`crate::reproduce::run`] takes them.
    pub fn measured_speedups(&self) -> Vec<(String, f64)> {
        self.speedups
            .iter()
            .map(|s| (s.name.clone(), s.measured))
            .collect()
    }
}

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

/// Seconds per call of `f`: the fastest of repeated rounds within `budget`.
pub fn time(mut f: impl FnMut(), budget: Duration) -> f64 {
    f();
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut rounds = 0;
    while rounds < 3 || start.elapsed() < budget {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed().as_secs_f64());
        rounds += 1;
        if rounds >= 10_000 {
            break;
        }
    }
    best
}

// ---------- FMA peak ----------

const ACC: usize = 256;

#[inline(always)]
fn fma_body(iters: usize, a: f32, b: f32) -> f32 {
    let mut acc = [0.0f32; ACC];
    for (i, x) in acc.iter_mut().enumerate() {
        *x = i as f32 * 1e-3;
    }
    for _ in 0..iters {
        for x in acc.iter_mut() {
            *x = x.mul_add(a, b);
        }
    }
    acc.iter().sum()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,fma")]
unsafe fn fma_avx512(iters: usize, a: f32, b: f32) -> f32 {
    fma_body(iters, a, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fma_avx2(iters: usize, a: f32, b: f32) -> f32 {
    fma_body(iters, a, b)
}

/// Whether this CPU has every feature the FMA loop for `isa` is compiled with (the
/// `#[target_feature]` sets of `fma_avx512` and `fma_avx2`); the SSE2 and scalar loops need
/// nothing beyond the target's baseline.
pub fn fma_supported(isa: Isa) -> bool {
    match isa {
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => {
            std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512vl")
                && std::is_x86_feature_detected!("fma")
        }
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2Fma => {
            std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        Isa::Avx512 | Isa::Avx2Fma => false,
        Isa::Sse2 | Isa::Scalar => true,
    }
}

/// Lane FMAs per second on one core with `isa` (256 independent accumulators, so the FMA
/// pipes, not their latency, limit it). Without FMA (SSE2) it counts a multiply-add pair
/// as one. `None` when this CPU lacks `isa` ([`fma_supported`]): the loop is never run
/// with instructions the CPU does not have.
pub fn fma_per_s(isa: Isa, budget: Duration) -> Option<f64> {
    if !fma_supported(isa) {
        return None;
    }
    let iters = 20_000;
    let (a, b) = (black_box(0.999_9f32), black_box(1e-4f32));
    let secs = time(
        || {
            let r = match isa {
                // SAFETY: `fma_supported(isa)` checked above that the CPU has avx512f,
                // avx512vl and fma, the features `fma_avx512` is compiled with.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe { fma_avx512(iters, a, b) },
                // SAFETY: `fma_supported(isa)` checked above that the CPU has avx2 and fma.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2Fma => unsafe { fma_avx2(iters, a, b) },
                _ => {
                    let mut acc = [0.0f32; ACC];
                    for _ in 0..iters {
                        for x in acc.iter_mut() {
                            *x = *x * a + b;
                        }
                    }
                    acc.iter().sum()
                }
            };
            black_box(r);
        },
        budget,
    );
    Some((iters * ACC) as f64 / secs)
}

// ---------- inputs ----------

/// Benchmark inputs of one size: cosines uniform in [0, 1] (uniform in solid angle), and
/// direction pairs uniform over the upper hemisphere.
pub struct Inputs {
    pub cos: Vec<f32>,
    pub dirs: [Vec<f32>; 6],
}

impl Inputs {
    /// `n` cosines and `n` direction pairs, deterministic.
    pub fn new(n: usize) -> Self {
        let cos: Vec<f32> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut s = i as u64 * 7 + 1;
                splitmix(&mut s) as f32
            })
            .collect();
        let pairs: Vec<[f32; 6]> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut s = (i as u64) << 20 | 12345;
                let mut dir = || {
                    let z = splitmix(&mut s).max(1e-3);
                    let r = (1.0 - z * z).sqrt();
                    let phi = std::f64::consts::TAU * splitmix(&mut s);
                    [(r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32]
                };
                let (a, b) = (dir(), dir());
                [a[0], a[1], a[2], b[0], b[1], b[2]]
            })
            .collect();
        let dirs = std::array::from_fn(|k| pairs.iter().map(|p| p[k]).collect());
        Self { cos, dirs }
    }

    fn input(&self, kind: Kind, len: usize) -> Input<'_> {
        if kind == Kind::Brdf {
            Input::Dirs(std::array::from_fn(|k| &self.dirs[k][..len]))
        } else {
            Input::Cos(&self.cos[..len])
        }
    }
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
        _ => unreachable!("kinds match their inputs"),
    }
}

/// The configurations measured: every model at its defaults, and the seed-000 Cook-Torrance
/// (V-cavity, Schlick, denominator (V.N)(L.N)) with each Beckmann form.
pub fn configurations() -> Vec<(String, Vec<(String, String)>)> {
    let mut v: Vec<(String, Vec<(String, String)>)> = registry::all()
        .iter()
        .filter(|e| e.info.kind != Kind::Shadowing)
        .map(|e| (e.info.id.to_string(), vec![]))
        .collect();
    // Lobes at n = 200 and distributions at alpha = 0.3 (defaults: n = 20 hides nothing, but a
    // sharper lobe is the more common specular case).
    for (id, p) in v.iter_mut() {
        if registry::find(id).is_ok_and(|e| e.info.kind == Kind::Lobe) {
            p.push(("n".into(), "200".into()));
        }
    }
    for d in ["beckmann-ct", "beckmann-pow", "beckmann-power16"] {
        v.push((
            format!("cook-torrance[seed-000,d={d}]"),
            vec![
                ("d".into(), d.into()),
                ("g".into(), "v-cavity".into()),
                ("f".into(), "schlick".into()),
                ("denominator".into(), "seed-000".into()),
            ],
        ));
    }
    v
}

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
    let small = 4096;
    let small_in = Inputs::new(small);
    let large_in = Inputs::new(opts.large);
    let mut out_small = vec![0.0f32; small];
    let mut out_large = vec![0.0f32; opts.large];
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
    let total = configs.len() + 2;
    let mut kernels = Vec::new();
    // Naive baselines.
    let n = black_box(200.0f32);
    let t = time(
        || {
            for (o, &c) in out_small.iter_mut().zip(&small_in.cos) {
                *o = c.powf(n);
            }
            black_box(&out_small);
        },
        budget,
    );
    kernels.push(baseline("powf-loop", t));
    progress(1, total);
    let k = black_box(3.0f32);
    let t = time(
        || {
            for (o, &c) in out_small.iter_mut().zip(&small_in.cos) {
                *o = (-k * c).exp();
            }
            black_box(&out_small);
        },
        budget,
    );
    kernels.push(baseline("expf-loop", t));
    // The Beckmann formula as a user would write it, one expf per element.
    let (inv_a2, scale) = (
        black_box(1.0f32 / 0.09),
        black_box(1.0f32 / (std::f32::consts::PI * 0.09)),
    );
    let t = time(
        || {
            for (o, &c) in out_small.iter_mut().zip(&small_in.cos) {
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
    kernels.push(baseline("beckmann-expf-loop", t));
    progress(2, total);
    for (i, (name, params)) in configs.iter().enumerate() {
        let id = registry_id(name);
        let given: Vec<(&str, &str)> = params
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect();
        let info = &registry::find(id)?.info;
        let kernel = Kernel::new(id, &given)?;
        let model = registry::build::<f32>(id, &given)?;
        let flops = f64::from(info.ops.mul) + f64::from(info.ops.add);
        let frac = |evals: f64| {
            if kernel.simd() && flops > 0.0 {
                Some(evals * flops / fma)
            } else {
                None
            }
        };
        let row =
            |variant: &str, batch: usize, evals: f64, isa: Isa, fraction: Option<f64>| KernelRow {
                model: name.clone(),
                variant: variant.into(),
                batch,
                evals_per_s: evals,
                isa: isa.name().into(),
                fma_fraction: fraction,
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
    Ok(Report {
        cpu: cpu_name(),
        isa: isa.name().into(),
        threads: rayon::current_num_threads(),
        fma_per_s: fma,
        kernels,
        speedups,
        quick: opts.quick,
        gpu: None,
    })
}

/// A naive scalar baseline's row from its time per 4096-element call.
fn baseline(model: &str, secs: f64) -> KernelRow {
    KernelRow {
        model: model.into(),
        variant: "scalar".into(),
        batch: 4096,
        evals_per_s: 4096.0 / secs,
        isa: "scalar".into(),
        fma_fraction: None,
    }
}

fn find(k: &[KernelRow], model: &str, variant: &str, batch: usize) -> Option<f64> {
    k.iter()
        .find(|r| r.model == model && r.variant == variant && r.batch == batch)
        .map(|r| r.evals_per_s)
}

/// A GPU figure (one batch size per run).
fn find_gpu(k: &[KernelRow], model: &str) -> Option<f64> {
    k.iter()
        .find(|r| r.model == model && r.variant == "gpu")
        .map(|r| r.evals_per_s)
}

/// The speedups of one run: the seed-000 claims, each approximation over its exact reference
/// (SIMD over SIMD, and SIMD over the naive scalar loop), and thread scaling.
pub fn speedups(k: &[KernelRow], small: usize, large: usize) -> Vec<SpeedupRow> {
    let mut v = Vec::new();
    let mut push =
        |name: String, num: Option<f64>, den: Option<f64>, claimed: Option<f64>, how: String| {
            if let (Some(a), Some(b)) = (num, den) {
                v.push(SpeedupRow {
                    name,
                    measured: a / b,
                    claimed,
                    how,
                });
            }
        };
    let ct = |d: &str| format!("cook-torrance[seed-000,d={d}]");
    push(
        "ct.speedup".into(),
        find(k, &ct("beckmann-power16"), "scalar", small),
        find(k, &ct("beckmann-ct"), "scalar", small),
        Some(4.34),
        "scalar f32 Cook-Torrance as seed 000 (V-cavity G, Schlick F, (V.N)(L.N)): D16 over exp-based D, batch 4096".into(),
    );
    push(
        "ct.speedup.simd".into(),
        find(k, &ct("beckmann-power16"), "simd", small),
        find(k, &ct("beckmann-ct"), "simd", small),
        None,
        "the same, SIMD kernels on both sides".into(),
    );
    push(
        "ct.speedup.pow".into(),
        find(k, &ct("beckmann-pow"), "scalar", small),
        find(k, &ct("beckmann-ct"), "scalar", small),
        None,
        "scalar, the one-pow D (cos^(2/m^2-4)) over exp-based D".into(),
    );
    push(
        "ward.speedup".into(),
        find(k, "ward-power16", "scalar", small),
        find(k, "ward", "scalar", small),
        Some(2.0),
        "scalar f32 isotropic Ward: the g = 16 form of the exponential over exp (seed: more than 2)".into(),
    );
    push(
        "ward.speedup.simd".into(),
        find(k, "ward-power16", "simd", small),
        find(k, "ward", "simd", small),
        None,
        "the same, SIMD".into(),
    );
    push(
        "ward.speedup.pow".into(),
        find(k, "ward-pow", "scalar", small),
        find(k, "ward", "scalar", small),
        None,
        "scalar, cos^(2/m^2) over exp".into(),
    );
    for e in registry::all() {
        for b in e.info.bounds.iter().take(1) {
            let id = e.info.id;
            push(
                format!("{id}.over.{}.simd", b.reference),
                find(k, id, "simd", small),
                find(k, b.reference, "simd", small),
                None,
                format!("SIMD {id} over SIMD {}", b.reference),
            );
            if e.info.kind == Kind::Lobe {
                push(
                    format!("{id}.over.powf-loop"),
                    find(k, id, "simd", small),
                    find(k, "powf-loop", "scalar", small),
                    None,
                    format!("SIMD {id} over a scalar powf loop"),
                );
            }
        }
    }
    push(
        "pow.simd.over.powf-loop".into(),
        find(k, "pow", "simd", small),
        find(k, "powf-loop", "scalar", small),
        None,
        "SIMD exact pow over a scalar powf loop".into(),
    );
    push(
        "beckmann.simd.over.beckmann-expf-loop".into(),
        find(k, "beckmann", "simd", small),
        find(k, "beckmann-expf-loop", "scalar", small),
        None,
        "SIMD exact beckmann over the Beckmann formula in a scalar loop with expf".into(),
    );
    push(
        "beckmann.simd.over.expf-loop".into(),
        find(k, "beckmann", "simd", small),
        find(k, "expf-loop", "scalar", small),
        None,
        "SIMD exact beckmann (exp and 12 more operations) over a bare scalar expf loop".into(),
    );
    // GPU rows (`fastbrdf bench --gpu`): the same ratios on the GPU, and GPU over all CPU threads.
    push(
        "ct.speedup.gpu".into(),
        find_gpu(k, &ct("beckmann-power16")),
        find_gpu(k, &ct("beckmann-ct")),
        None,
        "seed 000's Cook-Torrance on the GPU: D16 over exp-based D".into(),
    );
    push(
        "ward.speedup.gpu".into(),
        find_gpu(k, "ward-power16"),
        find_gpu(k, "ward"),
        None,
        "isotropic Ward on the GPU: the g = 16 form over exp".into(),
    );
    for e in registry::all() {
        for b in e.info.bounds.iter().take(1) {
            let id = e.info.id;
            push(
                format!("{id}.over.{}.gpu", b.reference),
                find_gpu(k, id),
                find_gpu(k, b.reference),
                None,
                format!("GPU {id} over GPU {}", b.reference),
            );
        }
    }
    for m in ["pow", "power16", "beckmann", "cook-torrance", "ward"] {
        push(
            format!("{m}.gpu.over.cpu-threads"),
            find_gpu(k, m),
            find(k, m, "simd-threads", large),
            None,
            format!("{m}: GPU (data resident) over SIMD on all CPU threads, batch {large}"),
        );
    }
    for m in ["power16", "pow", "cook-torrance", "ward"] {
        push(
            format!("{m}.threads.scaling"),
            find(k, m, "simd-threads", large),
            find(k, m, "simd", large),
            None,
            format!("{m}: all threads over one thread, batch {large}"),
        );
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `fma_per_s` is safe to call with every instruction set: a positive finite rate for
    /// those this CPU has, `None` (never an illegal instruction) for the others.
    #[test]
    fn fma_per_s_is_safe_for_every_isa() {
        let budget = Duration::from_millis(1);
        for isa in [Isa::Avx512, Isa::Avx2Fma, Isa::Sse2, Isa::Scalar] {
            let rate = fma_per_s(isa, budget);
            assert_eq!(rate.is_some(), fma_supported(isa), "{isa:?}");
            if let Some(r) = rate {
                assert!(r.is_finite() && r > 0.0, "{isa:?}: {r}");
            }
        }
        // The instruction set the benchmark picks is always measurable.
        assert!(fma_per_s(Isa::best(), budget).is_some());
        assert!(fma_supported(Isa::Sse2) && fma_supported(Isa::Scalar));
    }

    #[test]
    fn measured_speedups_keep_the_run_order() {
        let kernels = vec![
            baseline("powf-loop", 4096.0 / 1e8),
            KernelRow {
                model: "pow".into(),
                variant: "simd".into(),
                batch: 4096,
                evals_per_s: 4e8,
                isa: "avx2".into(),
                fma_fraction: None,
            },
        ];
        let r = Report {
            cpu: "test".into(),
            isa: "avx2".into(),
            threads: 1,
            fma_per_s: 1e10,
            speedups: speedups(&kernels, 4096, 1 << 24),
            kernels,
            quick: true,
            gpu: None,
        };
        let pairs = r.measured_speedups();
        assert_eq!(pairs.len(), r.speedups.len());
        let (name, v) = pairs
            .iter()
            .find(|(n, _)| n == "pow.simd.over.powf-loop")
            .expect("the pow speedup is computed");
        assert_eq!(name, "pow.simd.over.powf-loop");
        assert!((v - 4.0).abs() < 1e-12, "{v}");
    }
}
