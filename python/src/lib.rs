//! `fastbrdf._fastbrdf`: the native half of the Python package (pyo3 + numpy).
//!
//! Thin glue, like the CLI: the library computes, this module moves arrays and maps errors.
//! It takes only contiguous 1-D columns (and (N, 3) / (N, 2) direction arrays) of the exact
//! dtype; the Python layer (`python/fastbrdf/__init__.py`) checks dtypes and shapes,
//! broadcasts, and copies only when it must. Every evaluation releases the GIL. Errors are
//! `ValueError` (bad model, parameter or value: the library's own message) or `TypeError`.

use fastbrdf::batch::{Input, Kernel};
use fastbrdf::sample::Strategy;
use fastbrdf::{Model, Real, registry};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::sync::Arc;

/// Elements deinterleaved per step when a (N, 3) direction array feeds the SoA kernels: the
/// input is read in place, only this much is copied at a time.
const CHUNK: usize = 4096;

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn given(params: &[(String, String)]) -> Vec<(&str, &str)> {
    params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect()
}

/// The registry as `fastbrdf models --json` prints it: `{"models": [...]}` (pretty JSON).
#[pyfunction]
fn models_json() -> String {
    let models: Vec<_> = registry::all().iter().map(|e| &e.info).collect();
    serde_json::to_string_pretty(&serde_json::json!({ "models": models }))
        .expect("registry serialises")
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

fn slice<'a, T: numpy::Element>(a: &'a PyReadonlyArray1<'_, T>) -> PyResult<&'a [T]> {
    a.as_slice()
        .map_err(|_| PyTypeError::new_err("internal: a non-contiguous column reached the kernel"))
}

fn slice2<'a, T: numpy::Element>(
    a: &'a PyReadonlyArray2<'_, T>,
    cols: usize,
    name: &str,
) -> PyResult<&'a [T]> {
    if a.shape()[1] != cols {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape (N, {cols}), got {:?}",
            a.shape()
        )));
    }
    a.as_slice()
        .map_err(|_| PyTypeError::new_err("internal: a non-contiguous array reached the kernel"))
}

/// `Model::eval_row` over columns (the lenient shading rules), precision `T`.
fn rows<T: Real>(m: &Model<T>, cols: &[&[T]], n: usize) -> Vec<T> {
    let mut input = vec![None; cols.len()];
    (0..n)
        .map(|i| {
            for (k, c) in cols.iter().enumerate() {
                input[k] = Some(c[i]);
            }
            m.eval_row(&input)
        })
        .collect()
}

/// The BRDF over (N, 3) pairs, scalar model in precision `T`.
fn brdf_rows<T: Real>(m: &Model<T>, wi: &[T], wo: &[T]) -> Vec<T> {
    let Model::Brdf(b) = m else {
        unreachable!("checked by the caller")
    };
    wi.chunks_exact(3)
        .zip(wo.chunks_exact(3))
        .map(|(a, o)| b.eval([a[0], a[1], a[2]], [o[0], o[1], o[2]]))
        .collect()
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

/// Samples `n` rows: `(wi (N*3), weight, pdf)`; no sample gives zeros.
fn sample_rows<T: Real>(
    b: &dyn fastbrdf::Brdf<T>,
    s: Strategy,
    wo: &[T],
    u: &[T],
) -> (Vec<T>, Vec<T>, Vec<T>) {
    let n = wo.len() / 3;
    let (mut wi, mut weight, mut pdf) = (
        vec![T::zero(); 3 * n],
        vec![T::zero(); n],
        vec![T::zero(); n],
    );
    for i in 0..n {
        let o = [wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]];
        if let Some(x) = b.sample(o, [u[2 * i], u[2 * i + 1]], s) {
            wi[3 * i..3 * i + 3].copy_from_slice(&x.wi);
            weight[i] = x.weight;
            pdf[i] = x.pdf;
        }
    }
    (wi, weight, pdf)
}

#[pymethods]
impl Handle {
    /// Builds model `id` with parameters given as text (validated by the registry).
    #[new]
    fn new(id: &str, params: Vec<(String, String)>) -> PyResult<Self> {
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

    /// f32 over 1-D contiguous columns of equal length (not BRDFs).
    fn eval_f32<'py>(
        &self,
        py: Python<'py>,
        cols: Vec<PyReadonlyArray1<'py, f32>>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let cols: Vec<&[f32]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
        let n = cols.first().map_or(0, |c| c.len());
        let out = py.detach(|| -> fastbrdf::Result<Vec<f32>> {
            let mut out = vec![0.0f32; n];
            match (&self.kernel, self.kind, cols.as_slice()) {
                (Some(k), fastbrdf::Kind::Env, [c, a]) => {
                    k.eval_par(Input::Env([c, a]), &mut out)?
                }
                (
                    Some(k),
                    fastbrdf::Kind::Lobe | fastbrdf::Kind::Distribution | fastbrdf::Kind::Fresnel,
                    [c],
                ) => k.eval_par(Input::Cos(c), &mut out)?,
                _ => out = rows(&self.m32, &cols, n),
            }
            Ok(out)
        });
        Ok(out.map_err(value_error)?.into_pyarray(py))
    }

    /// f64 over 1-D contiguous columns of equal length (not BRDFs).
    fn eval_f64<'py>(
        &self,
        py: Python<'py>,
        cols: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let cols: Vec<&[f64]> = cols.iter().map(slice).collect::<PyResult<_>>()?;
        let n = cols.first().map_or(0, |c| c.len());
        let out = py.detach(|| rows(&self.m64, &cols, n));
        Ok(out.into_pyarray(py))
    }

    /// A BRDF in f32 over contiguous (N, 3) `wi`, `wo`: the SIMD kernel, fed in chunks of
    /// [`CHUNK`] deinterleaved elements (the inputs are not copied whole).
    fn eval_dirs_f32<'py>(
        &self,
        py: Python<'py>,
        wi: PyReadonlyArray2<'py, f32>,
        wo: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        brdf_of(&self.m32, self.id)?;
        let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
        let out = py.detach(|| -> fastbrdf::Result<Vec<f32>> {
            let n = wi.len() / 3;
            let mut out = vec![0.0f32; n];
            let k = self.kernel.as_ref().expect("a BRDF has a kernel");
            let mut soa = vec![[0.0f32; CHUNK]; 6];
            for (c, o) in out.chunks_mut(CHUNK).enumerate() {
                let len = o.len();
                let span = c * CHUNK * 3..(c * CHUNK + len) * 3;
                let pairs = wi[span.clone()]
                    .chunks_exact(3)
                    .zip(wo[span].chunks_exact(3));
                for (j, (a, o)) in pairs.enumerate() {
                    (soa[0][j], soa[1][j], soa[2][j]) = (a[0], a[1], a[2]);
                    (soa[3][j], soa[4][j], soa[5][j]) = (o[0], o[1], o[2]);
                }
                let s: [&[f32]; 6] = std::array::from_fn(|a| &soa[a][..len]);
                k.eval(Input::Dirs(s), o)?;
            }
            Ok(out)
        });
        Ok(out.map_err(value_error)?.into_pyarray(py))
    }

    /// A BRDF in f64 over contiguous (N, 3) `wi`, `wo` (the scalar model).
    fn eval_dirs_f64<'py>(
        &self,
        py: Python<'py>,
        wi: PyReadonlyArray2<'py, f64>,
        wo: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        brdf_of(&self.m64, self.id)?;
        let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
        let out = py.detach(|| brdf_rows(&self.m64, wi, wo));
        Ok(out.into_pyarray(py))
    }

    /// Samples `wi` given contiguous (N, 3) `wo` and (N, 2) `u`: `(wi (N*3), weight, pdf)`.
    #[allow(clippy::type_complexity)]
    fn sample_f32<'py>(
        &self,
        py: Python<'py>,
        wo: PyReadonlyArray2<'py, f32>,
        u: PyReadonlyArray2<'py, f32>,
        strategy_name: &str,
    ) -> PyResult<(
        Bound<'py, PyArray1<f32>>,
        Bound<'py, PyArray1<f32>>,
        Bound<'py, PyArray1<f32>>,
    )> {
        let b = brdf_of(&self.m32, self.id)?;
        let s = self.resolve(b, strategy_name)?;
        let (wo, u) = (slice2(&wo, 3, "wo")?, slice2(&u, 2, "u")?);
        let (a, w, p) = py.detach(|| sample_rows(b, s, wo, u));
        Ok((a.into_pyarray(py), w.into_pyarray(py), p.into_pyarray(py)))
    }

    #[allow(clippy::type_complexity)]
    fn sample_f64<'py>(
        &self,
        py: Python<'py>,
        wo: PyReadonlyArray2<'py, f64>,
        u: PyReadonlyArray2<'py, f64>,
        strategy_name: &str,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let b = brdf_of(&self.m64, self.id)?;
        let s = self.resolve(b, strategy_name)?;
        let (wo, u) = (slice2(&wo, 3, "wo")?, slice2(&u, 2, "u")?);
        let (a, w, p) = py.detach(|| sample_rows(b, s, wo, u));
        Ok((a.into_pyarray(py), w.into_pyarray(py), p.into_pyarray(py)))
    }

    /// The solid-angle density of `wi` given `wo`, both contiguous (N, 3).
    fn pdf_f32<'py>(
        &self,
        py: Python<'py>,
        wo: PyReadonlyArray2<'py, f32>,
        wi: PyReadonlyArray2<'py, f32>,
        strategy_name: &str,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let b = brdf_of(&self.m32, self.id)?;
        let s = self.resolve(b, strategy_name)?;
        let (wo, wi) = (slice2(&wo, 3, "wo")?, slice2(&wi, 3, "wi")?);
        let out = py.detach(|| pdf_rows(b, s, wo, wi));
        Ok(out.into_pyarray(py))
    }

    fn pdf_f64<'py>(
        &self,
        py: Python<'py>,
        wo: PyReadonlyArray2<'py, f64>,
        wi: PyReadonlyArray2<'py, f64>,
        strategy_name: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let b = brdf_of(&self.m64, self.id)?;
        let s = self.resolve(b, strategy_name)?;
        let (wo, wi) = (slice2(&wo, 3, "wo")?, slice2(&wi, 3, "wi")?);
        let out = py.detach(|| pdf_rows(b, s, wo, wi));
        Ok(out.into_pyarray(py))
    }

    /// The sampling strategies of a BRDF, its default first.
    fn strategies(&self) -> PyResult<Vec<&'static str>> {
        let b = brdf_of(&self.m64, self.id)?;
        Ok(b.strategies().iter().map(|s| s.name()).collect())
    }
}

impl Handle {
    fn resolve<T: Real>(&self, b: &dyn fastbrdf::Brdf<T>, name: &str) -> PyResult<Strategy> {
        b.resolve(strategy(name)?)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", self.id)))
    }
}

fn pdf_rows<T: Real>(b: &dyn fastbrdf::Brdf<T>, s: Strategy, wo: &[T], wi: &[T]) -> Vec<T> {
    wo.chunks_exact(3)
        .zip(wi.chunks_exact(3))
        .map(|(o, i)| b.pdf([o[0], o[1], o[2]], [i[0], i[1], i[2]], s))
        .collect()
}

/// The info of model `id` as `fastbrdf models --json` prints one entry.
#[pyfunction]
fn info_json(id: &str) -> PyResult<String> {
    let e = registry::find(id).map_err(value_error)?;
    Ok(serde_json::to_string(&e.info).expect("serialisable"))
}

/// `fastbrdf errors`' rows as JSON: `[{param, max_abs, max_abs_at, max_rel, max_rel_at, rms,
/// samples}]`, checked as the CLI checks (ids, kinds, the parameter, its values' range).
#[pyfunction]
fn errors_json(
    py: Python<'_>,
    model: &str,
    reference: &str,
    param: &str,
    values: Vec<f64>,
    zone: &str,
) -> PyResult<String> {
    use fastbrdf::Zone;
    use fastbrdf_analysis::errors;
    let zone = match zone {
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
    };
    if values.is_empty() {
        return Err(value_error(format!("{param}: no values")));
    }
    let spec = errors::Spec {
        model: model.into(),
        reference: reference.into(),
        param: param.into(),
        zone,
    };
    spec.validate().map_err(value_error)?;
    // Out-of-range values are refused before the sweep with the registry's message (as the CLI).
    for id in [model, reference] {
        if registry::find(id).map_err(value_error)?.info.kind == fastbrdf::Kind::Env {
            let (lo, hi) = fastbrdf::params::ALPHA.range();
            if let Some(v) = values.iter().find(|v| !(**v >= lo && **v <= hi)) {
                return Err(value_error(format!(
                    "alpha: {v} is outside the domain [{lo}, {hi}] of {id}'s alpha input"
                )));
            }
            continue;
        }
        for v in &values {
            registry::build::<f64>(id, &[(param, &fastbrdf_analysis::range::num(*v))])
                .map_err(value_error)?;
        }
    }
    let rows = py
        .detach(|| errors::sweep(&spec, &values, &|| ()))
        .map_err(value_error)?;
    Ok(serde_json::to_string(&rows).expect("serialisable"))
}

/// Parses a range text (`LO..HI[:STEP]`, `LO..HI:logK`, `A,B,C`) as the CLI does.
#[pyfunction]
fn parse_range(text: &str, default_step: f64) -> PyResult<Vec<f64>> {
    fastbrdf_analysis::range::parse(text, default_step).map_err(value_error)
}

/// `fastbrdf albedo --json`'s object, as JSON.
#[pyfunction]
fn albedo_json(
    py: Python<'_>,
    model: &str,
    params: Vec<(String, String)>,
    angles: Vec<f64>,
    as_brdf: &str,
    norm: &str,
) -> PyResult<String> {
    use fastbrdf_analysis::albedo;
    if let Some(bad) = angles.iter().find(|t| !(**t >= 0.0 && **t < 90.0)) {
        return Err(value_error(format!(
            "angles: {bad} is outside [0, 90) degrees"
        )));
    }
    let t = albedo::target(model, &params, as_brdf, norm).map_err(value_error)?;
    let rows = py
        .detach(|| albedo::curve(&t, &angles, 1e-7))
        .map_err(value_error)?;
    let (holds, _) = albedo::furnace(&rows, t.furnace_tolerance());
    let p = t.params_json();
    let v = serde_json::json!({"model": model, "brdf": t.id, "params": p,
        "claims_energy": t.claims_energy, "conserves": holds, "rows": rows});
    Ok(v.to_string())
}

/// A CPU render as a flat linear float32 array (H * W * 3, row-major, top row first).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    model: &str,
    params: Vec<(String, String)>,
    width: u32,
    height: u32,
    spp: u32,
    kd: f32,
    ks: f32,
    albedo: (f32, f32, f32),
    lights: Vec<String>,
    floor: bool,
    shadows: bool,
    env: Option<String>,
    env_samples: u32,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    use fastbrdf_render::render::{Options, Shading};
    use fastbrdf_render::scene::{Light, Specular};
    use fastbrdf_render::setup::{self, SceneSpec};
    let mut spec = SceneSpec::new();
    spec.kd = kd;
    spec.ks = ks;
    spec.albedo = glam::Vec3::new(albedo.0, albedo.1, albedo.2);
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
    spec.lights = lights
        .iter()
        .map(|l| Light::parse(l))
        .collect::<Result<_, _>>()
        .map_err(value_error)?;
    fastbrdf_render::film::check_size(width, height).map_err(value_error)?;
    let opts = Options {
        width,
        height,
        spp,
        shading: Shading::Batch,
    };
    let specular = Arc::new(Specular::new(model, &params).map_err(value_error)?);
    let film = py
        .detach(|| -> fastbrdf_render::Result<_> {
            let loaded = setup::load(&spec)?;
            let scene = setup::scene(&spec, &loaded, specular);
            let film = fastbrdf_render::render::render(&scene, &opts, &|_, _| ())?;
            film.check_finite()?;
            Ok(film
                .pixels
                .iter()
                .flat_map(|p| p.to_array())
                .collect::<Vec<f32>>())
        })
        .map_err(value_error)?;
    Ok(film.into_pyarray(py))
}

/// `fastbrdf shader`'s text for one model.
#[pyfunction]
fn shader(
    model: &str,
    params: Vec<(String, String)>,
    lang: &str,
    runtime_params: bool,
) -> PyResult<String> {
    use fastbrdf_gpu::export::{Form, Lang, export_form};
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
}

#[pymodule]
fn _fastbrdf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Handle>()?;
    m.add_function(wrap_pyfunction!(models_json, m)?)?;
    m.add_function(wrap_pyfunction!(info_json, m)?)?;
    m.add_function(wrap_pyfunction!(errors_json, m)?)?;
    m.add_function(wrap_pyfunction!(parse_range, m)?)?;
    m.add_function(wrap_pyfunction!(albedo_json, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(shader, m)?)?;
    Ok(())
}
