//! `fastbrdf plot KIND`: charts as PNG and SVG (1200x800), and the seeds' figures for
//! `fastbrdf reproduce --out DIR`.

use super::analysis::bar;
use super::eval::parse_params;
use crate::CliError;
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
The incident direction is drawn on the side opposite the mirror direction, at the lobe's peak length."
    )]
    Polar {
        /// A BRDF id (see `fastbrdf models --kind brdf`).
        #[arg(long)]
        model: String,
        /// A parameter of the model, NAME=VALUE; repeat for several.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Incidence angle from the normal, in degrees, in [0, 90).
        #[arg(long, default_value_t = 30.0)]
        theta_i: f64,
    },
    /// Directional albedo against the incidence angle.
    #[command(after_help = "Example:\n  fastbrdf plot albedo --model ward --param alpha=0.5")]
    Albedo {
        /// A BRDF id, or a lobe id (evaluated as an energy-normalised Phong BRDF).
        #[arg(long)]
        model: String,
        /// A parameter of the model, NAME=VALUE; repeat for several.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
    },
}

/// A chart that cannot be computed: bad input (exit code 2); the incidence angle is named
/// by its option.
fn chart_error(e: charts::ChartError) -> CliError {
    match e {
        charts::ChartError::IncidenceAngle(t) => {
            CliError::input(format!("--theta-i {t} is outside [0, 90) degrees"))
        }
        e => CliError::input(e.to_string()),
    }
}

/// A chart that could not be saved: an output failure (exit code 3).
pub fn save_error(e: plots::SaveError) -> CliError {
    match e {
        plots::SaveError::Io(e) => e.into(),
        plots::SaveError::Draw(_) => CliError::io(e.to_string()),
    }
}

/// Draws a chart in memory; a drawing failure means no output (exit code 3).
fn drawn(c: &Chart) -> Result<Drawn, CliError> {
    plots::render(c).map_err(|e| save_error(plots::SaveError::Draw(e)))
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
        } => vec![(
            base,
            charts::polar(model, &parse_params(params)?, *theta_i).map_err(chart_error)?,
        )],
        Kind::Albedo { model, params } => vec![(
            base,
            charts::albedo(model, &parse_params(params)?).map_err(chart_error)?,
        )],
    };
    let items = charts
        .iter()
        .map(|(b, c)| Ok((b.clone(), drawn(c)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    write_drawn(&items)
}

/// Draws the plots of the seeds' figures and stages them (PNG and SVG) in `set`, in its
/// subfolder `folder` ("" for its top).
pub fn stage_seed_figures(set: &mut fastbrdf_io::OutputSet, folder: &str) -> Result<(), CliError> {
    let pb = bar(charts::seed_figure_steps() as u64, "figures");
    let figures = charts::seed_figures(&|| pb.inc(1)).map_err(chart_error)?;
    pb.finish_and_clear();
    for (stem, chart) in figures {
        let name = Path::new(folder).join(stem);
        plots::stage(set, &drawn(&chart)?, &name.to_string_lossy())?;
    }
    Ok(())
}
