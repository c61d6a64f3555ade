//! `fastbrdf conform MODEL` (issue 31): the checks a renderer's BSDF must pass
//! (`fastbrdf_analysis::conform`), on a registry BRDF or a user's model (`file:PATH`), one
//! line per check and a verdict, or the report as JSON.

use super::common::progress;
use crate::model_args::{self, ModelArgs, Use};
use crate::{CliError, EXIT_CHECK_FAILED};
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, UserBrdf};
use fastbrdf_analysis::conform::{self, CHECKS, Config, Report};
use fastbrdf_io::{shorten, shorten_middle};
use std::sync::Arc;

/// The most characters of a given value quoted in a message.
const QUOTE: usize = 40;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf conform cook-torrance --param d=ggx --param alpha=0.1\n  \
fastbrdf conform ward --strategy cosine --json\n  \
fastbrdf conform cook-torrance --param alpha=0.3 --reference cook-torrance --reference-param alpha=0.3 --param d=ggx\n  \
fastbrdf conform file:my.brdf --param roughness=0.2 --full\n\n\
Checks (each prints PASS, FAIL or SKIP with its number and where it was found):\n  \
finite            f finite on a grid of direction pairs (z exactly 0 and 1 included) and random pairs\n  \
non-negative      the least value >= 0\n  \
non-finite-input  NaN or infinite components in wi or wo give finite values >= 0\n  \
reciprocity       max |f(wi,wo) - f(wo,wi)| cos_i cos_o <= 1e-3 of its peak\n  \
energy            directional albedo (integral of f cos over wi) <= 1 + 1e-3, normal to grazing\n  \
reference         with --reference: max |f - ref| <= 1e-3 of the reference's peak; relative, RMS\n  \
chi2              the sampler against its pdf (Mitsuba's chi-square test, Bonferroni over angles)\n  \
weight            weight = f cos / pdf per sample, within 1e-3 relative\n  \
pdf-integral      the pdf's integral over the hemisphere <= 1 + 1e-3 (= 1: covers the hemisphere)\n  \
pdf-coverage      pdf > 0 wherever f cos > 1e-4 of its peak (else the estimator is biased)\n  \
pdf-sample        pdf(wo, wi) of each drawn wi equals the pdf the sampler reported\n\
The sampling checks run at wo = 0, 45, 80 degrees (more with --full); a model that does not\n\
sample skips them. The book's conform page has the definitions.\n\n\
Exit codes: 0 every check passed, 1 a check failed (or the evaluator or GPU failed), 2 bad\n\
input (unknown model, invalid parameter or strategy; nothing on stdout). Progress on stderr."
)]
pub struct Args {
    /// Model id: a full BRDF (see `fastbrdf models --kind brdf`), or a user's model
    /// `file:PATH` (a BRDF Explorer `.brdf` file, a `.wgsl` or `.glsl` function).
    model: String,
    #[command(flatten)]
    model_args: ModelArgs,
    /// A reference BRDF to compare the model against (registry id or `file:PATH`).
    #[arg(long, value_name = "ID")]
    reference: Option<String>,
    /// A parameter of the reference, NAME=VALUE; repeat for several.
    #[arg(
        long = "reference-param",
        value_name = "NAME=VALUE",
        requires = "reference"
    )]
    reference_params: Vec<String>,
    /// Sampling strategy of a registry model: auto (its default), cosine, lobe, d-cos, vndf,
    /// twin.
    #[arg(long, default_value = "auto")]
    strategy: String,
    /// More samples, bins, angles and pairs (Mitsuba's chi-square sizes): minutes, not seconds.
    #[arg(long)]
    full: bool,
    /// Print the report as JSON (non-finite numbers are null).
    #[arg(long)]
    json: bool,
}

/// The model `id` with `args`' values: a user's model (`file:PATH`) or a registry BRDF
/// sampled by `--strategy`. Every error is exit 2 naming the model or the value, except a
/// GPU failure loading a user's model (1).
fn model(id: &str, args: &Args) -> Result<Arc<dyn UserBrdf>, CliError> {
    if let Some(u) = args.model_args.user(id)? {
        if args.strategy != "auto" {
            return Err(CliError::input(format!(
                "--strategy {}: a user's model ({}) samples as its file says",
                shorten(&args.strategy, QUOTE),
                shorten_middle(id, QUOTE)
            )));
        }
        return Ok(u);
    }
    let spec = args.model_args.spec(id, Use::AsIs)?;
    let s = Strategy::parse(&args.strategy).ok_or_else(|| {
        CliError::input(format!(
            "--strategy '{}': expected one of {}",
            shorten(&args.strategy, QUOTE),
            Strategy::ALL.map(|s| s.name()).join(", ")
        ))
    })?;
    Ok(Arc::new(Builtin::new(&spec, s)?))
}

/// The reference `id` with its `--reference-param` values (sampled by its default).
fn reference(id: &str, args: &Args) -> Result<Arc<dyn UserBrdf>, CliError> {
    let given = model_args::pairs(&args.reference_params).map_err(|e| CliError {
        message: e.message.replace("--param", "--reference-param"),
        ..e
    })?;
    if let Some(u) = model_args::user(id, &given)? {
        return Ok(u);
    }
    let spec = model_args::spec(id, &given, None, None, Use::AsIs).map_err(|e| {
        CliError::input(format!(
            "--reference {}: {}",
            shorten_middle(id, QUOTE),
            e.message
        ))
    })?;
    Ok(Arc::new(Builtin::new(&spec, Strategy::Auto).map_err(
        |e| CliError::input(format!("--reference {}: {e}", shorten_middle(id, QUOTE))),
    )?))
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let m = model(&a.model, a)?;
    let r = a
        .reference
        .as_deref()
        .map(|id| reference(id, a))
        .transpose()?;
    let cfg = if a.full { Config::full() } else { Config::ci() };
    let bar = progress::bar(CHECKS.len() as u64, "conform");
    let report = conform::run(m.as_ref(), r.as_deref(), &cfg, &|check: &str| {
        bar.set_message(check.to_string());
        bar.inc(1);
    });
    bar.finish_and_clear();
    let report = report.map_err(|e| CliError {
        code: EXIT_CHECK_FAILED,
        message: format!("conform: {e}"),
    })?;
    let text = if a.json {
        format!(
            "{}\n",
            serde_json::to_string_pretty(&report).expect("a report serialises")
        )
    } else {
        text(&report)
    };
    super::write_stdout(text.as_bytes())?;
    let failed = report.failed();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(CliError {
            code: EXIT_CHECK_FAILED,
            message: format!("{}: failed {}", report.model, failed.join(", ")),
        })
    }
}

/// One line per check, then the verdict.
fn text(r: &Report) -> String {
    let mut s = String::new();
    for c in &r.checks {
        s += &format!("{} {:<17} {}\n", c.status.label(), c.check, c.summary);
    }
    let failed = r.failed();
    let skipped = r
        .checks
        .iter()
        .filter(|c| c.status == conform::Status::Skip)
        .count();
    if failed.is_empty() {
        s += &format!(
            "{} conforms ({} mode: {} checks passed, {skipped} skipped)\n",
            r.model,
            r.mode,
            r.checks.len() - skipped
        );
    } else {
        s += &format!(
            "{} does not conform ({} mode): {} failed\n",
            r.model,
            r.mode,
            failed.join(", ")
        );
    }
    s
}
