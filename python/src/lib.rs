//! `fastbrdf._fastbrdf`: the native half of the Python package (pyo3 + numpy).
//!
//! Thin glue, like the CLI: the library computes, this module moves arrays and maps errors.
//! It takes 1-D columns (and (N, 3) / (N, 2) direction arrays) of the exact dtype; the Python
//! layer (`python/fastbrdf/__init__.py`) checks dtypes and shapes, broadcasts, and copies only
//! when it must. This module still checks everything it is given (issue 27), as a user can call
//! it directly:
//!
//! - BRDF inputs ((N, 3) directions, (N, 2) `u`) are read in place whatever their strides
//!   (`handle/rows.rs`); other arrays that are not C-contiguous or not aligned are copied (by
//!   numpy) before reading;
//!   lengths must agree, column counts must fit the model, `u` must lie in [0, 1);
//! - outputs are allocated by numpy (`numpy.empty`), so a size the address space cannot hold
//!   is numpy's `MemoryError`, never an abort;
//! - sequences are read item by item with a cap (the CLI's [`MAX_VALUES`] for parameter
//!   values and angles, [`MAX_ITEMS`] for the rest), never with a capacity taken from `len()`;
//! - integers and floats that do not fit are `ValueError` naming the argument (not
//!   `OverflowError`);
//! - long calls stop on Ctrl-C: evaluations run in chunks of [`STEP`](arrays::STEP)
//!   elements, the GIL released, with `check_signals` between chunks; sweeps, albedo curves
//!   and renders run on a worker thread that stops at its next cancellation point when this
//!   thread sees a signal ([`interruptible`](guard::interruptible));
//! - every entry point runs under [`guard`](guard::guard): a panic (a bug) is a
//!   `RuntimeError`, never pyo3's `PanicException` (a `BaseException` that `except Exception`
//!   does not catch).
//!
//! Errors are `ValueError` (bad model, parameter or value: the library's own message),
//! `TypeError` (wrong type, wrong number of columns), `MemoryError` or `KeyboardInterrupt`.
//!
//! Model parameters arrive as the text `__init__.py` makes of the keyword arguments (the
//! CLI's `--param` text) and are parsed once per call into a `fastbrdf::ModelSpec`
//! ([`args::spec`]); everything past the boundary takes the spec.
//!
//! Modules: [`args`] (Python arguments and the spec), [`arrays`] (numpy in and out,
//! GIL-released steps), [`guard`] (errors, panics, Ctrl-C), [`handle`] (`Handle`: one colour
//! channel's model: eval, sample, pdf), [`perelement`] (per-element parameter arrays),
//! [`models`] (registry, shader export), [`analysis`] (errors, ranges, albedo), [`tools`] (check,
//! reproduce, fit, normalize, lut, pareto, chi2), [`measured`] (MERL data, fit-measured),
//! [`render`] (render, compare, materials, metals). Each module registers its own functions.

mod analysis;
mod args;
mod arrays;
mod conform;
mod fork;
mod guard;
mod handle;
mod measured;
mod models;
mod perelement;
mod render;
mod tools;

use pyo3::prelude::*;

/// The most parameter values (`errors`) and angles (`albedo`): the CLI's cap on its ranges
/// and lists (`fastbrdf_analysis::range::MAX_VALUES`).
pub(crate) const MAX_VALUES: usize = fastbrdf_analysis::range::MAX_VALUES;

/// The most items of the other sequences (parameters, lights, columns). The CLI has no cap
/// there (its command line bounds them); this one bounds an endless iterable.
pub(crate) const MAX_ITEMS: usize = 4096;

/// The largest kd, ks and albedo channel, as the CLI's `--weights` and `--albedo`
/// (`MAX_WEIGHT` of crates/cli/src/commands/render.rs).
pub(crate) const MAX_WEIGHT: f64 = 1e3;

#[pymodule]
fn _fastbrdf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    fork::loaded();
    m.add_class::<handle::Handle>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The profile family, so that a timing script can tell the test suite's wheel (Cargo's dev
    // profile, debug assertions on, several times slower) from a release build.
    m.add(
        "BUILD",
        if cfg!(debug_assertions) {
            "dev"
        } else {
            "release"
        },
    )?;
    m.add("MAX_VALUES", MAX_VALUES)?;
    m.add("MAX_ITEMS", MAX_ITEMS)?;
    m.add("MAX_WEIGHT", MAX_WEIGHT)?;
    m.add_function(wrap_pyfunction!(models::models_json, m)?)?;
    m.add_function(wrap_pyfunction!(models::info_json, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::errors_json, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::parse_range, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::albedo_json, m)?)?;
    render::register(m)?;
    m.add_function(wrap_pyfunction!(models::shader, m)?)?;
    measured::register(m)?;
    perelement::register(m)?;
    tools::register(m)?;
    conform::register(m)?;
    Ok(())
}
