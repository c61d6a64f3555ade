//! Per-element parameters (`fastbrdf.Model(..., alpha=array)`): checks and evaluation
//! through `fastbrdf::batch::per_element` (elements grouped by value, each group evaluated by
//! the batch kernel of the model built for its values; see that module for the cost).
//!
//! Parameter values arrive as float64 (a float32 value widens exactly); inputs and outputs
//! in the precision evaluated. The work runs in GIL-released steps with Ctrl-C checked
//! between them ([`chunked`]).

use crate::MAX_ITEMS;
use crate::args::seq;
use crate::arrays::{STEP, empty, ready, same_rows, slice, slice2, writable};
use crate::guard::{guard, value_error};
use crate::handle::Handle;
use fastbrdf::batch::per_element::{PerElement, Rows, numeric};
use fastbrdf::batch::sample::{SampleOut, Sampler};
use fastbrdf::sample::Strategy;
use fastbrdf::{Model, Real};
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
            crate::fork::run(|| {
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

/// An error message of a per-element step (the library's, or a strategy's).
struct Msg(String);

impl From<fastbrdf::Error> for Msg {
    fn from(e: fastbrdf::Error) -> Self {
        Msg(e.to_string())
    }
}

impl std::fmt::Display for Msg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The BRDF of a per-element model (`ValueError` for another kind).
fn brdf_of<T: Real>(m: &Model<T>) -> Result<&dyn fastbrdf::Brdf<T>, String> {
    match m {
        Model::Brdf(b) => Ok(b.as_ref()),
        m => Err(format!(
            "a {} cannot be sampled (BRDFs only)",
            m.kind().name()
        )),
    }
}

/// `strategy_name` parsed (`ValueError` listing the strategies), as `Handle`'s.
fn strategy(name: &str) -> PyResult<Strategy> {
    Strategy::parse(name).ok_or_else(|| {
        value_error(format!(
            "strategy '{}': expected one of {}",
            fastbrdf_io::shorten(name, 40),
            Strategy::ALL.map(|s| s.name()).join(", ")
        ))
    })
}

/// Element `i`'s 3-vector of a flat (N, 3) array.
fn v3<T: Real>(a: &[T], i: usize) -> [T; 3] {
    [a[3 * i], a[3 * i + 1], a[3 * i + 2]]
}

type Sampled<'py, T> = (
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<T>>,
);

/// Element draws and densities as `Model.sample` and `Model.pdf` compute them: the scalar
/// model in f64, the batched `Sampler` of the element's value set in f32 (built once per
/// value set in a step; its SIMD path's unit tier is not the scalar model's bits).
trait Draw: Real + Element {
    type Cache: Default;
    fn density(
        cache: &mut Self::Cache,
        at: (&PerElement, Vec<f64>),
        b: &dyn fastbrdf::Brdf<Self>,
        wo_wi: ([Self; 3], [Self; 3]),
        s: Strategy,
    ) -> Result<Self, Msg>;
    fn draw(
        cache: &mut Self::Cache,
        at: (&PerElement, Vec<f64>),
        b: &dyn fastbrdf::Brdf<Self>,
        wo_u: ([Self; 3], [Self; 2]),
        s: Strategy,
    ) -> Result<Option<fastbrdf::sample::Sample<Self>>, Msg>;
}

impl Draw for f64 {
    type Cache = ();
    fn density(
        _: &mut (),
        _: (&PerElement, Vec<f64>),
        b: &dyn fastbrdf::Brdf<f64>,
        (wo, wi): ([f64; 3], [f64; 3]),
        s: Strategy,
    ) -> Result<f64, Msg> {
        Ok(b.pdf(wo, wi, s))
    }
    fn draw(
        _: &mut (),
        _: (&PerElement, Vec<f64>),
        b: &dyn fastbrdf::Brdf<f64>,
        (wo, u): ([f64; 3], [f64; 2]),
        s: Strategy,
    ) -> Result<Option<fastbrdf::sample::Sample<f64>>, Msg> {
        Ok(b.sample(wo, u, s))
    }
}

/// The batched sampler of one value set, built once per step.
fn sampler_at<'c>(
    cache: &'c mut std::collections::HashMap<Vec<u64>, Sampler>,
    pe: &PerElement,
    values: &[f64],
) -> Result<&'c Sampler, Msg> {
    let key: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
    Ok(match cache.entry(key) {
        std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
        std::collections::hash_map::Entry::Vacant(e) => {
            let spec = pe.spec_at(values)?;
            e.insert(Sampler::from_plan(spec.id(), spec.plan()?)?)
        }
    })
}

impl Draw for f32 {
    type Cache = std::collections::HashMap<Vec<u64>, Sampler>;
    fn density(
        cache: &mut Self::Cache,
        (pe, values): (&PerElement, Vec<f64>),
        _: &dyn fastbrdf::Brdf<f32>,
        (wo, wi): ([f32; 3], [f32; 3]),
        s: Strategy,
    ) -> Result<f32, Msg> {
        let sp = sampler_at(cache, pe, &values)?;
        let mut p = [0.0f32];
        sp.pdf(
            s,
            wo.each_ref().map(std::slice::from_ref),
            wi.each_ref().map(std::slice::from_ref),
            &mut p,
        )?;
        Ok(p[0])
    }
    fn draw(
        cache: &mut Self::Cache,
        (pe, values): (&PerElement, Vec<f64>),
        _: &dyn fastbrdf::Brdf<f32>,
        (wo, u): ([f32; 3], [f32; 2]),
        s: Strategy,
    ) -> Result<Option<fastbrdf::sample::Sample<f32>>, Msg> {
        let sp = sampler_at(cache, pe, &values)?;
        let (mut wi, mut weight, mut pdf) = ([[0.0f32]; 3], [0.0f32], [0.0f32]);
        let [x, y, z] = &mut wi;
        let out = SampleOut {
            wi: [x, y, z],
            weight: &mut weight,
            pdf: &mut pdf,
        };
        sp.sample(
            s,
            wo.each_ref().map(std::slice::from_ref),
            u.each_ref().map(std::slice::from_ref),
            out,
        )?;
        Ok((pdf[0] > 0.0).then(|| fastbrdf::sample::Sample {
            wi: wi.map(|w| w[0]),
            weight: weight[0],
            pdf: pdf[0],
        }))
    }
}

/// Samples `wi` given (N, 3) `wo` and (N, 2) `u` in [0, 1) with per-element parameters:
/// `(wi (N*3), weight, pdf)`, each element as `Model.sample` of the model built for its
/// values (no sample: zeros).
fn sample<'py, T: Draw>(
    py: Python<'py>,
    handle: &Handle,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    (wo, u): (Bound<'py, PyArray2<T>>, Bound<'py, PyArray2<T>>),
    strategy_name: &str,
) -> PyResult<Sampled<'py, T>> {
    let pe = per_element(handle, &names)?;
    let s = strategy(strategy_name)?;
    let (wo, u) = (ready(wo)?, ready(u)?);
    let (wo, u) = (slice2(&wo, 3, "wo")?, slice2(&u, 2, "u")?);
    let n = wo.len() / 3;
    same_rows("wo", n, "u", u.len() / 2)?;
    if let Some(i) = u.iter().position(|x| !(*x >= T::zero() && *x < T::one())) {
        return Err(value_error(format!(
            "u: {} (row {}, column {}) is outside [0, 1)",
            u[i],
            i / 2,
            i % 2
        )));
    }
    let p = params_of(&names, params, n)?;
    let p: Vec<&[f64]> = p.iter().map(slice).collect::<PyResult<_>>()?;
    let (wi_out, weight_out, pdf_out) = (
        empty::<T>(py, 3 * n)?,
        empty::<T>(py, n)?,
        empty::<T>(py, n)?,
    );
    {
        let (mut a, mut w, mut q) = (
            writable(&wi_out)?,
            writable(&weight_out)?,
            writable(&pdf_out)?,
        );
        let a = a.as_slice_mut().map_err(value_error)?;
        let w = w.as_slice_mut().map_err(value_error)?;
        let q = q.as_slice_mut().map_err(value_error)?;
        steps(py, n, |r| {
            let ps: Vec<&[f64]> = p.iter().map(|p| &p[r.clone()]).collect();
            let mut cache = T::Cache::default();
            pe.each_model::<T, Msg>(&ps, r.len(), |j, m| {
                let i = r.start + j;
                let b = brdf_of(m).map_err(Msg)?;
                let st = b
                    .resolve(s)
                    .map_err(|e| Msg(format!("{}: {e}", handle.model_spec().id())))?;
                let values = ps.iter().map(|p| p[j]).collect();
                let draw = (v3(wo, i), [u[2 * i], u[2 * i + 1]]);
                match T::draw(&mut cache, (&pe, values), b, draw, st)? {
                    Some(x) => {
                        a[3 * i..3 * i + 3].copy_from_slice(&x.wi);
                        (w[i], q[i]) = (x.weight, x.pdf);
                    }
                    None => {
                        a[3 * i..3 * i + 3].fill(T::zero());
                        (w[i], q[i]) = (T::zero(), T::zero());
                    }
                }
                Ok(())
            })
        })?;
    }
    Ok((wi_out, weight_out, pdf_out))
}

/// The density of `wi` given `wo` (both (N, 3)) with per-element parameters.
fn pdf<'py, T: Draw>(
    py: Python<'py>,
    handle: &Handle,
    names: Vec<String>,
    params: &Bound<'py, PyAny>,
    (wo, wi): (Bound<'py, PyArray2<T>>, Bound<'py, PyArray2<T>>),
    strategy_name: &str,
) -> PyResult<Bound<'py, PyArray1<T>>> {
    let pe = per_element(handle, &names)?;
    let s = strategy(strategy_name)?;
    let (wo, wi) = (ready(wo)?, ready(wi)?);
    let (wo, wi) = (slice2(&wo, 3, "wo")?, slice2(&wi, 3, "wi")?);
    let n = wo.len() / 3;
    same_rows("wo", n, "wi", wi.len() / 3)?;
    let p = params_of(&names, params, n)?;
    let p: Vec<&[f64]> = p.iter().map(slice).collect::<PyResult<_>>()?;
    let out = empty::<T>(py, n)?;
    {
        let mut rw = writable(&out)?;
        let o = rw.as_slice_mut().map_err(value_error)?;
        steps(py, n, |r| {
            let ps: Vec<&[f64]> = p.iter().map(|p| &p[r.clone()]).collect();
            let mut cache = T::Cache::default();
            pe.each_model::<T, Msg>(&ps, r.len(), |j, m| {
                let i = r.start + j;
                let b = brdf_of(m).map_err(Msg)?;
                let st = b
                    .resolve(s)
                    .map_err(|e| Msg(format!("{}: {e}", handle.model_spec().id())))?;
                let values = ps.iter().map(|p| p[j]).collect();
                o[i] = T::density(&mut cache, (&pe, values), b, (v3(wo, i), v3(wi, i)), st)?;
                Ok(())
            })
        })?;
    }
    Ok(out)
}

/// Runs `f` over `0..n` in GIL-released steps of [`STEP_MIN`] elements (sampling runs per
/// element: a step is at most a few tens of milliseconds, all-distinct values included),
/// Ctrl-C checked between them.
fn steps(
    py: Python<'_>,
    n: usize,
    mut f: impl FnMut(std::ops::Range<usize>) -> Result<(), Msg> + Send,
) -> PyResult<()> {
    let mut lo = 0;
    while lo < n {
        let hi = n.min(lo + STEP_MIN);
        py.detach(|| crate::fork::run(|| f(lo..hi)))
            .map_err(value_error)?;
        py.check_signals()?;
        lo = hi;
    }
    Ok(())
}

macro_rules! sample_fns {
    ($sample:ident, $pdf:ident, $t:ty) => {
        /// Samples with per-element parameters (see [`sample`]).
        #[pyfunction]
        fn $sample<'py>(
            py: Python<'py>,
            handle: PyRef<'py, Handle>,
            names: Vec<String>,
            params: &Bound<'py, PyAny>,
            wo: Bound<'py, PyArray2<$t>>,
            u: Bound<'py, PyArray2<$t>>,
            strategy_name: &str,
        ) -> PyResult<Sampled<'py, $t>> {
            guard(|| sample(py, &handle, names, params, (wo, u), strategy_name))
        }

        /// The density with per-element parameters (see [`pdf`]).
        #[pyfunction]
        fn $pdf<'py>(
            py: Python<'py>,
            handle: PyRef<'py, Handle>,
            names: Vec<String>,
            params: &Bound<'py, PyAny>,
            wo: Bound<'py, PyArray2<$t>>,
            wi: Bound<'py, PyArray2<$t>>,
            strategy_name: &str,
        ) -> PyResult<Bound<'py, PyArray1<$t>>> {
            guard(|| pdf(py, &handle, names, params, (wo, wi), strategy_name))
        }
    };
}

sample_fns!(perelement_sample_f32, perelement_pdf_f32, f32);
sample_fns!(perelement_sample_f64, perelement_pdf_f64, f64);

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(perelement_check, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_f32, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_f64, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_dirs_f32, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_eval_dirs_f64, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_sample_f32, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_sample_f64, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_pdf_f32, m)?)?;
    m.add_function(wrap_pyfunction!(perelement_pdf_f64, m)?)?;
    Ok(())
}
