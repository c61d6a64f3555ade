//! `fastbrdf lut`: the split-sum table as numpy arrays (and, given `out`, the file the
//! command writes).

use super::{io_error, to_json};
use crate::args::u32_arg;
use crate::arrays::empty;
use crate::guard::{guard, interruptible, stop_if, value_error};
use fastbrdf_analysis::lut as table_of;
use fastbrdf_analysis::lut::{Axis, MAX_SIZE};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// A float32 array.
type F32<'py> = Bound<'py, PyArray1<f32>>;

/// The output format: `format`, else the extension of `out` (as the CLI's `--format`).
fn format_of(out: &Path, format: Option<&str>) -> PyResult<&'static str> {
    if let Some(f) = format
        && !matches!(f, "exr" | "png" | "csv")
    {
        return Err(value_error(format!(
            "format '{}': expected exr, png or csv",
            fastbrdf_io::shorten(f, 40)
        )));
    }
    table_of::format_of(out, format).ok_or_else(|| {
        value_error(format!(
            "out {}: the file must end in .exr, .png or .csv (or give format)",
            fastbrdf_io::shorten_middle(&out.display().to_string(), 80)
        ))
    })
}

/// The table of env model `model`: `(metadata JSON, scale, bias)`, `scale` and `bias` float32
/// of `size * size` values, row-major (row `j` of roughness, column `i` of `cos_v`); the
/// metadata `{model, size, axis, clamped_rows, cos_v, roughness, alpha}`. With `out`, also
/// writes the file `fastbrdf lut --out` writes (EXR, PNG or CSV).
#[pyfunction]
#[pyo3(signature = (model, size, axis, out, format))]
pub(crate) fn lut_table<'py>(
    py: Python<'py>,
    model: &str,
    size: &Bound<'py, PyAny>,
    axis: &str,
    out: Option<PathBuf>,
    format: Option<&str>,
) -> PyResult<(String, F32<'py>, F32<'py>)> {
    guard(|| {
        let format = out.as_deref().map(|o| format_of(o, format)).transpose()?;
        let n = u32_arg(size, "size")?;
        let size = usize::try_from(n)
            .ok()
            .filter(|s| (1..=MAX_SIZE).contains(s))
            .ok_or_else(|| {
                value_error(format!(
                    "size {n}: expected 1 to {MAX_SIZE} (an N x N table)"
                ))
            })?;
        let axis = match axis {
            "roughness" => Axis::Roughness,
            "alpha" => Axis::Alpha,
            a => {
                return Err(value_error(format!(
                    "axis '{}': expected roughness or alpha",
                    fastbrdf_io::shorten(a, 40)
                )));
            }
        };
        // An unknown or non-env model is refused before any work.
        table_of::kernels(model).map_err(value_error)?;
        let table = interruptible(py, |cancel| {
            table_of::compute(model, size, axis, &|| stop_if(cancel))
        })?
        .map_err(value_error)?;
        if let (Some(path), Some(format)) = (&out, format) {
            let fail = |e: String| {
                pyo3::exceptions::PyOSError::new_err(format!("{}: {e}", path.display()))
            };
            match format {
                "csv" => fastbrdf_io::write_atomic_with(path, |w| table.write_csv(w)),
                "exr" => fastbrdf_io::write_atomic(path, &table.exr_bytes().map_err(fail)?),
                _ => fastbrdf_io::write_atomic(path, &table.png_bytes().map_err(fail)?),
            }
            .map_err(io_error)?;
        }
        let meta = serde_json::json!({
            "model": table.model,
            "size": size,
            "axis": axis.name(),
            "clamped_rows": table.clamped_rows(),
            "cos_v": table.cos_v,
            "roughness": table.rows.iter().map(|r| r.roughness).collect::<Vec<_>>(),
            "alpha": table.rows.iter().map(|r| r.alpha).collect::<Vec<_>>(),
        });
        let copy = |v: &[f32]| -> PyResult<F32<'py>> {
            let a = empty::<f32>(py, v.len())?;
            {
                let mut rw = a.try_readwrite()?;
                rw.as_slice_mut().map_err(value_error)?.copy_from_slice(v);
            }
            Ok(a)
        };
        Ok((to_json(&meta)?, copy(&table.scale)?, copy(&table.bias)?))
    })
}
