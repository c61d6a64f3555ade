//! Python arguments read and checked: numbers, integers, capped sequences, model parameters
//! (parsed once into a [`ModelSpec`]), weights.

use crate::guard::value_error;
use crate::{MAX_ITEMS, MAX_VALUES, MAX_WEIGHT};
use fastbrdf::ModelSpec;
use fastbrdf::params::Params;
use fastbrdf_analysis::model_spec::SpecError;
use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyComplex, PyFloat, PyInt, PyString};

/// A conversion error of argument `name`, named: `TypeError` stays one, `OverflowError` (an
/// integer or float too large for its type) and `ValueError` become `ValueError`; anything
/// else (`MemoryError`, `KeyboardInterrupt`, an error of the caller's own object) passes.
pub(crate) fn named(py: Python<'_>, e: PyErr, name: &str) -> PyErr {
    if e.is_instance_of::<PyTypeError>(py) {
        PyTypeError::new_err(format!("{name}: {}", e.value(py)))
    } else if e.is_instance_of::<PyOverflowError>(py) || e.is_instance_of::<PyValueError>(py) {
        PyValueError::new_err(format!("{name}: {}", e.value(py)))
    } else {
        e
    }
}

/// Argument `name` as a float (`ValueError` for an int too large for one).
pub(crate) fn float_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    real(obj).map_err(|e| named(obj.py(), e, name))
}

/// A real number: a float or an int (exactly, the fast path), else anything with `__float__`
/// but a complex number (Python's `float()` of numpy's complex scalars drops the imaginary
/// part with a warning).
pub(crate) fn real(x: &Bound<'_, PyAny>) -> PyResult<f64> {
    if !(x.is_exact_instance_of::<PyFloat>() || x.is_exact_instance_of::<PyInt>())
        && (x.is_instance_of::<PyComplex>()
            || x.get_type().name()?.to_str()?.starts_with("complex"))
    {
        return Err(PyTypeError::new_err(format!(
            "expected a real number, got {}",
            x.get_type().name()?
        )));
    }
    x.extract::<f64>()
}

/// Argument `name` as a `u32`: a negative or too large integer is a `ValueError` naming it.
pub(crate) fn u32_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<u32> {
    obj.extract::<u32>().map_err(|e| {
        let e = named(obj.py(), e, name);
        if e.is_instance_of::<PyValueError>(obj.py()) {
            value_error(format!(
                "{name} {}: must be an integer from 0 to {}",
                shown(obj),
                u32::MAX
            ))
        } else {
            e
        }
    })
}

/// An object as text for a message, shortened.
pub(crate) fn shown(obj: &Bound<'_, PyAny>) -> String {
    obj.str().map_or_else(
        |_| "?".into(),
        |s| fastbrdf_io::shorten(&s.to_string_lossy(), 40),
    )
}

/// A sequence read item by item, at most `cap` items (never a capacity taken from `len()`,
/// which a sequence may lie about; an endless one stops at the cap). Strings and bytes are not
/// sequences here. Items are converted by `item`; their errors are named `name[i]`.
pub(crate) fn seq<'py, T>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    cap: usize,
    mut item: impl FnMut(&Bound<'py, PyAny>) -> PyResult<T>,
) -> PyResult<Vec<T>> {
    let py = obj.py();
    if obj.is_instance_of::<PyString>()
        || obj.is_instance_of::<PyBytes>()
        || obj.is_instance_of::<PyByteArray>()
    {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a sequence, got {}",
            obj.get_type().name()?
        )));
    }
    let too_many = |n: Option<usize>| match n {
        Some(n) => value_error(format!("{name}: {n} values; at most {cap} are allowed")),
        None => value_error(format!(
            "{name}: more than {cap} values; at most {cap} are allowed"
        )),
    };
    if let Ok(n) = obj.len()
        && n > cap
    {
        return Err(too_many(Some(n)));
    }
    let iter = obj.try_iter().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected a sequence, got {}",
            obj.get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string())
        ))
    })?;
    let mut out = Vec::new();
    for (i, x) in iter.enumerate() {
        if i == cap {
            return Err(too_many(None));
        }
        let x = x?;
        out.push(item(&x).map_err(|e| named(py, e, &format!("{name}[{i}]")))?);
    }
    Ok(out)
}

/// Model parameters as `(name, value)` text pairs: what `fastbrdf/__init__.py` makes of the
/// keyword arguments (ints `str()`, floats `repr()`, strings as they are), the text the CLI's
/// `--param NAME=VALUE` carries. [`spec`] parses them once.
pub(crate) fn params_arg(obj: &Bound<'_, PyAny>) -> PyResult<Vec<(String, String)>> {
    seq(obj, "params", MAX_ITEMS, |x| {
        x.extract::<(String, String)>()
    })
}

/// Parameter values or angles: finite or not (the library says what is wrong with a value),
/// at least one, at most [`MAX_VALUES`].
pub(crate) fn values_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let v = seq(obj, name, MAX_VALUES, real)?;
    if v.is_empty() {
        return Err(value_error(format!("{name}: no values")));
    }
    Ok(v)
}

pub(crate) fn given(params: &[(String, String)]) -> Vec<(&str, &str)> {
    params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect()
}

/// Model `id` with `params` (see [`params_arg`]), parsed and validated once as the CLI parses
/// `--param` (`ModelSpec::parse`: an `R,G,B` value makes it coloured); the registry's message
/// as `ValueError`.
pub(crate) fn spec(id: &str, params: &[(String, String)]) -> PyResult<ModelSpec> {
    ModelSpec::parse(id, &given(params)).map_err(value_error)
}

/// [`spec`] of a grey model (`fastbrdf.Model`: one value per parameter). A value with a comma
/// is refused with the message the registry gives such text (not a number, not one of the
/// choices, or an unknown parameter), as before specs had colour channels.
pub(crate) fn grey_spec(id: &str, params: &[(String, String)]) -> PyResult<ModelSpec> {
    if params.iter().any(|(_, v)| v.contains(',')) {
        let e = fastbrdf::registry::find(id).map_err(value_error)?;
        Params::resolve(e.info.id, e.info.params, &given(params)).map_err(value_error)?;
    }
    let s = spec(id, params)?;
    s.plan().map_err(value_error)?;
    Ok(s)
}

/// Model `id` with `params` (see [`params_arg`]; an `R,G,B` value makes it coloured), then
/// the figures of MERL material `material` where no value was given (the CLI's `--material`)
/// and the colour of metal `metal` (`--metal`: `f = conductor`, `eta`, `k` per channel, given
/// values winning). Every error is a `ValueError` naming the argument.
pub(crate) fn full_spec(
    id: &str,
    params: &[(String, String)],
    material: Option<&str>,
    metal: Option<&str>,
) -> PyResult<ModelSpec> {
    // The library's `model_spec::spec`, the CLI's too (errors named as Python's arguments).
    use fastbrdf_analysis::model_spec::{self, Use};
    let material = material
        .map(|n| {
            fastbrdf_analysis::materials::find(n).map_err(|e| value_error(format!("material: {e}")))
        })
        .transpose()?;
    let metal = metal
        .map(|n| fastbrdf::colour::metal(n).map_err(|e| value_error(format!("metal: {e}"))))
        .transpose()?;
    model_spec::spec(id, params, material, metal, Use::AsIs).map_err(spec_error)
}

/// A weight or albedo channel: finite, from 0 to [`MAX_WEIGHT`] (as the CLI's).
pub(crate) fn weight_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f32> {
    let v = float_arg(obj, name)?;
    if !(0.0..=MAX_WEIGHT).contains(&v) {
        return Err(value_error(format!(
            "{name} {}: must be from 0 to {MAX_WEIGHT}",
            shown(obj)
        )));
    }
    Ok(v as f32)
}

/// A spec error as a `ValueError`, a material's and a metal's named as Python's arguments
/// (`material 'NAME': `, `metal 'NAME': `), as `fastbrdf.Model` names them.
pub(crate) fn spec_error(e: SpecError) -> PyErr {
    match &e {
        SpecError::NoFittedParams { material, .. } => {
            value_error(format!("material '{material}': {e}"))
        }
        SpecError::NoConductor { metal, .. } => value_error(format!("metal '{metal}': {e}")),
        SpecError::Unused { param } => value_error(format!("parameter {param}: {e}")),
        _ => value_error(e),
    }
}
