//! `Handle`: one model built once (its spec's plan in both precisions and its batch kernel)
//! and evaluated, sampled and its density computed over numpy arrays.

use crate::MAX_ITEMS;
use crate::args::{full_spec, grey_spec, params_arg, seq};
use crate::arrays::{aligned, chunked, output, ready, rows2, same_rows, slice, writable};
use crate::guard::{guard, value_error};
use fastbrdf::batch::sample::{SampleOut, Sampler};
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::sample::Strategy;
use fastbrdf::{Brdf, Model, ModelSpec, Real};
use numpy::{Element, PyArray1, PyArray2, PyReadonlyArray};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use rows::{Outs3, Rows, Soa, for_chunks, for_chunks3, prefetch};
use std::ops::Range;

mod interleave;
mod rows;

/// One model, built once in both precisions (and its batch kernel when it has one).
#[pyclass(frozen, module = "fastbrdf._fastbrdf")]
pub(crate) struct Handle {
    id: &'static str,
    kind: fastbrdf::Kind,
    m32: Model<f32>,
    m64: Model<f64>,
    kernel: Option<Kernel>,
    /// A BRDF's batched f32 sampler.
    sampler: Option<Sampler>,
    /// The grey spec it was built from (one colour channel).
    spec: ModelSpec,
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

/// The f32 kernel over rows `r` of (N, 3) `wi`, `wo` (any strides), deinterleaved and run
/// [`CHUNK`](crate::arrays::CHUNK) rows at a time over rayon's threads.
fn brdf_kernel(k: &Kernel, (wi, wo): Pairs<f32>, r: Range<usize>, out: &mut [f32]) -> Res {
    for_chunks(r.start, (out, 1), soa2::<3, 3, f32>, |(a, b), r, o| {
        let (i, w) = (a.load(&wi, r.clone()), b.load(&wo, r));
        k.eval(Input::Dirs([i[0], i[1], i[2], w[0], w[1], w[2]]), o)
    })
}

/// The scalar BRDF in precision `T` over rows `r` of (N, 3) `wi`, `wo`, threaded as
/// [`brdf_kernel`].
fn brdf_rows<T: Real>(b: &dyn Brdf<T>, (wi, wo): Pairs<T>, r: Range<usize>, out: &mut [T]) -> Res {
    for_chunks(r.start, (out, 1), soa2::<3, 3, T>, |(x, y), r, o| {
        let (i, w) = (x.load(&wi, r.clone()), y.load(&wo, r));
        for (j, o) in o.iter_mut().enumerate() {
            *o = b.eval([i[0][j], i[1][j], i[2][j]], [w[0][j], w[1][j], w[2][j]]);
        }
        Ok(())
    })
}

/// `Model::eval_row` over rows `r` of 1-D columns, threaded as [`brdf_kernel`].
fn rows_par<T: Real>(m: &Model<T>, cols: &[&[T]], r: Range<usize>, out: &mut [T]) -> Res {
    for_chunks(
        r.start,
        (out, 1),
        || (),
        |_, r, o| {
            rows(m, cols, r, o);
            Ok(())
        },
    )
}

/// Two per-thread buffers of `A` and `B` columns.
fn soa2<const A: usize, const B: usize, T: Copy + Default + 'static>() -> (Soa<T, A>, Soa<T, B>) {
    (Soa::new(), Soa::new())
}

fn brdf_of<'a, T: Real>(m: &'a Model<T>, id: &str) -> PyResult<&'a dyn Brdf<T>> {
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

/// Every `u` of rows `r` in [0, 1) (NaN is not), else the first one outside, named by row
/// and column.
fn check_u<T: Real>(u: &Rows<'_, T>, r: Range<usize>) -> Result<(), String> {
    let bad = |x: T| !(x >= T::zero() && x < T::one());
    let any_bad = |v: &[T]| v.iter().fold(false, |b, x| b | bad(*x));
    if let Some([x, y]) = rows::columns::<T, 2>(u, r.clone()) {
        // Column-major: the same branch-free pass, per column.
        if !(any_bad(x) | any_bad(y)) {
            return Ok(());
        }
    }
    let first = match u.as_slice() {
        // A branch-free pass (vectorised) first; the search only where it fails.
        Some(all) if any_bad(&all[2 * r.start..2 * r.end]) => all[2 * r.start..2 * r.end]
            .iter()
            .position(|x| bad(*x))
            .map(|i| (r.start + i / 2, i % 2)),
        Some(_) => None,
        None => r.clone().find_map(|i| {
            let row = u.row(i);
            (0..2).find(|c| bad(row[*c])).map(|c| (i, c))
        }),
    };
    match first {
        None => Ok(()),
        Some((i, c)) => Err(format!(
            "u: {} (row {i}, column {c}) is outside [0, 1)",
            u[[i, c]]
        )),
    }
}

/// Samples rows `r` per element with the scalar model in precision `T`, threaded: `wi`
/// (3 per row), weight, pdf; no sample gives zeros. `u` is checked first ([`check_u`]).
fn sample_rows<T: Real>(
    b: &dyn Brdf<T>,
    s: Strategy,
    (wo, u): Pairs<T>,
    r: Range<usize>,
    outs: Outs3<'_, T>,
) -> Result<(), String> {
    let run = for_chunks3(
        r.start,
        outs,
        [3, 1, 1],
        soa2::<3, 2, T>,
        |(x, y), r, outs| {
            check_u(&u, r.clone()).map_err(|_| ())?;
            let (wo, u) = (x.load(&wo, r.clone()), y.load(&u, r));
            let (wi, weight, pdf) = outs;
            let rows = wi.chunks_exact_mut(3).zip(weight).zip(pdf);
            for (j, ((wi, weight), pdf)) in rows.enumerate() {
                match b.sample([wo[0][j], wo[1][j], wo[2][j]], [u[0][j], u[1][j]], s) {
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
        },
    );
    // A chunk saw a `u` outside [0, 1): name the first one in order, whatever the threads.
    run.or_else(|()| check_u(&u, r))
}

/// Samples rows `r` in f32 with the batched [`Sampler`] (the scalar model's values, bit for
/// bit), threaded as [`sample_rows`].
fn sampler_rows(
    sp: &Sampler,
    s: Strategy,
    (wo, u): Pairs<f32>,
    r: Range<usize>,
    outs: Outs3<'_, f32>,
) -> Result<(), String> {
    let init = || {
        (
            Soa::<f32, 3>::new(),
            Soa::<f32, 2>::new(),
            Soa::<f32, 3>::new(),
        )
    };
    let run = for_chunks3(r.start, outs, [3, 1, 1], init, |(x, y, z), r, outs| {
        check_u(&u, r.clone()).map_err(|_| None)?;
        let (wi, weight, pdf) = outs;
        // Deinterleaved, sampled and interleaved back `FUSED` rows at a time: the columns
        // stay in L1, and the next rows, prefetched, stream in while these are computed.
        for lo in (0..r.len()).step_by(FUSED) {
            let hi = (lo + FUSED).min(r.len());
            let rows = r.start + lo..r.start + hi;
            let (a, b) = (x.load(&wo, rows.clone()), y.load(&u, rows));
            let next = r.start + hi..(r.start + hi + FUSED).min(r.end);
            prefetch(&wo, next.clone());
            prefetch(&u, next);
            let out = SampleOut {
                wi: z.cols_mut(hi - lo),
                weight: &mut weight[lo..hi],
                pdf: &mut pdf[lo..hi],
            };
            sp.sample(s, a, b, out).map_err(|e| Some(e.to_string()))?;
            z.store(&mut wi[3 * lo..3 * hi]);
        }
        Ok(())
    });
    match run {
        Ok(()) => Ok(()),
        Err(Some(e)) => Err(e),
        Err(None) => check_u(&u, r),
    }
}

/// The f32 density over rows `r` with the batched [`Sampler`], threaded.
fn sampler_pdf_rows(
    sp: &Sampler,
    s: Strategy,
    (wo, wi): Pairs<f32>,
    r: Range<usize>,
    out: &mut [f32],
) -> Res {
    for_chunks(r.start, (out, 1), soa2::<3, 3, f32>, |(x, y), r, o| {
        // `FUSED` rows at a time, as in `sampler_rows`.
        for lo in (0..r.len()).step_by(FUSED) {
            let hi = (lo + FUSED).min(r.len());
            let rows = r.start + lo..r.start + hi;
            let (a, b) = (x.load(&wo, rows.clone()), y.load(&wi, rows));
            let next = r.start + hi..(r.start + hi + FUSED).min(r.end);
            prefetch(&wo, next.clone());
            prefetch(&wi, next);
            sp.pdf(s, a, b, &mut o[lo..hi])?;
        }
        Ok(())
    })
}

/// Rows per step of the sampler's fused passes (deinterleave, compute, interleave): the SIMD
/// path's block. Every value depends on its own row alone, so the step changes none.
const FUSED: usize = 512;

/// The density per element over rows `r` with the scalar model in precision `T`, threaded.
fn pdf_rows<T: Real>(
    b: &dyn Brdf<T>,
    s: Strategy,
    (wo, wi): Pairs<T>,
    r: Range<usize>,
    out: &mut [T],
) -> Res {
    for_chunks(r.start, (out, 1), soa2::<3, 3, T>, |(x, y), r, o| {
        let (wo, wi) = (x.load(&wo, r.clone()), y.load(&wi, r));
        for (j, o) in o.iter_mut().enumerate() {
            *o = b.pdf(
                [wo[0][j], wo[1][j], wo[2][j]],
                [wi[0][j], wi[1][j], wi[2][j]],
                s,
            );
        }
        Ok(())
    })
}

/// Two (N, k) inputs read in place.
type Pairs<'a, T> = (Rows<'a, T>, Rows<'a, T>);
type Res = fastbrdf::Result<()>;

type Sampled<'py, T> = (
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<T>>,
    Bound<'py, PyArray1<T>>,
);

#[pymethods]
impl Handle {
    /// Builds grey model `id` with parameters given as text (parsed once into its spec; see
    /// [`grey_spec`]).
    #[new]
    fn new(id: &str, params: &Bound<'_, PyAny>) -> PyResult<Self> {
        guard(|| Self::from_spec(&grey_spec(id, &params_arg(params)?)?))
    }

    /// Model `id` with parameters given as text, a MERL material's fit and a named metal
    /// ([`full_spec`]): one handle per colour channel (1 or 3).
    #[staticmethod]
    #[pyo3(signature = (id, params, material=None, metal=None))]
    fn channels(
        id: &str,
        params: &Bound<'_, PyAny>,
        material: Option<&str>,
        metal: Option<&str>,
    ) -> PyResult<Vec<Self>> {
        guard(|| {
            let spec = full_spec(id, &params_arg(params)?, material, metal)?;
            spec.channel_specs().iter().map(Self::from_spec).collect()
        })
    }

    /// The spec as text, `id k=v ...` (the values given, a material's and a metal's).
    #[getter]
    fn spec(&self) -> String {
        self.spec.to_string()
    }

    #[getter]
    fn id(&self) -> &'static str {
        self.id
    }

    /// Every parameter resolved (given values and defaults), `[(name, number or choice)]`:
    /// what `Model.__eq__` compares, read from the spec.
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Vec<(&'static str, Bound<'py, PyAny>)>> {
        use fastbrdf::params::Value;
        let params = self.spec.params().map_err(value_error)?;
        params
            .iter()
            .map(|(k, v)| {
                let v = match v {
                    Value::Num(x) => x.into_pyobject(py)?.into_any(),
                    Value::Text(t) => t.into_pyobject(py)?.into_any(),
                };
                Ok((k, v))
            })
            .collect()
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
    #[pyo3(signature = (cols, out=None))]
    fn eval_f32<'py>(
        &self,
        py: Python<'py>,
        cols: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyArray1<f32>>>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            let cols = self.columns_arg::<f32>(cols)?;
            let cols: Vec<&[f32]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
            let n = self.check_columns(&cols)?;
            let out = output::<f32>(py, n, out)?;
            {
                let mut rw = writable(&out)?;
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
                        _ => rows_par(&self.m32, &cols, r, o),
                    }
                })?;
            }
            Ok(out)
        })
    }

    /// f64 over 1-D columns of equal length (not BRDFs).
    #[pyo3(signature = (cols, out=None))]
    fn eval_f64<'py>(
        &self,
        py: Python<'py>,
        cols: &Bound<'py, PyAny>,
        out: Option<Bound<'py, PyArray1<f64>>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let cols = self.columns_arg::<f64>(cols)?;
            let cols: Vec<&[f64]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
            let n = self.check_columns(&cols)?;
            let out = output::<f64>(py, n, out)?;
            {
                let mut rw = writable(&out)?;
                let o = rw.as_slice_mut().map_err(value_error)?;
                chunked(py, n, |r| rows_par(&self.m64, &cols, r.clone(), &mut o[r]))?;
            }
            Ok(out)
        })
    }

    /// A BRDF in f32 over (N, 3) `wi`, `wo` of any strides (read in place): the SIMD
    /// kernel, fed [`CHUNK`](crate::arrays::CHUNK) deinterleaved elements at a time, over
    /// rayon's threads.
    #[pyo3(signature = (wi, wo, out=None))]
    fn eval_dirs_f32<'py>(
        &self,
        py: Python<'py>,
        wi: Bound<'py, PyArray2<f32>>,
        wo: Bound<'py, PyArray2<f32>>,
        out: Option<Bound<'py, PyArray1<f32>>>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            brdf_of(&self.m32, self.id)?;
            let k = self.kernel.as_ref().ok_or_else(|| {
                PyRuntimeError::new_err("internal error in fastbrdf: a BRDF without a kernel")
            })?;
            let (wi, wo) = (aligned(wi)?, aligned(wo)?);
            let dirs = pairs((&wi, "wi", 3), (&wo, "wo", 3))?;
            self.eval_dirs(py, dirs, out, |d, r, o| brdf_kernel(k, d, r, o))
        })
    }

    /// A BRDF in f64 over (N, 3) `wi`, `wo` of any strides (the scalar model, threaded).
    #[pyo3(signature = (wi, wo, out=None))]
    fn eval_dirs_f64<'py>(
        &self,
        py: Python<'py>,
        wi: Bound<'py, PyArray2<f64>>,
        wo: Bound<'py, PyArray2<f64>>,
        out: Option<Bound<'py, PyArray1<f64>>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            let (wi, wo) = (aligned(wi)?, aligned(wo)?);
            let dirs = pairs((&wi, "wi", 3), (&wo, "wo", 3))?;
            self.eval_dirs(py, dirs, out, |d, r, o| brdf_rows(b, d, r, o))
        })
    }

    /// Samples `wi` given (N, 3) `wo` and (N, 2) `u` in [0, 1), both of any strides:
    /// `(wi (N*3), weight, pdf)`, written into `out` when given (three C-contiguous
    /// writeable 1-D arrays of 3N, N and N elements).
    #[pyo3(signature = (wo, u, strategy_name, out=None))]
    fn sample_f32<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f32>>,
        u: Bound<'py, PyArray2<f32>>,
        strategy_name: &str,
        out: Option<Sampled<'py, f32>>,
    ) -> PyResult<Sampled<'py, f32>> {
        guard(|| {
            let b = brdf_of(&self.m32, self.id)?;
            let sp = self.sampler()?;
            self.sample(py, b, (wo, u), strategy_name, out, |s, d, r, o| {
                sampler_rows(sp, s, d, r, o)
            })
        })
    }

    #[pyo3(signature = (wo, u, strategy_name, out=None))]
    fn sample_f64<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f64>>,
        u: Bound<'py, PyArray2<f64>>,
        strategy_name: &str,
        out: Option<Sampled<'py, f64>>,
    ) -> PyResult<Sampled<'py, f64>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            self.sample(py, b, (wo, u), strategy_name, out, |s, d, r, o| {
                sample_rows(b, s, d, r, o)
            })
        })
    }

    /// The solid-angle density of `wi` given `wo`, both (N, 3) of any strides (into `out`
    /// when given).
    #[pyo3(signature = (wo, wi, strategy_name, out=None))]
    fn pdf_f32<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f32>>,
        wi: Bound<'py, PyArray2<f32>>,
        strategy_name: &str,
        out: Option<Bound<'py, PyArray1<f32>>>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            let b = brdf_of(&self.m32, self.id)?;
            let sp = self.sampler()?;
            self.pdf(py, b, (wo, wi), strategy_name, out, |s, d, r, o| {
                sampler_pdf_rows(sp, s, d, r, o)
            })
        })
    }

    #[pyo3(signature = (wo, wi, strategy_name, out=None))]
    fn pdf_f64<'py>(
        &self,
        py: Python<'py>,
        wo: Bound<'py, PyArray2<f64>>,
        wi: Bound<'py, PyArray2<f64>>,
        strategy_name: &str,
        out: Option<Bound<'py, PyArray1<f64>>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let b = brdf_of(&self.m64, self.id)?;
            self.pdf(py, b, (wo, wi), strategy_name, out, |s, d, r, o| {
                pdf_rows(b, s, d, r, o)
            })
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
    /// Builds a grey spec's models (both precisions) and its batch kernel.
    pub(crate) fn from_spec(spec: &ModelSpec) -> PyResult<Self> {
        let plan = spec.plan().map_err(value_error)?;
        let kernel = match plan.kind() {
            fastbrdf::Kind::Shadowing => None,
            _ => Some(Kernel::new(spec).map_err(value_error)?),
        };
        let sampler = match plan.kind() {
            fastbrdf::Kind::Brdf => Some(Sampler::from_plan(spec.id(), plan).map_err(value_error)?),
            _ => None,
        };
        Ok(Self {
            id: spec.id(),
            kind: plan.kind(),
            m32: plan.model::<f32>(),
            m64: plan.model::<f64>(),
            kernel,
            sampler,
            spec: spec.clone(),
        })
    }

    /// A BRDF's f32 sampler (every BRDF has one).
    fn sampler(&self) -> PyResult<&Sampler> {
        self.sampler.as_ref().ok_or_else(|| {
            PyRuntimeError::new_err("internal error in fastbrdf: a BRDF without a sampler")
        })
    }

    /// The grey spec it was built from.
    pub(crate) fn model_spec(&self) -> &ModelSpec {
        &self.spec
    }

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

    /// A BRDF's value over two (N, 3) inputs into `out` (or a new array): `f` over steps of
    /// rows (the GIL released, Ctrl-C checked between them).
    fn eval_dirs<'py, T: Element + Sync>(
        &self,
        py: Python<'py>,
        dirs: Pairs<'_, T>,
        out: Option<Bound<'py, PyArray1<T>>>,
        f: impl Fn(Pairs<'_, T>, Range<usize>, &mut [T]) -> Res + Send + Sync,
    ) -> PyResult<Bound<'py, PyArray1<T>>> {
        let n = dirs.0.nrows();
        let out = output::<T>(py, n, out)?;
        {
            let mut rw = writable(&out)?;
            let o = rw.as_slice_mut().map_err(value_error)?;
            chunked(py, n, |r| f(dirs, r.clone(), &mut o[r]))?;
        }
        Ok(out)
    }

    fn sample<'py, T: Real + Element>(
        &self,
        py: Python<'py>,
        b: &dyn Brdf<T>,
        (wo, u): (Bound<'py, PyArray2<T>>, Bound<'py, PyArray2<T>>),
        strategy_name: &str,
        out: Option<Sampled<'py, T>>,
        rows: impl Fn(Strategy, Pairs<'_, T>, Range<usize>, Outs3<'_, T>) -> Result<(), String>
        + Send
        + Sync,
    ) -> PyResult<Sampled<'py, T>> {
        let s = self.resolve(b, strategy_name)?;
        let (wo, u) = (aligned(wo)?, aligned(u)?);
        let (wo, u) = pairs((&wo, "wo", 3), (&u, "u", 2))?;
        let n = wo.nrows();
        let (a, w, p) = match out {
            Some((a, w, p)) => (Some(a), Some(w), Some(p)),
            None => (None, None, None),
        };
        let (wi_out, weight_out, pdf_out) = (
            output::<T>(py, 3 * n, a)?,
            output::<T>(py, n, w)?,
            output::<T>(py, n, p)?,
        );
        {
            let (mut a, mut w, mut p) = (
                writable(&wi_out)?,
                writable(&weight_out)?,
                writable(&pdf_out)?,
            );
            let (a, w, p) = (
                a.as_slice_mut().map_err(value_error)?,
                w.as_slice_mut().map_err(value_error)?,
                p.as_slice_mut().map_err(value_error)?,
            );
            chunked(py, n, |r| {
                let outs = (
                    &mut a[3 * r.start..3 * r.end],
                    &mut w[r.clone()],
                    &mut p[r.clone()],
                );
                rows(s, (wo, u), r, outs)
            })?;
        }
        Ok((wi_out, weight_out, pdf_out))
    }

    fn pdf<'py, T: Real + Element>(
        &self,
        py: Python<'py>,
        b: &dyn Brdf<T>,
        (wo, wi): (Bound<'py, PyArray2<T>>, Bound<'py, PyArray2<T>>),
        strategy_name: &str,
        out: Option<Bound<'py, PyArray1<T>>>,
        rows: impl Fn(Strategy, Pairs<'_, T>, Range<usize>, &mut [T]) -> Res + Send + Sync,
    ) -> PyResult<Bound<'py, PyArray1<T>>> {
        let s = self.resolve(b, strategy_name)?;
        let (wo, wi) = (aligned(wo)?, aligned(wi)?);
        let dirs = pairs((&wo, "wo", 3), (&wi, "wi", 3))?;
        self.eval_dirs(py, dirs, out, |d, r, o| rows(s, d, r, o))
    }
}

/// Two aligned (N, k) arrays as rows, their widths and row counts checked (the second
/// named against the first).
fn pairs<'a, T: Element>(
    (a, an, ak): (&'a PyReadonlyArray<'_, T, numpy::Ix2>, &str, usize),
    (b, bn, bk): (&'a PyReadonlyArray<'_, T, numpy::Ix2>, &str, usize),
) -> PyResult<Pairs<'a, T>> {
    let (a, b) = (rows2(a, ak, an)?, rows2(b, bk, bn)?);
    same_rows(an, a.nrows(), bn, b.nrows())?;
    Ok((a, b))
}
