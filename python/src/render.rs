//! The CPU renderer (`render`): a scene as the CLI's `render` builds it, the film's linear
//! radiance as float32.

use crate::MAX_ITEMS;
use crate::MAX_WEIGHT;
use crate::args::{params_arg, seq, shown, spec, u32_arg, weight_arg};
use crate::arrays::empty;
use crate::guard::{guard, interruptible, value_error};
use fastbrdf::ModelSpec;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyValueError};
use pyo3::prelude::*;
use std::sync::Arc;
use std::sync::atomic::Ordering;

/// A CPU render as a flat linear float32 array (H * W * 3, row-major, top row first). Runs on
/// a worker that Ctrl-C stops.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render<'py>(
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
        let specular = Arc::new(Specular::new(&shaded_spec(model, &params)?).map_err(value_error)?);
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

/// The spec `render` shades with: every value of `params` validated against the BRDF that
/// shading with `model` evaluates (a lobe's `blinn-phong`, a distribution's `cook-torrance`:
/// `ModelSpec::shaded`), so a distribution takes that BRDF's `f`, `g`, ... too, as `render`
/// always has; `R,G,B` values make it coloured. A term that cannot be shaded is refused with
/// the renderer's message.
fn shaded_spec(model: &str, params: &[(String, String)]) -> PyResult<ModelSpec> {
    // The model with its defaults, for its shading policy (an unknown id: the registry's
    // message).
    let bare = spec(model, &[])?;
    let shaded = fastbrdf_render::scene::shading_brdf(&bare).map_err(value_error)?;
    let mut all = params.to_vec();
    all.extend(shaded.pairs());
    spec(shaded.id(), &all)
}
