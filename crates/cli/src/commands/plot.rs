//! `fastbrdf plot KIND`: charts as PNG and SVG (1200x800), and the seeds' figures for
//! `fastbrdf reproduce --out DIR`.

use super::common::figures::{chart_error, drawn};
use super::common::progress::bar;
use crate::CliError;
use crate::model_args::{ParamArgs, Use};
use fastbrdf::Zone;
use fastbrdf_analysis::plot::{self as plots, Chart, Drawn};
use fastbrdf_analysis::{charts, normalize, range};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf plot lobes --models pow,flog,schlick --n 20\n  \
fastbrdf plot error --model cubic --reference pow --n 200\n  \
fastbrdf plot max-error --models flog,schlick --reference pow --n 1..1000 --metric rel --zone epicentre\n  \
fastbrdf plot coef --model flog --n 1..1000 --fit seed\n  \
fastbrdf plot polar --model cook-torrance --param alpha=0.3 --theta-i 45\n  \
fastbrdf plot albedo --model ward --param alpha=0.5\n\n\
Output: OUT.png and OUT.svg (1200x800), written together or not at all (`coef` also writes\n\
OUT-residual.png and .svg). Every option is checked before anything is computed or written."
)]
pub struct Args {
    #[command(subcommand)]
    kind: Kind,
    /// Output path without extension (writes .png and .svg); default fastbrdf-out/plot-KIND.
    #[arg(long, global = true, value_name = "PATH")]
    out: Option<PathBuf>,
}

const PLOT_PARAM_HELP: &str = "A parameter of the model, NAME=VALUE; repeat for several";

#[derive(clap::Subcommand)]
enum Kind {
    /// Lobe curves of several models against the angle, at one n (the seeds' figures).
    #[command(
        after_help = "Example:\n  fastbrdf plot lobes --models pow,flog,schlick --n 20 --out lobes"
    )]
    Lobes {
        /// Lobe ids, comma-separated (see `fastbrdf models --kind lobe`).
        #[arg(long, value_delimiter = ',', default_value = "pow,flog,schlick")]
        models: Vec<String>,
        /// The exponent n of every lobe (dimensionless, > 0).
        #[arg(long, default_value_t = 20.0)]
        n: f64,
    },
    /// Signed error (model - reference) against the angle, at one n.
    #[command(after_help = "Example:\n  fastbrdf plot error --model cubic --reference pow --n 200")]
    Error {
        /// The approximating lobe id.
        #[arg(long)]
        model: String,
        /// The reference lobe id (pow is cos^n).
        #[arg(long, default_value = "pow")]
        reference: String,
        /// The exponent n (dimensionless, > 0).
        #[arg(long, default_value_t = 20.0)]
        n: f64,
    },
    /// Max error against n for several lobes (log scale).
    #[command(
        after_help = "Example:\n  fastbrdf plot max-error --models flog,schlick --n 1..1000 --metric rel --zone epicentre"
    )]
    MaxError {
        /// Lobe ids, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "flog,schlick")]
        models: Vec<String>,
        /// The reference lobe id.
        #[arg(long, default_value = "pow")]
        reference: String,
        /// Exponents: LO..HI[:STEP] (step 1), LO..HI:logK (K log-spaced values per decade) or
        /// a list A,B,C; at most 1000000 values. The default is the whole domain; beyond
        /// n = 1000 the n axis is logarithmic.
        #[arg(long, default_value = "1..100000:log50")]
        n: String,
        /// abs: max |f - ref|; rel: max |f - ref| / ref.
        #[arg(long, default_value = "abs", value_parser = ["abs", "rel"])]
        metric: String,
        /// all: every cosine in [0, 1]; epicentre: where ref >= 0.5 of its peak.
        #[arg(long, default_value = "all", value_parser = ["all", "epicentre"])]
        zone: String,
    },
    /// coef(n) = 1 / (2 pi Int(n)) of a lobe, with a fitted closed form.
    #[command(
        after_help = "Example:\n  fastbrdf plot coef --model flog --n 1..1000 --fit seed --out coef"
    )]
    Coef {
        /// A lobe id.
        #[arg(long, default_value = "flog")]
        model: String,
        /// Exponents: LO..HI[:STEP] (step 1) or a list A,B,C; at most 1000000 values.
        #[arg(long, default_value = "1..1000")]
        n: String,
        /// The closed form: seed (a (n + b) + c / (d + n)), linear (a (n + b)) or
        /// seed-published (seed 001's printed constants).
        #[arg(long, default_value = "seed", value_parser = ["seed", "linear", "seed-published"])]
        fit: String,
    },
    /// A full BRDF in the plane of incidence, as a polar lobe (f cos theta_o along wo).
    #[command(
        after_help = "Example:\n  fastbrdf plot polar --model cook-torrance --param alpha=0.3 --theta-i 45\n\n\
The incident direction is drawn on the side opposite the mirror direction, at the lobe's peak length.",
        mut_arg("params", |a| a.help(PLOT_PARAM_HELP))
    )]
    Polar {
        /// A BRDF id (see `fastbrdf models --kind brdf`).
        #[arg(long)]
        model: String,
        #[command(flatten)]
        params: ParamArgs,
        /// Incidence angle from the normal, in degrees, in [0, 90).
        #[arg(long, default_value_t = 30.0)]
        theta_i: f64,
    },
    /// Directional albedo against the incidence angle.
    #[command(
        after_help = "Example:\n  fastbrdf plot albedo --model ward --param alpha=0.5",
        mut_arg("params", |a| a.help(PLOT_PARAM_HELP))
    )]
    Albedo {
        /// A BRDF id, or a lobe id (evaluated as an energy-normalised Phong BRDF).
        #[arg(long)]
        model: String,
        #[command(flatten)]
        params: ParamArgs,
    },
}

/// Writes every `(base, drawing)` as `base.png` and `base.svg`, all or nothing.
fn write_drawn(items: &[(PathBuf, Drawn)]) -> Result<(), CliError> {
    let refs: Vec<(&Path, &Drawn)> = items.iter().map(|(b, d)| (b.as_path(), d)).collect();
    for f in plots::write_all(&refs)? {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}

fn finite_n(n: f64) -> Result<f64, CliError> {
    if n.is_finite() && n > 0.0 {
        Ok(n)
    } else {
        Err(CliError::input(format!(
            "--n {n}: must be a positive finite number"
        )))
    }
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let name = match &a.kind {
        Kind::Lobes { .. } => "lobes",
        Kind::Error { .. } => "error",
        Kind::MaxError { .. } => "max-error",
        Kind::Coef { .. } => "coef",
        Kind::Polar { .. } => "polar",
        Kind::Albedo { .. } => "albedo",
    };
    let base = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("fastbrdf-out/plot-{name}")));
    if base.file_name().is_none() {
        return Err(CliError::input(format!(
            "--out {}: expected a path without extension, e.g. out/plot",
            base.display()
        )));
    }
    // Every chart is computed and drawn in memory first; the files are written together.
    let charts: Vec<(PathBuf, Chart)> = match &a.kind {
        Kind::Lobes { models, n } => vec![(
            base,
            charts::lobes(models, finite_n(*n)?).map_err(chart_error)?,
        )],
        Kind::Error {
            model,
            reference,
            n,
        } => vec![(
            base,
            charts::signed_error(model, reference, finite_n(*n)?).map_err(chart_error)?,
        )],
        Kind::MaxError {
            models,
            reference,
            n,
            metric,
            zone,
        } => {
            let ns = range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
            charts::check_lobes(
                models
                    .iter()
                    .map(String::as_str)
                    .chain([reference.as_str()]),
                &ns,
            )
            .map_err(chart_error)?;
            let zone = if zone == "epicentre" {
                Zone::Epicentre
            } else {
                Zone::All
            };
            let title = format!("Max {metric} error against {reference} ({zone:?})");
            let pb = bar((ns.len() * models.len()) as u64, "sweeping");
            let c = charts::max_error(
                models,
                reference,
                &ns,
                metric == "rel",
                zone,
                &title,
                &|| pb.inc(1),
            )
            .map_err(chart_error)?;
            pb.finish_and_clear();
            vec![(base, c)]
        }
        Kind::Coef { model, n, fit } => {
            let ns = range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
            charts::check_lobes([model.as_str()], &ns).map_err(chart_error)?;
            let form = normalize::Form::parse(fit).expect("clap checked the value");
            let (c, r) = charts::coef(model, &ns, form).map_err(chart_error)?;
            let mut rb = base.clone().into_os_string();
            rb.push("-residual");
            vec![(base, c), (PathBuf::from(rb), r)]
        }
        Kind::Polar {
            model,
            params,
            theta_i,
        } => {
            let spec = params.spec(model, Use::AsIs)?;
            vec![(base, charts::polar(&spec, *theta_i).map_err(chart_error)?)]
        }
        Kind::Albedo { model, params } => {
            let spec = params.spec(model, Use::AsIs)?;
            vec![(base, charts::albedo(&spec).map_err(chart_error)?)]
        }
    };
    let items = charts
        .iter()
        .map(|(b, c)| Ok((b.clone(), drawn(c)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    write_drawn(&items)
}
