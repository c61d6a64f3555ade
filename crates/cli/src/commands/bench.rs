//! `fastbrdf bench`: scalar and SIMD throughput of every model, the FMA peak, and the seeds'
//! speedup claims, in one run (fastbrdf-analysis::speed).

use super::common::progress::bar;
use crate::CliError;
use fastbrdf_analysis::speed::{self, Report};
use std::fmt::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf bench --quick\n  fastbrdf bench --json > bench.json\n  \
fastbrdf bench --from bench.json --markdown\n  fastbrdf bench --models pow,power16,cook-torrance\n  \
fastbrdf bench --gpu --quick\n  \
fastbrdf bench --quick --compare docs/bench/bench.json\n\n\
Every run also races each lobe's (n = 200), Beckmann's and GGX's (alpha = 0.3) batch kernel against\n\
the plain C loop a user would write (powf, exp2f, expf, squarings; compiled with the system C\n\
compiler at -O3 -march=native -ffast-math), interleaved in the same process on the same\n\
inputs, with both sides' error against the f64 model and the FTZ/DAZ state (\"C peers\").\n\n\
--gpu adds, in the same run, each model's evaluations per second on the GPU with the data\n\
resident (variant `gpu`) and with upload and read-back (`gpu+transfer`), batch min(--large,\n\
4194304), and GPU speedup rows. The adapter is named in the output; a software adapter\n\
(lavapipe, llvmpipe) runs on the CPU, and the output says its figures are CPU figures."
)]
pub struct Args {
    /// About 10 s instead of about a minute (shorter timing rounds; one run of the large batch).
    #[arg(long)]
    quick: bool,
    /// Print JSON: {"cpu", "isa", "threads", "fma_per_s", "div_per_s", "kernels": [{model,
    /// variant, batch, evals_per_s, isa, fma_fraction, limit, limit_fraction}], "speedups": [{name, measured, claimed, how}], "quick",
    /// "peers": [{model, params, batch, repeats, rounds, isa, kernel_evals_per_s,
    /// peer_evals_per_s, ratio, kernel_max_error, peer_max_error, peer, compiler, flags,
    /// libmvec, ftz, daz, kernel_limit, kernel_limit_fraction, peer_limit_fraction}], and with --gpu "gpu" (the adapter's label)}; GPU rows have variant
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
    /// square root or transcendental makes the count meaningless.
    #[arg(long, conflicts_with = "markdown")]
    json: bool,
    /// Print the Markdown tables that README.md shows.
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

/// Adds the GPU rows and speedups to a CPU run.
fn add_gpu(r: &mut Report, a: &Args) -> Result<(), CliError> {
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
    let pb = bar(configs.len() as u64, "bench --gpu");
    for (name, spec) in &configs {
        let input = GpuInput::from(inputs.input(spec.kind(), inputs.cos.len()));
        let m = fastbrdf_gpu::bench::measure(&gpu.device, &gpu.queue, spec, input, budget)?;
        for (variant, v) in [
            ("gpu", m.kernel_evals_per_s),
            ("gpu+transfer", m.transfer_evals_per_s),
        ] {
            r.kernels.push(speed::KernelRow {
                model: name.clone(),
                variant: variant.into(),
                batch: n,
                evals_per_s: v,
                isa: "gpu".into(),
                fma_fraction: None,
                limit: None,
                limit_fraction: None,
            });
        }
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
                fastbrdf::registry::find(m)?;
            }
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
                add_gpu(&mut r, a)?;
            }
            r
        }
    };
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

/// `--compare`'s output: JSON, Markdown or text, slower rows marked.
fn compare_table(
    rows: &[speed::CompareRow],
    old: &Report,
    new: &Report,
    json: bool,
    md: bool,
) -> String {
    if json {
        let v = serde_json::json!({
            "old": {"cpu": old.cpu, "isa": old.isa, "quick": old.quick},
            "new": {"cpu": new.cpu, "isa": new.isa, "quick": new.quick},
            "slower_below": speed::SLOWER_BELOW,
            "rows": rows,
        });
        return format!(
            "{}\n",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    }
    let mut s = String::new();
    let slower = rows.iter().filter(|r| r.slower).count();
    if md {
        let _ = writeln!(s, "| model | variant | batch | old | new | new / old | |");
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    } else {
        let _ = writeln!(
            s,
            "{:<44} {:<13} {:>9} {:>10} {:>10} {:>9}",
            "model", "variant", "batch", "old", "new", "new/old"
        );
    }
    for r in rows {
        let mark = if r.slower { "slower" } else { "" };
        let (m, v, n) = (&r.model, &r.variant, r.batch);
        let (old, new) = (eng(r.old_evals_per_s), eng(r.new_evals_per_s));
        let line = if md {
            format!(
                "| `{m}` | {v} | {n} | {old} | {new} | {:.2} | {mark} |",
                r.ratio
            )
        } else {
            format!(
                "{m:<44} {v:<13} {n:>9} {old:>10} {new:>10} {:>9.2} {mark}",
                r.ratio
            )
        };
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(
        s,
        "\n{} rows in common, {slower} below {} of the saved run (old: {}, {}{}; new: {}, {}{})",
        rows.len(),
        speed::SLOWER_BELOW,
        old.cpu,
        old.isa,
        if old.quick { ", --quick" } else { "" },
        new.cpu,
        new.isa,
        if new.quick { ", --quick" } else { "" },
    );
    s
}

fn eng(x: f64) -> String {
    if x >= 1e9 {
        format!("{:.2} G", x / 1e9)
    } else if x >= 1e6 {
        format!("{:.1} M", x / 1e6)
    } else {
        format!("{:.0} k", x / 1e3)
    }
}

fn table(r: &Report, md: bool) -> String {
    let mut s = String::new();
    let large = r
        .kernels
        .iter()
        .filter(|k| !k.variant.starts_with("gpu"))
        .map(|k| k.batch)
        .max()
        .unwrap_or(0);
    let gpu_batch = r
        .kernels
        .iter()
        .find(|k| k.variant == "gpu")
        .map(|k| k.batch);
    let models: Vec<&str> = {
        let mut v: Vec<&str> = vec![];
        for k in &r.kernels {
            if !v.contains(&k.model.as_str()) {
                v.push(&k.model);
            }
        }
        v
    };
    let get = |m: &str, variant: &str, batch: usize| {
        r.kernels
            .iter()
            .find(|k| k.model == m && k.variant == variant && k.batch == batch)
    };
    let (gpu_md, gpu_md_rule, gpu_txt) = match gpu_batch {
        Some(b) => (
            format!(" GPU ({b}) | GPU with transfers ({b}) |"),
            "---|---|",
            format!(" {:>12} {:>12}", "gpu", "gpu+xfer"),
        ),
        None => (String::new(), "", String::new()),
    };
    if md {
        let _ = writeln!(
            s,
            "| model | scalar (4096) | SIMD (4096) | % of limit | SIMD 1 thread ({large}) | SIMD {} threads ({large}) | ISA |{gpu_md}",
            r.threads
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|{gpu_md_rule}");
    } else {
        let _ = writeln!(
            s,
            "  {:<40} {:>12} {:>12} {:>8} {:>14} {:>14}{gpu_txt}  isa",
            "model (evals/s)",
            "scalar 4096",
            "simd 4096",
            "% limit",
            "simd 1T large",
            "simd all large"
        );
    }
    for m in models {
        let c = |v: &str, b: usize| {
            get(m, v, b)
                .map(|k| eng(k.evals_per_s))
                .unwrap_or_else(|| "-".into())
        };
        let frac = get(m, "simd", 4096)
            .map(|k| limit_text(k.limit.as_deref(), k.limit_fraction, k.fma_fraction))
            .unwrap_or_else(|| "-".into());
        let isa = get(m, "simd", 4096)
            .map(|k| k.isa.clone())
            .unwrap_or_else(|| "scalar".into());
        let (g_md, g_txt) = match gpu_batch {
            Some(b) => (
                format!(" {} | {} |", c("gpu", b), c("gpu+transfer", b)),
                format!(" {:>12} {:>12}", c("gpu", b), c("gpu+transfer", b)),
            ),
            None => (String::new(), String::new()),
        };
        if md {
            let _ = writeln!(
                s,
                "| `{m}` | {} | {} | {frac} | {} | {} | {isa} |{g_md}",
                c("scalar", 4096),
                c("simd", 4096),
                c("simd", large),
                c("simd-threads", large)
            );
        } else {
            let _ = writeln!(
                s,
                "  {:<40} {:>12} {:>12} {:>8} {:>14} {:>14}{g_txt}  {isa}",
                m,
                c("scalar", 4096),
                c("simd", 4096),
                frac,
                c("simd", large),
                c("simd-threads", large)
            );
        }
    }
    s
}

/// The GPU figures: per model, all-thread SIMD on the CPU, the GPU with data resident and with
/// transfers, and their ratio; then the GPU speedup rows.
fn gpu_tables(r: &Report, md: bool) -> String {
    let mut s = String::new();
    let gpu = r.gpu.as_deref().unwrap_or("-");
    let large = r
        .kernels
        .iter()
        .filter(|k| k.variant == "simd-threads")
        .map(|k| k.batch)
        .max()
        .unwrap_or(0);
    let get = |m: &str, v: &str| {
        r.kernels
            .iter()
            .find(|k| k.model == m && k.variant == v)
            .map(|k| (k.evals_per_s, k.batch))
    };
    let mut models: Vec<&str> = vec![];
    for k in r.kernels.iter().filter(|k| k.variant == "gpu") {
        if !models.contains(&k.model.as_str()) {
            models.push(&k.model);
        }
    }
    let batch = models
        .first()
        .and_then(|m| get(m, "gpu"))
        .map(|g| g.1)
        .unwrap_or(0);
    if md {
        let _ = writeln!(
            s,
            "GPU: {gpu}; CPU: {} ({} threads){}.\n",
            r.cpu,
            r.threads,
            if r.quick { " (quick run)" } else { "" }
        );
        let _ = writeln!(
            s,
            "| model | CPU SIMD, {} threads ({large}) | GPU ({batch}) | GPU with transfers ({batch}) | GPU / CPU |\n|---|---|---|---|---|",
            r.threads
        );
    } else {
        let _ = writeln!(s, "GPU: {gpu}\nCPU: {} ({} threads)\n", r.cpu, r.threads);
        let _ = writeln!(
            s,
            "  {:<40} {:>14} {:>12} {:>12} {:>9}",
            "model (evals/s)", "cpu all simd", "gpu", "gpu+xfer", "gpu/cpu"
        );
    }
    for m in models {
        let cpu = get(m, "simd-threads").map(|k| k.0);
        let g = get(m, "gpu").map(|k| k.0);
        let x = get(m, "gpu+transfer").map(|k| k.0);
        let f = |v: Option<f64>| v.map(eng).unwrap_or_else(|| "-".into());
        let ratio = match (g, cpu) {
            (Some(g), Some(c)) => format!("{:.2}", g / c),
            _ => "-".into(),
        };
        if md {
            let _ = writeln!(s, "| `{m}` | {} | {} | {} | {ratio} |", f(cpu), f(g), f(x));
        } else {
            let _ = writeln!(
                s,
                "  {:<40} {:>14} {:>12} {:>12} {:>9}",
                m,
                f(cpu),
                f(g),
                f(x),
                ratio
            );
        }
    }
    let gpu_rows = Report {
        speedups: r
            .speedups
            .iter()
            .filter(|sp| sp.name.contains("gpu"))
            .cloned()
            .collect(),
        ..r.clone()
    };
    let _ = writeln!(s);
    s.push_str(&speed_table(&gpu_rows, md));
    s
}

fn speed_table(r: &Report, md: bool) -> String {
    let mut s = String::new();
    if md {
        let _ = writeln!(
            s,
            "| speedup | measured | seed's claim | how |\n|---|---|---|---|"
        );
    }
    for sp in &r.speedups {
        let claim = sp
            .claimed
            .map(|c| format!("{c}"))
            .unwrap_or_else(|| "-".into());
        if md {
            let _ = writeln!(
                s,
                "| `{}` | {:.2} | {claim} | {} |",
                sp.name, sp.measured, sp.how
            );
        } else {
            let _ = writeln!(
                s,
                "  {:<40} {:>8.2}x  claimed {:>5}   {}",
                sp.name, sp.measured, claim, sp.how
            );
        }
    }
    s
}

/// `87% fma` or `64% div`: the share of the machine limit a kernel uses; a run saved before
/// the limits were named shows its FMA fraction alone.
fn limit_text(limit: Option<&str>, fraction: Option<f64>, fma_fraction: Option<f64>) -> String {
    match (limit, fraction, fma_fraction) {
        (Some(l), Some(f), _) => {
            format!(
                "{:.0}% {}",
                100.0 * f,
                if l == "divider" { "div" } else { l }
            )
        }
        (None, None, Some(f)) => format!("{:.0}%", 100.0 * f),
        _ => "-".into(),
    }
}

fn header(r: &Report) -> String {
    let gpu = match &r.gpu {
        Some(g) => format!("; GPU: {g}"),
        None => String::new(),
    };
    format!(
        "CPU: {}; instruction set: {}; {} threads; FMA peak {} lane-FMA/s per core{}{}{gpu}",
        r.cpu,
        r.isa,
        r.threads,
        eng(r.fma_per_s),
        match r.div_per_s {
            Some(d) => format!(", divider {} lane-div/s", eng(d)),
            None => String::new(),
        },
        if r.quick { " (quick run)" } else { "" }
    )
}

fn text(r: &Report) -> String {
    let mut s = format!(
        "{}\n\nThroughput (evaluations per second, best of repeated rounds)\n{}\nSpeedups (ratios within this run)\n{}",
        header(r),
        table(r, false),
        speed_table(r, false)
    );
    if !r.peers.is_empty() {
        let _ = write!(s, "\nC peers\n{}", peer_table(r, false));
    }
    s
}

/// The kernels against their C peers (nothing for a run saved without them).
fn peer_table(r: &Report, md: bool) -> String {
    let mut s = String::new();
    let Some(first) = r.peers.first() else {
        return s;
    };
    let state = first.ftz.zip(first.daz);
    let _ = writeln!(
        s,
        "{}C: {}, {}{}. {}.{}",
        if md { "" } else { "  " },
        first.compiler,
        first.flags,
        if first.libmvec {
            ", powf/expf/exp2f vectorised by glibc's libmvec"
        } else {
            ""
        },
        speed::ftz_note(state),
        if md { "\n" } else { "" }
    );
    let _ = writeln!(
        s,
        "{}Evaluations per second on {} cosines: median [interquartile range] of interleaved rounds (kernel, C, kernel, C, ...) of repeated calls; kernel / C from the same rounds; max error |v - v64| / max(1, |v64|) against the f64 model.{}",
        if md { "" } else { "  " },
        first.batch,
        if md { "\n" } else { "" }
    );
    let iqr = |x: &speed::Spread| format!("{} [{}, {}]", eng(x.median), eng(x.q1), eng(x.q3));
    let ratio = |x: &speed::Spread| format!("{:.2} [{:.2}, {:.2}]", x.median, x.q1, x.q3);
    if md {
        let _ = writeln!(
            s,
            "| model | kernel | C peer | kernel / C | kernel max error | C max error | kernel % of limit | C % of limit | ISA | rounds x calls |\n|---|---|---|---|---|---|---|---|---|---|"
        );
    } else {
        let _ = writeln!(
            s,
            "  {:<22} {:>26} {:>26} {:>20} {:>9} {:>9} {:>9} {:>9}  {:<7} rounds x calls",
            "model", "kernel", "C peer", "kernel / C", "k err", "C err", "% limit", "C %", "isa"
        );
    }
    for p in &r.peers {
        let name = format!("{} {}", p.model, p.params);
        let limit = limit_text(p.kernel_limit.as_deref(), p.kernel_limit_fraction, None);
        let peer_limit = limit_text(p.kernel_limit.as_deref(), p.peer_limit_fraction, None);
        if md {
            let _ = writeln!(
                s,
                "| `{}` {} | {} | {} | {} | {:.1e} | {:.1e} | {limit} | {peer_limit} | {} | {} x {} |",
                p.model,
                p.params,
                iqr(&p.kernel_evals_per_s),
                iqr(&p.peer_evals_per_s),
                ratio(&p.ratio),
                p.kernel_max_error,
                p.peer_max_error,
                p.isa,
                p.rounds,
                p.repeats
            );
        } else {
            let _ = writeln!(
                s,
                "  {:<22} {:>26} {:>26} {:>20} {:>9.1e} {:>9.1e} {limit:>9} {peer_limit:>9}  {:<7} {} x {}",
                name,
                iqr(&p.kernel_evals_per_s),
                iqr(&p.peer_evals_per_s),
                ratio(&p.ratio),
                p.kernel_max_error,
                p.peer_max_error,
                p.isa,
                p.rounds,
                p.repeats
            );
        }
    }
    s
}

/// The Markdown README shows.
pub fn markdown(r: &Report) -> String {
    let mut s = format!(
        "{}.\n\n{}\n{}",
        header(r),
        table(r, true),
        speed_table(r, true)
    );
    // Runs saved before the C peers (README's docs/bench/bench.json) print as they did.
    if !r.peers.is_empty() {
        let _ = write!(s, "\n{}", peer_table(r, true));
    }
    s
}
