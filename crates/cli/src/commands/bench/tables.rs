//! `fastbrdf bench`'s outputs: the text and Markdown tables (kernels, GPU, speedups, C
//! peers) and `--compare`'s table.

use fastbrdf_analysis::speed::{self, Report};
use std::fmt::Write;

/// `--compare`'s output: JSON, Markdown or text, slower rows marked.
pub fn compare_table(
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

/// The instruction counts of a run's models by name: the run's own (`instructions` of the
/// model's rows: a user's shader is counted at run time), else the committed table of the
/// benchmark's configurations (`speed::configurations`; `fastbrdf_gpu::cost`: SPIR-V after
/// `spirv-opt -O`, the same on every machine), as `total (transcendental/division-sqrt/
/// branches)`, or `-` when neither has them (a user's shader counted without `spirv-opt`, a
/// saved run's model that no longer exists).
fn instructions(r: &Report) -> impl Fn(&str) -> String + use<> {
    let mut table: Vec<(String, speed::Instructions)> = r
        .kernels
        .iter()
        .filter_map(|k| Some((k.model.clone(), k.instructions?)))
        .collect();
    table.extend(
        speed::configurations()
            .into_iter()
            .filter_map(|(name, spec)| {
                let c = fastbrdf_gpu::cost::lookup(&spec)?;
                Some((name, super::users::instructions(c)))
            }),
    );
    move |model: &str| {
        table
            .iter()
            .find(|(n, _)| n == model)
            .map(|(_, c)| {
                format!(
                    "{} ({}/{}/{})",
                    c.total, c.transcendental, c.division_sqrt, c.branches
                )
            })
            .unwrap_or_else(|| "-".into())
    }
}

/// What the instruction column holds (printed under the tables that have it).
const INSTRUCTIONS_NOTE: &str = concat!(
    "SPIR-V instructions of the model's shader after spirv-opt -O, total ",
    "(transcendental/division-sqrt/branches); the same on every machine (fastbrdf_gpu::cost)."
);

/// The note under a table with the instruction column.
fn instructions_note(md: bool) -> String {
    let label = if md { "\ninstructions: " } else { "  instr: " };
    format!("{label}{INSTRUCTIONS_NOTE}")
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
    let instr = instructions(r);
    let (gpu_md, gpu_md_rule, gpu_txt) = match gpu_batch {
        Some(b) => (
            format!(" GPU ({b}) | GPU with transfers ({b}) | instructions |"),
            "---|---|---|",
            format!(" {:>12} {:>12} {:>13}", "gpu", "gpu+xfer", "instr"),
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
        // A user's model has GPU rows alone.
        let gpu_only = r
            .kernels
            .iter()
            .filter(|k| k.model == m)
            .all(|k| k.variant.starts_with("gpu"));
        let isa = get(m, "simd", 4096)
            .map(|k| k.isa.clone())
            .unwrap_or_else(|| if gpu_only { "gpu" } else { "scalar" }.into());
        let (g_md, g_txt) = match gpu_batch {
            Some(b) => (
                format!(
                    " {} | {} | {} |",
                    c("gpu", b),
                    c("gpu+transfer", b),
                    instr(m)
                ),
                format!(
                    " {:>12} {:>12} {:>13}",
                    c("gpu", b),
                    c("gpu+transfer", b),
                    instr(m)
                ),
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
    if gpu_batch.is_some() {
        let _ = writeln!(s, "{}", instructions_note(md));
    }
    s
}

/// The GPU figures: per model, all-thread SIMD on the CPU, the GPU with data resident and with
/// transfers, and their ratio; then the GPU speedup rows.
pub fn gpu_tables(r: &Report, md: bool) -> String {
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
            "| model | CPU SIMD, {} threads ({large}) | GPU ({batch}) | GPU with transfers ({batch}) | GPU / CPU | instructions |\n|---|---|---|---|---|---|",
            r.threads
        );
    } else {
        let _ = writeln!(s, "GPU: {gpu}\nCPU: {} ({} threads)\n", r.cpu, r.threads);
        let _ = writeln!(
            s,
            "  {:<40} {:>14} {:>12} {:>12} {:>9} {:>13}",
            "model (evals/s)", "cpu all simd", "gpu", "gpu+xfer", "gpu/cpu", "instr"
        );
    }
    let instr = instructions(r);
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
            let _ = writeln!(
                s,
                "| `{m}` | {} | {} | {} | {ratio} | {} |",
                f(cpu),
                f(g),
                f(x),
                instr(m)
            );
        } else {
            let _ = writeln!(
                s,
                "  {:<40} {:>14} {:>12} {:>12} {:>9} {:>13}",
                m,
                f(cpu),
                f(g),
                f(x),
                ratio,
                instr(m)
            );
        }
    }
    let _ = writeln!(s, "{}", instructions_note(md));
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

pub fn text(r: &Report) -> String {
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

/// The Markdown the book shows (docs/book/src/speed.md).
pub fn markdown(r: &Report) -> String {
    let mut s = format!(
        "{}.\n\n{}\n{}",
        header(r),
        table(r, true),
        speed_table(r, true)
    );
    // Runs saved before the C peers (the book's docs/bench/bench.json) print as they did.
    if !r.peers.is_empty() {
        let _ = write!(s, "\n{}", peer_table(r, true));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every configuration the benchmark times has committed instruction counts (a new model
    /// or configuration needs `FASTBRDF_BLESS=1 cargo test -p fastbrdf-gpu --test cost`).
    /// A run without rows: the committed table alone.
    fn empty_run() -> Report {
        Report {
            cpu: "test".into(),
            isa: "avx2".into(),
            threads: 1,
            fma_per_s: 1e10,
            div_per_s: None,
            kernels: vec![],
            speedups: vec![],
            quick: true,
            gpu: None,
            peers: vec![],
            skipped: vec![],
        }
    }

    #[test]
    fn every_benchmark_configuration_has_instruction_counts() {
        let instr = instructions(&empty_run());
        let configs = speed::configurations();
        assert!(configs.len() >= 40, "{} configurations", configs.len());
        for (name, spec) in &configs {
            let c = fastbrdf_gpu::cost::lookup(spec)
                .unwrap_or_else(|| panic!("{name} ({spec}) has no instruction counts"));
            assert_eq!(
                instr(name),
                format!(
                    "{} ({}/{}/{})",
                    c.total, c.transcendental, c.division_sqrt, c.branches
                )
            );
        }
        assert_eq!(instr("no-such-model"), "-");
    }

    /// A run's own counts (a user's shader, counted at run time) are shown for its model; a
    /// built-in model's come from the committed table; a model with neither shows `-`.
    #[test]
    fn a_runs_own_instruction_counts_are_shown() {
        let counts = speed::Instructions {
            arithmetic: 7,
            transcendental: 3,
            division_sqrt: 2,
            branches: 1,
            select: 0,
            other: 4,
            total: 17,
        };
        let row = |model: &str, instructions| speed::KernelRow {
            model: model.into(),
            variant: "gpu".into(),
            batch: 1024,
            evals_per_s: 1e6,
            isa: "gpu".into(),
            fma_fraction: None,
            limit: None,
            limit_fraction: None,
            instructions,
        };
        let mut r = empty_run();
        r.kernels = vec![
            row("file:mine.brdf", Some(counts)),
            row("file:uncounted.brdf", None),
        ];
        r.gpu = Some("test adapter".into());
        let instr = instructions(&r);
        assert_eq!(instr("file:mine.brdf"), "17 (3/2/1)");
        assert_eq!(instr("file:uncounted.brdf"), "-");
        let pow = fastbrdf_gpu::cost::lookup(&fastbrdf::ModelSpec::parse("pow", &[]).unwrap())
            .expect("pow is in the committed table");
        assert_eq!(
            instr("pow"),
            format!(
                "{} ({}/{}/{})",
                pow.total, pow.transcendental, pow.division_sqrt, pow.branches
            )
        );
        let t = table(&r, false);
        let line = t
            .lines()
            .find(|l| l.contains("file:mine.brdf"))
            .expect("a row for the user's model");
        assert!(
            line.contains("17 (3/2/1)") && line.trim_end().ends_with("gpu"),
            "{line}"
        );
    }
}
