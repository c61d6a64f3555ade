//! Charts shared by `plot`, `fit`, `pareto`, `reproduce` and `demo`: drawing in memory,
//! the seeds' figures, and the exit codes of a chart that cannot be computed (2) or saved (3).

use super::progress::bar;
use crate::CliError;
use fastbrdf_analysis::charts;
use fastbrdf_analysis::plot::{self as plots, Chart, Drawn};
use std::path::Path;

/// A chart that cannot be computed: bad input (exit code 2); the incidence angle is named
/// by its option.
pub fn chart_error(e: charts::ChartError) -> CliError {
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
pub fn drawn(c: &Chart) -> Result<Drawn, CliError> {
    plots::render(c).map_err(|e| save_error(plots::SaveError::Draw(e)))
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
