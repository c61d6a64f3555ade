//! The split-sum "DFG" look-up table (`fastbrdf lut`): the two terms `scale` and `bias` of an
//! env model (`Kind::Env`; `env-brdf` by default) on an `N x N` grid, as engines load it for
//! image-based lighting (specular = prefiltered radiance x (f0 scale + bias)).
//!
//! Layout: x (column `i`) is `cos_v = (i + 0.5) / N`; y (row `j`) is the roughness axis at
//! `t = (j + 0.5) / N`, either perceptual roughness `r = t`, `alpha = r^2` ([`Axis::Roughness`],
//! as Unreal and Filament index their tables) or `alpha = t` ([`Axis::Alpha`]). Both at texel
//! centres, where an engine's bilinear fetch returns the texel's own value. Row 0 holds the
//! smallest roughness. `alpha` is clamped to the models' domain (`params::ALPHA`, >= 0.005):
//! the rows whose nominal `alpha` is below it hold the values at `alpha = 0.005`.
//!
//! Values are computed by the batch kernel (`batch::Kernel`, one per term), rows in parallel on
//! rayon's pool; memory is the two `N x N` f32 tables and the encoded file. Encoders (no I/O
//! here): CSV (streamed), EXR (32-bit float RGB, R = scale, G = bias, B = 0, linear, scanline
//! ZIP) and PNG (16-bit RGB, same channels, values in [0, 1] quantised to 65535 steps).

use fastbrdf::batch::{Input, Kernel};
use fastbrdf::{Error, Kind, Result, registry};
use rayon::prelude::*;
use std::io::{self, Write};

/// The largest table side (`--size`): 4096 x 4096 is 2^24 texels, 128 MiB of f32 for the two
/// terms (and about 10 CPU-minutes of `env-brdf`, at ~20 us per value and two per texel).
pub const MAX_SIZE: usize = 4096;

/// What the table's y axis indexes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Perceptual roughness `r`, `alpha = r^2` (Unreal, Filament).
    Roughness,
    /// `alpha` itself.
    Alpha,
}

impl Axis {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Axis::Roughness => "roughness",
            Axis::Alpha => "alpha",
        }
    }
}

/// The file format of a table written to `out`: `format` when given, else the extension of
/// `out` (either case); `None` when neither names exr, png or csv.
pub fn format_of(out: &std::path::Path, format: Option<&str>) -> Option<&'static str> {
    let by_ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match format.or(by_ext.as_deref()) {
        Some("exr") => Some("exr"),
        Some("png") => Some("png"),
        Some("csv") => Some("csv"),
        _ => None,
    }
}

/// The smallest `alpha` evaluated (`params::ALPHA`'s lower bound), as the f32 the kernels see.
pub fn alpha_min() -> f32 {
    fastbrdf::params::ALPHA.range().0 as f32
}

/// The texel centre `(k + 0.5) / n`.
fn centre(k: usize, n: usize) -> f64 {
    (k as f64 + 0.5) / n as f64
}

/// One row of the table: the nominal roughness `r` of its texel centre and the `alpha`
/// evaluated (clamped to the domain).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub roughness: f32,
    pub alpha: f32,
}

/// The rows of an `n`-row table on `axis`.
pub fn rows(n: usize, axis: Axis) -> Vec<Row> {
    (0..n)
        .map(|j| {
            let t = centre(j, n);
            let (r, a) = match axis {
                Axis::Roughness => (t, t * t),
                Axis::Alpha => (t.sqrt(), t),
            };
            Row {
                roughness: r as f32,
                alpha: (a as f32).max(alpha_min()),
            }
        })
        .collect()
}

/// The columns' `cos_v` of an `n`-column table.
pub fn cos_v(n: usize) -> Vec<f32> {
    (0..n).map(|i| centre(i, n) as f32).collect()
}

/// The table: `scale` and `bias`, row-major (`[j * size + i]`: row `j` of roughness, column
/// `i` of `cos_v`).
#[derive(Clone, Debug)]
pub struct Lut {
    pub model: &'static str,
    pub size: usize,
    pub axis: Axis,
    pub cos_v: Vec<f32>,
    pub rows: Vec<Row>,
    pub scale: Vec<f32>,
    pub bias: Vec<f32>,
}

/// Checks a table size: 1 to [`MAX_SIZE`].
pub fn check_size(size: usize) -> Result<()> {
    if !(1..=MAX_SIZE).contains(&size) {
        return Err(Error::InvalidParam {
            model: "lut".into(),
            param: "size".into(),
            value: size.to_string(),
            expected: format!("1 to {MAX_SIZE} (an N x N table)"),
        });
    }
    Ok(())
}

/// The two kernels (scale, bias) of env model `id`; errors for an unknown id or another kind.
pub fn kernels(id: &str) -> Result<(Kernel, Kernel)> {
    let e = registry::find(id)?;
    // The split-sum models have a `term` (scale or bias); the sheen albedo models, env
    // models too, have one value and no `term`.
    let split_sum = |info: &fastbrdf::ModelInfo| {
        info.kind == Kind::Env && info.params.iter().any(|p| p.name == "term")
    };
    if !split_sum(&e.info) {
        let ids: Vec<&str> = registry::all()
            .iter()
            .filter(|m| split_sum(&m.info))
            .map(|m| m.info.id)
            .collect();
        return Err(Error::WrongKind {
            model: e.info.id.into(),
            expected: format!(
                "split-sum (env) model with a scale and a bias ({})",
                ids.join(", ")
            ),
            found: if e.info.kind == Kind::Env {
                "one-value env model (a sheen albedo: no `term`)".into()
            } else {
                e.info.kind.name().into()
            },
        });
    }
    let term = |t: &str| {
        Kernel::new(&fastbrdf::ModelSpec::new(
            e.info.id,
            &[("term", fastbrdf::Given::Choice(t.into()))],
        )?)
    };
    Ok((term("scale")?, term("bias")?))
}

/// Computes the table of env model `id`. `row_done` is called once per finished row (from
/// rayon's threads), for a progress bar.
pub fn compute(id: &str, size: usize, axis: Axis, row_done: &(dyn Fn() + Sync)) -> Result<Lut> {
    check_size(size)?;
    let (ks, kb) = kernels(id)?;
    let cos = cos_v(size);
    let rows = rows(size, axis);
    let mut scale = vec![0f32; size * size];
    let mut bias = vec![0f32; size * size];
    // One row per task, each by `Kernel::eval` on one thread: `eval_par` times its first
    // 16384 values on the calling thread before it splits, which for `env-brdf` (~50 us per
    // value) is most of a small table run serially.
    scale
        .par_chunks_mut(size)
        .zip(bias.par_chunks_mut(size))
        .zip(rows.par_iter())
        .try_for_each(|((s, b), row)| -> Result<()> {
            let alpha = vec![row.alpha; size];
            ks.eval(Input::Env([&cos, &alpha]), s)?;
            kb.eval(Input::Env([&cos, &alpha]), b)?;
            row_done();
            Ok(())
        })?;
    Ok(Lut {
        model: ks.id(),
        size,
        axis,
        cos_v: cos,
        rows,
        scale,
        bias,
    })
}

/// The CSV header.
pub const CSV_HEADER: &str = "cos_v,roughness,alpha,scale,bias";

impl Lut {
    /// How many rows (from row 0) hold clamped `alpha` (nominal `alpha` below the domain).
    pub fn clamped_rows(&self) -> usize {
        let n = self.size;
        (0..n)
            .take_while(|&j| {
                let t = centre(j, n);
                let a = match self.axis {
                    Axis::Roughness => t * t,
                    Axis::Alpha => t,
                };
                (a as f32) < alpha_min()
            })
            .count()
    }

    /// The table as CSV: [`CSV_HEADER`], then one line per texel, row by row (roughness
    /// outer, `cos_v` inner); numbers in the shortest text that reads back as the same f32.
    pub fn write_csv(&self, w: &mut dyn Write) -> io::Result<()> {
        writeln!(w, "{CSV_HEADER}")?;
        for (j, row) in self.rows.iter().enumerate() {
            for (i, c) in self.cos_v.iter().enumerate() {
                let k = j * self.size + i;
                writeln!(
                    w,
                    "{c},{},{},{},{}",
                    row.roughness, row.alpha, self.scale[k], self.bias[k]
                )?;
            }
        }
        Ok(())
    }

    /// The table as OpenEXR: 32-bit float RGB, R = scale, G = bias, B = 0, linear, one
    /// scanline layer with ZIP compression; scanline 0 (the top) is row 0 (smallest roughness).
    pub fn exr_bytes(&self) -> std::result::Result<Vec<u8>, String> {
        use exr::prelude::*;
        let n = self.size;
        let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
            let k = y * n + x;
            (self.scale[k], self.bias[k], 0f32)
        });
        let encoding = Encoding {
            compression: Compression::ZIP16,
            blocks: Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        };
        let layer = Layer::new((n, n), LayerAttributes::default(), encoding, channels);
        let mut cursor = std::io::Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut cursor)
            .map_err(|e| e.to_string())?;
        Ok(cursor.into_inner())
    }

    /// The table as PNG: 16-bit RGB, R = scale, G = bias, B = 0, each clamped to [0, 1] and
    /// quantised as `round(v * 65535)`; no colour-space chunk (the values are data, linear);
    /// image row 0 (the top) is table row 0 (smallest roughness).
    pub fn png_bytes(&self) -> std::result::Result<Vec<u8>, String> {
        let n = self.size;
        let q =
            |v: f32| -> [u8; 2] { ((v.clamp(0.0, 1.0) * 65535.0).round() as u16).to_be_bytes() };
        let mut data = Vec::with_capacity(n * n * 6);
        for (s, b) in self.scale.iter().zip(&self.bias) {
            data.extend_from_slice(&q(*s));
            data.extend_from_slice(&q(*b));
            data.extend_from_slice(&[0, 0]);
        }
        let mut bytes = Vec::new();
        {
            let side = u32::try_from(n).map_err(|e| e.to_string())?;
            let mut enc = png::Encoder::new(&mut bytes, side, side);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Sixteen);
            let mut writer = enc.write_header().map_err(|e| e.to_string())?;
            writer.write_image_data(&data).map_err(|e| e.to_string())?;
            writer.finish().map_err(|e| e.to_string())?;
        }
        Ok(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texel_centres_and_clamped_rows() {
        assert_eq!(cos_v(4), vec![0.125, 0.375, 0.625, 0.875]);
        let r = rows(128, Axis::Roughness);
        // r^2 < 0.005 for r < 0.0707: rows 0..=8 at N = 128.
        assert!(r[..9].iter().all(|x| x.alpha == alpha_min()));
        assert!(r[9].alpha > alpha_min());
        assert_eq!(r[64].roughness, 0.50390625);
        let a = rows(128, Axis::Alpha);
        assert_eq!(a[0].alpha, alpha_min());
        assert_eq!(a[1].alpha, 1.5 / 128.0);
    }

    #[test]
    fn non_env_models_and_bad_sizes_are_refused() {
        assert!(matches!(kernels("ggx"), Err(Error::WrongKind { .. })));
        assert!(matches!(kernels("nope"), Err(Error::UnknownModel(_))));
        // An env model of one value: refused by kind, naming the models that work.
        let e = kernels("sheen-albedo-table").err().map(|e| e.to_string());
        let e = e.expect("sheen-albedo-table has no split-sum table");
        assert!(
            e.contains("no `term`") && e.contains("env-brdf-table"),
            "{e}"
        );
        assert!(!e.contains("sheen-albedo-khronos,"), "{e}");
        assert!(check_size(0).is_err());
        assert!(check_size(MAX_SIZE + 1).is_err());
        assert!(check_size(MAX_SIZE).is_ok());
    }

    #[test]
    fn clamped_rows_are_counted() {
        let lut = compute("env-brdf-approx", 128, Axis::Roughness, &|| {}).unwrap();
        assert_eq!(lut.clamped_rows(), 9);
        let lut = compute("env-brdf-approx", 128, Axis::Alpha, &|| {}).unwrap();
        assert_eq!(lut.clamped_rows(), 1);
    }
}
