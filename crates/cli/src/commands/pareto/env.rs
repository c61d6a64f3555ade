//! `fastbrdf pareto --env`: the DFG ledger, every split-sum model and table configuration
//! against `env-brdf` beside its cost, the front marked (fastbrdf-analysis::pareto_env).

use crate::CliError;
use crate::commands::common::progress::bar;
use fastbrdf_analysis::pareto_env;

pub fn run(json: bool, markdown: bool) -> Result<(), CliError> {
    let pb = bar(pareto_env::configs().len() as u64, "pareto --env");
    let rows = pareto_env::rows(&|| pb.inc(1))?;
    pb.finish_and_clear();
    if json {
        let v = serde_json::json!({
            "reference": pareto_env::REFERENCE,
            "rows": rows.iter().map(|r| serde_json::json!({
                "label": r.label(), "model": r.model,
                "params": r.params.iter().cloned().collect::<std::collections::BTreeMap<_, _>>(),
                "ops": r.ops, "ns_per_eval": r.ns_per_eval, "max_abs": r.max_abs,
                "scale": r.errors.scale, "bias": r.errors.bias, "furnace": r.errors.furnace,
                "furnace_gain": r.errors.furnace_gain, "furnace_loss": r.errors.furnace_loss,
                "pareto": r.pareto,
            })).collect::<Vec<_>>(),
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    } else if markdown {
        crate::outln!(
            "| model | ops m/a/d/s/t | ns/eval | scale max (cos_v, alpha) | scale mean | bias max (cos_v, alpha) | bias mean | furnace max | furnace mean | too bright / too dark | Pareto |\n|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &rows {
            let e = &r.errors;
            crate::outln!(
                "| `{}` | {} | {:.1} | {:.4} ({:.3}, {:.3}) | {:.5} | {:.4} ({:.3}, {:.3}) | {:.5} | {:.4} | {:.5} | {:.4} / {:.4} | {} |",
                r.label(),
                r.ops,
                r.ns_per_eval,
                e.scale.max_abs,
                e.scale.cos_v,
                e.scale.alpha,
                e.scale.mean_abs,
                e.bias.max_abs,
                e.bias.cos_v,
                e.bias.alpha,
                e.bias.mean_abs,
                e.furnace.max_abs,
                e.furnace.mean_abs,
                e.furnace_gain,
                e.furnace_loss,
                if r.pareto { "yes" } else { "" }
            );
        }
    } else {
        crate::outln!(
            "{:<40} {:>13} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10}  pareto",
            "env model (vs env-brdf)",
            "ops m/a/d/s/t",
            "ns/eval",
            "scale max",
            "scale mean",
            "bias max",
            "bias mean",
            "furn. max"
        );
        for r in &rows {
            let e = &r.errors;
            crate::outln!(
                "{:<40} {:>13} {:>9.1} {:>10.4} {:>10.5} {:>10.4} {:>10.5} {:>10.4}  {}",
                r.label(),
                r.ops,
                r.ns_per_eval,
                e.scale.max_abs,
                e.scale.mean_abs,
                e.bias.max_abs,
                e.bias.mean_abs,
                e.furnace.max_abs,
                if r.pareto { "*" } else { "" }
            );
        }
    }
    Ok(())
}
