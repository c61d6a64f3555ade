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

use fastbrdf::accuracy::splitmix;
use fastbrdf::batch::{Input, Isa, Kernel};
use fastbrdf::{Kind, Model, PipeOps, registry};
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
    /// Fraction of the measured FMA-pipe throughput used by the formula's own multiplies and
    /// adds (`fma_slots`): only for kernels of cosines whose formula is multiplies and adds
    /// alone (no division, square root or transcendental, whose cost the registry's counts do
    /// not measure); `null` otherwise.
    pub fma_fraction: Option<f64>,
    /// The machine limit that bounds this kernel, `"fma"` (the FMA pipes) or `"divider"`
    /// (the divide unit), with the fraction of it used ([`limit_fraction`]): for kernels of
    /// cosines whose formula is multiplies, adds and divisions, and for those whose family
    /// counts its kernel's operations (`Kernel::pipe_ops`: `sg`, `ue4-phong-approx`,
    /// `sg-tuned`, `beckmann`, `beckmann-ct`, whose vectorised `exp2` is a polynomial the
    /// registry's counts do not see); `null` otherwise. Absent from runs saved before it
    /// existed.
    #[serde(default)]
    pub limit: Option<String>,
    #[serde(default)]
    pub limit_fraction: Option<f64>,
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
    /// Lane divisions per second on one core with `isa` (independent division chains);
    /// absent from runs saved before it was measured.
    #[serde(default)]
    pub div_per_s: Option<f64>,
    pub kernels: Vec<KernelRow>,
    pub speedups: Vec<SpeedupRow>,
    pub quick: bool,
    /// The GPU adapter of `--gpu` rows (variants `gpu`, `gpu+transfer`), with a warning when it
    /// is a software adapter (its figures are CPU figures); absent without `--gpu`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu: Option<String>,
    /// Each batch kernel raced against its C peer (absent from runs saved before issue 13,
    /// which load with none).
    #[serde(default)]
    pub peers: Vec<PeerRow>,
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
        if let Some(d) = r.div_per_s.filter(|&d| !rate(d)) {
            return Err(bad(format!(
                "div_per_s = {d} is not a possible rate (finite, positive, at most 1e15)"
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
            let fractions = [
                ("fma_fraction", k.fma_fraction),
                ("limit_fraction", k.limit_fraction),
            ];
            for (name, f) in fractions {
                if let Some(f) = f.filter(|f| !(f.is_finite() && *f >= 0.0)) {
                    return Err(bad(format!(
                        "kernels[{i}] ({}): {name} = {f} is not a fraction",
                        k.model
                    )));
                }
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
        for (i, p) in r.peers.iter().enumerate() {
            let spreads = [&p.kernel_evals_per_s, &p.peer_evals_per_s];
            let rates_ok = spreads.iter().all(|s| s.values().into_iter().all(rate));
            let ratio_ok = p
                .ratio
                .values()
                .into_iter()
                .all(|x| x.is_finite() && x > 0.0);
            let err_ok = |e: f64| e.is_finite() && e >= 0.0;
            if !rates_ok || !ratio_ok || p.batch == 0 || p.rounds == 0 || p.repeats == 0 {
                return Err(bad(format!(
                    "peers[{i}] ({}): rates, ratio, batch, rounds and repeats must be possible measurements",
                    p.model
                )));
            }
            if !err_ok(p.kernel_max_error) || !err_ok(p.peer_max_error) {
                return Err(bad(format!(
                    "peers[{i}] ({}): an error is finite and non-negative",
                    p.model
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

// ---------- FMA peak ----------

const ACC: usize = 256;

/// `ACC` independent chains of `iters` steps each: `x a + b` fused (`DIV` false), or `x / a`
/// (`DIV` true; `a` near 1 keeps every value normal).
#[inline(always)]
fn peak_body<const DIV: bool>(iters: usize, a: f32, b: f32) -> f32 {
    let mut acc = [0.0f32; ACC];
    for (i, x) in acc.iter_mut().enumerate() {
        *x = if DIV { 1.0 } else { 0.0 } + i as f32 * 1e-3;
    }
    for _ in 0..iters {
        for x in acc.iter_mut() {
            *x = if DIV { *x / a } else { x.mul_add(a, b) };
        }
    }
    acc.iter().sum()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,fma")]
unsafe fn fma_avx512<const DIV: bool>(iters: usize, a: f32, b: f32) -> f32 {
    peak_body::<DIV>(iters, a, b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fma_avx2<const DIV: bool>(iters: usize, a: f32, b: f32) -> f32 {
    peak_body::<DIV>(iters, a, b)
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
    peak_per_s::<false>(isa, budget, (0.999_9, 1e-4))
}

/// Lane divisions per second on one core with `isa`: the divide unit's throughput (256
/// independent chains of `x / a`, so its latency does not enter), the limit of the kernels
/// whose formula divides (`schlick`, `rational`, GGX's D). `None` as [`fma_per_s`].
pub fn div_per_s(isa: Isa, budget: Duration) -> Option<f64> {
    peak_per_s::<true>(isa, budget, (1.000_1, 0.0))
}

fn peak_per_s<const DIV: bool>(isa: Isa, budget: Duration, (a, b): (f32, f32)) -> Option<f64> {
    if !fma_supported(isa) {
        return None;
    }
    let iters = if DIV { 4_000 } else { 20_000 };
    let (a, b) = (black_box(a), black_box(b));
    let secs = time(
        || {
            let r = match isa {
                // SAFETY: `fma_supported(isa)` checked above that the CPU has avx512f,
                // avx512vl and fma, the features `fma_avx512` is compiled with.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe { fma_avx512::<DIV>(iters, a, b) },
                // SAFETY: `fma_supported(isa)` checked above that the CPU has avx2 and fma.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2Fma => unsafe { fma_avx2::<DIV>(iters, a, b) },
                _ => {
                    let mut acc = [1.0f32; ACC];
                    for _ in 0..iters {
                        for x in acc.iter_mut() {
                            *x = if DIV { *x / a } else { *x * a + b };
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

/// FMA-pipe slots per evaluation of a kernel of cosines whose formula is multiplies and adds
/// only (registry counts): `max(mul, add)` where the instruction set fuses them (each add
/// rides on a multiply), `mul + add` otherwise. `None` for BRDFs (their counts leave out the
/// pair set-up), for formulas with a division, square root or transcendental (the divider or
/// a polynomial of ~10-40 operations bounds those, not this count: issue 13 found `sg`
/// counted as 2 operations where it executes about 26), and for scalar fallbacks.
pub fn fma_slots(info: &fastbrdf::ModelInfo, isa: Isa) -> Option<f64> {
    let o = info.ops;
    let simple = o.div == 0 && o.sqrt == 0 && o.transcendental == 0;
    if info.kind == Kind::Brdf || !simple || isa == Isa::Scalar {
        return None;
    }
    let (m, a) = (f64::from(o.mul), f64::from(o.add));
    let slots = if isa.fma() { m.max(a) } else { m + a };
    (slots > 0.0).then_some(slots)
}

/// The machine limit a kernel of cosines is measured against, and the fraction of it that
/// `evals_per_s` evaluations use: the FMA pipes or the divider (`div` lane divisions per
/// evaluation, against `div_per_s`), whichever the kernel uses more of. The count is the
/// kernel's own where its family gives one (`kernel`, from `Kernel::pipe_ops`: its
/// multiply-pipe operations, a vectorised `exp2`'s polynomial included), else the formula's
/// (`max(mul, add)` slots per evaluation where the instruction set fuses, `mul + add`
/// otherwise). `None` for BRDFs, uncounted formulas with a square root or transcendental,
/// scalar fallbacks, and where the divider's rate is unknown but needed.
pub fn limit_fraction(
    info: &fastbrdf::ModelInfo,
    isa: Isa,
    evals_per_s: f64,
    fma_per_s: f64,
    div_per_s: Option<f64>,
    kernel: Option<PipeOps>,
) -> Option<(&'static str, f64)> {
    let o = info.ops;
    if info.kind == Kind::Brdf || isa == Isa::Scalar {
        return None;
    }
    let (slots, divs) = match kernel {
        Some(k) if isa.fma() => (f64::from(k.mul), k.div),
        _ if o.sqrt != 0 || o.transcendental != 0 => return None,
        _ => {
            let (m, a) = (f64::from(o.mul), f64::from(o.add));
            (if isa.fma() { m.max(a) } else { m + a }, o.div)
        }
    };
    let fma = evals_per_s * slots / fma_per_s;
    if divs == 0 {
        return (slots > 0.0).then_some(("fma", fma));
    }
    let div = evals_per_s * f64::from(divs) / div_per_s?;
    Some(if div >= fma {
        ("divider", div)
    } else {
        ("fma", fma)
    })
}

/// Below this ratio of a kernel's rate to a saved run's, `fastbrdf bench --compare` marks the
/// row `slower`: this shared 2-core machine moves a kernel by 10-20% between runs, while the
/// regressions this is for were 2-10x (the Cook-Torrance kernels ran 6-10x slower for a day of
/// commits before anyone compared the tables).
pub const SLOWER_BELOW: f64 = 0.8;

/// One kernel row of two runs: `ratio = new / old` evaluations per second.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CompareRow {
    pub model: String,
    pub variant: String,
    pub batch: usize,
    pub old_evals_per_s: f64,
    pub new_evals_per_s: f64,
    pub ratio: f64,
    /// `ratio < SLOWER_BELOW`.
    pub slower: bool,
}

/// The kernel rows `new` shares with `old` (same model, variant and batch), in `new`'s order.
pub fn compare(old: &Report, new: &Report) -> Vec<CompareRow> {
    new.kernels
        .iter()
        .filter_map(|k| {
            let o = old
                .kernels
                .iter()
                .find(|o| o.model == k.model && o.variant == k.variant && o.batch == k.batch)?;
            let ratio = k.evals_per_s / o.evals_per_s;
            Some(CompareRow {
                model: k.model.clone(),
                variant: k.variant.clone(),
                batch: k.batch,
                old_evals_per_s: o.evals_per_s,
                new_evals_per_s: k.evals_per_s,
                ratio,
                slower: ratio < SLOWER_BELOW,
            })
        })
        .collect()
}

// ---------- inputs ----------

/// `len` floats starting on a 64-byte boundary (a cache line, one AVX-512 vector). Every
/// timed loop reads and writes these: where a buffer starts decides whether each vector load
/// and store straddles two cache lines, and with a `Vec` of its own per side (16-byte
/// aligned by the allocator) the C peers' `cubic` and `schlick` rates moved by up to 40%
/// from one run to the next (issue 13). Written by hand: `Vec::as_ptr().align_offset` and
/// a slice are all it takes (no unsafe code).
pub struct Aligned {
    buf: Vec<f32>,
    off: usize,
    len: usize,
}

impl Aligned {
    /// `len` zeros.
    pub fn zeroed(len: usize) -> Self {
        let buf = vec![0.0f32; len + 15];
        // `align_offset` may decline (usize::MAX): the buffer is then merely unaligned, which
        // costs speed, not correctness.
        let off = match buf.as_ptr().align_offset(64) {
            o if o < 16 => o,
            _ => 0,
        };
        Self { buf, off, len }
    }

    /// A copy of `v`.
    pub fn from_slice(v: &[f32]) -> Self {
        let mut a = Self::zeroed(v.len());
        a.copy_from_slice(v);
        a
    }
}

impl std::ops::Deref for Aligned {
    type Target = [f32];
    fn deref(&self) -> &[f32] {
        &self.buf[self.off..self.off + self.len]
    }
}

impl std::ops::DerefMut for Aligned {
    fn deref_mut(&mut self) -> &mut [f32] {
        &mut self.buf[self.off..self.off + self.len]
    }
}

/// Benchmark inputs of one size: cosines uniform in [0, 1] (uniform in solid angle),
/// direction pairs uniform over the upper hemisphere, and roughnesses `alpha` uniform in
/// [0.005, 1] (the split-sum terms' second input, beside `cos`).
pub struct Inputs {
    pub cos: Aligned,
    pub dirs: [Aligned; 6],
    pub alpha: Aligned,
}

impl Inputs {
    /// `n` cosines and `n` direction pairs, deterministic.
    pub fn new(n: usize) -> Self {
        // Each column is written in place into its aligned buffer (no Vec to copy from: the
        // large batch is 16M elements a column).
        let fill = |f: &(dyn Fn(usize) -> f32 + Sync)| {
            let mut a = Aligned::zeroed(n);
            a.par_iter_mut().enumerate().for_each(|(i, o)| *o = f(i));
            a
        };
        let cos = fill(&|i| {
            let mut s = i as u64 * 7 + 1;
            splitmix(&mut s) as f32
        });
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
        let dirs = std::array::from_fn(|k| fill(&|i| pairs[i][k]));
        let alpha = fill(&|i| {
            let mut s = i as u64 * 13 + 5;
            (0.005 + 0.995 * splitmix(&mut s)) as f32
        });
        Self { cos, dirs, alpha }
    }

    /// The batch input of a model of `kind`: its first `len` elements.
    pub fn input(&self, kind: Kind, len: usize) -> Input<'_> {
        match kind {
            Kind::Brdf => Input::Dirs(std::array::from_fn(|k| &self.dirs[k][..len])),
            Kind::Env => Input::Env([&self.cos[..len], &self.alpha[..len]]),
            _ => Input::Cos(&self.cos[..len]),
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
        (Model::Env(e), Input::Env([v, a])) => {
            for (i, o) in out.iter_mut().enumerate() {
                *o = e.e(v[i], a[i]);
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
        // Shadowing terms take several cosines (no batch kernel); `env-brdf` is a quadrature
        // reference (1152 points per value: 16M values would take minutes), not a shading
        // model: engines read it from a table (`fastbrdf lut`).
        .filter(|e| e.info.kind != Kind::Shadowing && e.info.id != "env-brdf")
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
    kernels.push(baseline("powf-loop", t));
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
    kernels.push(baseline("expf-loop", t));
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
        limit: None,
        limit_fraction: None,
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

// ---------- C peers (issue 13) ----------

/// The system C compiler that built `c/peer.c` (its `--version` line).
pub const PEER_COMPILER: &str = env!("FASTBRDF_PEER_CC");
/// The flags `c/peer.c` was compiled with (`-O3 -march=native -ffast-math`, or the fallback
/// without `-march=native`, which says so).
pub const PEER_FLAGS: &str = env!("FASTBRDF_PEER_FLAGS");
/// Whether the compiler vectorised libm calls into glibc's libmvec (then linked).
pub const PEER_LIBMVEC: bool = matches!(env!("FASTBRDF_PEER_LIBMVEC").as_bytes(), b"yes");

mod ffi {
    // The loops of `crates/analysis/c/peer.c`: each reads `n` floats from `x` and writes `n`
    // floats to `out`, nothing else.
    unsafe extern "C" {
        pub fn peer_pow(x: *const f32, out: *mut f32, n: usize, e: f32);
        pub fn peer_sg(x: *const f32, out: *mut f32, n: usize, rate: f32);
        pub fn peer_power4(x: *const f32, out: *mut f32, n: usize, k: f32);
        pub fn peer_power8(x: *const f32, out: *mut f32, n: usize, k: f32);
        pub fn peer_power16(x: *const f32, out: *mut f32, n: usize, k: f32);
        pub fn peer_cubic(x: *const f32, out: *mut f32, n: usize, a: f32, b: f32, d: f32, cut: f32);
        pub fn peer_schlick(x: *const f32, out: *mut f32, n: usize, e: f32);
        pub fn peer_beckmann(x: *const f32, out: *mut f32, n: usize, inv_a2: f32, scale: f32);
        pub fn peer_ggx(x: *const f32, out: *mut f32, n: usize, a2m1: f32, scale: f32);
    }
}

/// A C peer's parameters, computed once in f64 from the model's parameters and rounded to f32,
/// as a user would hoist them out of the loop.
#[derive(Clone, Copy, Debug)]
enum PeerFn {
    /// `powf(c, n)`, unclamped: where `c^n` underflows (c < 0.645 at n = 200) libmvec's
    /// powf falls back to scalar calls, and that is part of the measurement.
    Pow(f32),
    /// `exp2f(max(-126, rate (c - 1)))`, `rate = n / ln 2` (clamped like Beckmann's exponent,
    /// so libmvec's underflow fallback is not what is measured).
    Sg(f32),
    /// `max(0, 1 + k (c - 1))^(2^squarings)`, `k = n / g`.
    Power { squarings: u32, k: f32 },
    /// Seed 003's monomial form `a c^3 + b c^2 + d c`, clipped below `cut` and where negative.
    Cubic { a: f32, b: f32, d: f32, cut: f32 },
    /// `c / (n - n c + c)`.
    Schlick(f32),
    /// `scale expf(max(-87, -tan^2 inv_a2)) / cos^4`.
    Beckmann { inv_a2: f32, scale: f32 },
    /// `scale / ((alpha^2 - 1) c^2 + 1)^2`, `scale = alpha^2 / pi`, 0 for `c <= 0`.
    Ggx { a2m1: f32, scale: f32 },
}

/// One C peer: the model it stands in for (id and parameters) and its loop.
#[derive(Clone, Debug)]
pub struct Peer {
    pub id: &'static str,
    pub params: Vec<(String, String)>,
    /// The C function's name.
    pub function: &'static str,
    f: PeerFn,
}

impl Peer {
    /// The peer of `id` (`pow`, `sg`, `power4`, `power8`, `power16`, `cubic`, `schlick`: at
    /// `n`; `beckmann`, `ggx`: at `alpha`), `None` for a model without one.
    pub fn new(id: &str, param: f64) -> Option<Self> {
        let n = param;
        let (id, function, name, f) = match id {
            "pow" => ("pow", "peer_pow", "n", PeerFn::Pow(n as f32)),
            "sg" => (
                "sg",
                "peer_sg",
                "n",
                PeerFn::Sg((n / std::f64::consts::LN_2) as f32),
            ),
            "power4" => ("power4", "peer_power4", "n", power(2, n)),
            "power8" => ("power8", "peer_power8", "n", power(3, n)),
            "power16" => ("power16", "peer_power16", "n", power(4, n)),
            "cubic" => {
                // Seed 003's closed forms, q = 0.5^(1/n) (as the library takes it), in f64.
                let q = 0.5f64.powf(1.0 / n);
                let den = 2.0 * (q - 1.0) * (q - 1.0) * q * q;
                let a = ((q - 1.0) * (2.0 * q + n) + 1.0) / den;
                let b = -(q * q * (4.0 * q - 3.0) + n * (q * q - 1.0) + 1.0) / den;
                let cut = fastbrdf::lobes::cubic::CubicShape::hermite(n).cut;
                let f = PeerFn::Cubic {
                    a: a as f32,
                    b: b as f32,
                    d: (1.0 - a - b) as f32,
                    cut: cut as f32,
                };
                ("cubic", "peer_cubic", "n", f)
            }
            "schlick" => ("schlick", "peer_schlick", "n", PeerFn::Schlick(n as f32)),
            "beckmann" => {
                let a2 = param * param;
                let f = PeerFn::Beckmann {
                    inv_a2: (1.0 / a2) as f32,
                    scale: (1.0 / (std::f64::consts::PI * a2)) as f32,
                };
                ("beckmann", "peer_beckmann", "alpha", f)
            }
            "ggx" => {
                let a2 = param * param;
                let f = PeerFn::Ggx {
                    a2m1: (a2 - 1.0) as f32,
                    scale: (a2 / std::f64::consts::PI) as f32,
                };
                ("ggx", "peer_ggx", "alpha", f)
            }
            _ => return None,
        };
        Some(Self {
            id,
            params: vec![(name.into(), format!("{param}"))],
            function,
            f,
        })
    }

    /// The model's parameters as `Kernel::new` and `registry::build` take them.
    pub fn given(&self) -> Vec<(&str, &str)> {
        self.params
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect()
    }

    /// The model's parameters as `name=value` (the CLI's form).
    pub fn params_text(&self) -> String {
        self.params
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(",")
    }

    /// Runs the C loop over `x` into `out`.
    ///
    /// # Panics
    /// When the lengths differ.
    pub fn eval(&self, x: &[f32], out: &mut [f32]) {
        assert_eq!(x.len(), out.len(), "peer input and output lengths differ");
        let (x, o, n) = (x.as_ptr(), out.as_mut_ptr(), x.len());
        // SAFETY: every peer reads exactly `n` floats from `x` and writes exactly `n` floats to
        // `out` (c/peer.c), and both slices hold `n` elements (asserted above); the slices
        // cannot overlap (one is borrowed shared, the other mutably). The loops touch no other
        // memory and keep no pointer.
        unsafe {
            match self.f {
                PeerFn::Pow(e) => ffi::peer_pow(x, o, n, e),
                PeerFn::Sg(r) => ffi::peer_sg(x, o, n, r),
                PeerFn::Power { squarings: 2, k } => ffi::peer_power4(x, o, n, k),
                PeerFn::Power { squarings: 3, k } => ffi::peer_power8(x, o, n, k),
                PeerFn::Power { k, .. } => ffi::peer_power16(x, o, n, k),
                PeerFn::Cubic { a, b, d, cut } => ffi::peer_cubic(x, o, n, a, b, d, cut),
                PeerFn::Schlick(e) => ffi::peer_schlick(x, o, n, e),
                PeerFn::Beckmann { inv_a2, scale } => ffi::peer_beckmann(x, o, n, inv_a2, scale),
                PeerFn::Ggx { a2m1, scale } => ffi::peer_ggx(x, o, n, a2m1, scale),
            }
        }
    }
}

fn power(squarings: u32, n: f64) -> PeerFn {
    PeerFn::Power {
        squarings,
        k: (n / f64::from(1u32 << squarings)) as f32,
    }
}

/// The peers the benchmark races: the lobes at n = 200 (as the kernel rows), Beckmann and GGX
/// at alpha = 0.3.
pub fn peers() -> Vec<Peer> {
    let lobes = [
        "pow", "sg", "power4", "power8", "power16", "cubic", "schlick",
    ];
    let mut v: Vec<Peer> = lobes
        .iter()
        .map(|id| Peer::new(id, 200.0).expect("a peer exists"))
        .collect();
    v.push(Peer::new("beckmann", 0.3).expect("a peer exists"));
    v.push(Peer::new("ggx", 0.3).expect("a peer exists"));
    v
}

/// The process's flush-to-zero and denormals-are-zero flags (MXCSR bits 15 and 6); `None`
/// off x86-64.
pub fn ftz_daz() -> Option<(bool, bool)> {
    #[cfg(target_arch = "x86_64")]
    {
        // `_mm_getcsr` is deprecated in favour of inline assembly because *setting* MXCSR
        // behind the compiler's back is undefined; reading it is what this needs.
        #[allow(deprecated)]
        // SAFETY: `_mm_getcsr` only reads the MXCSR register (stmxcsr), which SSE (part of the
        // x86-64 baseline, so always present) provides; it changes no state.
        let csr = unsafe { std::arch::x86_64::_mm_getcsr() };
        Some((csr & 0x8000 != 0, csr & 0x0040 != 0))
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        None
    }
}

/// What the FTZ/DAZ state means for the peers, in words.
pub fn ftz_note(state: Option<(bool, bool)>) -> String {
    match state {
        Some((ftz, daz)) => format!(
            "FTZ {}, DAZ {} in this process (MXCSR, read at run time). The C peers are a static library compiled with -ffast-math: that sets no flag (only linking an executable with -ffast-math adds GCC's crtfastmath.o, which sets FTZ/DAZ at start-up), so the kernels and the peers both run with the state read here{}",
            if ftz { "on" } else { "off" },
            if daz { "on" } else { "off" },
            if ftz || daz {
                ""
            } else {
                "; subnormal results (e.g. pow's tail) are computed in full on both sides"
            }
        ),
        None => "FTZ/DAZ unknown (not x86-64)".into(),
    }
}

/// Median and spread of repeated measurements.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Spread {
    pub median: f64,
    /// First and third quartiles.
    pub q1: f64,
    pub q3: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// The summary of `xs` (quartiles by linear interpolation). `xs` must not be empty.
    pub fn of(xs: &[f64]) -> Self {
        let mut v = xs.to_vec();
        v.sort_by(f64::total_cmp);
        let q = |p: f64| {
            let t = p * (v.len() - 1) as f64;
            let (i, f) = (t.floor() as usize, t.fract());
            if i + 1 < v.len() {
                v[i] + f * (v[i + 1] - v[i])
            } else {
                v[i]
            }
        };
        Self {
            median: q(0.5),
            q1: q(0.25),
            q3: q(0.75),
            min: v[0],
            max: v[v.len() - 1],
        }
    }

    fn values(&self) -> [f64; 5] {
        [self.median, self.q1, self.q3, self.min, self.max]
    }
}

/// A batch kernel against its C peer, from the same rounds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PeerRow {
    pub model: String,
    /// `name=value` (the CLI's form).
    pub params: String,
    /// Elements per call.
    pub batch: usize,
    /// Calls per timed round (one clock read each side of them).
    pub repeats: usize,
    /// Rounds, each timing the kernel then the peer.
    pub rounds: usize,
    /// The kernel's instruction set.
    pub isa: String,
    pub kernel_evals_per_s: Spread,
    pub peer_evals_per_s: Spread,
    /// Kernel rate over peer rate, per round.
    pub ratio: Spread,
    /// Max of `|v - v64| / max(1, |v64|)` against the f64 model, over the benchmark's inputs
    /// and a grid of 65537 cosines.
    pub kernel_max_error: f64,
    pub peer_max_error: f64,
    /// The C function.
    pub peer: String,
    pub compiler: String,
    pub flags: String,
    /// Whether powf/expf/exp2f calls went to glibc's vector library.
    pub libmvec: bool,
    /// MXCSR's flush-to-zero and denormals-are-zero bits (absent off x86-64).
    pub ftz: Option<bool>,
    pub daz: Option<bool>,
    /// The machine limit of the kernel's median rate, as `KernelRow::limit` (absent from runs
    /// saved before it existed).
    #[serde(default)]
    pub kernel_limit: Option<String>,
    #[serde(default)]
    pub kernel_limit_fraction: Option<f64>,
    /// The C loop's median rate against the same limit, counted with the model's own
    /// operations (what the same arithmetic at the C loop's rate would use): how close the
    /// peer is to the bound the kernel is held to.
    #[serde(default)]
    pub peer_limit_fraction: Option<f64>,
    /// The kernel's own operation count where its family gives one (`Kernel::pipe_ops`),
    /// read when the race builds the kernel; not saved (the limit fields carry its use).
    #[serde(skip)]
    pub kernel_pipe_ops: Option<PipeOps>,
}

/// How long the race runs.
pub struct PeerOptions {
    pub rounds: usize,
    /// Target duration of one side of one round.
    pub round: Duration,
}

/// Max mixed error `|v - v64| / max(1, |v64|)` of `f` over `xs` against the f64 model.
pub fn max_mixed_error(m64: &Model<f64>, xs: &[f32], f: impl FnOnce(&[f32], &mut [f32])) -> f64 {
    let mut out = vec![0.0f32; xs.len()];
    f(xs, &mut out);
    xs.iter()
        .zip(&out)
        .map(|(&c, &v)| {
            let r = match m64 {
                Model::Lobe(l) => l.eval(f64::from(c)),
                Model::Distribution(d) => d.eval(f64::from(c)),
                _ => unreachable!("peers stand in for lobes and distributions"),
            };
            let e = (f64::from(v) - r).abs() / r.abs().max(1.0);
            // A non-finite value is the worst error there is.
            if e.is_nan() { f64::INFINITY } else { e }
        })
        .fold(0.0, f64::max)
}

/// The inputs accuracy is measured on: `cos` and 65537 evenly spaced cosines in [0, 1].
pub fn accuracy_inputs(cos: &[f32]) -> Vec<f32> {
    let grid = (0..=65536).map(|i| (f64::from(i) / 65536.0) as f32);
    cos.iter().copied().chain(grid).collect()
}

/// Seconds for `repeats` calls of `f` (one clock read each side).
fn timed(repeats: usize, mut f: impl FnMut()) -> f64 {
    let t = Instant::now();
    for _ in 0..repeats {
        f();
    }
    t.elapsed().as_secs_f64()
}

/// Races every peer of `models` (all when empty) against its kernel on `cos` (4096 cosines).
pub fn peer_rows(
    models: &[String],
    cos: &[f32],
    opts: &PeerOptions,
) -> fastbrdf::Result<Vec<PeerRow>> {
    let state = ftz_daz();
    let acc_in = accuracy_inputs(cos);
    let mut rows = Vec::new();
    for peer in peers() {
        if !(models.is_empty() || models.iter().any(|m| m == peer.id)) {
            continue;
        }
        let given = peer.given();
        let kernel = Kernel::new(peer.id, &given)?;
        let m64 = registry::build::<f64>(peer.id, &given)?;
        let kernel_max_error = max_mixed_error(&m64, &acc_in, |x, o| {
            kernel.eval(Input::Cos(x), o).expect("shapes match")
        });
        let peer_max_error = max_mixed_error(&m64, &acc_in, |x, o| peer.eval(x, o));
        // One input and one output buffer, both 64-byte aligned, for both sides: the same
        // addresses, so neither gains from where its allocation happened to land.
        let x = Aligned::from_slice(cos);
        let mut out = Aligned::zeroed(cos.len());
        let run_kernel = |o: &mut [f32]| {
            kernel
                .eval(Input::Cos(black_box(&x)), o)
                .expect("shapes match");
            black_box(o);
        };
        let run_peer = |o: &mut [f32]| {
            peer.eval(black_box(&x), o);
            black_box(o);
        };
        // Warm up, then size a round: enough calls that the slower side takes `opts.round`.
        let one = timed(8, || run_kernel(&mut out)).max(timed(8, || run_peer(&mut out))) / 8.0;
        let repeats = repeats_for(opts.round.as_secs_f64(), one);
        let evals = (repeats * cos.len()) as f64;
        let (mut k, mut p, mut ratio) = (vec![], vec![], vec![]);
        for _ in 0..opts.rounds.max(1) {
            let tk = timed(repeats, || run_kernel(&mut out)).max(1e-12);
            let tp = timed(repeats, || run_peer(&mut out)).max(1e-12);
            k.push(evals / tk);
            p.push(evals / tp);
            ratio.push(tp / tk);
        }
        rows.push(PeerRow {
            model: peer.id.into(),
            params: peer.params_text(),
            batch: cos.len(),
            repeats,
            rounds: opts.rounds.max(1),
            isa: kernel.isa().name().into(),
            kernel_evals_per_s: Spread::of(&k),
            peer_evals_per_s: Spread::of(&p),
            ratio: Spread::of(&ratio),
            kernel_max_error,
            peer_max_error,
            peer: peer.function.into(),
            compiler: PEER_COMPILER.into(),
            flags: PEER_FLAGS.into(),
            libmvec: PEER_LIBMVEC,
            ftz: state.map(|s| s.0),
            daz: state.map(|s| s.1),
            kernel_limit: None,
            kernel_limit_fraction: None,
            peer_limit_fraction: None,
            kernel_pipe_ops: kernel.pipe_ops(),
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aligned_buffers_start_on_a_cache_line_and_hold_their_values() {
        for len in [0usize, 1, 15, 16, 4096, 4097] {
            let v: Vec<f32> = (0..len).map(|i| i as f32 * 0.5).collect();
            let a = Aligned::from_slice(&v);
            assert_eq!(&a[..], &v[..]);
            // `align_offset` may decline in principle (then only speed suffers); on the
            // platforms we build for it does not.
            assert_eq!(a.as_ptr() as usize % 64, 0, "len {len}");
            let mut z = Aligned::zeroed(len);
            assert!(z.iter().all(|x| *x == 0.0) && z.len() == len);
            z.copy_from_slice(&v);
            assert_eq!(&z[..], &v[..]);
        }
    }

    #[test]
    fn fma_slots_count_only_what_the_registry_can_count() {
        let info = |id: &str| fastbrdf::registry::find(id).unwrap().info;
        // power16: 5 mul, 1 add; fused, the add rides on a multiply.
        assert_eq!(fma_slots(&info("power16"), Isa::Avx2Fma), Some(5.0));
        assert_eq!(fma_slots(&info("power16"), Isa::Sse2), Some(6.0));
        // Transcendentals, divisions and BRDFs have no such count.
        for id in ["sg", "pow", "schlick", "ward", "cook-torrance"] {
            assert_eq!(fma_slots(&info(id), Isa::Avx512), None, "{id}");
        }
        assert_eq!(fma_slots(&info("power16"), Isa::Scalar), None);
    }

    /// The limit is the unit the formula's counted operations load more: power16 (5 fused
    /// slots, no division) the FMA pipes; schlick (one division, two fused slots) the divider
    /// unless divisions are nearly as cheap as FMAs; nothing for transcendentals and BRDFs.
    #[test]
    fn limit_fraction_names_the_unit_the_formula_loads_most() {
        let info = |id: &str| fastbrdf::registry::find(id).unwrap().info;
        let (fma, div) = (100e9, 20e9);
        let l = limit_fraction(&info("power16"), Isa::Avx512, 10e9, fma, Some(div), None);
        assert_eq!(l, Some(("fma", 10e9 * 5.0 / fma)));
        let l = limit_fraction(&info("schlick"), Isa::Avx512, 10e9, fma, Some(div), None);
        assert_eq!(l, Some(("divider", 10e9 / div)));
        // Divisions as cheap as a third of an FMA slot: the pipes bound it again.
        let l = limit_fraction(
            &info("schlick"),
            Isa::Avx512,
            10e9,
            fma,
            Some(3.0 * fma),
            None,
        );
        assert_eq!(l.map(|l| l.0), Some("fma"));
        // Without a divider rate a dividing kernel has no stated limit.
        assert_eq!(
            limit_fraction(&info("schlick"), Isa::Avx512, 1e9, fma, None, None),
            None
        );
        for id in ["sg", "pow", "ward", "cook-torrance"] {
            assert_eq!(
                limit_fraction(&info(id), Isa::Avx512, 1e9, fma, Some(div), None),
                None
            );
        }
        assert_eq!(
            limit_fraction(&info("power16"), Isa::Scalar, 1e9, fma, Some(div), None),
            None
        );
    }

    /// A family that counts its kernel (`Kernel::pipe_ops`) is measured with that count on
    /// the FMA instruction sets: sg's exponential is a polynomial the registry's
    /// `1 mul, 1 add, 1 transcendental` cannot see; beckmann's one division against its
    /// eleven multiply-pipe operations picks whichever unit it loads more.
    #[test]
    fn limit_fraction_uses_a_kernels_own_count() {
        let info = |id: &str| fastbrdf::registry::find(id).unwrap().info;
        let (fma, div) = (100e9, 20e9);
        let sg = Some(PipeOps { mul: 7, div: 0 });
        let l = limit_fraction(&info("sg"), Isa::Avx512, 10e9, fma, Some(div), sg);
        assert_eq!(l, Some(("fma", 10e9 * 7.0 / fma)));
        // Not on SSE2 (the count is the FMA kernels') and not for scalar fallbacks.
        for isa in [Isa::Sse2, Isa::Scalar] {
            assert_eq!(
                limit_fraction(&info("sg"), isa, 1e9, fma, Some(div), sg),
                None
            );
        }
        let b = Some(PipeOps { mul: 11, div: 1 });
        let l = limit_fraction(&info("beckmann"), Isa::Avx2Fma, 5e9, fma, Some(div), b);
        assert_eq!(l, Some(("fma", 5e9 * 11.0 / fma)));
        let l = limit_fraction(&info("beckmann"), Isa::Avx2Fma, 5e9, fma, Some(4e9), b);
        assert_eq!(l, Some(("divider", 5e9 / 4e9)));
        assert_eq!(
            limit_fraction(&info("beckmann"), Isa::Avx2Fma, 5e9, fma, None, b),
            None
        );
    }

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
        for isa in [Isa::Avx512, Isa::Avx2Fma, Isa::Sse2, Isa::Scalar] {
            let rate = div_per_s(isa, budget);
            assert_eq!(rate.is_some(), fma_supported(isa), "{isa:?}");
            // A division is never cheaper than a fused multiply-add.
            if let (Some(d), Some(f)) = (rate, fma_per_s(isa, budget)) {
                assert!(
                    d.is_finite() && d > 0.0 && d < 2.0 * f,
                    "{isa:?}: {d} vs {f}"
                );
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
                limit: None,
                limit_fraction: None,
            },
        ];
        let r = Report {
            cpu: "test".into(),
            isa: "avx2".into(),
            threads: 1,
            fma_per_s: 1e10,
            div_per_s: None,
            speedups: speedups(&kernels, 4096, 1 << 24),
            kernels,
            quick: true,
            gpu: None,
            peers: vec![],
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

    /// `compare` pairs rows by model, variant and batch, in the new run's order, and marks
    /// only the ones below `SLOWER_BELOW`.
    #[test]
    fn compare_pairs_rows_and_marks_the_slower_ones() {
        let row = |model: &str, variant: &str, batch: usize, rate: f64| KernelRow {
            model: model.into(),
            variant: variant.into(),
            batch,
            evals_per_s: rate,
            isa: "avx512".into(),
            fma_fraction: None,
            limit: None,
            limit_fraction: None,
        };
        let run = |kernels: Vec<KernelRow>| Report {
            cpu: "test".into(),
            isa: "avx512".into(),
            threads: 2,
            fma_per_s: 1e11,
            div_per_s: None,
            speedups: vec![],
            kernels,
            quick: true,
            gpu: None,
            peers: vec![],
        };
        let old = run(vec![
            row("power4", "simd", 4096, 4e10),
            row("cook-torrance", "simd", 4096, 5e8),
            row("cook-torrance", "simd", 1 << 24, 5e8),
            row("ward", "simd", 4096, 5e8),
        ]);
        let new = run(vec![
            row("cook-torrance", "simd", 4096, 6e7),
            row("power4", "simd", 4096, 3.3e10),
            row("power4", "scalar", 4096, 7e8),
            row("phong", "simd", 4096, 4e8),
        ]);
        let c = compare(&old, &new);
        let got: Vec<(&str, f64, bool)> = c
            .iter()
            .map(|r| (r.model.as_str(), r.ratio, r.slower))
            .collect();
        assert_eq!(
            got,
            [("cook-torrance", 0.12, true), ("power4", 0.825, false)]
        );
        assert_eq!((c[0].old_evals_per_s, c[0].new_evals_per_s), (5e8, 6e7));
        assert!(
            compare(&new, &new)
                .iter()
                .all(|r| r.ratio == 1.0 && !r.slower)
        );
    }

    /// Each C peer's maximum mixed error against the f64 model of the same id and
    /// parameters, on the benchmark's inputs and a 65537-point grid.
    fn peer_errors() -> Vec<(&'static str, f64, f64)> {
        let xs = accuracy_inputs(&Inputs::new(4096).cos);
        peers()
            .iter()
            .map(|p| {
                let given = p.given();
                let m64 = registry::build::<f64>(p.id, &given).unwrap();
                let kernel = Kernel::new(p.id, &given).unwrap();
                let ke = max_mixed_error(&m64, &xs, |x, o| kernel.eval(Input::Cos(x), o).unwrap());
                (p.id, max_mixed_error(&m64, &xs, |x, o| p.eval(x, o)), ke)
            })
            .collect()
    }

    /// The peers compile, link and compute their models: each within 1e-5 (mixed) of the f64
    /// model of the same id and parameters (measured: 3e-8 to 7e-7; GGX's engine form
    /// 1.2e-6, its cancellation near the peak), like the kernels.
    /// The exception is the seed cubic, which C evaluates in the seed's monomial form: at
    /// n = 200 its coefficients are about 1.3e4 and cancel in f32 (measured 4.8e-4; the
    /// library's Newton form is 1e-7), so it is held to 2e-3 only and must stay a cubic (a
    /// wrong coefficient errs by far more).
    #[test]
    fn c_peers_agree_with_the_f64_models() {
        let errors = peer_errors();
        let ids: Vec<&str> = errors.iter().map(|e| e.0).collect();
        assert_eq!(
            ids,
            [
                "pow", "sg", "power4", "power8", "power16", "cubic", "schlick", "beckmann", "ggx"
            ]
        );
        for (id, peer, kernel) in errors {
            let bound = if id == "cubic" { 2e-3 } else { 1e-5 };
            assert!(
                peer <= bound,
                "{id}: C peer errs by {peer:e} (bound {bound:e})"
            );
            assert!(kernel <= 1e-5, "{id}: kernel errs by {kernel:e}");
        }
    }

    /// A peer of no registered model, and the peers' parameters in the CLI's form.
    #[test]
    fn peers_name_their_models_and_parameters() {
        assert!(Peer::new("gauss", 200.0).is_none());
        let p = Peer::new("beckmann", 0.3).unwrap();
        assert_eq!(
            (p.params_text().as_str(), p.function),
            ("alpha=0.3", "peer_beckmann")
        );
        for p in peers() {
            let given = p.given();
            assert!(registry::build::<f64>(p.id, &given).is_ok(), "{}", p.id);
            assert_eq!(p.function, format!("peer_{}", p.id));
        }
    }

    #[test]
    fn spread_is_the_median_and_quartiles() {
        let s = Spread::of(&[5.0, 1.0, 3.0, 2.0, 4.0]);
        assert_eq!(
            s,
            Spread {
                median: 3.0,
                q1: 2.0,
                q3: 4.0,
                min: 1.0,
                max: 5.0
            }
        );
        let s = Spread::of(&[1.0, 2.0]);
        assert_eq!((s.median, s.q1, s.q3), (1.5, 1.25, 1.75));
        assert_eq!(Spread::of(&[7.0]).values(), [7.0; 5]);
    }

    /// The race's rows (not their timings): one per selected peer, every figure a possible
    /// measurement, the ratio the kernel's rate over the peer's, FTZ/DAZ read on x86-64.
    #[test]
    fn peer_rows_have_every_field() {
        let cos = Inputs::new(4096).cos;
        let opts = PeerOptions {
            rounds: 3,
            round: Duration::from_micros(1),
        };
        let models = vec!["power16".to_string(), "beckmann".into(), "ward".into()];
        let rows = peer_rows(&models, &cos, &opts).unwrap();
        let ids: Vec<&str> = rows.iter().map(|r| r.model.as_str()).collect();
        assert_eq!(ids, ["power16", "beckmann"]);
        for r in &rows {
            assert_eq!((r.batch, r.rounds), (4096, 3));
            assert!(r.repeats >= 1);
            for s in [&r.kernel_evals_per_s, &r.peer_evals_per_s, &r.ratio] {
                assert!(
                    s.values().iter().all(|x| x.is_finite() && *x > 0.0),
                    "{r:?}"
                );
                assert!(s.min <= s.q1 && s.q1 <= s.median && s.median <= s.q3 && s.q3 <= s.max);
            }
            assert!(
                r.kernel_max_error <= 1e-5 && r.peer_max_error <= 1e-5,
                "{r:?}"
            );
            assert_eq!(
                (r.compiler.as_str(), r.flags.as_str()),
                (PEER_COMPILER, PEER_FLAGS)
            );
            assert!(r.flags.starts_with("-O3"));
            assert_eq!(r.ftz.is_some(), cfg!(target_arch = "x86_64"));
        }
        assert_eq!(rows[1].params, "alpha=0.3");
        assert!(ftz_note(ftz_daz()).contains("FTZ"));
    }
}
