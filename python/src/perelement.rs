//! Per-element parameters (`fastbrdf.Model(..., alpha=array)`): checks and evaluation
//! through `fastbrdf::batch::per_element` (elements grouped by value, each group evaluated by
//! the batch kernel of the model built for its values; see that module for the cost).
//!
//! Parameter values arrive as float64 (a float32 value widens exactly); inputs and outputs
//! in the precision evaluated. The work runs in GIL-released steps with Ctrl-C checked
//! between them ([`chunked`]).

use crate::MAX_ITEMS;
use crate::args::seq;
use crate::arrays::{STEP, ready, same_rows, slice, slice2, writable};
use crate::guard::{guard, value_error};
use crate::handle::Handle;
use fastbrdf::Real;
use fastbrdf::batch::per_element::{PerElement, Rows, numeric};
use numpy::{Element, PyArray1, PyArray2, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

/// The per-element model of `h` with parameters `names`: an unknown name is the registry's
/// `ValueError`, a choice parameter a `TypeError`.
fn per_element(h: &Handle, names: &[String]) -> PyResult<PerElement> {
    let spec = h.model_spec();
    for n in names {
        if !numeric(spec, n).map_err(value_error)? {
            return Err(PyTypeError::new_err(format!(
                "model '{}': parameter {n} is a choice: it takes one value, not an array \
                 (per-element values are for numeric parameters)",
                spec.id()
            )));
        }
    }
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    PerElement::new(spec, &names).map_err(value_error)
}

/// Checks parameter `name`'s values (float64, flat) for model `handle`: `None` when the model
/// takes them all, else `(index, message)` of the first it refuses (the library's message,
/// which names the value). A choice or unknown parameter raises.
#[pyfunction]
fn perelement_check(
    handle: PyRef<'_, Handle>,
    name: String,
    values: PyReadonlyArray1<'_, f64>,
) -> PyResult<Option<(usize, String)>> {
    guard(|| {
        let pe = per_element(&handle, std::slice::from_ref(&name))?;
        let v = values.as_slice().map_err(value_error)?;
        Ok(pe.check(0, v).err().map(|(i, e)| (i, e.to_string())))
    })
}

/// The parameter arrays: float64, flat, `n` values each.
fn params_of<'py>(
    names: &[String],
    params: &Bound<'py, PyAny>,
    n: usize,
) -> PyResult<Vec<PyReadonlyArray1<'py, f64>>> {
    let p = seq(params, "params", MAX_ITEMS, |a| {
        ready(a.cast::<PyArray1<f64>>()?.clone())
    })?;
    if p.len() != names.len() {
        return Err(value_error(format!(
            "params: {} arrays for {} names",
            p.len(),
            names.len()
        )));
    }
    for (k, a) in names.iter().zip(&p) {
        if a.len() != n {
            return Err(value_error(format!(
                "params: {k} has {} values, the output has {n}",
                a.len()
            )));
        }
    }
    Ok(p)
}

/// The fewest and most elements per GIL-released step, and the time a step aims at: the
/// steps adapt (a step's time per element sizes the next), as a map with few values runs at
/// the kernels' speed but all-distinct values build a model per element (microseconds
/// each), and Ctrl-C is seen between steps. Built models are kept within a step.
const STEP_MIN: usize = 1 << 14;
const STEP_TIME: std::time::Duration = std::time::Duration::from_millis(100);

/// Evaluates `f` over the rows of `out` in GIL-released steps with Ctrl-C checked between
/// them, each step's parameters and inputs sliced from the whole.
fn run<T: Real + Element>(
    py: Python<'_>,
    params: &[&[f64]],
    rows: Rows<'_, T>,
    out: &Bound<'_, PyArray1<T>>,
    f: impl Fn(&[&[f64]], Rows<'_, T>, &mut [T]) -> fastbrdf::Result<()> + Sync,
) -> PyResult<()> {
    let mut rw = writable(out)?;
    let o = rw.as_slice_mut().map_err(value_error)?;
    let n = o.len();
    let (mut lo, mut step) = (0, STEP_MIN);
    while lo < n {
        let r = lo..n.min(lo + step);
        let t0 = std::time::Instant::now();
        py.detach(|| {
            let p: Vec<&[f64]> = params.iter().map(|p| &p[r.clone()]).collect();
            match rows {
                Rows::Cols(cols) => {
                    let c: Vec<&[T]> = cols.iter().map(|c| &c[r.clone()]).collect();
                    f(&p, Rows::Cols(&c), &mut o[r.clone()])
                }
                Rows::Dirs(wi, wo) => {
                    let span = 3 * r.start..3 * r.end;
                    f(
                        &p,
                        Rows::Dirs(&wi[span.clone()], &wo[span]),
                        &mut o[r.clone()],
                    )
                }
            }
        })
        .map_err(value_error)?;
        py.check_signals()?;
        let per = t0.elapsed().as_secs_f64() / r.len() as f64;
        step = ((STEP_TIME.as_secs_f64() / per.max(1e-12)) as usize).clamp(STEP_MIN, STEP);
        lo = r.end;
    }
    Ok(())
}

/// Columns (not BRDFs) with per-element parameters, into `out` (precision `T`).
fn eval_cols<'py, T: Real + Element>(
    py: Python<'py>,
    handle: &Handle,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    cols: &Bound<'py, PyAny>,
    out: &Bound<'py, PyArray1<T>>,
    f: impl Fn(&PerElement, &[&[f64]], Rows<'_, T>, &mut [T]) -> fastbrdf::Result<()> + Sync,
) -> PyResult<()> {
    let pe = per_element(handle, &names)?;
    let n = out.len();
    let cols = seq(cols, "cols", MAX_ITEMS, |c| {
        ready(c.cast::<PyArray1<T>>()?.clone())
    })?;
    let cols: Vec<&[T]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
    let (req, opt) = handle
        .model_spec()
        .model::<f64>()
        .map_err(value_error)?
        .columns();
    if cols.len() < req.len().max(1) || cols.len() > req.len() + opt.len() {
        return Err(PyTypeError::new_err(format!(
            "cols: model '{}' takes {} column(s), got {}",
            handle.model_spec().id(),
            req.join(", "),
            cols.len()
        )));
    }
    if let Some((i, c)) = cols.iter().enumerate().find(|(_, c)| c.len() != n) {
        return Err(value_error(format!(
            "cols: column {i} has {} values, out has {n}",
            c.len()
        )));
    }
    let p = params_of(&names, params, n)?;
    let p: Vec<&[f64]> = p.iter().map(slice).collect::<PyResult<_>>()?;
    run(py, &p, Rows::Cols(&cols), out, |p, r, o| f(&pe, p, r, o))
}

/// A BRDF over (N, 3) `wi`, `wo` with per-element parameters, into `out`.
#[allow(clippy::too_many_arguments)]
fn eval_dirs<'py, T: Real + Element>(
    py: Python<'py>,
    handle: &Handle,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    wi: Bound<'py, PyArray2<T>>,
    wo: Bound<'py, PyArray2<T>>,
    out: &Bound<'py, PyArray1<T>>,
    f: impl Fn(&PerElement, &[&[f64]], Rows<'_, T>, &mut [T]) -> fastbrdf::Result<()> + Sync,
) -> PyResult<()> {
    let pe = per_element(handle, &names)?;
    let (wi, wo) = (ready(wi)?, ready(wo)?);
    let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
    same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
    same_rows("wi", wi.len() / 3, "out", out.len())?;
    let p = params_of(&names, params, out.len())?;
    let p: Vec<&[f64]> = p.iter().map(slice).collect::<PyResult<_>>()?;
    run(py, &p, Rows::Dirs(wi, wo), out, |p, r, o| f(&pe, p, r, o))
}

/// f32 columns: each element as `Model.eval` of the model built for its values (the batch
/// kernel; the scalar model for shadowing terms).
#[pyfunction]
fn perelement_eval_f32<'py>(
    py: Python<'py>,
    handle: PyRef<'py, Handle>,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    cols: &Bound<'py, PyAny>,
    out: Bound<'py, PyArray1<f32>>,
) -> PyResult<()> {
    guard(|| eval_cols(py, &handle, names, params, cols, &out, PerElement::eval_f32))
}

/// f64 columns (the scalar f64 model of each element's values).
#[pyfunction]
fn perelement_eval_f64<'py>(
    py: Python<'py>,
    handle: PyRef<'py, Handle>,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    cols: &Bound<'py, PyAny>,
    out: Bound<'py, PyArray1<f64>>,
) -> PyResult<()> {
    guard(|| eval_cols(py, &handle, names, params, cols, &out, PerElement::eval_f64))
}

/// A BRDF in f32 over (N, 3) directions (the batch kernel per group of equal values).
#[pyfunction]
fn perelement_eval_dirs_f32<'py>(
    py: Python<'py>,
    handle: PyRef<'py, Handle>,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    wi: Bound<'py, PyArray2<f32>>,
    wo: Bound<'py, PyArray2<f32>>,
    out: Bound<'py, PyArray1<f32>>,
) -> PyResult<()> {
    guard(|| {
        eval_dirs(
            py,
            &handle,
            names,
            params,
            wi,
            wo,
            &out,
            PerElement::eval_f32,
        )
    })
}

/// A BRDF in f64 over (N, 3) directions (the scalar f64 model).
#[pyfunction]
fn perelement_eval_dirs_f64<'py>(
    py: Python<'py>,
    handle: PyRef<'py, Handle>,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    wi: Bound<'py, PyArray2<f64>>,
    wo: Bound<'py, PyArray2<f64>>,
    out: Bound<'py, PyArray1<f64>>,
) -> PyResult<()> {
    guard(|| {
        eval_dirs(
            py,
            &handle,
            names,
            params,
            wi,
            wo,
            &out,
            PerElement::eval_f64,
        )
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(perelement_check, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_f32, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_f64, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_dirs_f32, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_dirs_f64, m)?)?;
    Ok(())
}
