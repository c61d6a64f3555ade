//! `fastbrdf pareto --sheen`: the sheen rows of the DFG ledger, every sheen albedo model and
//! configuration against `sheen-albedo` at its visibility beside its cost, the front marked per
//! visibility (fastbrdf-analysis::sheen_ledger).

use crate::CliError;
use crate::commands::common::progress::bar;
use fastbrdf_analysis::sheen_ledger;

pub fn run(json: bool, markdown: bool) -> Result<(), CliError> {
    let pb = bar(sheen_ledger::configs().len() as u64, "pareto --sheen");
    let rows = sheen_ledger::rows(&|| pb.inc(1))?;
    pb.finish_and_clear();
    if json {
        let v = serde_json::json!({
            "reference": sheen_ledger::REFERENCE,
            "rows": rows.iter().map(|r| serde_json::json!({
                "label": r.label(), "model": r.model, "v": r.errors.v,
                "params": r.params.iter().cloned().collect::<std::collections::BTreeMap<_, _>>(),
                "ops": r.ops, "ns_per_eval": r.ns_per_eval,
                "albedo": r.errors.albedo, "furnace": r.errors.furnace,
                "furnace_gain": r.errors.furnace_gain, "furnace_loss": r.errors.furnace_loss,
                "furnace_peak": r.errors.furnace_peak,
                "furnace_peak_exact": r.errors.furnace_peak_exact,
                "pareto": r.pareto,
            })).collect::<Vec<_>>(),
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    } else if markdown {
        crate::outln!(
            "| model | v | ops m/a/d/s/t | ns/eval | E max (mu, alpha) | E mean | furnace max (mu, alpha) | furnace mean | too bright / too dark | largest albedo | Pareto |\n|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &rows {
            let e = &r.errors;
            crate::outln!(
                "| `{}` | {} | {} | {:.1} | {:.4} ({:.3}, {:.3}) | {:.5} | {:.4} ({:.3}, {:.3}) | {:.5} | {:.4} / {:.4} | {:.3} | {} |",
                r.label(),
                e.v,
                r.ops,
                r.ns_per_eval,
                e.albedo.max_abs,
                e.albedo.cos_v,
                e.albedo.alpha,
                e.albedo.mean_abs,
                e.furnace.max_abs,
                e.furnace.cos_v,
                e.furnace.alpha,
                e.furnace.mean_abs,
                e.furnace_gain,
                e.furnace_loss,
                e.furnace_peak,
                if r.pareto { "yes" } else { "" }
            );
        }
    } else {
        crate::outln!(
            "{:<38} {:<8} {:>13} {:>9} {:>10} {:>10} {:>10} {:>10}  pareto",
            "sheen albedo row (vs sheen-albedo)",
            "v",
            "ops m/a/d/s/t",
            "ns/eval",
            "E max",
            "E mean",
            "furn. max",
            "furn. mean"
        );
        for r in &rows {
            let e = &r.errors;
            crate::outln!(
                "{:<38} {:<8} {:>13} {:>9.1} {:>10.4} {:>10.5} {:>10.4} {:>10.5}  {}",
                r.label(),
                e.v,
                r.ops,
                r.ns_per_eval,
                e.albedo.max_abs,
                e.albedo.mean_abs,
                e.furnace.max_abs,
                e.furnace.mean_abs,
                if r.pareto { "*" } else { "" }
            );
        }
    }
    Ok(())
}
