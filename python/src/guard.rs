//! Errors and interruption: the library's messages as `ValueError`, panics as
//! `RuntimeError` ([`guard`]), and long work on a worker thread that Ctrl-C stops
//! ([`interruptible`]).

use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// How often a worker's caller looks for Ctrl-C.
pub(crate) const POLL: Duration = Duration::from_millis(20);

pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A panic's message as a `RuntimeError` (a bug: the message asks for a report).
pub(crate) fn internal(payload: Box<dyn Any + Send>) -> PyErr {
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
pub(crate) fn guard<R>(body: impl FnOnce() -> PyResult<R>) -> PyResult<R> {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|p| Err(internal(p)))
}

/// The payload with which a worker unwinds when [`interruptible`] asks it to stop.
pub(crate) struct Cancelled;

/// A cancellation point of a worker run by [`interruptible`]: unwinds (without the panic
/// hook: nothing is printed) once the caller saw Ctrl-C. Callable from rayon's threads,
/// which carry the unwinding to the worker.
pub(crate) fn stop_if(cancel: &AtomicBool) {
    if cancel.load(Ordering::Relaxed) {
        resume_unwind(Box::new(Cancelled));
    }
}

/// Runs `work` on a worker thread, the GIL released, while this thread checks for signals
/// every [`POLL`]: when a handler raises (Ctrl-C's `KeyboardInterrupt`), the flag given to
/// `work` is set, `work` stops at its next [`stop_if`], and the handler's exception is
/// raised. A panic in `work` is a `RuntimeError` (see [`guard`]).
pub(crate) fn interruptible<R: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> R + Send,
) -> PyResult<R> {
    let cancel = AtomicBool::new(false);
    let done = AtomicBool::new(false);
    let caller = std::thread::current();
    std::thread::scope(|s| {
        let (cancel, done) = (&cancel, &done);
        let worker = s.spawn(move || {
            let r = catch_unwind(AssertUnwindSafe(|| crate::fork::run(|| work(cancel))));
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
