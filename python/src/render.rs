//! The renderer from Python: `render` (a model on the built-in sphere or a mesh, CPU or GPU,
//! as the CLI's `render`), `compare_json` (the CLI's `compare --json`), `materials_json` and
//! `metals_json` (`materials --json`, `metals --json`). The scene's options arrive as one dict
//! ([`scene::scene_arg`]); the model's text, material and metal become a spec through the
//! library's `model_spec::spec`, the one the CLI calls.

mod compare;
mod scene;

use crate::args::params_arg;
use crate::arrays::empty;
use crate::guard::{guard, interruptible, value_error};
use fastbrdf::ModelSpec;
use fastbrdf_analysis::model_spec::{self, Use};
use fastbrdf_render::film::Film;
use fastbrdf_render::scene::Specular;
use fastbrdf_render::setup;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;
use std::sync::atomic::Ordering;

pub(crate) use crate::args::spec_error;
pub(crate) use scene::{Colour, scene_arg};

/// A CPU (or, with `gpu`, GPU) render of `model` as a flat linear float32 array (H * W * 3,
/// row-major, top row first). `scene` holds the scene's options (see [`scene_arg`]);
/// `material` and `metal` are the CLI's `--material` and `--metal`. Runs on a worker that
/// Ctrl-C stops (the CPU renderer at its next row; the GPU one after its frame).
#[pyfunction]
#[pyo3(signature = (model, params, material, metal, scene, gpu=false))]
pub(crate) fn render<'py>(
    py: Python<'py>,
    model: &str,
    params: &Bound<'py, PyAny>,
    material: Option<String>,
    metal: Option<String>,
    scene: &Bound<'py, PyDict>,
    gpu: bool,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    guard(|| {
        let params = params_arg(params)?;
        let mut sc = scene_arg(scene)?;
        let colour = Colour::new(material.as_deref(), metal.as_deref())?;
        colour.apply(&mut sc, model);
        let spec = model_spec::spec(model, &params, colour.material, colour.metal, Use::Shaded)
            .map_err(spec_error)?;
        if gpu {
            gpu_refusals(model, &spec)?;
        }
        let (w, h) = (sc.opts.width, sc.opts.height);
        // The output first: a size the process cannot have is numpy's MemoryError before any
        // work (the film below is allocated fallibly too).
        let out = empty::<f32>(py, 3 * w as usize * h as usize)?;
        let film = if gpu {
            render_gpu(py, &sc, model, &spec)?
        } else {
            let mut specular = Specular::new(&spec).map_err(value_error)?;
            specular.id = model.into();
            render_cpu(py, &sc, Arc::new(specular))?
        };
        {
            let mut rw = out.try_readwrite()?;
            film_into(&film, rw.as_slice_mut().map_err(value_error)?);
        }
        Ok(out)
    })
}

/// What the GPU renderer cannot draw, refused before an adapter is looked for (the answer
/// does not depend on the machine): the CLI's `--gpu` refusals, named as Python's arguments.
fn gpu_refusals(model: &str, spec: &ModelSpec) -> PyResult<()> {
    if spec.is_coloured() {
        return Err(value_error(format!(
            "gpu=True: coloured specular ({model} with a parameter given as R,G,B, e.g. by metal=) is CPU-only for now: drop gpu=True"
        )));
    }
    Ok(())
}

/// The film of one specular model on the CPU, on a worker that Ctrl-C stops.
pub(crate) fn render_cpu(
    py: Python<'_>,
    sc: &scene::Scene,
    specular: Arc<Specular>,
) -> PyResult<Film> {
    let id = specular.id.clone();
    interruptible(py, |cancel| -> fastbrdf_render::Result<_> {
        let loaded = setup::load(&sc.spec)?;
        let scene = setup::scene(&sc.spec, &loaded, specular);
        let stop = || cancel.load(Ordering::Relaxed);
        fastbrdf_render::render::render_until(&scene, &sc.opts, &|_, _| (), &stop)
    })?
    .map_err(render_error)?
    .ok_or_else(|| PyKeyboardInterrupt::new_err(()))
    .and_then(|film| {
        film.check_finite()
            .map_err(|e| value_error(format!("model '{id}': {e}")))?;
        Ok(film)
    })
}

/// The film on the GPU (fastbrdf-gpu, as `render --gpu`). No adapter (no GPU and no software
/// one such as Mesa's lavapipe) is a `RuntimeError`: the machine, not the arguments, is
/// missing something; bad input is a `ValueError`.
fn render_gpu(py: Python<'_>, sc: &scene::Scene, id: &str, spec: &ModelSpec) -> PyResult<Film> {
    let mut specular = Specular::new(spec).map_err(value_error)?;
    specular.id = id.into();
    let specular = Arc::new(specular);
    interruptible(py, |_| -> Result<Film, PyErrText> {
        let loaded = setup::load(&sc.spec).map_err(PyErrText::render)?;
        let scene = setup::scene(&sc.spec, &loaded, specular);
        let gpu = fastbrdf_gpu::Gpu::new().map_err(PyErrText::gpu)?;
        fastbrdf_gpu::render::render(&gpu.device, &gpu.queue, &scene, &sc.opts)
            .map_err(PyErrText::gpu)
    })?
    .map_err(|e| match e {
        PyErrText::Value(m) => value_error(m),
        PyErrText::Memory(m) => PyMemoryError::new_err(m),
        PyErrText::Runtime(m) => PyRuntimeError::new_err(m),
    })
    .and_then(|film| {
        film.check_finite()
            .map_err(|e| value_error(format!("model '{id}': {e}")))?;
        Ok(film)
    })
}

/// An error made on a worker thread (a `PyErr` is made on the caller's).
enum PyErrText {
    Value(String),
    Memory(String),
    Runtime(String),
}

impl PyErrText {
    fn render(e: fastbrdf_render::RenderError) -> Self {
        match e {
            fastbrdf_render::RenderError::Memory(m) => PyErrText::Memory(m),
            e => PyErrText::Value(e.to_string()),
        }
    }

    fn gpu(e: fastbrdf_gpu::GpuError) -> Self {
        use fastbrdf_gpu::GpuError as G;
        match e {
            G::Input(_) | G::Model(_) => PyErrText::Value(e.to_string()),
            _ => PyErrText::Runtime(e.to_string()),
        }
    }
}

/// A renderer's error as Python's: `MemoryError` for a film that could not be allocated,
/// else `ValueError`.
pub(crate) fn render_error(e: fastbrdf_render::RenderError) -> PyErr {
    match e {
        fastbrdf_render::RenderError::Memory(m) => PyMemoryError::new_err(m),
        e => value_error(e),
    }
}

/// Copies a film into a flat slice of its size (H * W * 3).
pub(crate) fn film_into(film: &Film, out: &mut [f32]) {
    for (o, p) in out.chunks_exact_mut(3).zip(&film.pixels) {
        o.copy_from_slice(&p.to_array());
    }
}

/// `fastbrdf materials --json`'s document (the library's, as the CLI prints it).
#[pyfunction]
pub(crate) fn materials_json() -> PyResult<String> {
    guard(|| {
        serde_json::to_string_pretty(&fastbrdf_analysis::render_json::materials())
            .map_err(value_error)
    })
}

/// `fastbrdf metals --json`'s document (the library's, as the CLI prints it).
#[pyfunction]
pub(crate) fn metals_json() -> PyResult<String> {
    guard(|| {
        serde_json::to_string_pretty(&fastbrdf_analysis::render_json::metals()).map_err(value_error)
    })
}

/// Registers `render`, `compare_json`, `materials_json` and `metals_json`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare_json, m)?)?;
    m.add_function(wrap_pyfunction!(materials_json, m)?)?;
    m.add_function(wrap_pyfunction!(metals_json, m)?)?;
    Ok(())
}
