//! `compare_json`: the CLI's `compare --json` (several models and a reference, a model or
//! measured data, rendered in one scene and scored), without the grid picture.

use super::scene::{Colour, scene_arg};
use super::{film_into, render_cpu, spec_error};
use crate::args::{float_arg, params_arg, seq};
use crate::arrays::empty;
use crate::guard::{guard, value_error};
use fastbrdf_analysis::model_spec::{self, Use};
use fastbrdf_analysis::render_json;
use fastbrdf_render::compare;
use fastbrdf_render::film::Film;
use fastbrdf_render::scene::{RgbBrdf, Specular};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;

/// The largest exposure (the CLI's `--exposure`).
const MAX_EXPOSURE: f64 = 1e6;

/// `fastbrdf compare --json`'s document as JSON, and with `films` the linear films (the
/// reference first, then the models; one flat float32 array of (models + 1) * H * W * 3).
/// `models` are model ids; the reference is model `reference` or the MERL file `measured`
/// (exactly one); `params` go to every model that takes them; `exposure` scales the 8-bit
/// sRGB pictures the sRGB scores are measured on, as the CLI's.
#[pyfunction]
#[pyo3(signature = (models, reference, measured, params, material, metal, scene, exposure, films=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn compare_json<'py>(
    py: Python<'py>,
    models: &Bound<'py, PyAny>,
    reference: Option<String>,
    measured: Option<PathBuf>,
    params: &Bound<'py, PyAny>,
    material: Option<String>,
    metal: Option<String>,
    scene: &Bound<'py, PyDict>,
    exposure: &Bound<'py, PyAny>,
    films: bool,
) -> PyResult<(String, Option<Bound<'py, PyArray1<f32>>>)> {
    guard(|| {
        let models = seq(models, "models", compare::MAX_MODELS + 1, |m| {
            m.extract::<String>()
        })?;
        let params = params_arg(params)?;
        let exposure = float_arg(exposure, "exposure")?;
        if !(exposure > 0.0 && exposure <= MAX_EXPOSURE) {
            return Err(value_error(format!(
                "exposure {exposure}: must be positive and at most {MAX_EXPOSURE}"
            )));
        }
        let exposure = exposure as f32;
        let ref_id = match (&reference, &measured, models.first()) {
            (Some(r), None, _) => r.clone(),
            (None, Some(_), Some(first)) => first.clone(),
            (None, Some(_), None) => String::new(),
            _ => {
                return Err(value_error(
                    "reference, measured: give exactly one (a model id or a MERL .binary file)",
                ));
            }
        };
        let mut sc = scene_arg(scene)?;
        let colour = Colour::new(material.as_deref(), metal.as_deref())?;
        colour.apply(&mut sc, &ref_id);
        let (w, h, spp) = (sc.opts.width, sc.opts.height, sc.opts.spp);
        compare::check_compare(models.len(), w, h, spp).map_err(value_error)?;
        if sc.spec.env.is_some() {
            // Each environment sample is a pass over every primary sample.
            let samples = (models.len() as u64 + 1)
                * u64::from(w)
                * u64::from(h)
                * u64::from(spp).pow(2)
                * u64::from(sc.spec.env_samples);
            let cap = compare::MAX_COMPARE_SAMPLES;
            if samples > cap {
                return Err(value_error(format!(
                    "the comparison would trace {samples} environment samples ({} renders of {w}x{h} at {spp}x{spp} samples per pixel, {} environment samples each): at most {cap}; use a smaller size, spp, env_samples or fewer models",
                    models.len() + 1,
                    sc.spec.env_samples
                )));
            }
        }
        let ids: Vec<&str> = reference
            .iter()
            .chain(&models)
            .map(String::as_str)
            .collect();
        let mut specs =
            model_spec::specs(&ids, &params, colour.material, colour.metal, Use::Shaded)
                .map_err(spec_error)?
                .into_iter();
        // The reference: the whole measured BRDF (weights 0, 1, as the CLI's `render_rgb`) or
        // a model.
        let (ref_name, rf) = match &measured {
            Some(file) => {
                let b = fastbrdf::measured::MeasuredBrdf::read(file).map_err(value_error)?;
                let label = format!("measured {}", file.display());
                let whole = sc.with_weights(0.0, 1.0);
                let specular = Specular::rgb(&label, Arc::new(b) as Arc<dyn RgbBrdf>);
                let film = render_cpu(py, &whole, Arc::new(specular))?;
                (file.display().to_string(), film)
            }
            None => {
                let spec = specs.next().ok_or_else(|| value_error("no reference"))?;
                let mut specular = Specular::new(&spec).map_err(value_error)?;
                specular.id = ref_id.clone();
                (ref_id.clone(), render_cpu(py, &sc, Arc::new(specular))?)
            }
        };
        let r = rf.to_srgb8(exposure);
        let mut all: Vec<Film> = vec![];
        let mut rows = vec![];
        for (id, spec) in models.iter().zip(specs) {
            let label = model_spec::label(id, &spec);
            let mut specular = Specular::new(&spec).map_err(value_error)?;
            specular.id = id.clone();
            let film = render_cpu(py, &sc, Arc::new(specular))?;
            let t = film.to_srgb8(exposure);
            rows.push(render_json::scores(
                &compare::metrics(&label, &r, &t, w, h),
                &compare::linear_metrics(&rf, &film, exposure),
            ));
            if films {
                all.push(film);
            }
        }
        let doc = serde_json::to_string_pretty(&render_json::comparison(&ref_name, rows))
            .map_err(value_error)?;
        if !films {
            return Ok((doc, None));
        }
        let n = 3 * w as usize * h as usize;
        let out = empty::<f32>(py, n * (all.len() + 1))?;
        {
            let mut rw = out.try_readwrite()?;
            let o = rw.as_slice_mut().map_err(value_error)?;
            for (f, o) in std::iter::once(&rf).chain(&all).zip(o.chunks_exact_mut(n)) {
                film_into(f, o);
            }
        }
        Ok((doc, Some(out)))
    })
}
