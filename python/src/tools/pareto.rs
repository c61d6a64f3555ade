//! `fastbrdf pareto` (lobes against `pow`) and `fastbrdf pareto --brdf` (Cook-Torrance
//! configurations against a reference), as their `--json` objects.

use super::{bench_report, to_json};
use crate::args::{u32_arg, values_arg};
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf_analysis::pareto;
use fastbrdf_analysis::pareto_brdf::{self as pb, Config, FrontOn, Grid, Images};
use fastbrdf_analysis::range;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::time::Duration;

/// `fastbrdf pareto --json [--bench BENCH.json]`'s object, as JSON.
#[pyfunction]
#[pyo3(signature = (bench))]
pub(crate) fn pareto_json(py: Python<'_>, bench: Option<PathBuf>) -> PyResult<String> {
    guard(|| {
        let saved = bench.as_deref().map(bench_report).transpose()?;
        let rows = interruptible(py, |cancel| {
            pareto::rows(saved.as_ref(), &|| stop_if(cancel))
        })?;
        to_json(&pareto::json(&rows))
    })
}

/// `fastbrdf pareto --brdf --json`'s object, as JSON; the arguments are its options
/// (`alpha` the values of `--alpha`).
#[pyfunction]
#[pyo3(signature = (alpha, reference, size, mesh, all, quick, front_on, grid, costs))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn pareto_brdf_json(
    py: Python<'_>,
    alpha: &Bound<'_, PyAny>,
    reference: &str,
    size: &Bound<'_, PyAny>,
    mesh: Option<PathBuf>,
    all: bool,
    quick: bool,
    front_on: &str,
    grid: Option<&str>,
    costs: Option<PathBuf>,
) -> PyResult<String> {
    guard(|| {
        let alphas = values_arg(alpha, "alpha")?;
        let (lo, hi) = (fastbrdf::params::ALPHA_MIN, 1.0);
        if let Some(bad) = alphas.iter().find(|x| !(**x >= lo && **x <= hi)) {
            return Err(value_error(format!(
                "alpha: {} is outside [{lo}, {hi}]",
                range::num(*bad)
            )));
        }
        if alphas.len() > 16 {
            return Err(value_error("alpha: at most 16 values"));
        }
        let reference =
            Config::parse(reference).map_err(|e| value_error(format!("reference: {e}")))?;
        let size = u32_arg(size, "size")?;
        let size = if quick { size.min(32) } else { size };
        if size > 1024 {
            return Err(value_error("size: at most 1024"));
        }
        let front_on = FrontOn::parse(front_on).ok_or_else(|| {
            value_error(format!(
                "front_on '{}': expected rms, max or flip",
                fastbrdf_io::shorten(front_on, 40)
            ))
        })?;
        let grid = match grid {
            Some(g) => Grid::parse(g).map_err(|e| value_error(format!("grid {e}")))?,
            None if quick => Grid::QUICK,
            None => Grid::DEFAULT,
        };
        let images = if size == 0 {
            if mesh.is_some() {
                return Err(value_error("mesh needs renders: size above 0"));
            }
            None
        } else {
            Some(Images::new(size, mesh.clone()).map_err(value_error)?)
        };
        let saved_costs = match &costs {
            None => None,
            Some(p) => {
                let bytes =
                    fastbrdf_io::read_bounded(p, 64 << 20, "costs").map_err(super::io_error)?;
                let v: serde_json::Value = serde_json::from_slice(&bytes)
                    .map_err(|e| value_error(format!("costs {}: {e}", p.display())))?;
                Some(
                    pb::saved_costs(&v)
                        .map_err(|e| value_error(format!("costs {}: {e}", p.display())))?,
                )
            }
        };
        let o = pb::Options {
            saved_costs,
            reference,
            configs: pb::configurations(all),
            alphas,
            grid,
            budget: Duration::from_millis(if quick { 5 } else { 60 }),
            images,
            front_on,
        };
        let rows =
            interruptible(py, |cancel| pb::run(&o, &|| stop_if(cancel)))?.map_err(
                |e| match &costs {
                    Some(p) if e.starts_with("the saved costs") => {
                        value_error(format!("costs {}: {e}", p.display()))
                    }
                    _ => value_error(e),
                },
            )?;
        let mesh = mesh.as_ref().map(|m| m.display().to_string());
        to_json(&pb::json(&o, &rows, size, mesh.as_deref()))
    })
}
