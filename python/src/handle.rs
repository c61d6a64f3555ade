//! `Handle`: one model built once (its spec's plan in both precisions and its batch kernel)
//! and evaluated, sampled and its density computed over numpy arrays.

use crate::MAX_ITEMS;
use crate::args::{full_spec, grey_spec, params_arg, seq};
use crate::arrays::{CHUNK, chunked, empty, output, ready, same_rows, slice, slice2, writable};
use crate::guard::{guard, value_error};
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::sample::Strategy;
use fastbrdf::{Model, ModelSpec, Real};
use numpy::{Element, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::ops::Range;

/// One model, built once in both precisions (and its batch kernel when it has one).
#[pyclass(frozen, module = "fastbrdf._fastbrdf")]
pub(crate) struct Handle {
    id: &'static str,
    kind: fastbrdf::Kind,
    m32: Model<f32>,
    m64: Model<f64>,
    kernel: Option<Kernel>,
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
            let (wi, wo) = (ready(wi)?, ready(wo)?);
            let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
            same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
            let n = wi.len() / 3;
            let out = output::<f32>(py, n, out)?;
            {
                let mut rw = writable(&out)?;
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
            let (wi, wo) = (ready(wi)?, ready(wo)?);
            let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
            same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
            let n = wi.len() / 3;
            let out = output::<f64>(py, n, out)?;
            {
                let mut rw = writable(&out)?;
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
    /// Builds a grey spec's models (both precisions) and its batch kernel.
    pub(crate) fn from_spec(spec: &ModelSpec) -> PyResult<Self> {
        let plan = spec.plan().map_err(value_error)?;
        let kernel = match plan.kind() {
            fastbrdf::Kind::Shadowing => None,
            _ => Some(Kernel::new(spec).map_err(value_error)?),
        };
        Ok(Self {
            id: spec.id(),
            kind: plan.kind(),
            m32: plan.model::<f32>(),
            m64: plan.model::<f64>(),
            kernel,
            spec: spec.clone(),
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
