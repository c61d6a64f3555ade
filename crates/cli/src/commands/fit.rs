//! `fastbrdf fit`: coefficients that minimise the error over the whole lobe
//! (fastbrdf-analysis::fit).

use super::common::numbers::num;
use super::common::progress::bar;
use crate::CliError;
use fastbrdf_analysis::fit::{self, Family, Metric};
use fastbrdf_analysis::range;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf fit --family power16 --reference pow --n 1..1e5:3\n  \
fastbrdf fit --family exp2 --reference pow --n 8,16,100 --metric max-rel-epicentre\n  \
fastbrdf fit --family beckmann-power16 --reference beckmann-ct --m 0.05..0.6:0.05 --json"
)]
pub struct FitArgs {
    /// power4, power8, power16, exp2, cubic-rational or beckmann-power16.
    #[arg(long, value_parser = ["power4", "power8", "power16", "exp2", "cubic-rational", "beckmann-power16"])]
    family: String,
    /// The exact model: pow for the lobe families, beckmann-ct for beckmann-power16.
    #[arg(long)]
    reference: String,
    /// Exponents (lobe families): LO..HI[:STEP] or a list.
    #[arg(long, conflicts_with = "m")]
    n: Option<String>,
    /// Slopes (beckmann-power16): LO..HI[:STEP] or a list.
    #[arg(long)]
    m: Option<String>,
    /// What to minimise.
    #[arg(long, default_value = "max-abs", value_parser = ["max-abs", "max-rel-epicentre", "rms"])]
    metric: String,
    /// Fit the energy-normalised forms: coef(n) lobe against (n + 2)/(2 pi) c^n, coef(n) by
    /// quadrature for every candidate coefficient (lobe families).
    #[arg(long)]
    normalized: bool,
    /// Print JSON: {"family", "metric", "normalized", "param": "n"|"alpha", "rows": [{n or alpha,
    /// coefficient, error, untuned_coefficient, untuned_error}], "closed_form": {r,
    /// max_coefficient_deviation, worst_gain, worst_gain_at}}; no finite value is null.
    #[arg(long)]
    json: bool,
}

/// A numeric parameter's documented range (the one `Params::resolve` enforces).
fn number_range(spec: &fastbrdf::params::ParamSpec) -> (f64, f64) {
    match spec.kind {
        fastbrdf::params::ParamKind::Number { min, max, .. } => (min, max),
        fastbrdf::params::ParamKind::Choice { .. } => unreachable!("n and alpha are numbers"),
    }
}

pub fn run_fit(a: &FitArgs) -> Result<(), CliError> {
    let family = Family::parse(&a.family).expect("clap checked it");
    let metric = Metric::parse(&a.metric).expect("clap checked it");
    let want_ref = if family.is_microfacet() {
        "beckmann-ct"
    } else {
        "pow"
    };
    fastbrdf::registry::find(&a.reference)?;
    if a.reference != want_ref {
        return Err(CliError::input(format!(
            "--reference {}: the {} family approximates {want_ref}",
            a.reference,
            family.name()
        )));
    }
    let (text, step, name, lo, hi) = match (&a.n, &a.m, family.is_microfacet()) {
        (Some(n), None, false) => {
            let (lo, hi) = number_range(&fastbrdf::params::N);
            (n, 1.0, "n", lo, hi)
        }
        (None, Some(m), true) => {
            let (lo, hi) = number_range(&fastbrdf::params::ALPHA);
            (m, 0.01, "alpha", lo, hi)
        }
        (_, _, true) => {
            return Err(CliError::input(
                "the beckmann-power16 family takes --m RANGE",
            ));
        }
        _ => return Err(CliError::input("the lobe families take --n RANGE")),
    };
    let flag = if name == "n" { "n" } else { "m" };
    let ps = range::parse(text, step).map_err(|e| CliError::input(format!("--{flag}: {e}")))?;
    if let Some(bad) = ps.iter().find(|p| !(**p >= lo && **p <= hi)) {
        return Err(CliError::input(format!(
            "--{flag}: {name} = {} is outside [{lo}, {hi}]",
            num(*bad)
        )));
    }
    let pb = bar(ps.len() as u64, "fitting");
    if a.normalized && family.is_microfacet() {
        return Err(CliError::input("--normalized applies to the lobe families"));
    }
    let rows = fit::fit_with(family, metric, &ps, a.normalized, &|| pb.inc(1));
    pb.finish_and_clear();
    let closed = fit::closed_form_of(family, metric, &rows);
    if a.json {
        let v = fit::json(family, metric, a.normalized, &rows, closed.as_ref());
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    let norm = if a.normalized {
        ", energy-normalised forms, errors in units of the normalised reference's peak"
    } else {
        ""
    };
    crate::outln!(
        "{} against {} ({}{norm}), optimal coefficient per {name}:",
        family.name(),
        a.reference,
        a.metric
    );
    crate::outln!(
        "  {name:>8} {:>14} {:>12} {:>14} {:>12} {:>7}",
        "coefficient",
        "error",
        "untuned coef",
        "untuned err",
        "ratio"
    );
    let shown: Vec<_> = if rows.len() <= 30 {
        rows.iter().collect()
    } else {
        rows.iter()
            .step_by(rows.len().div_ceil(20))
            .chain(rows.last())
            .collect()
    };
    for r in shown {
        let ratio = if r.untuned_error > 0.0 {
            format!("{:.3}", r.error / r.untuned_error)
        } else {
            "exact".into()
        };
        crate::outln!(
            "  {:>8} {:>14.8} {:>12.6e} {:>14.8} {:>12.6e} {:>7}",
            r.param,
            r.coefficient,
            r.error,
            r.untuned_coefficient,
            r.untuned_error,
            ratio
        );
    }
    let worst = fit::worst_tuned_gain(&rows);
    crate::outln!("\nworst tuned / untuned error over {name} >= 8: {worst:.4}");
    if let Some(c) = closed {
        let what = if family == Family::CubicRational {
            "Q(n) = R(1/n)"
        } else {
            "k(n) = k0(n) R(1/n)"
        };
        crate::outln!("closed form {what}, R(x) = r0 + r1 x + r2 x^2 + r3 x^3 + r4 x^4:");
        crate::outln!(
            "  r = [{}]",
            c.r.iter()
                .map(|v| format!("{v:e}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        crate::outln!(
            "  its own error: coefficient within {:.2e} of the optima; tuned / untuned error with it <= {:.4} (worst at {name} = {})",
            c.max_coefficient_deviation,
            c.worst_gain,
            c.worst_gain_at
        );
    }
    Ok(())
}
