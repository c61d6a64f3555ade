//! The CLI's analyses (issue 29): `check`, `reproduce`, `fit`, `normalize` (here), `lut`
//! ([`lut`]), `pareto` and `pareto --brdf` ([`pareto`]), `chi2` ([`chi2`]). Each returns the
//! JSON text its command prints with `--json`, built by the same function of the analysis
//! crate, so that the two cannot drift; arguments are checked as the CLI checks its flags
//! (the messages name the Python argument), and long work runs on a worker that Ctrl-C stops.

mod chi2;
mod lut;
mod pareto;

use crate::args::values_arg;
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf::registry;
use fastbrdf_analysis::{check, fit, normalize, reproduce, speed};
use pyo3::exceptions::{PyOSError, PyRuntimeError};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_json, m)?)?;
    m.add_function(wrap_pyfunction!(reproduce_json, m)?)?;
    m.add_function(wrap_pyfunction!(fit_json, m)?)?;
    m.add_function(wrap_pyfunction!(normalize_json, m)?)?;
    m.add_function(wrap_pyfunction!(lut::lut_table, m)?)?;
    m.add_function(wrap_pyfunction!(pareto::pareto_json, m)?)?;
    m.add_function(wrap_pyfunction!(pareto::pareto_brdf_json, m)?)?;
    m.add_function(wrap_pyfunction!(chi2::chi2_json, m)?)?;
    Ok(())
}

/// A value as compact JSON text.
pub(crate) fn to_json(v: &serde_json::Value) -> PyResult<String> {
    serde_json::to_string(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// A file error: an input that cannot be read or is not what it should be is a `ValueError`
/// (the CLI's exit code 2), an output that cannot be written an `OSError` (exit code 3).
pub(crate) fn io_error(e: fastbrdf_io::IoError) -> PyErr {
    match e {
        fastbrdf_io::IoError::Input { .. } => value_error(e),
        fastbrdf_io::IoError::Output { .. } => PyOSError::new_err(e.to_string()),
    }
}

/// A saved `fastbrdf bench --json` run (read once, at most 64 MiB, as the CLI).
pub(crate) fn bench_report(path: &Path) -> PyResult<speed::Report> {
    speed::Report::load(path).map_err(io_error)
}

/// `fastbrdf check --json [--model M] [--full]`'s object, as JSON.
#[pyfunction]
#[pyo3(signature = (model, full))]
pub(crate) fn check_json(py: Python<'_>, model: Option<&str>, full: bool) -> PyResult<String> {
    guard(|| {
        let entries: Vec<&'static fastbrdf::entry::Entry> = match model {
            Some(id) => vec![registry::find(id).map_err(value_error)?],
            None => registry::all().iter().collect(),
        };
        let size = if full {
            fastbrdf::accuracy::SearchSize::FULL
        } else {
            fastbrdf::accuracy::SearchSize::CI
        };
        let report = interruptible(py, |cancel| check::run(&entries, size, &|| stop_if(cancel)))?;
        to_json(&report.json())
    })
}

/// `fastbrdf reproduce --json [--speedups BENCH.json]`'s object, as JSON.
#[pyfunction]
#[pyo3(signature = (speedups))]
pub(crate) fn reproduce_json(py: Python<'_>, speedups: Option<PathBuf>) -> PyResult<String> {
    guard(|| {
        let speedups = match &speedups {
            None => vec![],
            Some(p) => bench_report(p)?.measured_speedups(),
        };
        let report = interruptible(py, |cancel| reproduce::run(&speedups, &|| stop_if(cancel)))?
            .map_err(value_error)?;
        serde_json::to_string(&report).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// A numeric parameter's documented range.
fn number_range(spec: &fastbrdf::params::ParamSpec) -> (f64, f64) {
    match spec.kind {
        fastbrdf::params::ParamKind::Number { min, max, .. } => (min, max),
        fastbrdf::params::ParamKind::Choice { .. } => (f64::NAN, f64::NAN),
    }
}

/// `fastbrdf fit --json`'s object, as JSON. `arg` is the argument the values came in, `n`
/// (lobe families) or `m` (beckmann-power16).
#[pyfunction]
pub(crate) fn fit_json(
    py: Python<'_>,
    family: &str,
    reference: &str,
    arg: &str,
    values: &Bound<'_, PyAny>,
    metric: &str,
    normalized: bool,
) -> PyResult<String> {
    guard(|| {
        let fam = fit::Family::parse(family).ok_or_else(|| {
            value_error(format!(
                "family '{}': expected one of power4, power8, power16, exp2, cubic-rational, beckmann-power16",
                fastbrdf_io::shorten(family, 40)
            ))
        })?;
        let met = fit::Metric::parse(metric).ok_or_else(|| {
            value_error(format!(
                "metric '{}': expected one of max-abs, max-rel-epicentre, rms",
                fastbrdf_io::shorten(metric, 40)
            ))
        })?;
        let want = if fam.is_microfacet() {
            "beckmann-ct"
        } else {
            "pow"
        };
        registry::find(reference).map_err(value_error)?;
        if reference != want {
            return Err(value_error(format!(
                "reference {reference}: the {} family approximates {want}",
                fam.name()
            )));
        }
        let (name, (lo, hi)) = match (arg, fam.is_microfacet()) {
            ("n", false) => ("n", number_range(&fastbrdf::params::N)),
            ("m", true) => ("alpha", number_range(&fastbrdf::params::ALPHA)),
            (_, true) => return Err(value_error("the beckmann-power16 family takes m=...")),
            _ => return Err(value_error("the lobe families take n=...")),
        };
        let ps = values_arg(values, arg)?;
        if let Some(bad) = ps.iter().find(|p| !(**p >= lo && **p <= hi)) {
            return Err(value_error(format!(
                "{arg}: {name} = {} is outside [{lo}, {hi}]",
                fastbrdf_analysis::range::num(*bad)
            )));
        }
        if normalized && fam.is_microfacet() {
            return Err(value_error("normalized applies to the lobe families"));
        }
        let v = interruptible(py, |cancel| {
            let rows = fit::fit_with(fam, met, &ps, normalized, &|| stop_if(cancel));
            let closed = fit::closed_form_of(fam, met, &rows);
            fit::json(fam, met, normalized, &rows, closed.as_ref())
        })?;
        to_json(&v)
    })
}

/// `fastbrdf normalize --json`'s object, as JSON.
#[pyfunction]
#[pyo3(signature = (model, n, fit))]
pub(crate) fn normalize_json(
    py: Python<'_>,
    model: &str,
    n: &Bound<'_, PyAny>,
    fit: Option<&str>,
) -> PyResult<String> {
    guard(|| {
        let e = registry::find(model).map_err(value_error)?;
        if e.info.kind != fastbrdf::Kind::Lobe {
            return Err(value_error(format!(
                "normalize needs a lobe; '{model}' is a {}",
                e.info.kind.name()
            )));
        }
        let ns = values_arg(n, "n")?;
        // Out-of-range exponents are refused before the table, with the registry's message.
        for &v in &ns {
            fastbrdf::ModelSpec::new(model, &[("n", fastbrdf::Given::Num(v))])
                .map_err(value_error)?;
        }
        let form = match fit {
            None => None,
            Some(f) => Some(normalize::Form::parse(f).ok_or_else(|| {
                value_error(format!(
                    "fit '{}': expected seed, linear or seed-published",
                    fastbrdf_io::shorten(f, 40)
                ))
            })?),
        };
        if let Some(form) = form {
            form.check_points(ns.len()).map_err(value_error)?;
        }
        let v = interruptible(py, |_| -> fastbrdf::Result<_> {
            let rows = normalize::table(model, &ns)?;
            let fit = form.map(|f| normalize::fit(f, &rows));
            Ok(normalize::json(model, &rows, fit.as_ref()))
        })?
        .map_err(value_error)?;
        to_json(&v)
    })
}
