//! `fastbrdf chi2`: the chi-square goodness-of-fit test of a BRDF's sampling, as its `--json`
//! object (and, given `out`, its picture).

use super::to_json;
use crate::args::{float_arg, params_arg, spec};
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf::sample::Strategy;
use fastbrdf::{Brdf, Model, ModelSpec, Real};
use fastbrdf_analysis::chi2 as analysis_chi2;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use std::path::PathBuf;

/// The BRDF of `spec` in precision `T` and the strategy resolved for it (the CLI's messages).
fn brdf<T: Real>(spec: &ModelSpec, strategy: &str) -> PyResult<(Box<dyn Brdf<T>>, Strategy)> {
    let id = spec.id();
    let b = match spec.model::<T>().map_err(value_error)? {
        Model::Brdf(b) => b,
        m => {
            return Err(value_error(format!(
                "{id} is a {} model: only full BRDFs sample (a lobe through phong or blinn-phong's lobe=, a distribution through cook-torrance's d=)",
                m.kind().name()
            )));
        }
    };
    let s = Strategy::parse(strategy).ok_or_else(|| {
        value_error(format!(
            "strategy '{}': expected one of {}",
            fastbrdf_io::shorten(strategy, 40),
            Strategy::ALL.map(|s| s.name()).join(", ")
        ))
    })?;
    let s = b
        .resolve(s)
        .map_err(|e| value_error(format!("{id}: {e}")))?;
    Ok((b, s))
}

/// An optional non-negative integer argument.
fn count_arg(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<usize>> {
    obj.map(|o| {
        o.extract::<u64>()
            .map_err(|e| crate::args::named(o.py(), e, name))
            .map(|v| usize::try_from(v).unwrap_or(usize::MAX))
    })
    .transpose()
}

/// `fastbrdf chi2 --json`'s object, as JSON; with `out`, the picture (PNG) is written there.
#[pyfunction]
#[pyo3(signature = (model, params, theta_i, strategy, samples, res, seed, full, precision, out))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn chi2_json(
    py: Python<'_>,
    model: &str,
    params: &Bound<'_, PyAny>,
    theta_i: &Bound<'_, PyAny>,
    strategy: &str,
    samples: Option<&Bound<'_, PyAny>>,
    res: Option<&Bound<'_, PyAny>>,
    seed: &Bound<'_, PyAny>,
    full: bool,
    precision: &str,
    out: Option<PathBuf>,
) -> PyResult<String> {
    guard(|| {
        let spec = spec(model, &params_arg(params)?)?;
        let theta = float_arg(theta_i, "theta_i")?;
        if !(0.0..90.0).contains(&theta) {
            return Err(value_error(format!(
                "theta_i {theta}: expected degrees in [0, 90)"
            )));
        }
        let seed = seed
            .extract::<u64>()
            .map_err(|e| crate::args::named(py, e, "seed"))?;
        let cfg = analysis_chi2::config(
            full,
            count_arg(samples, "samples")?,
            count_arg(res, "res")?,
            seed,
        )
        .map_err(value_error)?;
        let f32 = match precision {
            "f64" => false,
            "f32" => true,
            p => {
                return Err(value_error(format!(
                    "precision '{}': expected f32 or f64",
                    fastbrdf_io::shorten(p, 40)
                )));
            }
        };
        let (b64, s) = brdf::<f64>(&spec, strategy)?;
        let b32 = if f32 {
            Some(brdf::<f32>(&spec, strategy)?.0)
        } else {
            None
        };
        let t = theta.to_radians();
        let wo = [t.sin(), 0.0, t.cos()];
        // Ctrl-C stops the test at its next draw batch or density evaluation.
        let outcome = interruptible(py, |cancel| {
            let check = || stop_if(cancel);
            fastbrdf::chi2::run_brdf_with(b64.as_ref(), b32.as_deref(), wo, s, &cfg, 1, &check)
        })?;
        if let Some(path) = &out {
            let png = analysis_chi2::picture(&outcome).map_err(PyOSError::new_err)?;
            fastbrdf_io::write_atomic(path, &png).map_err(super::io_error)?;
        }
        to_json(&analysis_chi2::json(&outcome, model, s, theta, &spec))
    })
}
