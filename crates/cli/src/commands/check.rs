//! `fastbrdf check`: re-measures every documented bound of the registry on this machine and
//! says whether each holds. Two families of checks:
//! - error against the reference model: a dense grid plus golden-section refinement over the
//!   bound's parameter range (`fastbrdf::accuracy::worst`) and an adversarial search over the
//!   parameter as a continuum and the input together (`accuracy::worst_search`);
//! - f32 against f64 on the same inputs over the whole documented domain, mixed metric
//!   `|v32 - v64| / max(1, |v64|)`: a grid of parameter sets (`accuracy::f32_worst` over
//!   `accuracy::domain_configs`) and an adversarial search (`accuracy::f32_search`: every
//!   combination of choice parameters, random restarts at parameter extremes, special and
//!   random values, hill climbing over parameters and inputs together; seeded, so
//!   reproducible). The search also fails a model that returns a non-finite or negative
//!   value in either precision.
//!
//! The default search has the size of the test `tests/precision.rs`
//! (`SearchSize::CI`); `--full` runs `SearchSize::FULL` (32 times the evaluations, another
//! seed). Exit code 1 if any bound is exceeded.

use crate::CliError;
use fastbrdf::{Metric, Zone, accuracy, registry};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::Serialize;

#[derive(clap::Args)]
pub struct Args {
    /// Print JSON: {"ok", "bounds": [...], "f32": [...]}.
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

#[derive(Serialize)]
struct BoundRow {
    model: &'static str,
    reference: &'static str,
    metric: Metric,
    zone: Zone,
    param: (&'static str, f64, f64),
    documented: f64,
    measured: f64,
    at_param: f64,
    at_x: f64,
    samples: usize,
    ok: bool,
}

#[derive(Serialize)]
struct F32Row {
    model: &'static str,
    documented: f64,
    /// The larger of the grid's and the search's maximum (`null` in JSON if infinite).
    measured: f64,
    configurations: usize,
    /// Evaluations (each in both precisions) of the adversarial search.
    evaluations: usize,
    at: String,
    /// Every value found finite and non-negative in both precisions.
    finite: bool,
    /// Where a non-finite or negative value was found ("" when none).
    invalid: String,
    ok: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let entries: Vec<_> = match &a.model {
        Some(id) => vec![registry::find(id)?],
        None => registry::all().iter().collect(),
    };
    let bound_jobs: Vec<_> = entries
        .iter()
        .flat_map(|e| e.info.bounds.iter().map(move |b| (e, b)))
        .collect();
    let size = if a.full {
        accuracy::SearchSize::FULL
    } else {
        accuracy::SearchSize::CI
    };
    let bar = ProgressBar::new((bound_jobs.len() + entries.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} {elapsed}")
            .expect("valid template"),
    );
    bar.set_message("checking");
    let bounds: Vec<BoundRow> = bound_jobs
        .par_iter()
        .map(|(e, b)| {
            let grid = accuracy::worst(e.info.id, b).expect("registry bounds name valid models");
            let found = accuracy::worst_search(e.info.id, b, size)
                .expect("registry bounds name valid models");
            let w = accuracy::Worst {
                samples: grid.samples + found.samples,
                ..if found.err > grid.err { found } else { grid }
            };
            bar.inc(1);
            BoundRow {
                model: e.info.id,
                reference: b.reference,
                metric: b.metric,
                zone: b.zone,
                param: b.param,
                documented: b.bound,
                measured: w.err,
                at_param: w.param,
                at_x: w.x,
                samples: w.samples,
                ok: w.err <= b.bound,
            }
        })
        .collect();
    let f32_rows: Vec<F32Row> = entries
        .par_iter()
        .map(|e| {
            let configs = accuracy::domain_configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf);
            let mut worst = (0.0, String::new());
            for c in &configs {
                let given: Vec<(&str, &str)> =
                    c.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
                let (err, at) = accuracy::f32_worst(e.info.id, &given)
                    .expect("domain configurations are valid");
                if err.is_nan() || err > worst.0 || worst.1.is_empty() {
                    worst = (err, format!("{} {at}", fmt_params(c)));
                }
            }
            let found = accuracy::f32_search(&e.info, size);
            if found.err > worst.0 {
                worst = (
                    found.err,
                    format!("{} {}", fmt_params(&found.params), found.at),
                );
            }
            bar.inc(1);
            F32Row {
                model: e.info.id,
                documented: e.info.f32_bound,
                measured: worst.0,
                configurations: configs.len(),
                evaluations: found.evaluations,
                at: worst.1,
                finite: found.invalid.is_none(),
                invalid: found.invalid.clone().unwrap_or_default(),
                ok: worst.0 <= e.info.f32_bound && found.invalid.is_none(),
            }
        })
        .collect();
    bar.finish_and_clear();
    let ok = bounds.iter().all(|r| r.ok) && f32_rows.iter().all(|r| r.ok);
    if a.json {
        let v = serde_json::json!({ "ok": ok, "bounds": bounds, "f32": f32_rows });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    } else {
        println!("Error against the reference (documented bound vs measured maximum)");
        println!(
            "  {:<18} {:<12} {:<16} {:<22} {:>11} {:>11}  verdict  where",
            "model", "reference", "metric/zone", "range", "documented", "measured"
        );
        for r in &bounds {
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
            "\nf32 against f64 (|v32 - v64| / max(1, |v64|), same inputs, whole documented domain:\n  grid of parameter sets + adversarial search{})",
            if a.full { ", --full" } else { "" }
        );
        println!(
            "  {:<24} {:>11} {:>11} {:>8} {:>10}  verdict",
            "model", "documented", "measured", "configs", "searched"
        );
        for r in &f32_rows {
            println!(
                "  {:<24} {:>11.1e} {:>11.3e} {:>8} {:>10}  {}",
                r.model,
                r.documented,
                r.measured,
                r.configurations,
                r.evaluations,
                if !r.finite {
                    "NON-FINITE OR NEGATIVE VALUE"
                } else if r.ok {
                    "ok"
                } else {
                    "EXCEEDED"
                }
            );
            if !r.ok {
                println!("      at {}", if r.finite { &r.at } else { &r.invalid });
            }
        }
        let n_ok =
            bounds.iter().filter(|r| r.ok).count() + f32_rows.iter().filter(|r| r.ok).count();
        println!(
            "\n{} of {} documented bounds hold on this machine.",
            n_ok,
            bounds.len() + f32_rows.len()
        );
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

/// Parameters as `k=v k=v` (how `check` names a configuration).
fn fmt_params(params: &[(String, String)]) -> String {
    let kv: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    kv.join(" ")
}
