//! `fastbrdf pareto`: error against cost for every lobe (fastbrdf-analysis::pareto), and with
//! `--brdf` for Cook-Torrance configurations ([`brdf`]), with `--env` for the split-sum models
//! (the DFG ledger, [`env`]) and with `--sheen` for the sheen albedo rows ([`sheen`]).

mod brdf;
mod env;
mod sheen;

use super::common::figures::save_error;
use super::common::progress::bar;
use crate::CliError;
use fastbrdf_analysis::pareto;
use fastbrdf_analysis::plot::save_scatter;
use std::path::PathBuf;

/// Every lobe against `pow` (the energy-normalised flog variants are left out: their scale
/// differs from `pow` by design and the energy tests cover them).
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf pareto\n  fastbrdf pareto --json\n  fastbrdf pareto --markdown --out fastbrdf-out/pareto\n  \
fastbrdf pareto --brdf --mesh face.obj\n  fastbrdf pareto --env --markdown\n  fastbrdf pareto --sheen --markdown\n  fastbrdf pareto --brdf --alpha 0.1,0.3,0.6 --reference d=beckmann,g=smith,f=dielectric,eta=1.5 --json\n\n\
Output: a table on stdout (text, --json or --markdown). The plot (PNG and SVG, written both or\n\
neither) is written only with --out; nothing is written to disk otherwise. A model whose\n\
error or throughput is unknown has null in JSON.\n\n\
--brdf: cook-torrance configurations (D x G x F) against --reference at each --alpha: ns per\n\
evaluation of the batch kernel (4096 direction pairs, one core, measured now) and its ratio to\n\
the reference's; max |g - g_ref| / max g_ref and the relative L2 error (rms_rel) of\n\
g = f cos_i cos_o over pairs of hemisphere directions (f64); mean FLIP of a sphere render (and\n\
of --mesh) against the reference's. JSON: {reference, reference_label, alphas, grid, size, spp,\n\
mesh, front_on, rows: [{label, d, g, f, denominator, params, alpha, reference, simd,\n\
ns_per_eval, cost_ratio, max_rel_peak, max_at_deg: [theta_i, theta_o, phi], rms_rel, rms_abs,\n\
flip_sphere, flip_mesh, pareto}]}.\n\n\
--env: every split-sum model (kind env) and every table configuration (env-brdf-table's size\n\
and bits) against env-brdf over cos_v in (0, 1] and alpha in [0.005, 1]: ns per evaluation of\n\
the scale term's batch kernel (4096 values, one core, measured now); per term and for the\n\
white furnace (scale + bias) the max absolute error, where (cos_v, alpha), and the mean\n\
(uniform in cos_v and alpha); the front on (ns, the larger term's max). JSON: {reference,\n\
rows: [{label, model, params, ops, ns_per_eval, max_abs, scale, bias, furnace: {max_abs, cos_v,\n\
alpha, mean_abs, mean_abs_r}, furnace_gain, furnace_loss, pareto}]}.\n\n\
--sheen: every sheen albedo row (sheen-albedo-*, each visibility v and storage) against\n\
sheen-albedo at its v over mu in [0.001, 1] and alpha in [0.07, 1] (sheen-albedo-khronos, which\n\
has no v, at both): ns per evaluation (4096 values, one core, measured now); the albedo's max\n\
absolute error, where (mu, alpha), and mean; the furnace of gltf-pbr's white Lambertian base\n\
under a white sheen with that E in the scaling (A' - A: max, where, mean, gain and loss; the\n\
largest albedo A'); the front per v on (ns, E max). JSON: {reference, rows: [{label, model, v,\n\
params, ops, ns_per_eval, albedo, furnace: {max_abs, cos_v, alpha, mean_abs, mean_abs_r},\n\
furnace_gain, furnace_loss, furnace_peak, furnace_peak_exact, pareto}]}."
)]
pub struct Args {
    /// Print JSON: {"models": [{model, ops, simd_evals_per_s, max_abs_1_1e5, max_abs_8_1e5,
    /// max_rel_epicentre_8_1e5, pareto}]}.
    #[arg(long, conflicts_with = "markdown")]
    json: bool,
    /// Print the Markdown table the book shows (docs/book/src/tuned.md).
    #[arg(long)]
    markdown: bool,
    /// Also write the plot as PATH.png and PATH.svg (PATH without extension); no plot without it.
    #[arg(long, value_name = "PATH")]
    out: Option<PathBuf>,
    /// Use this saved `fastbrdf bench --json` run for the SIMD throughput instead of measuring.
    #[arg(long, value_name = "BENCH.json", conflicts_with = "brdf")]
    bench: Option<PathBuf>,
    #[command(flatten)]
    brdf: brdf::BrdfArgs,
    /// The split-sum models (kind env) and table configurations against env-brdf: the DFG
    /// ledger (docs/book/src/dfg-ledger.md).
    #[arg(long, conflicts_with_all = ["brdf", "bench", "out"])]
    env: bool,
    /// The sheen albedo rows (sheen-albedo-*) against sheen-albedo at their visibility: the
    /// sheen rows of the DFG ledger (docs/book/src/dfg-ledger.md).
    #[arg(long, conflicts_with_all = ["brdf", "bench", "out", "env"])]
    sheen: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    if a.env {
        return env::run(a.json, a.markdown);
    }
    if a.sheen {
        return sheen::run(a.json, a.markdown);
    }
    if a.brdf.brdf {
        return brdf::run(&a.brdf, a.json, a.markdown, a.out.as_deref());
    }
    let saved = match &a.bench {
        None => None,
        Some(p) => Some(fastbrdf_analysis::speed::Report::load(p)?),
    };
    let pb = bar(pareto::lobes().len() as u64, "pareto");
    let rows = pareto::rows(saved.as_ref(), &|| pb.inc(1));
    pb.finish_and_clear();
    if let Some(out) = &a.out {
        let [png, svg] = save_scatter(
            "Lobes: max |error| against cos^n (n = 8..1e5) and SIMD cost",
            "ns per evaluation (SIMD, one core, batch 4096)",
            "max absolute error, n = 8..1e5",
            &pareto::front(&rows),
            &pareto::points(&rows),
            out,
        )
        .map_err(save_error)?;
        eprintln!("wrote {} and {}", png.display(), svg.display());
    }
    if a.json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&pareto::json(&rows)).expect("serialisable")
        );
    } else if a.markdown {
        crate::outln!(
            "| model | ops m/a/d/s/t | SIMD evals/s | max abs, n 1..1e5 | max abs, n 8..1e5 | max rel epicentre, n 8..1e5 | Pareto |\n|---|---|---|---|---|---|---|"
        );
        for r in &rows {
            crate::outln!(
                "| `{}` | {} | {:.2} G | {:.4} | {:.5} | {:.5} | {} |",
                r.model,
                r.ops,
                r.simd_evals_per_s / 1e9,
                r.max_abs_1_1e5,
                r.max_abs_8_1e5,
                r.max_rel_epicentre_8_1e5,
                if r.pareto { "yes" } else { "" }
            );
        }
    } else {
        crate::outln!(
            "{:<26} {:>13} {:>12} {:>12} {:>12} {:>12}  pareto",
            "lobe",
            "ops m/a/d/s/t",
            "SIMD eval/s",
            "abs n1-1e5",
            "abs n8-1e5",
            "rel epi 8+"
        );
        for r in &rows {
            crate::outln!(
                "{:<26} {:>13} {:>11.2}G {:>12.5} {:>12.5} {:>12.5}  {}",
                r.model,
                r.ops,
                r.simd_evals_per_s / 1e9,
                r.max_abs_1_1e5,
                r.max_abs_8_1e5,
                r.max_rel_epicentre_8_1e5,
                if r.pareto { "*" } else { "" }
            );
        }
    }
    Ok(())
}
