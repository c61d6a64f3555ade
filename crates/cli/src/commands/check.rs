//! `fastbrdf check`: re-measures every documented bound of the registry on this machine and
//! says whether each holds. Three families of checks:
//! - error against the reference model: a dense grid plus golden-section refinement over the
//!   bound's parameter range (`fastbrdf::accuracy::worst`) and an adversarial search over the
//!   parameter as a continuum and the input together (`accuracy::worst_search`);
//! - f32 against f64 on the same inputs over the whole documented domain, mixed metric
//!   `|v32 - v64| / max(1, |v64|)`: a grid of parameter sets (`accuracy::f32_worst` over
//!   `accuracy::domain_configs`) and an adversarial search (`accuracy::f32_search`: every
//!   combination of choice parameters, random restarts at parameter extremes, special and
//!   random values, hill climbing over parameters and inputs together; seeded, so
//!   reproducible), and the corners of the domain (`check::corners`: zero, subnormal and tiny
//!   cosines, grazing pairs, `eta` near 1 as typed). The search and the corners also fail a
//!   model that returns a non-finite or negative value in either precision.
//!
//! - the batch kernels (the SIMD code `eval` runs) against f64 on every instruction set of
//!   this CPU, held to the model's f32 bound, invalid inputs answered finite and >= 0.
//!
//! The measuring is fastbrdf-analysis::check; this command prints it.
//!
//! The default search has the size of the test `tests/precision.rs`
//! (`SearchSize::CI`); `--full` runs `SearchSize::FULL` (32 times the evaluations, another
//! seed). Exit code 1 if any bound is exceeded.

use crate::CliError;
use fastbrdf::{Metric, Zone, accuracy, registry};
use fastbrdf_analysis::check;
use indicatif::{ProgressBar, ProgressStyle};

#[derive(clap::Args)]
pub struct Args {
    /// Print JSON: {"ok", "bounds": [...], "f32": [...], "kernels": [...]}.
    #[arg(long)]
    json: bool,
    /// Only this model.
    #[arg(long)]
    model: Option<String>,
    /// Search 32 times longer (with another seed) than the default, which is the size the
    /// test suite runs. Example: `fastbrdf check --full --model cook-torrance`.
    #[arg(long)]
    full: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let entries: Vec<&'static fastbrdf::entry::Entry> = match &a.model {
        Some(id) => vec![registry::find(id)?],
        None => registry::all().iter().collect(),
    };
    let size = if a.full {
        accuracy::SearchSize::FULL
    } else {
        accuracy::SearchSize::CI
    };
    let bar = ProgressBar::new(check::steps(&entries) as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} {elapsed}")
            .expect("valid template"),
    );
    bar.set_message("checking");
    let report = check::run(&entries, size, &|| bar.inc(1));
    bar.finish_and_clear();
    let (bounds, f32_rows) = (&report.bounds, &report.f32);
    let ok = report.ok();
    if a.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report.json()).expect("serialisable")
        );
    } else {
        println!("Error against the reference (documented bound vs measured maximum)");
        println!(
            "  {:<18} {:<12} {:<16} {:<22} {:>11} {:>11}  verdict  where",
            "model", "reference", "metric/zone", "range", "documented", "measured"
        );
        for r in bounds {
            let metric = match r.metric {
                Metric::MaxAbs => "max abs",
                Metric::MaxRel => "max rel",
            };
            let zone = match r.zone {
                Zone::All => "all".to_string(),
                Zone::Epicentre => "epicentre".to_string(),
                Zone::Band { lo, hi } => format!("{lo}<ref<{hi}"),
            };
            println!(
                "  {:<18} {:<12} {:<16} {:<22} {:>11.4e} {:>11.4e}  {:<7}  {}={} x={:.6}",
                r.model,
                r.reference,
                format!("{metric} {zone}"),
                format!("{} in [{}, {}]", r.param.0, r.param.1, r.param.2),
                r.documented,
                r.measured,
                if r.ok { "ok" } else { "EXCEEDED" },
                r.param.0,
                r.at_param,
                r.at_x
            );
        }
        println!(
            "\nf32 against f64 (|v32 - v64| / max(1, |v64|), same inputs, whole documented domain:\n  grid of parameter sets + adversarial search{} + corners)",
            if a.full { ", --full" } else { "" }
        );
        print_table("searched", f32_rows.iter().map(|r| table_line!(r)));
        println!(
            "\nBatch kernels against f64 (what `eval` runs; every instruction set of this CPU: {}):\n  the f32 grid at every configuration and the search's worst, the ends of the inputs, invalid inputs (finite, >= 0)",
            report
                .kernels
                .first()
                .map_or(String::new(), |r| r.isas.join(", "))
        );
        print_table("values", report.kernels.iter().map(|r| table_line!(r)));
        let (n_ok, total) = report.holding();
        println!("\n{n_ok} of {total} documented bounds hold on this machine.");
    }
    if ok {
        Ok(())
    } else {
        Err(CliError {
            code: 1,
            message: "some documented bounds do not hold (see above)".into(),
        })
    }
}

/// The [`Line`] of an f32 or a kernel row (both have these fields).
macro_rules! table_line {
    ($r:expr) => {
        Line {
            model: $r.model,
            documented: $r.documented,
            measured: $r.measured,
            counts: ($r.configurations, $r.evaluations),
            ok: $r.ok,
            finite: $r.finite,
            at: &$r.at,
            invalid: &$r.invalid,
        }
    };
}
use table_line;

/// One row of the f32 or the kernels' table: the model, its bound and maximum,
/// (configurations, evaluations), the verdict, and where it failed.
struct Line<'a> {
    model: &'a str,
    documented: f64,
    measured: f64,
    counts: (usize, usize),
    ok: bool,
    finite: bool,
    at: &'a str,
    invalid: &'a str,
}

/// The f32 or the kernels' table: a header (`counted` names the evaluations' column) and
/// one line per model, with where a failed one failed.
fn print_table<'a>(counted: &str, lines: impl Iterator<Item = Line<'a>>) {
    println!(
        "  {:<24} {:>11} {:>11} {:>8} {:>10}  verdict",
        "model", "documented", "measured", "configs", counted
    );
    for l in lines {
        let verdict = if !l.finite {
            "NON-FINITE OR NEGATIVE VALUE"
        } else if l.ok {
            "ok"
        } else {
            "EXCEEDED"
        };
        let (configurations, evaluations) = l.counts;
        println!(
            "  {:<24} {:>11.1e} {:>11.3e} {configurations:>8} {evaluations:>10}  {verdict}",
            l.model, l.documented, l.measured
        );
        if !l.ok {
            println!("      at {}", if l.finite { l.at } else { l.invalid });
        }
    }
}
