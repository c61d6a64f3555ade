//! Measured BRDFs in MERL's `.binary` format (`fastbrdf::measured`) and registry BRDFs fitted
//! to them (`fastbrdf_analysis::measured_fit`): the CLI's `measured info|eval|render` and
//! `fit-measured`. `MeasuredData` holds one file, read once by the library's bounded reader;
//! `info_json` and `fit_measured_json` return the CLI's `--json` documents
//! (`fastbrdf_analysis::measured_json`, the function the CLI prints).

use crate::MAX_ITEMS;
use crate::args::{params_arg, seq, shown, spec, u32_arg};
use crate::arrays::{chunked, empty, ready, same_rows, slice2};
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf::measured::MeasuredBrdf;
use fastbrdf_analysis::measured_fit::{self, Data, Metric, Options, Problem};
use fastbrdf_analysis::measured_json;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyRuntimeError};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::Ordering;

/// A MERL file read once (`MeasuredBrdf::read`: the header checked before anything else is
/// read, at most one byte over the format's size read, every sample finite and plausible).
#[pyclass(frozen, module = "fastbrdf._fastbrdf")]
pub(crate) struct MeasuredData {
    brdf: Arc<MeasuredBrdf>,
    /// The path as given, for `info`'s "file", `fit-measured`'s "data" and messages.
    path: PathBuf,
}

/// A float array's elements written by `fill` into a new numpy array of `3 n` elements,
/// `fill` called over row ranges in GIL-released steps (Ctrl-C checked between them).
fn rows_out<'py, T: numpy::Element + Send>(
    py: Python<'py>,
    n: usize,
    fill: impl Fn(usize, &mut [T]) + Sync,
) -> PyResult<Bound<'py, PyArray1<T>>> {
    let out = empty::<T>(py, 3 * n)?;
    {
        let mut rw = out.try_readwrite()?;
        let o = rw.as_slice_mut().map_err(value_error)?;
        chunked(py, n, |r| -> Result<(), String> {
            for (k, px) in o[3 * r.start..3 * r.end].chunks_exact_mut(3).enumerate() {
                fill(r.start + k, px);
            }
            Ok(())
        })?;
    }
    Ok(out)
}

#[pymethods]
impl MeasuredData {
    /// Reads the MERL file at `path` (the GIL released); a missing, short, long or malformed
    /// file is a `ValueError` with the library's message, which names the file.
    #[new]
    fn new(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        guard(|| {
            let brdf = py
                .detach(|| crate::fork::run(|| MeasuredBrdf::read(&path)))
                .map_err(value_error)?;
            Ok(Self {
                brdf: Arc::new(brdf),
                path,
            })
        })
    }

    /// `fastbrdf measured info FILE --json`'s document, as JSON.
    fn info_json(&self) -> PyResult<String> {
        guard(|| {
            let doc = measured_json::info(&self.path.display().to_string(), &self.brdf);
            serde_json::to_string(&doc).map_err(|e| PyRuntimeError::new_err(e.to_string()))
        })
    }

    /// The R, G, B values over (N, 3) float32 `wi`, `wo`, flat (3 N), as `measured eval
    /// --precision f32` (the bin found in f64, the value rounded to f32).
    fn eval_f32<'py>(
        &self,
        py: Python<'py>,
        wi: Bound<'py, PyArray2<f32>>,
        wo: Bound<'py, PyArray2<f32>>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        guard(|| {
            let (wi, wo) = (ready(wi)?, ready(wo)?);
            let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
            same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
            let b = &*self.brdf;
            rows_out(py, wi.len() / 3, |i, px| {
                let a = [wi[3 * i], wi[3 * i + 1], wi[3 * i + 2]];
                let c = [wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]];
                px.copy_from_slice(&b.eval_rgb_f32(a, c));
            })
        })
    }

    /// The R, G, B values over (N, 3) float64 `wi`, `wo`, flat (3 N), as `measured eval
    /// --precision f64`.
    fn eval_f64<'py>(
        &self,
        py: Python<'py>,
        wi: Bound<'py, PyArray2<f64>>,
        wo: Bound<'py, PyArray2<f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        guard(|| {
            let (wi, wo) = (ready(wi)?, ready(wo)?);
            let (wi, wo) = (slice2(&wi, 3, "wi")?, slice2(&wo, 3, "wo")?);
            same_rows("wi", wi.len() / 3, "wo", wo.len() / 3)?;
            let b = &*self.brdf;
            rows_out(py, wi.len() / 3, |i, px| {
                let a = [wi[3 * i], wi[3 * i + 1], wi[3 * i + 2]];
                let c = [wo[3 * i], wo[3 * i + 1], wo[3 * i + 2]];
                px.copy_from_slice(&b.eval_rgb(a, c));
            })
        })
    }

    /// `measured render`'s film as a flat linear float32 array (H * W * 3, row-major, top row
    /// first): the file is the whole BRDF (weights 0, 1). Runs on a worker that Ctrl-C stops.
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: &Bound<'py, PyAny>,
        height: &Bound<'py, PyAny>,
        spp: &Bound<'py, PyAny>,
        lights: &Bound<'py, PyAny>,
        floor: bool,
        shadows: bool,
        env: Option<String>,
        env_samples: &Bound<'py, PyAny>,
        mesh: Option<PathBuf>,
    ) -> PyResult<Bound<'py, PyArray1<f32>>> {
        use fastbrdf_render::render::{Options, Shading};
        use fastbrdf_render::scene::{Light, RgbBrdf, Specular};
        use fastbrdf_render::setup::{self, SceneSpec};
        guard(|| {
            let (width, height) = (u32_arg(width, "width")?, u32_arg(height, "height")?);
            let (spp, env_samples) = (u32_arg(spp, "spp")?, u32_arg(env_samples, "env_samples")?);
            let mut spec = SceneSpec::new();
            // As the CLI's `render_rgb`: the file is the whole BRDF.
            (spec.kd, spec.ks) = (0.0, 1.0);
            spec.floor = floor;
            spec.shadows = shadows;
            spec.env = env;
            spec.mesh = mesh;
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
                sampler: fastbrdf_render::render::Sampler::default(),
                aa: fastbrdf_render::render::Antialias::default(),
            };
            let label = self.path.display().to_string();
            let brdf = Arc::clone(&self.brdf) as Arc<dyn RgbBrdf>;
            let specular = Arc::new(Specular::rgb(&label, brdf));
            // The output first: a size the process cannot have is numpy's MemoryError before
            // any work.
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
}

/// `fastbrdf fit-measured --json`'s document, as JSON, without a picture ("picture" null),
/// checked as the CLI checks (restarts, metric, model, parameters, `free`, an empty file).
/// Runs on a worker that Ctrl-C stops after the Nelder-Mead run in progress.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_measured_json(
    py: Python<'_>,
    data: &MeasuredData,
    model: &str,
    params: &Bound<'_, PyAny>,
    free: &Bound<'_, PyAny>,
    metric: &str,
    samples: &Bound<'_, PyAny>,
    restarts: &Bound<'_, PyAny>,
) -> PyResult<String> {
    guard(|| {
        let params = params_arg(params)?;
        let free = seq(free, "free", MAX_ITEMS, |x| x.extract::<String>())?;
        // Types are checked by the Python layer; a value out of range is named here.
        let samples: usize = samples.extract().map_err(|_| {
            value_error(format!(
                "samples {}: must be an integer from 0 (every eligible bin) to {}",
                shown(samples),
                usize::MAX
            ))
        })?;
        let restarts = restarts
            .extract::<usize>()
            .ok()
            .filter(|r| (1..=64).contains(r))
            .ok_or_else(|| value_error(format!("restarts {}: must be 1 to 64", shown(restarts))))?;
        let metric = Metric::parse(metric).ok_or_else(|| {
            value_error(format!(
                "metric '{}': expected ngan-l2, low-log or max",
                fastbrdf_io::shorten(metric, 40)
            ))
        })?;
        let shown_model = fastbrdf_io::shorten(model, 64);
        let fixed = spec(model, &params)
            .map_err(|e| value_error(format!("model {shown_model}: {}", e.value(py))))?;
        let problem = Problem::with_free(&fixed, true, &free).map_err(|e| {
            if e.starts_with("--free ") {
                // The CLI's message, naming this function's argument.
                value_error(e.replace("--free ", "free "))
            } else {
                value_error(format!("model {shown_model}: {e}"))
            }
        })?;
        let name = data.path.display().to_string();
        let b = Arc::clone(&data.brdf);
        let result = interruptible(py, |cancel| {
            let d = Data::from_measured(&b, samples);
            if d.is_empty() {
                return Err(format!(
                    "{name}: no valid (measured) bin within {} degrees of the normal",
                    measured_fit::MAX_THETA_DEG
                ));
            }
            stop_if(cancel);
            let t = std::time::Instant::now();
            let f = measured_fit::fit(
                &problem,
                &d,
                &Options {
                    metric,
                    restarts,
                    ..Options::default()
                },
                &|_, _| stop_if(cancel),
            )
            .map_err(|e| format!("{name}: {e}"))?;
            let seconds = t.elapsed().as_secs_f64();
            let doc = measured_json::fit(
                &measured_json::FitReport {
                    data: &name,
                    model,
                    fixed: &fixed,
                    eligible: d.eligible,
                    seconds,
                    picture: None,
                },
                &f,
            );
            Ok(doc.to_string())
        })?;
        result.map_err(value_error)
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<MeasuredData>()?;
    m.add_function(wrap_pyfunction!(fit_measured_json, m)?)?;
    Ok(())
}
