//! `fastbrdf._fastbrdf`: the native half of the Python package (pyo3 + numpy).
//!
//! Thin glue, like the CLI: the library computes, this module moves arrays and maps errors.
//! It takes 1-D columns (and (N, 3) / (N, 2) direction arrays) of the exact dtype; the Python
//! layer (`python/fastbrdf/__init__.py`) checks dtypes and shapes, broadcasts, and copies only
//! when it must. This module still checks everything it is given (issue 27), as a user can call
//! it directly:
//!
//! - arrays that are not C-contiguous or not aligned are copied (by numpy) before reading;
//!   lengths must agree, column counts must fit the model, `u` must lie in [0, 1);
//! - outputs are allocated by numpy (`numpy.empty`), so a size the address space cannot hold
//!   is numpy's `MemoryError`, never an abort;
//! - sequences are read item by item with a cap (the CLI's [`MAX_VALUES`] for parameter
//!   values and angles, [`MAX_ITEMS`] for the rest), never with a capacity taken from `len()`;
//! - integers and floats that do not fit are `ValueError` naming the argument (not
//!   `OverflowError`);
//! - long calls stop on Ctrl-C: evaluations run in chunks of [`STEP`] elements, the GIL
//!   released, with `check_signals` between chunks; sweeps, albedo curves and renders run on a
//!   worker thread that stops at its next cancellation point when this thread sees a signal
//!   ([`interruptible`]);
//! - every entry point runs under [`guard`]: a panic (a bug) is a `RuntimeError`, never pyo3's
//!   `PanicException` (a `BaseException` that `except Exception` does not catch).
//!
//! Errors are `ValueError` (bad model, parameter or value: the library's own message),
//! `TypeError` (wrong type, wrong number of columns), `MemoryError` or `KeyboardInterrupt`.

use fastbrdf::batch::{Input, Kernel};
use fastbrdf::sample::Strategy;
use fastbrdf::{Model, Real, registry};
use numpy::ndarray::Dimension;
use numpy::{
    Element, PyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{
    PyKeyboardInterrupt, PyMemoryError, PyOverflowError, PyRuntimeError, PyTypeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyComplex, PyFloat, PyInt, PyString};
use std::any::Any;
use std::ops::Range;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Elements deinterleaved per step when a (N, 3) direction array feeds the SoA kernels: the
/// input is read in place, only this much is copied at a time.
const CHUNK: usize = 4096;

/// Elements evaluated per release of the GIL; Ctrl-C is checked between two (a multiple of
/// [`CHUNK`]).
const STEP: usize = 256 * CHUNK;

/// The most parameter values (`errors`) and angles (`albedo`): the CLI's cap on its ranges
/// and lists (`fastbrdf_analysis::range::MAX_VALUES`).
const MAX_VALUES: usize = fastbrdf_analysis::range::MAX_VALUES;

/// The most items of the other sequences (parameters, lights, columns). The CLI has no cap
/// there (its command line bounds them); this one bounds an endless iterable.
const MAX_ITEMS: usize = 4096;

/// The largest kd, ks and albedo channel, as the CLI's `--weights` and `--albedo`
/// (`MAX_WEIGHT` of crates/cli/src/commands/render.rs).
const MAX_WEIGHT: f64 = 1e3;

/// How often a worker's caller looks for Ctrl-C.
const POLL: Duration = Duration::from_millis(20);

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A panic's message as a `RuntimeError` (a bug: the message asks for a report).
fn internal(payload: Box<dyn Any + Send>) -> PyErr {
    let msg = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("a panic");
    PyRuntimeError::new_err(format!(
        "internal error in fastbrdf (please report it): {msg}"
    ))
}

/// Runs an entry point's body; a panic in it (a bug) becomes a `RuntimeError` instead of
/// pyo3's `PanicException`.
fn guard<R>(body: impl FnOnce() -> PyResult<R>) -> PyResult<R> {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|p| Err(internal(p)))
}

/// A conversion error of argument `name`, named: `TypeError` stays one, `OverflowError` (an
/// integer or float too large for its type) and `ValueError` become `ValueError`; anything
/// else (`MemoryError`, `KeyboardInterrupt`, an error of the caller's own object) passes.
fn named(py: Python<'_>, e: PyErr, name: &str) -> PyErr {
    if e.is_instance_of::<PyTypeError>(py) {
        PyTypeError::new_err(format!("{name}: {}", e.value(py)))
    } else if e.is_instance_of::<PyOverflowError>(py) || e.is_instance_of::<PyValueError>(py) {
        PyValueError::new_err(format!("{name}: {}", e.value(py)))
    } else {
        e
    }
}

/// Argument `name` as a float (`ValueError` for an int too large for one).
fn float_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    real(obj).map_err(|e| named(obj.py(), e, name))
}

/// A real number: a float or an int (exactly, the fast path), else anything with `__float__`
/// but a complex number (Python's `float()` of numpy's complex scalars drops the imaginary
/// part with a warning).
fn real(x: &Bound<'_, PyAny>) -> PyResult<f64> {
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
fn u32_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<u32> {
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
fn shown(obj: &Bound<'_, PyAny>) -> String {
    obj.str().map_or_else(
        |_| "?".into(),
        |s| fastbrdf_io::shorten(&s.to_string_lossy(), 40),
    )
}

/// A sequence read item by item, at most `cap` items (never a capacity taken from `len()`,
/// which a sequence may lie about; an endless one stops at the cap). Strings and bytes are not
/// sequences here. Items are converted by `item`; their errors are named `name[i]`.
fn seq<'py, T>(
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

/// Model parameters as `(name, value)` text pairs.
fn params_arg(obj: &Bound<'_, PyAny>) -> PyResult<Vec<(String, String)>> {
    seq(obj, "params", MAX_ITEMS, |x| {
        x.extract::<(String, String)>()
    })
}

/// Parameter values or angles: finite or not (the library says what is wrong with a value),
/// at least one, at most [`MAX_VALUES`].
fn values_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let v = seq(obj, name, MAX_VALUES, real)?;
    if v.is_empty() {
        return Err(value_error(format!("{name}: no values")));
    }
    Ok(v)
}

fn given(params: &[(String, String)]) -> Vec<(&str, &str)> {
    params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect()
}

/// `a` itself when it is C-contiguous and aligned, else numpy's C-ordered copy of it (a
/// `MemoryError` if that cannot be allocated), borrowed read-only.
fn ready<'py, T: Element, D: Dimension>(
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

/// A ready array's elements.
fn slice<'a, T: Element, D: Dimension>(a: &'a PyReadonlyArray<'_, T, D>) -> PyResult<&'a [T]> {
    a.as_slice().map_err(|_| {
        PyRuntimeError::new_err("internal error in fastbrdf: an array was not made contiguous")
    })
}

/// A ready (N, `cols`) array's elements, row-major.
fn slice2<'a, T: Element>(
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
fn same_rows(first: &str, a: usize, second: &str, b: usize) -> PyResult<()> {
    if a == b {
        Ok(())
    } else {
        Err(value_error(format!("{second}: {b} rows, {first} has {a}")))
    }
}

/// A new uninitialised 1-D output of `n` elements, allocated by numpy: a size that cannot be
/// had is numpy's `MemoryError` (the caller writes every element).
fn empty<T: Element>(py: Python<'_>, n: usize) -> PyResult<Bound<'_, PyArray1<T>>> {
    let np = py.import("numpy")?;
    Ok(np
        .call_method1("empty", (n, numpy::dtype::<T>(py)))?
        .cast_into::<PyArray1<T>>()?)
}

/// Runs `f` over `0..n` in ranges of [`STEP`], the GIL released during each, and checks for
/// Ctrl-C (and other signals) between them.
fn chunked<E: std::fmt::Display + Send>(
    py: Python<'_>,
    n: usize,
    mut f: impl FnMut(Range<usize>) -> Result<(), E> + Send,
) -> PyResult<()> {
    let mut lo = 0;
    while lo < n {
        let hi = n.min(lo.saturating_add(STEP));
        py.detach(|| f(lo..hi)).map_err(value_error)?;
        py.check_signals()?;
        lo = hi;
    }
    Ok(())
}

/// The payload with which a worker unwinds when [`interruptible`] asks it to stop.
struct Cancelled;

/// A cancellation point of a worker run by [`interruptible`]: unwinds (without the panic
/// hook: nothing is printed) once the caller saw Ctrl-C. Callable from rayon's threads,
/// which carry the unwinding to the worker.
fn stop_if(cancel: &AtomicBool) {
    if cancel.load(Ordering::Relaxed) {
        resume_unwind(Box::new(Cancelled));
    }
}

/// Runs `work` on a worker thread, the GIL released, while this thread checks for signals
/// every [`POLL`]: when a handler raises (Ctrl-C's `KeyboardInterrupt`), the flag given to
/// `work` is set, `work` stops at its next [`stop_if`], and the handler's exception is
/// raised. A panic in `work` is a `RuntimeError` (see [`guard`]).
fn interruptible<R: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> R + Send,
) -> PyResult<R> {
    let cancel = AtomicBool::new(false);
    let done = AtomicBool::new(false);
    let caller = std::thread::current();
    std::thread::scope(|s| {
        let (cancel, done) = (&cancel, &done);
        let worker = s.spawn(move || {
            let r = catch_unwind(AssertUnwindSafe(|| work(cancel)));
            done.store(true, Ordering::Release);
            caller.unpark();
            r
        });
        let mut raised = None;
        while !done.load(Ordering::Acquire) {
            py.detach(|| std::thread::park_timeout(POLL));
            if raised.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                raised = Some(e);
            }
        }
        let r = py.detach(|| worker.join());
        if let Some(e) = raised {
            return Err(e);
        }
        match r {
            Ok(Ok(v)) => Ok(v),
            Ok(Err(p)) | Err(p) if p.is::<Cancelled>() => Err(PyKeyboardInterrupt::new_err(())),
            Ok(Err(p)) | Err(p) => Err(internal(p)),
        }
    })
}

/// The registry as `fastbrdf models --json` prints it: `{"models": [...]}` (pretty JSON).
#[pyfunction]
fn models_json() -> PyResult<String> {
    guard(|| {
        let models: Vec<_> = registry::all().iter().map(|e| &e.info).collect();
        serde_json::to_string_pretty(&serde_json::json!({ "models": models }))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// One model, built once in both precisions (and its batch kernel when it has one).
#[pyclass(frozen, module = "fastbrdf._fastbrdf")]
struct Handle {
    id: &'static str,
    kind: fastbrdf::Kind,
    m32: Model<f32>,
    m64: Model<f64>,
    kernel: Option<Kernel>,
}

/// `Model::eval_row` over the rows `r` of columns (the lenient shading rules), precision `T`.
fn rows<T: Real>(m: &Model<T>, cols: &[&[T]], r: Range<usize>, out: &mut [T]) {
    let mut input = vec![None; cols.len()];
    for (o, i) in out.iter_mut().zip(r) {
        for (k, c) in cols.iter().enumerate() {
            input[k] = Some(c[i]);
        }
        *o = m.eval_row(&input);
    }
}

/// The BRDF over (N, 3) pairs, scalar model in precision `T`.
fn brdf_rows<T: Real>(b: &dyn fastbrdf::Brdf<T>, wi: &[T], wo: &[T], out: &mut [T]) {
    for ((o, a), w) in out
        .iter_mut()
        .zip(wi.chunks_exact(3))
        .zip(wo.chunks_exact(3))
    {
        *o = b.eval([a[0], a[1], a[2]], [w[0], w[1], w[2]]);
    }
}

/// The f32 kernel over (N, 3) pairs, deinterleaved [`CHUNK`] at a time.
fn brdf_kernel(k: &Kernel, wi: &[f32], wo: &[f32], out: &mut [f32]) -> fastbrdf::Result<()> {
    let mut soa = vec![[0.0f32; CHUNK]; 6];
    for ((o, wi), wo) in out
        .chunks_mut(CHUNK)
        .zip(wi.chunks(3 * CHUNK))
        .zip(wo.chunks(3 * CHUNK))
    {
        let len = o.len();
        for (j, (a, w)) in wi.chunks_exact(3).zip(wo.chunks_exact(3)).enumerate() {
            (soa[0][j], soa[1][j], soa[2][j]) = (a[0], a[1], a[2]);
            (soa[3][j], soa[4][j], soa[5][j]) = (w[0], w[1], w[2]);
        }
        let s: [&[f32]; 6] = std::array::from_fn(|a| &soa[a][..len]);
        k.eval(Input::Dirs(s), o)?;
    }
    Ok(())
}

fn brdf_of<'a, T: Real>(m: &'a Model<T>, id: &str) -> PyResult<&'a dyn fastbrdf::Brdf<T>> {
    match m {
        Model::Brdf(b) => Ok(b.as_ref()),
        m => Err(value_error(fastbrdf::Error::WrongKind {
            model: id.into(),
            expected: "brdf".into(),
            found: m.kind().name().into(),
        })),
    }
}

fn strategy(name: &str) -> PyResult<Strategy> {
    Strategy::parse(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "strategy '{}': expected one of {}",
            fastbrdf_io::shorten(name, 40),
            Strategy::ALL.map(|s| s.name()).join(", ")
        ))
    })
}

/// Every `u` in [0, 1) (NaN is not): the rows from `first` on, two per row.
fn check_u<T: Real>(u: &[T], first: usize) -> Result<(), String> {
    match u.iter().position(|x| !(*x >= T::zero() && *x < T::one())) {
        None => Ok(()),
        Some(i) => Err(format!(
            "u: {} (row {}, column {}) is outside [0, 1)",
            u[i],
            first + i / 2,
            i % 2
        )),
    }
}

/// Samples rows `r`: `wi` (3 per row), weight, pdf; no sample gives zeros.
fn sample_rows<T: Real>(
    b: &dyn fastbrdf::Brdf<T>,
    s: Strategy,
    (wo, u): (&[T], &[T]),
    r: Range<usize>,
    (wi, weight, pdf): (&mut [T], &mut [T], &mut [T]),
) -> Result<(), String> {
    let (lo, hi) = (r.start, r.end);
    let u = &u[2 * lo..2 * hi];
    check_u(u, lo)?;
    let rows = wo[3 * lo..3 * hi].chunks_exact(3).zip(u.chunks_exact(2));
    let outs = wi[3 * lo..3 * hi]
        .chunks_exact_mut(3)
        .zip(&mut weight[lo..hi])
        .zip(&mut pdf[lo..hi]);
    for ((o, u), ((wi, weight), pdf)) in rows.zip(outs) {
        match b.sample([o[0], o[1], o[2]], [u[0], u[1]], s) {
            Some(x) => {
                wi.copy_from_slice(&x.wi);
                (*weight, *pdf) = (x.weight, x.pdf);
            }
            None => {
                wi.fill(T::zero());
                (*weight, *pdf) = (T::zero(), T::zero());
            }
        }
    }
    Ok(())
}

fn pdf_rows<T: Real>(b: &dyn fastbrdf::Brdf<T>, s: Strategy, wo: &[T], wi: &[T], out: &mut [T]) {
    for ((p, o), i) in out
        .iter_mut()
        .zip(wo.chunks_exact(3))
        .zip(wi.chunks_exact(3))
    {
        *p = b.pdf([o[0], o[1], o[2]], [i[0], i[1], i[2]], s);
    }
}

type Sampled<'py, T> = (
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<T>>,
);

#[pymethods]
impl Handle {
    /// Builds model `id` with parameters given as text (validated by the registry).
    #[new]
    fn new(id: &str, params: &Bound<'_, PyAny>) -> PyResult<Self> {
        guard(|| {
            let params = params_arg(params)?;
            let g = given(&params);
            let e = registry::find(id).map_err(value_error)?;
            let plan = registry::plan(id, &g).map_err(value_error)?;
            let kernel = match plan.kind() {
                fastbrdf::Kind::Shadowing => None,
                _ => Some(Kernel::from_plan(e.info.id, &plan).map_err(value_error)?),
            };
            Ok(Self {
                id: e.info.id,
                kind: plan.kind(),
                m32: plan.model::<f32>(),
                m64: plan.model::<f64>(),
                kernel,
            })
        })
    }

    #[getter]
    fn id(&self) -> &'static str {
        self.id
    }

    #[getter]
    fn kind(&self) -> &'static str {
        self.kind.name()
    }

    /// `(required, optional)` input names, as `fastbrdf eval`'s columns.
    #[getter]
    fn columns(&self) -> (Vec<&'static str>, Vec<&'static str>) {
        let (r, o) = self.m64.columns();
        (r.to_vec(), o.to_vec())
    }

    /// Whether f32 evaluation runs a vectorised kernel (else the scalar model per element).
    #[getter]
    fn simd(&self) -> bool {
        self.kernel.as_ref().is_some_and(Kernel::simd)
    }

    /// f32 over 1-D columns of equal length (not BRDFs).
    fn eval_f32<'py>(
        &self,
        py: Python<'py>,
        cols: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            let cols = self.columns_arg::<f32>(cols)?;
            let cols: Vec<&[f32]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
            let n = self.check_columns(&cols)?;
            let out = empty::<f32>(py, n)?;
            {
                let mut rw = out.try_readwrite()?;
                let o = rw.as_slice_mut().map_err(value_error)?;
                chunked(py, n, |r| -> fastbrdf::Result<()> {
                    let o = &mut o[r.clone()];
                    match (&self.kernel, self.kind, cols.as_slice()) {
                        (Some(k), fastbrdf::Kind::Env, [c, a]) => {
                            k.eval_par(Input::Env([&c[r.clone()], &a[r]]), o)
                        }
                        (
                            Some(k),
                            fastbrdf::Kind::Lobe
                            | fastbrdf::Kind::Distribution
                            | fastbrdf::Kind::Fresnel,
                            [c],
                        ) => k.eval_par(Input::Cos(&c[r]), o),
                        _ => {
                            rows(&self.m32, &cols, r, o);
                            Ok(())
                        }
                    }
                })?;
            }
            Ok(out)
        })
    }

    /// f64 over 1-D columns of equal length (not BRDFs).
    fn eval_f64<'py>(
        &self,
        py: Python<'py>,
        cols: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let cols = self.columns_arg::<f64>(cols)?;
            let cols: Vec<&[f64]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
            let n = self.check_columns(&cols)?;
            let out = empty::<f64>(py, n)?;
            {
                let mut rw = out.try_readwrite()?;
                let o = rw.as_slice_mut().map_err(value_error)?;
                chunked(py, n, |r| -> Result<(), String> {
                    rows(&self.m64, &cols, r.clone(), &mut o[r]);
                    Ok(())
                })?;
            }
            Ok(out)
        })
    }

    /// A BRDF in f32 over (N, 3) `wi`, `wo`: the SIMD kernel, fed in chunks of [`CHUNK`]
    /// deinterleaved elements (the inputs are not copied whole).
    fn eval_dirs_f32<'py>(
        &self,
        py: Python<'py>,
        wi: Bound<'py, PyArray2<f32>>,
        wo: Bound<'py, PyArray2<f32>>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            brdf_of(&self.m32, self.id)?;
            let k = self.kernel.as_ref().ok_or_else(|| {
                PyRuntimeError::new_err("internal error in fastbrdf: a BRDF without a kernel")
            })?;
            let (wi, wo) = (ready(wi)?, ready(wo)?);
            let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
            same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
            let n = wi.len() / 3;
            let out = empty::<f32>(py, n)?;
            {
                let mut rw = out.try_readwrite()?;
                let o = rw.as_slice_mut().map_err(value_error)?;
                chunked(py, n, |r| {
                    let span = 3 * r.start..3 * r.end;
                    brdf_kernel(k, &wi[span.clone()], &wo[span], &mut o[r])
                })?;
            }
            Ok(out)
        })
    }

    /// A BRDF in f64 over (N, 3) `wi`, `wo` (the scalar model).
    fn eval_dirs_f64<'py>(
        &self,
        py: Python<'py>,
        wi: Bound<'py, PyArray2<f64>>,
        wo: Bound<'py, PyArray2<f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            let (wi, wo) = (ready(wi)?, ready(wo)?);
            let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
            same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
            let n = wi.len() / 3;
            let out = empty::<f64>(py, n)?;
            {
                let mut rw = out.try_readwrite()?;
                let o = rw.as_slice_mut().map_err(value_error)?;
                chunked(py, n, |r| -> Result<(), String> {
                    let span = 3 * r.start..3 * r.end;
                    brdf_rows(b, &wi[span.clone()], &wo[span], &mut o[r]);
                    Ok(())
                })?;
            }
            Ok(out)
        })
    }

    /// Samples `wi` given (N, 3) `wo` and (N, 2) `u` in [0, 1): `(wi (N*3), weight, pdf)`.
    fn sample_f32<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f32>>,
        u: Bound<'py, PyArray2<f32>>,
        strategy_name: &str,
    ) -> PyResult<Sampled<'py, f32>> {
        guard(|| {
            let b = brdf_of(&self.m32, self.id)?;
            self.sample(py, b, wo, u, strategy_name)
        })
    }

    fn sample_f64<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f64>>,
        u: Bound<'py, PyArray2<f64>>,
        strategy_name: &str,
    ) -> PyResult<Sampled<'py, f64>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            self.sample(py, b, wo, u, strategy_name)
        })
    }

    /// The solid-angle density of `wi` given `wo`, both (N, 3).
    fn pdf_f32<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f32>>,
        wi: Bound<'py, PyArray2<f32>>,
        strategy_name: &str,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            let b = brdf_of(&self.m32, self.id)?;
            self.pdf(py, b, wo, wi, strategy_name)
        })
    }

    fn pdf_f64<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f64>>,
        wi: Bound<'py, PyArray2<f64>>,
        strategy_name: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            self.pdf(py, b, wo, wi, strategy_name)
        })
    }

    /// The sampling strategies of a BRDF, its default first.
    fn strategies(&self) -> PyResult<Vec<&'static str>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            Ok(b.strategies().iter().map(|s| s.name()).collect())
        })
    }
}

impl Handle {
    fn resolve<T: Real>(&self, b: &dyn fastbrdf::Brdf<T>, name: &str) -> PyResult<Strategy> {
        b.resolve(strategy(name)?)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.id)))
    }

    /// The columns of `eval_f32`/`eval_f64`: a sequence of 1-D arrays of dtype `T`, ready.
    fn columns_arg<'py, T: Element>(
        &self,
        cols: &Bound<'py, PyAny>,
    ) -> PyResult<Vec<PyReadonlyArray<'py, T, numpy::Ix1>>> {
        seq(cols, "cols", MAX_ITEMS, |c| {
            ready(c.cast::<PyArray1<T>>()?.clone())
        })
    }

    /// The column count must fit the model and the lengths must agree: returns the length.
    fn check_columns<T>(&self, cols: &[&[T]]) -> PyResult<usize> {
        let (req, opt) = self.m64.columns();
        if !(req.len() <= cols.len() && cols.len() <= req.len() + opt.len()) || cols.is_empty() {
            let optional = if opt.is_empty() {
                String::new()
            } else {
                format!(" (optionally {})", opt.join(", "))
            };
            return Err(PyTypeError::new_err(format!(
                "cols: model '{}' takes {}{optional}, got {} column(s)",
                self.id,
                req.join(", "),
                cols.len()
            )));
        }
        let n = cols[0].len();
        if let Some((i, c)) = cols.iter().enumerate().find(|(_, c)| c.len() != n) {
            return Err(value_error(format!(
                "cols: column {i} has {} values, column 0 has {n}",
                c.len()
            )));
        }
        Ok(n)
    }

    fn sample<'py, T: Real + Element>(
        &self,
        py: Python<'py>,
        b: &dyn fastbrdf::Brdf<T>,
        wo: Bound<'py, PyArray2<T>>,
        u: Bound<'py, PyArray2<T>>,
        strategy_name: &str,
    ) -> PyResult<Sampled<'py, T>> {
        let s = self.resolve(b, strategy_name)?;
        let (wo, u) = (ready(wo)?, ready(u)?);
        let (wo, u) = (slice2(&wo, 3, "wo")?, slice2(&u, 2, "u")?);
        let n = wo.len() / 3;
        same_rows("wo", n, "u", u.len() / 2)?;
        let (wi_out, weight_out, pdf_out) = (
            empty::<T>(py, 3 * n)?,
            empty::<T>(py, n)?,
            empty::<T>(py, n)?,
        );
        {
            let (mut a, mut w, mut p) = (
                wi_out.try_readwrite()?,
                weight_out.try_readwrite()?,
                pdf_out.try_readwrite()?,
            );
            let (a, w, p) = (
                a.as_slice_mut().map_err(value_error)?,
                w.as_slice_mut().map_err(value_error)?,
                p.as_slice_mut().map_err(value_error)?,
            );
            chunked(py, n, |r| {
                sample_rows(b, s, (wo, u), r, (&mut *a, &mut *w, &mut *p))
            })?;
        }
        Ok((wi_out, weight_out, pdf_out))
    }

    fn pdf<'py, T: Real + Element>(
        &self,
        py: Python<'py>,
        b: &dyn fastbrdf::Brdf<T>,
        wo: Bound<'py, PyArray2<T>>,
        wi: Bound<'py, PyArray2<T>>,
        strategy_name: &str,
    ) -> PyResult<Bound<'py, PyArray1<T>>> {
        let s = self.resolve(b, strategy_name)?;
        let (wo, wi) = (ready(wo)?, ready(wi)?);
        let (wo, wi) = (slice2(&wo, 3, "wo")?, slice2(&wi, 3, "wi")?);
        let n = wo.len() / 3;
        same_rows("wo", n, "wi", wi.len() / 3)?;
        let out = empty::<T>(py, n)?;
        {
            let mut rw = out.try_readwrite()?;
            let o = rw.as_slice_mut().map_err(value_error)?;
            chunked(py, n, |r| -> Result<(), String> {
                let span = 3 * r.start..3 * r.end;
                pdf_rows(b, s, &wo[span.clone()], &wi[span], &mut o[r]);
                Ok(())
            })?;
        }
        Ok(out)
    }
}

/// The info of model `id` as `fastbrdf models --json` prints one entry.
#[pyfunction]
fn info_json(id: &str) -> PyResult<String> {
    guard(|| {
        let e = registry::find(id).map_err(value_error)?;
        serde_json::to_string(&e.info).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

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
fn errors_json(
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
                    registry::build::<f64>(id, &[(param, &fastbrdf_analysis::range::num(*v))])
                        .map_err(|e| e.to_string())?;
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
fn parse_range(text: &str, default_step: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    guard(|| {
        let step = float_arg(default_step, "default_step")?;
        fastbrdf_analysis::range::parse(text, step).map_err(value_error)
    })
}

/// `fastbrdf albedo --json`'s object, as JSON. Runs on a worker that Ctrl-C stops.
#[pyfunction]
fn albedo_json(
    py: Python<'_>,
    model: &str,
    params: &Bound<'_, PyAny>,
    angles: &Bound<'_, PyAny>,
    as_brdf: &str,
    norm: &str,
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
        let t = albedo::target(model, &params, as_brdf, norm).map_err(value_error)?;
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
        let v = serde_json::json!({"model": model, "brdf": t.id, "params": p,
            "claims_energy": t.claims_energy, "conserves": holds, "rows": rows});
        Ok(v.to_string())
    })
}

/// A weight or albedo channel: finite, from 0 to [`MAX_WEIGHT`] (as the CLI's).
fn weight_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f32> {
    let v = float_arg(obj, name)?;
    if !(0.0..=MAX_WEIGHT).contains(&v) {
        return Err(value_error(format!(
            "{name} {}: must be from 0 to {MAX_WEIGHT}",
            shown(obj)
        )));
    }
    Ok(v as f32)
}

/// A CPU render as a flat linear float32 array (H * W * 3, row-major, top row first). Runs on
/// a worker that Ctrl-C stops.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    model: &str,
    params: &Bound<'py, PyAny>,
    width: &Bound<'py, PyAny>,
    height: &Bound<'py, PyAny>,
    spp: &Bound<'py, PyAny>,
    kd: &Bound<'py, PyAny>,
    ks: &Bound<'py, PyAny>,
    albedo: &Bound<'py, PyAny>,
    lights: &Bound<'py, PyAny>,
    floor: bool,
    shadows: bool,
    env: Option<String>,
    env_samples: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    use fastbrdf_render::render::{Options, Shading};
    use fastbrdf_render::scene::{Light, Specular};
    use fastbrdf_render::setup::{self, SceneSpec};
    guard(|| {
        let params = params_arg(params)?;
        let (width, height) = (u32_arg(width, "width")?, u32_arg(height, "height")?);
        let (spp, env_samples) = (u32_arg(spp, "spp")?, u32_arg(env_samples, "env_samples")?);
        let rgb = seq(albedo, "albedo", 3, |x| weight_arg(x, "albedo"))
            .and_then(|v| <[f32; 3]>::try_from(v).map_err(|_| value_error("too few")))
            .map_err(|e| {
                if e.is_instance_of::<PyValueError>(py)
                    && !e.value(py).to_string().starts_with("albedo[")
                {
                    value_error(format!(
                        "albedo {}: expected 3 numbers from 0 to {MAX_WEIGHT}",
                        shown(albedo)
                    ))
                } else {
                    e
                }
            })?;
        let mut spec = SceneSpec::new();
        spec.kd = weight_arg(kd, "kd")?;
        spec.ks = weight_arg(ks, "ks")?;
        spec.albedo = glam::Vec3::from_array(rgb);
        spec.floor = floor;
        spec.shadows = shadows;
        spec.env = env;
        if !(1..=fastbrdf_render::env::MAX_ENV_SAMPLES).contains(&env_samples) {
            return Err(value_error(format!(
                "env_samples {env_samples}: must be 1 to {}",
                fastbrdf_render::env::MAX_ENV_SAMPLES
            )));
        }
        spec.env_samples = env_samples;
        spec.lights = seq(lights, "lights", MAX_ITEMS, |l| l.extract::<String>())?
            .iter()
            .map(|l| Light::parse(l))
            .collect::<Result<_, _>>()
            .map_err(value_error)?;
        fastbrdf_render::film::check_size(width, height).map_err(value_error)?;
        if !(1..=16).contains(&spp) {
            return Err(value_error(format!(
                "spp {spp}: must be 1 to 16 (N x N samples per pixel)"
            )));
        }
        let opts = Options {
            width,
            height,
            spp,
            shading: Shading::Batch,
        };
        let specular = Arc::new(Specular::new(model, &params).map_err(value_error)?);
        // The output first: a size the process cannot have is numpy's MemoryError before any
        // work (the film below is allocated fallibly too).
        let out = empty::<f32>(py, 3 * width as usize * height as usize)?;
        let film = interruptible(py, |cancel| -> fastbrdf_render::Result<_> {
            let loaded = setup::load(&spec)?;
            let scene = setup::scene(&spec, &loaded, specular);
            let stop = || cancel.load(Ordering::Relaxed);
            let film = fastbrdf_render::render::render_until(&scene, &opts, &|_, _| (), &stop)?;
            if let Some(film) = &film {
                film.check_finite()?;
            }
            Ok(film)
        })?
        .map_err(|e| match e {
            fastbrdf_render::RenderError::Memory(m) => PyMemoryError::new_err(m),
            e => value_error(e),
        })?
        .ok_or_else(|| PyKeyboardInterrupt::new_err(()))?;
        {
            let mut rw = out.try_readwrite()?;
            let o = rw.as_slice_mut().map_err(value_error)?;
            for (o, p) in o.chunks_exact_mut(3).zip(&film.pixels) {
                o.copy_from_slice(&p.to_array());
            }
        }
        Ok(out)
    })
}

/// `fastbrdf shader`'s text for one model.
#[pyfunction]
fn shader(
    model: &str,
    params: &Bound<'_, PyAny>,
    lang: &str,
    runtime_params: bool,
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
        export_form(model, &given(&params), l, form).map_err(value_error)
    })
}

#[pymodule]
fn _fastbrdf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Handle>()?;
    m.add("MAX_VALUES", MAX_VALUES)?;
    m.add("MAX_ITEMS", MAX_ITEMS)?;
    m.add("MAX_WEIGHT", MAX_WEIGHT)?;
    m.add_function(wrap_pyfunction!(models_json, m)?)?;
    m.add_function(wrap_pyfunction!(info_json, m)?)?;
    m.add_function(wrap_pyfunction!(errors_json, m)?)?;
    m.add_function(wrap_pyfunction!(parse_range, m)?)?;
    m.add_function(wrap_pyfunction!(albedo_json, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(shader, m)?)?;
    Ok(())
}
