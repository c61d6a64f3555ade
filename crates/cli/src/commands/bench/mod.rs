//! `fastbrdf bench`: scalar and SIMD throughput of every model, the FMA peak, and the seeds'
//! speedup claims, in one run (fastbrdf-analysis::speed).

mod tables;
mod users;

use super::common::progress::bar;
use crate::CliError;
use crate::model_args::ParamArgs;
use fastbrdf_analysis::speed::{self, Report};
use std::path::PathBuf;
use tables::{compare_table, gpu_tables, markdown, text};

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf bench --quick\n  fastbrdf bench --json > bench.json\n  \
fastbrdf bench --from bench.json --markdown\n  fastbrdf bench --models pow,power16,cook-torrance\n  \
fastbrdf bench --gpu --quick\n  \
fastbrdf bench --gpu --quick --models ggx,cook-torrance --model file:walter.brdf --param alphaG=0.3\n  \
fastbrdf bench --quick --compare docs/bench/bench.json\n\n\
Every run also races each lobe's (n = 200), Beckmann's and GGX's (alpha = 0.3) batch kernel against\n\
the plain C loop a user would write (powf, exp2f, expf, squarings; compiled with the system C\n\
compiler at -O3 -march=native -ffast-math), interleaved in the same process on the same\n\
inputs, with both sides' error against the f64 model and the FTZ/DAZ state (\"C peers\").\n\n\
--gpu adds, in the same run, each model's evaluations per second on the GPU with the data\n\
resident (variant `gpu`) and with upload and read-back (`gpu+transfer`), batch min(--large,\n\
4194304), and GPU speedup rows. The adapter is named in the output; a software adapter\n\
(lavapipe, llvmpipe) runs on the CPU, and the output says its figures are CPU figures.\n\n\
--model file:PATH (with --gpu) times a user's BRDF (a BRDF Explorer .brdf file or a .wgsl or .glsl\n\
function; the book's user-shaders page) on the GPU by the same method, on the same direction\n\
pairs, beside the built-in models, with its instruction count (counted with spirv-opt at run\n\
time; without spirv-opt it shows as - and a note says why). Its rows are named file:PATH, with\n\
[NAME=VALUE,...] when --param values are given (each file takes the --param values it\n\
declares, checked against the declared ranges)."
)]
pub struct Args {
    /// About 25 s instead of about a minute (shorter timing rounds; one run of the large batch).
    #[arg(long)]
    quick: bool,
    /// Print JSON: {"cpu", "isa", "threads", "fma_per_s", "div_per_s", "kernels": [{model,
    /// variant, batch, evals_per_s, isa, fma_fraction, limit, limit_fraction, instructions}], "speedups": [{name, measured, claimed, how}], "quick",
    /// "peers": [{model, params, batch, repeats, rounds, isa, kernel_evals_per_s,
    /// peer_evals_per_s, ratio, kernel_max_error, peer_max_error, peer, compiler, flags,
    /// libmvec, ftz, daz, kernel_limit, kernel_limit_fraction, peer_limit_fraction}], "skipped":
    /// [{model, variant, batch, projected_s}] (large-batch figures not timed because one call
    /// was projected to take over 3 s: quadrature references such as sheen-albedo), and with
    /// --gpu "gpu" (the adapter's label)}; GPU rows have variant
    /// "gpu" or "gpu+transfer" and isa "gpu". Each peers row races the batch kernel against
    /// the C loop `peer` (crates/analysis/c/peer.c, built with `compiler` at `flags`):
    /// `kernel_evals_per_s`, `peer_evals_per_s` and `ratio` (kernel over peer, per round) are
    /// {median, q1, q3, min, max} over `rounds` interleaved rounds of `repeats` calls on `batch`
    /// cosines; the errors are max |v - v64| / max(1, |v64|) against the f64 model; `ftz`/`daz`
    /// are the process's MXCSR flags (null off x86-64). Runs saved without "peers" load with none.
    /// `fma_fraction` is the share of the measured FMA-pipe peak used by the formula's own
    /// multiplies and adds (fused pairs count once on FMA instruction sets); null for BRDFs and
    /// for formulas with a division, square root or transcendental, which it cannot count.
    /// `limit` names the machine limit a kernel is held against, "fma" (the FMA pipes,
    /// `fma_per_s`) or "divider" (the divide unit, `div_per_s` lane divisions per second),
    /// whichever its multiplies, adds and divisions use more of, and `limit_fraction` the share
    /// used (single-thread "simd" rows; `kernel_limit*` for the peers' median, and
    /// `peer_limit_fraction` the C loop's median against the same limit with the same
    /// operation count). A kernel whose family counts its own operations (sg,
    /// ue4-phong-approx, sg-tuned, beckmann, beckmann-ct: their vectorised exp2's polynomial
    /// included, on FMA instruction sets) is held to that count, and its C loop, which calls
    /// libm's or libmvec's exponential, gets no peer_limit_fraction. Null where an uncounted
    /// square root or transcendental makes the count meaningless. `instructions` is the model's
    /// shader's SPIR-V instruction count after spirv-opt -O, {arithmetic, transcendental,
    /// division_sqrt, branches, select, other, total} (fastbrdf_gpu::cost; the committed table
    /// for built-in models, counted at run time for a --model file), on every row of the model;
    /// null when unknown.
    #[arg(long, conflicts_with = "markdown")]
    json: bool,
    /// Print the Markdown tables the book shows (docs/book/src/speed.md).
    #[arg(long)]
    markdown: bool,
    /// Render a saved `--json` run instead of measuring (read once, at most 64 MiB).
    #[arg(long, value_name = "FILE")]
    from: Option<PathBuf>,
    /// Only these models (comma-separated ids).
    #[arg(long, value_delimiter = ',')]
    models: Vec<String>,
    /// Elements of the large batch.
    #[arg(long, default_value_t = 16 * 1024 * 1024)]
    large: usize,
    /// Also measure every model on the GPU (wgpu; fails if there is no adapter).
    #[arg(long, conflicts_with = "from")]
    gpu: bool,
    /// A user's model, file:PATH (a BRDF Explorer .brdf file, or a .wgsl or .glsl function),
    /// timed on the GPU beside the built-in models (needs --gpu; --models chooses the
    /// built-ins); repeatable. A bad file or a compile error is exit 2 before any timing,
    /// naming the file, line and column.
    #[arg(long = "model", value_name = "file:PATH", requires = "gpu")]
    model: Vec<String>,
    // The --model files' parameter values: each file takes the names it declares, checked
    // against the declared range (`users::load`).
    #[command(flatten)]
    param: ParamArgs,
    /// Print only the GPU figures (with the CPU's all-thread SIMD figure beside them) and the
    /// GPU speedups; for a run made with --gpu.
    #[arg(long, conflicts_with = "json")]
    gpu_only: bool,
    /// Instead of the tables, compare this run (measured, or --from) with a saved `--json`
    /// run: every kernel row both have (same model, variant and batch), old and new
    /// evaluations per second and new/old, rows below 0.8 marked slower (runs on a shared
    /// machine move 10-20%; look for 2x). With --json: {"old", "new", "slower_below", "rows":
    /// [{model, variant, batch, old_evals_per_s, new_evals_per_s, ratio, slower}]}.
    #[arg(long, value_name = "OLD.json", conflicts_with = "gpu_only")]
    compare: Option<PathBuf>,
}

/// A model's GPU figures into `r`: the rows `gpu` and `gpu+transfer`, or, when one dispatch
/// of the batch was projected too long to time, a `skipped` entry for each.
fn push_gpu(
    r: &mut Report,
    name: &str,
    batch: usize,
    t: fastbrdf_gpu::bench::Timing,
    instructions: Option<speed::Instructions>,
) {
    use fastbrdf_gpu::bench::Timing;
    match t {
        Timing::Measured(m) => {
            for (variant, evals_per_s) in [
                ("gpu", m.kernel_evals_per_s),
                ("gpu+transfer", m.transfer_evals_per_s),
            ] {
                r.kernels.push(speed::KernelRow {
                    model: name.into(),
                    variant: variant.into(),
                    batch,
                    evals_per_s,
                    isa: "gpu".into(),
                    fma_fraction: None,
                    limit: None,
                    limit_fraction: None,
                    instructions,
                });
            }
        }
        Timing::TooSlow { projected_s } => {
            for variant in ["gpu", "gpu+transfer"] {
                r.skipped.push(speed::Skipped {
                    model: name.into(),
                    variant: variant.into(),
                    batch,
                    projected_s,
                });
            }
        }
    }
}

/// Adds the GPU rows and speedups to a CPU run.
fn add_gpu(r: &mut Report, a: &Args, users: &[users::UserModel]) -> Result<(), CliError> {
    use fastbrdf_gpu::compute::{CHUNK, GpuInput};
    let gpu = fastbrdf_gpu::Gpu::new()?;
    let label = gpu.label();
    eprintln!("GPU: {label}");
    let n = a.large.min(CHUNK);
    let inputs = speed::Inputs::new(n);
    let budget = std::time::Duration::from_millis(if a.quick { 40 } else { 200 });
    let configs: Vec<_> = speed::configurations()
        .into_iter()
        .filter(|(name, _)| {
            a.models.is_empty() || a.models.iter().any(|m| m == speed::registry_id(name))
        })
        .collect();
    let pb = bar((configs.len() + users.len()) as u64, "bench --gpu");
    for (name, spec) in &configs {
        let input = GpuInput::from(inputs.input(spec.kind(), inputs.cos.len()));
        let t = fastbrdf_gpu::bench::measure(&gpu.device, &gpu.queue, spec, input, budget)?;
        push_gpu(r, name, n, t, None);
        pb.inc(1);
    }
    for u in users {
        users::measure(r, &gpu, u, &inputs, n, budget)?;
        pb.inc(1);
    }
    pb.finish_and_clear();
    let large = r.kernels.iter().map(|k| k.batch).max().unwrap_or(0);
    r.speedups = speed::speedups(&r.kernels, 4096, large);
    r.gpu = Some(label);
    Ok(())
}

pub fn run(a: &Args) -> Result<(), CliError> {
    // The saved run to compare with is read first: a bad file fails before a minute of timing.
    let old = a.compare.as_deref().map(Report::load).transpose()?;
    let report: Report = match &a.from {
        Some(path) => Report::load(path)?,
        None => {
            if !(1024..=(1usize << 28)).contains(&a.large) {
                return Err(CliError::input(format!(
                    "--large {}: must be between 1024 and 268435456",
                    a.large
                )));
            }
            for m in &a.models {
                if crate::model_args::is_user(m) {
                    return Err(CliError::input(format!(
                        "--models {}: a user's model is given with --model file:PATH (with --gpu)",
                        fastbrdf_io::shorten(m, 60)
                    )));
                }
                fastbrdf::registry::find(m)?;
            }
            // Users' files are read, compiled and counted before a minute of timing.
            let users = users::load(&a.model, &a.param.params)?;
            let pb = bar(1, "bench");
            let opts = speed::Options {
                quick: a.quick,
                large: a.large,
                models: a.models.clone(),
            };
            let r = speed::run(&opts, &|done, total| {
                pb.set_length(total as u64);
                pb.set_position(done as u64);
            })?;
            pb.finish_and_clear();
            let mut r = r;
            if a.gpu {
                add_gpu(&mut r, a, &users)?;
            }
            users::fill_builtin(&mut r.kernels);
            r
        }
    };
    for k in &report.skipped {
        match k.variant.as_str() {
            "simd" => eprintln!(
                "bench: {}: one call on the large batch ({}) would take about {:.0} s (projected from the 4096-element batch): its large-batch figures are left out (`skipped` in --json)",
                k.model, k.batch, k.projected_s
            ),
            "gpu" => eprintln!(
                "bench: {}: one GPU dispatch of {} elements would take about {:.0} s (projected from {} elements): its GPU figures are left out (`skipped` in --json)",
                k.model,
                k.batch,
                k.projected_s,
                fastbrdf_gpu::bench::PROBE
            ),
            _ => {}
        }
    }
    if let (Some(old), Some(old_path)) = (&old, &a.compare) {
        let rows = speed::compare(old, &report);
        if rows.is_empty() {
            return Err(CliError::input(format!(
                "--compare {}: no kernel row (model, variant, batch) in common with this run",
                old_path.display()
            )));
        }
        crate::out!("{}", compare_table(&rows, old, &report, a.json, a.markdown));
        return Ok(());
    }
    if a.gpu_only {
        if report.gpu.is_none() {
            return Err(CliError::input(
                "--gpu-only: this run has no GPU figures (measure with --gpu)",
            ));
        }
        crate::out!("{}", gpu_tables(&report, a.markdown));
    } else if a.json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&report).expect("serialisable")
        );
    } else if a.markdown {
        crate::out!("{}", markdown(&report));
    } else {
        crate::out!("{}", text(&report));
    }
    Ok(())
}
