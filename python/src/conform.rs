//! `fastbrdf.conform` (issue 31): the conformance checks of `fastbrdf conform` on a registry
//! model or on a Python object, as the CLI's `--json` record.
//!
//! A Python object is adapted to [`UserBrdf`] by [`Callbacks`]: each batch the checks ask for
//! is one call of the object's `eval(wi, wo)`, `sample(wo, u)` or `pdf(wo, wi)` on float64
//! numpy arrays, the GIL taken for it (the checks run on rayon threads, the GIL released).
//! What a method returns is checked (a real dtype, the shape for the rows asked); the first
//! Python error of a callback (the object's own exception, with a note naming the call, or a
//! `TypeError`/`ValueError` naming the method and what it returned) stops the run and is
//! raised once it has stopped. Ctrl-C stops it too ([`interruptible`]).

use crate::args::{full_spec, params_arg, shown};
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, SampleBatch, UserBrdf, check_rows};
use fastbrdf_analysis::conform;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(conform_json, m)?)
}

/// `fastbrdf conform --json`'s record for `model`, checked against `reference` when given.
/// Each is a registry model as a tuple `(id, params, material, metal)` (params as
/// `params_arg` takes them) or a Python object with `eval(wi, wo)` and, optionally, both
/// `sample(wo, u)` and `pdf(wo, wi)`. `strategy` samples a registry model (`auto`, ...); a
/// Python object samples by its own `sample`. `full`: the full sizes, else CI's.
#[pyfunction]
#[pyo3(signature = (model, reference, full, strategy))]
pub(crate) fn conform_json(
    py: Python<'_>,
    model: &Bound<'_, PyAny>,
    reference: Option<&Bound<'_, PyAny>>,
    full: bool,
    strategy: &str,
) -> PyResult<String> {
    guard(|| {
        let strategy = Strategy::parse(strategy).ok_or_else(|| {
            value_error(format!(
                "strategy '{}': expected one of {}",
                fastbrdf_io::shorten(strategy, 40),
                Strategy::ALL.map(|s| s.name()).join(", ")
            ))
        })?;
        let model = Source::new(model, "model", strategy)?;
        let reference = reference
            .map(|r| Source::new(r, "reference", Strategy::Auto))
            .transpose()?;
        let cfg = if full {
            conform::Config::full()
        } else {
            conform::Config::ci()
        };
        let shared = Shared::default();
        let result = interruptible(py, |cancel| {
            let (m_cb, r_cb);
            let m: &dyn UserBrdf = match &model {
                Source::Builtin(b) => b,
                Source::Gpu(g) => &**g,
                Source::Object(o) => {
                    m_cb = Callbacks::new(o, &shared, cancel);
                    &m_cb
                }
            };
            let r: Option<&dyn UserBrdf> = match &reference {
                None => None,
                Some(Source::Builtin(b)) => Some(b),
                Some(Source::Gpu(g)) => Some(&**g),
                Some(Source::Object(o)) => {
                    r_cb = Callbacks::new(o, &shared, cancel);
                    Some(&r_cb)
                }
            };
            conform::run(m, r, &cfg, &|_check| stop_if(cancel))
        })?;
        // A callback's Python error first: conform's message only repeats it.
        if let Some(e) = shared.error.into_inner().unwrap_or_else(|p| p.into_inner()) {
            return Err(e);
        }
        let report = result.map_err(value_error)?;
        serde_json::to_string(&report).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// A model to check: a registry model, or a Python object.
enum Source {
    Builtin(Builtin),
    /// A user's shader (`file:PATH`) on the GPU.
    Gpu(Box<fastbrdf_gpu::user::GpuBrdf>),
    Object(Object),
}

impl Source {
    /// `obj` as argument `arg` (see [`conform_json`]).
    fn new(obj: &Bound<'_, PyAny>, arg: &str, strategy: Strategy) -> PyResult<Self> {
        if let Ok(t) = obj.cast::<PyTuple>() {
            let (id, params, material, metal): (
                String,
                Bound<'_, PyAny>,
                Option<String>,
                Option<String>,
            ) = t.extract().map_err(|e| {
                PyTypeError::new_err(format!(
                    "{arg}: a registry model is (id, params, material, metal): {e}"
                ))
            })?;
            if let Some(path) = id.strip_prefix("file:") {
                return Self::file(
                    path,
                    &id,
                    &params_arg(&params)?,
                    material,
                    metal,
                    arg,
                    strategy,
                );
            }
            let spec = full_spec(
                &id,
                &params_arg(&params)?,
                material.as_deref(),
                metal.as_deref(),
            )?;
            let b =
                Builtin::new(&spec, strategy).map_err(|e| value_error(format!("{arg}: {e}")))?;
            return Ok(Self::Builtin(b));
        }
        if strategy != Strategy::Auto {
            return Err(value_error(format!(
                "strategy '{strategy}': applies to a registry model; a Python object samples by its own sample(wo, u)"
            )));
        }
        Object::new(obj, arg).map(Self::Object)
    }
}

impl Source {
    /// A user's shader `file:PATH` (as the CLI's `--model file:PATH`), compiled on the GPU
    /// with the values `given` (checked against the ranges the file declares).
    fn file(
        path: &str,
        id: &str,
        given: &[(String, String)],
        material: Option<String>,
        metal: Option<String>,
        arg: &str,
        strategy: Strategy,
    ) -> PyResult<Self> {
        if material.is_some() || metal.is_some() {
            return Err(value_error(format!(
                "{arg}: a user's model ({}) takes neither material nor metal",
                fastbrdf_io::shorten_middle(id, 60)
            )));
        }
        if strategy != Strategy::Auto {
            return Err(value_error(format!(
                "strategy '{strategy}': a user's model samples as its file says"
            )));
        }
        match fastbrdf_gpu::user::load(std::path::Path::new(path), given) {
            Ok(g) => Ok(Self::Gpu(Box::new(g))),
            Err(e) => Err(match e.kind {
                fastbrdf_gpu::user::UserErrorKind::Input => value_error(format!("{arg}: {e}")),
                fastbrdf_gpu::user::UserErrorKind::Gpu => {
                    PyRuntimeError::new_err(format!("{arg}: {e}"))
                }
            }),
        }
    }
}

/// A Python object with `eval` (and maybe `sample` and `pdf`), probed once.
struct Object {
    obj: Py<PyAny>,
    name: String,
    channels: usize,
    samples: bool,
}

/// Directions of the probe call of `eval`: normal, oblique, mirror pairs.
const PROBE_WI: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8]];
const PROBE_WO: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [-0.6, 0.0, 0.8], [0.0, 0.8, 0.6]];

impl Object {
    /// Reads `obj`'s methods and its channel count (1 or 3: one call of `eval` on three pairs;
    /// its exception is raised as it is, with a note).
    fn new(obj: &Bound<'_, PyAny>, arg: &str) -> PyResult<Self> {
        let py = obj.py();
        let type_name = obj.get_type().name()?.to_string();
        let has =
            |m: &str| -> PyResult<bool> { Ok(obj.hasattr(m)? && obj.getattr(m)?.is_callable()) };
        if !has("eval")? {
            return Err(PyTypeError::new_err(format!(
                "{arg}: expected a registry id, a fastbrdf.Model or an object with eval(wi, wo), got {type_name}"
            )));
        }
        let (sample, pdf) = (has("sample")?, has("pdf")?);
        if sample != pdf {
            let (with, without) = if sample {
                ("sample", "pdf")
            } else {
                ("pdf", "sample")
            };
            return Err(PyTypeError::new_err(format!(
                "{arg}: {type_name} has {with} but no {without}: the sampling checks need both (or neither)"
            )));
        }
        let name = name(obj)?;
        let r = call(obj, "eval", "eval(wi, wo)", &name, |py| {
            (dirs(py, &PROBE_WI), dirs(py, &PROBE_WO))
        })?;
        let (channels, _) = numbers(py, &r, "eval", PROBE_WI.len(), &[1, 3])?;
        Ok(Self {
            obj: obj.clone().unbind(),
            name,
            channels,
            samples: sample,
        })
    }
}

/// How the report names an object: its `repr` when its class defines one, else the class's
/// name.
fn name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    let py = obj.py();
    let ty = obj.get_type();
    let own_repr = !ty.getattr(intern!(py, "__repr__"))?.is(&py
        .import(intern!(py, "builtins"))?
        .getattr(intern!(py, "object"))?
        .getattr(intern!(py, "__repr__"))?);
    Ok(if own_repr {
        fastbrdf_io::shorten(&shown_full(obj), 80)
    } else {
        ty.name()?.to_string()
    })
}

fn shown_full(obj: &Bound<'_, PyAny>) -> String {
    obj.repr()
        .map_or_else(|_| shown(obj), |s| s.to_string_lossy().into_owned())
}

/// `obj.method(*args(py))`; its exception gains a note naming the call (`what`) and `name`.
fn call<'py>(
    obj: &Bound<'py, PyAny>,
    method: &str,
    what: &str,
    name: &str,
    args: impl FnOnce(Python<'py>) -> (Bound<'py, PyAny>, Bound<'py, PyAny>),
) -> PyResult<Bound<'py, PyAny>> {
    let py = obj.py();
    obj.call_method1(method, args(py)).inspect_err(|e| {
        let v = e.value(py);
        if v.hasattr(intern!(py, "add_note")).unwrap_or(false) {
            let note = format!("in fastbrdf.conform, calling {what} of {name}");
            let _ = v.call_method1(intern!(py, "add_note"), (note,));
        }
    })
}

/// Rows as a new (N, K) float64 array.
fn dirs<'py, const K: usize>(py: Python<'py>, rows: &[[f64; K]]) -> Bound<'py, PyAny> {
    let flat = PyArray1::from_slice(py, rows.as_flattened());
    flat.reshape([rows.len(), K])
        .map_or_else(|_| flat.into_any(), Bound::into_any)
}

/// A shape as Python writes it: `(10,)`, `(10, 3)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// What `what` returned, as float64 numbers row-major: `n` rows of one of `cols` (1: shape
/// `(n,)`; k > 1: `(n, k)`), with the columns found. A `TypeError` for what is not an array
/// of real numbers, a `ValueError` for another shape, each naming `what`.
fn numbers(
    py: Python<'_>,
    r: &Bound<'_, PyAny>,
    what: &str,
    n: usize,
    cols: &[usize],
) -> PyResult<(usize, Vec<f64>)> {
    let np = py.import(intern!(py, "numpy"))?;
    let a = np.call_method1(intern!(py, "asarray"), (r,)).map_err(|e| {
        PyTypeError::new_err(format!(
            "{what} returned {}, not an array ({e})",
            r.get_type()
                .name()
                .map_or_else(|_| "?".into(), |t| t.to_string())
        ))
    })?;
    let dtype = a.getattr(intern!(py, "dtype"))?;
    let kind: String = dtype.getattr(intern!(py, "kind"))?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(PyTypeError::new_err(format!(
            "{what} returned an array of dtype {}: expected real numbers (float64)",
            shown(&dtype)
        )));
    }
    let shape: Vec<usize> = a.getattr(intern!(py, "shape"))?.extract()?;
    let c = match shape.as_slice() {
        [m] if *m == n && cols.contains(&1) => 1,
        [m, c] if *m == n && *c > 1 && cols.contains(c) => *c,
        _ => {
            let want: Vec<String> = cols
                .iter()
                .map(|&c| {
                    if c == 1 {
                        shape_text(&[n])
                    } else {
                        shape_text(&[n, c])
                    }
                })
                .collect();
            return Err(PyValueError::new_err(format!(
                "{what} returned shape {} for {n} rows; expected {}",
                shape_text(&shape),
                want.join(" or ")
            )));
        }
    };
    let a = np
        .call_method1(
            intern!(py, "ascontiguousarray"),
            (a, intern!(py, "float64")),
        )?
        .cast_into::<PyArrayDyn<f64>>()?;
    let v = a.readonly().as_slice()?.to_vec();
    Ok((c, v))
}

/// What the callbacks of one run share.
#[derive(Default)]
struct Shared {
    /// The first Python error of a callback.
    error: Mutex<Option<PyErr>>,
}

/// An [`Object`] as a [`UserBrdf`] for one run: each call takes the GIL (and nothing else: a
/// lock held across the call would deadlock when the object's code runs rayon work, as
/// fastbrdf's own functions do, and that work steals another chunk of the checks); the first
/// Python error goes to [`Shared::error`] (and every later call fails at once), a set `cancel`
/// fails them too. Calls may overlap where the object's code releases the GIL.
struct Callbacks<'a> {
    o: &'a Object,
    shared: &'a Shared,
    cancel: &'a AtomicBool,
}

impl<'a> Callbacks<'a> {
    fn new(o: &'a Object, shared: &'a Shared, cancel: &'a AtomicBool) -> Self {
        Self { o, shared, cancel }
    }

    /// Runs `f` with the GIL on the object; a Python error is kept and becomes the message.
    fn with<R>(
        &self,
        method: &str,
        f: impl FnOnce(&Bound<'_, PyAny>) -> PyResult<R>,
    ) -> Result<R, String> {
        if self.cancel.load(Ordering::Relaxed) {
            return Err("interrupted".into());
        }
        let slot = || self.shared.error.lock().unwrap_or_else(|p| p.into_inner());
        if slot().is_some() {
            return Err(format!("{method}: not called after an earlier error"));
        }
        Python::attach(|py| {
            f(self.o.obj.bind(py)).map_err(|e| {
                let msg = e.to_string();
                slot().get_or_insert(e);
                msg
            })
        })
    }
}

impl UserBrdf for Callbacks<'_> {
    fn name(&self) -> String {
        self.o.name.clone()
    }
    fn channels(&self) -> usize {
        self.o.channels
    }
    fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        let c = self.o.channels;
        check_rows(wi.len(), wo.len(), out.len(), c)?;
        self.with("eval", |obj| {
            let py = obj.py();
            let r = call(obj, "eval", "eval(wi, wo)", &self.o.name, |py| {
                (dirs(py, wi), dirs(py, wo))
            })?;
            let (_, v) = numbers(py, &r, "eval", wi.len(), &[c])?;
            out.copy_from_slice(&v);
            Ok(())
        })
    }
    fn samples(&self) -> bool {
        self.o.samples
    }
    fn sample(&self, wo: &[[f64; 3]], u: &[[f64; 2]]) -> Result<SampleBatch, String> {
        let (n, c) = (wo.len(), self.o.channels);
        if u.len() != n {
            return Err(format!("{n} wo rows but {} u rows", u.len()));
        }
        self.with("sample", |obj| {
            let py = obj.py();
            let r = call(obj, "sample", "sample(wo, u)", &self.o.name, |py| {
                (dirs(py, wo), dirs(py, u))
            })?;
            let parts = triple(&r)?;
            let (_, wi) = numbers(py, &parts[0], "sample's wi", n, &[3])?;
            let (wc, weight) = numbers(py, &parts[1], "sample's weight", n, &[1, c])?;
            let (_, pdf) = numbers(py, &parts[2], "sample's pdf", n, &[1])?;
            // A grey weight serves every channel.
            let weight = if wc == c {
                weight
            } else {
                weight
                    .iter()
                    .flat_map(|w| std::iter::repeat_n(*w, c))
                    .collect()
            };
            Ok(SampleBatch {
                valid: pdf.iter().map(|p| *p != 0.0).collect(),
                wi: wi.chunks_exact(3).map(|w| [w[0], w[1], w[2]]).collect(),
                weight,
                pdf,
            })
        })
    }
    fn pdf(&self, wo: &[[f64; 3]], wi: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        check_rows(wo.len(), wi.len(), out.len(), 1)?;
        self.with("pdf", |obj| {
            let py = obj.py();
            let r = call(obj, "pdf", "pdf(wo, wi)", &self.o.name, |py| {
                (dirs(py, wo), dirs(py, wi))
            })?;
            let (_, v) = numbers(py, &r, "pdf", wo.len(), &[1])?;
            out.copy_from_slice(&v);
            Ok(())
        })
    }
}

/// `sample`'s result as its three parts (any sequence of three).
fn triple<'py>(r: &Bound<'py, PyAny>) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let bad = || {
        PyTypeError::new_err(format!(
            "sample returned {}: expected a tuple (wi, weight, pdf)",
            r.get_type()
                .name()
                .map_or_else(|_| "?".into(), |t| t.to_string())
        ))
    };
    let it = r.try_iter().map_err(|_| bad())?;
    let parts: Vec<_> = it.take(4).collect::<PyResult<_>>()?;
    if parts.len() != 3 {
        return Err(PyValueError::new_err(format!(
            "sample returned {} items: expected 3 (wi, weight, pdf)",
            if parts.len() > 3 {
                "more than 3".to_string()
            } else {
                parts.len().to_string()
            }
        )));
    }
    Ok(parts)
}
