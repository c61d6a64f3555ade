//! The analysis crate's error sweeps (`errors_json`), ranges (`parse_range`) and albedo
//! curves (`albedo_json`), checked as the CLI checks and returned as its JSON.

use crate::args::{float_arg, full_spec, grey_spec, params_arg, values_arg};
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf::{ModelSpec, registry};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

fn zone_arg(zone: &str) -> PyResult<fastbrdf::Zone> {
    use fastbrdf::Zone;
    Ok(match zone {
        "all" => Zone::All,
        "epicentre" => Zone::Epicentre,
        z => {
            let band = z.strip_prefix("band:").ok_or_else(|| {
                value_error(format!(
                    "zone '{}': expected all, epicentre or band:LO,HI",
                    fastbrdf_io::shorten(z, 40)
                ))
            })?;
            let parsed = band.split_once(',').and_then(|(a, b)| {
                Some((a.trim().parse::<f64>().ok()?, b.trim().parse::<f64>().ok()?))
            });
            match parsed {
                Some((lo, hi)) if lo >= 0.0 && hi > lo && hi <= 1.0 => Zone::Band { lo, hi },
                _ => {
                    return Err(value_error(format!(
                        "zone '{}': need band:LO,HI with 0 <= LO < HI <= 1 (fractions of the reference's peak)",
                        fastbrdf_io::shorten(z, 40)
                    )));
                }
            }
        }
    })
}

/// `fastbrdf errors`' rows as JSON: `[{param, max_abs, max_abs_at, max_rel, max_rel_at, rms,
/// samples}]`, checked as the CLI checks (ids, kinds, the parameter, its values' range and
/// count). Runs on a worker that Ctrl-C stops.
#[pyfunction]
pub(crate) fn errors_json(
    py: Python<'_>,
    model: &str,
    reference: &str,
    param: &str,
    values: &Bound<'_, PyAny>,
    zone: &str,
) -> PyResult<String> {
    use fastbrdf_analysis::errors;
    guard(|| {
        let zone = zone_arg(zone)?;
        let values = values_arg(values, "values")?;
        let spec = errors::Spec {
            model: model.into(),
            reference: reference.into(),
            param: param.into(),
            zone,
        };
        spec.validate().map_err(value_error)?;
        let kinds = [model, reference]
            .map(|id| registry::find(id).map(|e| (e.info.id, e.info.kind)))
            .into_iter()
            .collect::<Result<Vec<_>, _>>()
            .map_err(value_error)?;
        let rows = interruptible(py, |cancel| -> Result<_, String> {
            // Out-of-range values are refused before the sweep with the registry's message
            // (as the CLI).
            for &(id, kind) in &kinds {
                if kind == fastbrdf::Kind::Env {
                    let (lo, hi) = fastbrdf::params::ALPHA.range();
                    if let Some(v) = values.iter().find(|v| !(**v >= lo && **v <= hi)) {
                        return Err(format!(
                            "alpha: {v} is outside the domain [{lo}, {hi}] of {id}'s alpha input"
                        ));
                    }
                    continue;
                }
                for (i, v) in values.iter().enumerate() {
                    if i % 1024 == 0 {
                        stop_if(cancel);
                    }
                    // The value as the CLI's text of it, so the message quotes it alike.
                    let v = fastbrdf_analysis::range::num(*v);
                    ModelSpec::parse(id, &[(param, &v)]).map_err(|e| e.to_string())?;
                }
            }
            errors::sweep(&spec, &values, &|| stop_if(cancel)).map_err(|e| e.to_string())
        })?
        .map_err(value_error)?;
        serde_json::to_string(&rows).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// Parses a range text (`LO..HI[:STEP]`, `LO..HI:logK`, `A,B,C`) as the CLI does.
#[pyfunction]
pub(crate) fn parse_range(text: &str, default_step: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    guard(|| {
        let step = float_arg(default_step, "default_step")?;
        fastbrdf_analysis::range::parse(text, step).map_err(value_error)
    })
}

/// `fastbrdf albedo --json`'s object, as JSON. Runs on a worker that Ctrl-C stops.
#[pyfunction]
#[pyo3(signature = (model, params, angles, as_brdf, norm, material=None))]
pub(crate) fn albedo_json(
    py: Python<'_>,
    model: &str,
    params: &Bound<'_, PyAny>,
    angles: &Bound<'_, PyAny>,
    as_brdf: &str,
    norm: &str,
    material: Option<&str>,
) -> PyResult<String> {
    use fastbrdf_analysis::albedo;
    guard(|| {
        let params = params_arg(params)?;
        let angles = values_arg(angles, "angles")?;
        if let Some(bad) = angles.iter().find(|t| !(**t >= 0.0 && **t < 90.0)) {
            return Err(value_error(format!(
                "angles: {bad} is outside [0, 90) degrees"
            )));
        }
        let spec = match material {
            None => grey_spec(model, &params)?,
            Some(_) => full_spec(model, &params, material, None)?,
        };
        let t = albedo::target(&spec, as_brdf, norm).map_err(value_error)?;
        let rows = interruptible(py, |cancel| -> fastbrdf::Result<_> {
            let mut rows = Vec::with_capacity(angles.len());
            for a in &angles {
                stop_if(cancel);
                rows.extend(albedo::curve(&t, std::slice::from_ref(a), 1e-7)?);
            }
            Ok(rows)
        })?
        .map_err(value_error)?;
        let (holds, _) = albedo::furnace(&rows, t.furnace_tolerance());
        let p = t.params_json();
        let v = serde_json::json!({"model": model, "brdf": t.id(), "params": p,
            "claims_energy": t.claims_energy, "conserves": holds, "rows": rows});
        Ok(v.to_string())
    })
}
