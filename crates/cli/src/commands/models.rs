//! `fastbrdf models`: the registry as a table or JSON.

use crate::CliError;
use fastbrdf::{Kind, Zone, registry};
use std::fmt::Write;

#[derive(clap::Args)]
pub struct Args {
    /// Print JSON: {"models": [{id, kind, params, formula, source, ops, bounds, f32_bound, note,
    /// instructions}]}. `instructions`: the model's exported shader at its defaults, counted
    /// after an optimising compiler (SPIR-V through `spirv-opt -O`), {arithmetic,
    /// transcendental, division_sqrt, branches, select, other, total}; the same on every
    /// machine (fastbrdf_gpu::cost; its committed table, so no spirv-opt is needed here).
    #[arg(long)]
    json: bool,
    /// Only models of this kind.
    #[arg(long, value_parser = ["lobe", "distribution", "shadowing", "fresnel", "brdf", "env"])]
    kind: Option<String>,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let models: Vec<_> = registry::all()
        .iter()
        .map(|e| &e.info)
        .filter(|i| a.kind.as_deref().is_none_or(|k| i.kind.name() == k))
        .collect();
    if a.json {
        let list: Vec<serde_json::Value> = models
            .iter()
            .map(|m| fastbrdf_gpu::cost::model_entry(m))
            .collect();
        let v = serde_json::json!({ "models": list });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("registry serialises")
        );
        return Ok(());
    }
    crate::out!("{}", table(&models));
    Ok(())
}

/// A bound as `abs|abs/peak|rel [zone] BOUND (PARAM LO..HI)`: the label says what the error
/// is divided by for a model of `kind` (`fastbrdf::accuracy::bound_label`).
fn bound_text(kind: Kind, b: &fastbrdf::ErrorBound) -> String {
    let metric = fastbrdf::accuracy::bound_label(kind, b.metric);
    let zone = match b.zone {
        Zone::All => String::new(),
        Zone::Epicentre => " epi".into(),
        Zone::Band { lo, hi } => format!(" {lo}-{hi}"),
    };
    format!(
        "{metric}{zone} {} ({} {}..{})",
        b.bound, b.param.0, b.param.1, b.param.2
    )
}

/// A plain-text table, one block per kind.
pub fn table(models: &[&fastbrdf::ModelInfo]) -> String {
    let mut out = String::new();
    // The id column fits the longest id (31 characters today), in every block alike.
    let w = models.iter().map(|m| m.id.len()).max().unwrap_or(0).max(24);
    for kind in [
        Kind::Lobe,
        Kind::Distribution,
        Kind::Shadowing,
        Kind::Fresnel,
        Kind::Brdf,
        Kind::Env,
    ] {
        let rows: Vec<_> = models.iter().filter(|m| m.kind == kind).collect();
        if rows.is_empty() {
            continue;
        }
        let _ = writeln!(out, "{}", kind.name().to_uppercase());
        let _ = writeln!(
            out,
            "  {:<w$} {:<34} {:<14} {:<8} error bound vs reference",
            "id", "parameters (default)", "ops m/a/d/s/t", "f32"
        );
        for m in rows {
            let params: Vec<String> = m
                .params
                .iter()
                .map(|p| format!("{}={}", p.name, p.default_text()))
                .collect();
            let o = m.ops;
            let ops = format!(
                "{}/{}/{}/{}/{}",
                o.mul, o.add, o.div, o.sqrt, o.transcendental
            );
            let bounds: Vec<String> = m
                .bounds
                .iter()
                .map(|b| format!("{}: {}", b.reference, bound_text(m.kind, b)))
                .collect();
            let mut params_text = params.join(" ");
            if params_text.len() > 34 {
                params_text.truncate(31);
                params_text.push_str("...");
            }
            let first = bounds.first().cloned().unwrap_or_else(|| "-".into());
            let _ = writeln!(
                out,
                "  {:<w$} {:<34} {:<14} {:<8.0e} {}",
                m.id, params_text, ops, m.f32_bound, first
            );
            for b in bounds.iter().skip(1) {
                let _ = writeln!(out, "  {:<w$} {:<34} {:<14} {:<8} {}", "", "", "", "", b);
            }
        }
        out.push('\n');
    }
    out.push_str(
        "ops: multiplies/adds/divides/square roots/transcendental calls per evaluation.\n",
    );
    out.push_str("f32: documented bound of |f32 - f64| / max(1, |f64|) over the whole domain.\n");
    out.push_str("error bound: abs/peak = max |f - ref| / peak, peak = the reference's largest value at the same\n");
    out.push_str("  parameter (\"divided_by\": \"peak\" in --json); abs = the same where that peak is 1 (lobes, shadowing),\n");
    out.push_str(
        "  so an absolute error; rel = max |f - ref| / ref (\"divided_by\": \"reference\");\n",
    );
    out.push_str("  epi = where ref >= 0.5 peak, lo-hi = where lo < ref/peak < hi; '-' = a reference, an exact model,\n");
    out.push_str("  or a normalised/wrapper model (checked by the energy tests). `fastbrdf check` re-measures every bound.\n");
    out
}
