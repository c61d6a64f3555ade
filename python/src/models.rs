//! The registry (`models_json`, `info_json`) and shader export (`shader`).

use crate::args::{full_spec, params_arg};
use crate::guard::{guard, value_error};
use fastbrdf::registry;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// The registry as `fastbrdf models --json` prints it: `{"models": [...]}` (pretty JSON).
#[pyfunction]
pub(crate) fn models_json() -> PyResult<String> {
    guard(|| {
        // As `fastbrdf models --json`: the info and the committed instruction counts.
        let models: Vec<_> = registry::all()
            .iter()
            .map(|e| fastbrdf_gpu::cost::model_entry(&e.info))
            .collect();
        serde_json::to_string_pretty(&serde_json::json!({ "models": models }))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// The info of model `id` as `fastbrdf models --json` prints one entry.
#[pyfunction]
pub(crate) fn info_json(id: &str) -> PyResult<String> {
    guard(|| {
        let e = registry::find(id).map_err(value_error)?;
        serde_json::to_string(&fastbrdf_gpu::cost::model_entry(&e.info))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// `fastbrdf shader`'s text for one model.
#[pyfunction]
#[pyo3(signature = (model, params, lang, runtime_params, material=None, metal=None))]
pub(crate) fn shader(
    model: &str,
    params: &Bound<'_, PyAny>,
    lang: &str,
    runtime_params: bool,
    material: Option<&str>,
    metal: Option<&str>,
) -> PyResult<String> {
    use fastbrdf_gpu::export::{Form, Lang, export_form};
    guard(|| {
        let params = params_arg(params)?;
        let l = Lang::parse(lang).ok_or_else(|| {
            value_error(format!(
                "lang '{}': expected one of wgsl, glsl, hlsl, msl, brdf-explorer",
                fastbrdf_io::shorten(lang, 40)
            ))
        })?;
        let form = if runtime_params {
            Form::Runtime
        } else {
            Form::Literals
        };
        export_form(&full_spec(model, &params, material, metal)?, l, form).map_err(value_error)
    })
}
