//! `fastbrdf normalize`: Int(n) and coef(n) of a lobe by quadrature, and closed-form fits
//! (fastbrdf-analysis::normalize).

use crate::CliError;
use fastbrdf::{Given, ModelSpec};
use fastbrdf_analysis::{normalize, range};

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf normalize --model flog --n 1..7\n  \
fastbrdf normalize --model flog --n 1..1000 --fit seed\n  fastbrdf normalize --model cubic-rational --n 1..1000 --fit linear --json"
)]
pub struct Args {
    /// A lobe id.
    #[arg(long)]
    model: String,
    /// Exponents: LO..HI[:STEP] (step 1) or a list.
    #[arg(long)]
    n: String,
    /// Fit a closed form to coef(n): seed (a (n + b) + c / (d + n)), linear (a (n + b)), or
    /// seed-published (seed 001's printed constants, not fitted).
    #[arg(long, value_parser = ["seed", "linear", "seed-published"])]
    fit: Option<String>,
    /// Print JSON: {"model", "rows": [{n, int, coef, int_err}], "fit": {...}}.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let e = fastbrdf::registry::find(&a.model)?;
    if e.info.kind != fastbrdf::Kind::Lobe {
        return Err(CliError::input(format!(
            "normalize needs a lobe; '{}' is a {}",
            a.model,
            e.info.kind.name()
        )));
    }
    let ns = range::parse(&a.n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
    // Out-of-range exponents are refused before the table, with the registry's message.
    for n in [ns[0], ns[ns.len() - 1]] {
        ModelSpec::new(&a.model, &[("n", Given::Num(n))])?;
    }
    if let Some(form) = a.fit.as_deref().and_then(normalize::Form::parse) {
        form.check_points(ns.len()).map_err(CliError::input)?;
    }
    let rows = normalize::table(&a.model, &ns)?;
    let fit = a
        .fit
        .as_deref()
        .and_then(normalize::Form::parse)
        .map(|f| normalize::fit(f, &rows));
    if a.json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&normalize::json(&a.model, &rows, fit.as_ref()))
                .expect("serialisable")
        );
        return Ok(());
    }
    crate::outln!(
        "Int(n) = integral_0^1 {}(c) c dc and coef(n) = 1 / (2 pi Int(n)) (adaptive Gauss-Kronrod, rel. tol. 1e-12)",
        a.model
    );
    let shown: Vec<_> = if rows.len() <= 40 {
        rows.iter().collect()
    } else {
        rows.iter()
            .step_by(rows.len().div_ceil(20))
            .chain(rows.last())
            .collect()
    };
    crate::outln!(
        "  {:>8} {:>20} {:>14} {:>10}",
        "n",
        "Int(n)",
        "coef(n)",
        "err(Int)"
    );
    for r in shown {
        crate::outln!(
            "  {:>8} {:>20.14e} {:>14.8} {:>10.1e}",
            r.n,
            r.int,
            r.coef,
            r.int_err
        );
    }
    if let Some(f) = fit {
        crate::outln!("\nfit {} over {} values of n:", f.form, rows.len());
        for (k, v) in &f.constants {
            crate::outln!("  {k} = {v:.8}");
        }
        crate::outln!("  RMS of coef_fit - coef        {:.6e}", f.rms);
        crate::outln!(
            "  max |coef_fit / coef - 1|     {:.6e} (n = {})",
            f.max_rel,
            f.max_rel_at
        );
        crate::outln!(
            "  energy residual max |coef_fit 2 pi Int - 1| = {:.6e}",
            f.energy_residual_max
        );
    }
    Ok(())
}
