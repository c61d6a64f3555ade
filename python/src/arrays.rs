//! numpy arrays in and out: inputs made C-contiguous and aligned, outputs allocated by
//! numpy, long loops run in GIL-released steps with Ctrl-C checked between them.

use crate::guard::value_error;
use numpy::ndarray::Dimension;
use numpy::{Element, PyArray, PyArray1, PyArrayMethods, PyReadonlyArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::ops::Range;

/// Elements deinterleaved per step when a (N, 3) direction array feeds the SoA kernels: the
/// input is read in place, only this much is copied at a time.
pub(crate) const CHUNK: usize = 4096;

/// Elements evaluated per release of the GIL; Ctrl-C is checked between two (a multiple of
/// [`CHUNK`]).
pub(crate) const STEP: usize = 256 * CHUNK;

/// `a` itself when it is C-contiguous and aligned, else numpy's C-ordered copy of it (a
/// `MemoryError` if that cannot be allocated), borrowed read-only.
pub(crate) fn ready<'py, T: Element, D: Dimension>(
    a: Bound<'py, PyArray<T, D>>,
) -> PyResult<PyReadonlyArray<'py, T, D>> {
    let a = if a.is_c_contiguous() && a.is_aligned() {
        a
    } else {
        a.call_method1("copy", ("C",))?
            .cast_into::<PyArray<T, D>>()?
    };
    Ok(a.try_readonly()?)
}

/// `a` itself when it is aligned, whatever its strides (a transposed or broadcast array is
/// read in place), else numpy's C-ordered copy of it, borrowed read-only.
pub(crate) fn aligned<'py, T: Element, D: Dimension>(
    a: Bound<'py, PyArray<T, D>>,
) -> PyResult<PyReadonlyArray<'py, T, D>> {
    let a = if a.is_aligned() {
        a
    } else {
        a.call_method1("copy", ("C",))?
            .cast_into::<PyArray<T, D>>()?
    };
    Ok(a.try_readonly()?)
}

/// An aligned (N, `cols`) array's rows, any strides (see [`aligned`]).
pub(crate) fn rows2<'a, T: Element>(
    a: &'a PyReadonlyArray<'_, T, numpy::Ix2>,
    cols: usize,
    name: &str,
) -> PyResult<numpy::ndarray::ArrayView2<'a, T>> {
    if a.shape()[1] != cols {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape (N, {cols}), got {:?}",
            a.shape()
        )));
    }
    Ok(a.as_array())
}

/// A ready array's elements.
pub(crate) fn slice<'a, T: Element, D: Dimension>(
    a: &'a PyReadonlyArray<'_, T, D>,
) -> PyResult<&'a [T]> {
    a.as_slice().map_err(|_| {
        PyRuntimeError::new_err("internal error in fastbrdf: an array was not made contiguous")
    })
}

/// A ready (N, `cols`) array's elements, row-major.
pub(crate) fn slice2<'a, T: Element>(
    a: &'a PyReadonlyArray<'_, T, numpy::Ix2>,
    cols: usize,
    name: &str,
) -> PyResult<&'a [T]> {
    if a.shape()[1] != cols {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape (N, {cols}), got {:?}",
            a.shape()
        )));
    }
    slice(a)
}

/// Two (N, k) arrays must have as many rows: `second` is named against `first`.
pub(crate) fn same_rows(first: &str, a: usize, second: &str, b: usize) -> PyResult<()> {
    if a == b {
        Ok(())
    } else {
        Err(value_error(format!("{second}: {b} rows, {first} has {a}")))
    }
}

/// A new uninitialised 1-D output of `n` elements, allocated by numpy: a size that cannot be
/// had is numpy's `MemoryError` (the caller writes every element).
pub(crate) fn empty<T: Element>(py: Python<'_>, n: usize) -> PyResult<Bound<'_, PyArray1<T>>> {
    let np = py.import("numpy")?;
    Ok(np
        .call_method1("empty", (n, numpy::dtype::<T>(py)))?
        .cast_into::<PyArray1<T>>()?)
}

/// The output of `n` elements: `out` when given (1-D, C-contiguous, writeable, of `n`
/// elements: else a `ValueError` naming `out`), else a new one ([`empty`]).
pub(crate) fn output<'py, T: Element>(
    py: Python<'py>,
    n: usize,
    out: Option<Bound<'py, PyArray1<T>>>,
) -> PyResult<Bound<'py, PyArray1<T>>> {
    let Some(o) = out else {
        return empty(py, n);
    };
    if o.len() != n {
        return Err(value_error(format!(
            "out: {} elements, the result has {n}",
            o.len()
        )));
    }
    if !o.is_c_contiguous() {
        return Err(value_error("out: must be C-contiguous"));
    }
    Ok(o)
}

/// `out` borrowed for writing: a read-only array, or one that overlaps an input borrowed for
/// reading, is a `ValueError` naming `out`.
pub(crate) fn writable<'py, T: Element>(
    out: &Bound<'py, PyArray1<T>>,
) -> PyResult<numpy::PyReadwriteArray<'py, T, numpy::Ix1>> {
    out.try_readwrite()
        .map_err(|e| value_error(format!("out: cannot be written ({e})")))
}

/// Runs `f` over `0..n` in ranges of [`STEP`], the GIL released during each, and checks for
/// Ctrl-C (and other signals) between them.
pub(crate) fn chunked<E: std::fmt::Display + Send>(
    py: Python<'_>,
    n: usize,
    mut f: impl FnMut(Range<usize>) -> Result<(), E> + Send,
) -> PyResult<()> {
    let mut lo = 0;
    while lo < n {
        let hi = n.min(lo.saturating_add(STEP));
        py.detach(|| crate::fork::run(|| f(lo..hi)))
            .map_err(value_error)?;
        py.check_signals()?;
        lo = hi;
    }
    Ok(())
}
