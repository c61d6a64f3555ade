//! Comparing renders. Two sets of metrics:
//! - on the pictures as shown ([`metrics`]): RMSE and PSNR of clipped 8-bit sRGB values in
//!   [0, 1], and FLIP (NVIDIA's perceptual metric, `nv-flip` bindings to the reference
//!   implementation, default 67 pixels per degree) on those pictures. Clipping hides errors in
//!   highlights above 1.0;
//! - on the linear film ([`linear_metrics`]): RMSE of the linear radiance (no exposure, no
//!   clipping), PSNR against the reference's peak channel value (`20 log10(peak / rmse)`), and
//!   FLIP after the Reinhard tone map `x / (1 + x)` (exposure applied) and sRGB encoding, which
//!   compresses highlights instead of clipping them (nv-flip has no HDR-FLIP).
//!
//! Heat maps of the per-pixel difference (magma colour map, shared scale, with a colour bar),
//! and a labelled grid whose whole size and the comparison's total work are capped
//! ([`check_compare`]) before anything is rendered.

use crate::error::{RenderError, Result};
use crate::film::Film;
use crate::texture::linear_to_srgb;
use plotters::prelude::*;
use serde::Serialize;

/// Metrics of one test image against the reference.
#[derive(Clone, Debug, Serialize)]
pub struct Metrics {
    pub model: String,
    /// Root mean square difference of sRGB values in [0, 1], over all channels.
    pub rmse: f64,
    /// `20 log10(1 / rmse)` in dB; infinite for identical images (JSON: null).
    pub psnr: f64,
    /// Mean FLIP error in [0, 1].
    pub flip: f64,
}

/// RMSE, PSNR and FLIP of `test` against `reference` (sRGB 8-bit RGB, `w` x `h`).
pub fn metrics(model: &str, reference: &[u8], test: &[u8], w: u32, h: u32) -> Metrics {
    Metrics {
        flip: mean_flip(reference, test, w, h),
        ..pixel_metrics(model, reference, test)
    }
}

/// RMSE and PSNR of [`metrics`] without its FLIP (NaN here): a few milliseconds, where FLIP
/// takes hundreds (the explorer answers with these first and computes FLIP off the request).
pub fn pixel_metrics(model: &str, reference: &[u8], test: &[u8]) -> Metrics {
    let se: f64 = reference
        .iter()
        .zip(test)
        .map(|(&a, &b)| ((a as f64 - b as f64) / 255.0).powi(2))
        .sum();
    let rmse = (se / reference.len().max(1) as f64).sqrt();
    let psnr = if rmse == 0.0 {
        f64::INFINITY
    } else {
        20.0 * (1.0 / rmse).log10()
    };
    Metrics {
        model: model.into(),
        rmse,
        psnr,
        flip: f64::NAN,
    }
}

/// Metrics on the linear film (see the module's documentation).
#[derive(Clone, Debug, Serialize)]
pub struct LinearMetrics {
    /// Root mean square difference of linear radiance, over all channels (no exposure).
    pub rmse: f64,
    /// `20 log10(peak / rmse)` in dB; infinite for identical films (JSON: null).
    pub psnr: f64,
    /// The peak used for PSNR: the reference's largest channel value.
    pub peak: f64,
    /// Mean FLIP error in [0, 1] after the Reinhard tone map (exposure applied) and sRGB.
    pub flip_reinhard: f64,
}

/// The Reinhard tone map `x / (1 + x)` per channel after `exposure`, sRGB 8-bit.
pub fn reinhard_srgb8(film: &Film, exposure: f32) -> Vec<u8> {
    film.pixels
        .iter()
        .flat_map(|p| {
            (*p * exposure).to_array().map(|c| {
                let c = c.max(0.0);
                (linear_to_srgb(c / (1.0 + c)) * 255.0 + 0.5) as u8
            })
        })
        .collect()
}

/// RMSE and PSNR of linear radiance and FLIP after the Reinhard tone map, of `test` against
/// `reference` (same size).
pub fn linear_metrics(reference: &Film, test: &Film, exposure: f32) -> LinearMetrics {
    let se: f64 = reference
        .pixels
        .iter()
        .zip(&test.pixels)
        .map(|(a, b)| {
            let d = (*a - *b).as_dvec3();
            d.length_squared()
        })
        .sum();
    let rmse = (se / (3 * reference.pixels.len()).max(1) as f64).sqrt();
    let peak = reference
        .pixels
        .iter()
        .map(|p| f64::from(p.max_element()))
        .fold(0.0, f64::max);
    let psnr = if rmse == 0.0 {
        f64::INFINITY
    } else {
        20.0 * (peak.max(f64::MIN_POSITIVE) / rmse).log10()
    };
    let (r, t) = (
        reinhard_srgb8(reference, exposure),
        reinhard_srgb8(test, exposure),
    );
    let flip_reinhard = mean_flip(&r, &t, reference.width, reference.height);
    LinearMetrics {
        rmse,
        psnr,
        peak,
        flip_reinhard,
    }
}

/// Most models in one comparison.
pub const MAX_MODELS: usize = 64;
/// Most samples a comparison may take: cells x pixels x samples per pixel (2^31, minutes of
/// rendering).
pub const MAX_COMPARE_SAMPLES: u64 = 1 << 31;
/// Largest side of a grid picture.
pub const MAX_GRID_SIDE: u64 = 1 << 16;
/// Largest grid picture: 2^26 pixels (192 MiB of 8-bit RGB; the renders of its cells then
/// take at most ~400 MiB).
pub const MAX_GRID_PIXELS: u64 = 1 << 26;

const LABEL_H: u32 = 34;
const PAD: u32 = 8;
const BAR_W: u32 = 150;

/// The size of a grid of `rows` x `cols` cells of `w` x `h` (with a colour bar or not), in
/// u64 so that it cannot overflow.
pub fn grid_size(rows: usize, cols: usize, w: u32, h: u32, bar: bool) -> (u64, u64) {
    let (pad, w, h) = (u64::from(PAD), u64::from(w), u64::from(h));
    (
        pad + cols as u64 * (w + pad) + if bar { u64::from(BAR_W) } else { 0 },
        pad + rows as u64 * (h + u64::from(LABEL_H) + pad),
    )
}

/// Checks a comparison of `models` models (plus the reference) at `w` x `h` pixels, `spp` x
/// `spp` samples per pixel, before anything is rendered: at most [`MAX_MODELS`] models, the
/// whole grid picture (two rows) within [`MAX_GRID_SIDE`] per side and [`MAX_GRID_PIXELS`]
/// pixels, and the total work within [`MAX_COMPARE_SAMPLES`].
pub fn check_compare(models: usize, w: u32, h: u32, spp: u32) -> Result<()> {
    if models == 0 || models > MAX_MODELS {
        return Err(RenderError::Invalid(format!(
            "{models} models: compare takes 1 to {MAX_MODELS}"
        )));
    }
    let (gw, gh) = grid_size(2, models + 1, w, h, true);
    if !grid_fits(gw, gh) {
        return Err(RenderError::Invalid(format!(
            "the comparison picture would be {gw}x{gh} pixels ({} cells of {w}x{h} and their heat maps): at most {MAX_GRID_SIDE} per side and {MAX_GRID_PIXELS} pixels; use a smaller --size or fewer models",
            models + 1
        )));
    }
    let samples = (models as u64 + 1) * u64::from(w) * u64::from(h) * u64::from(spp).pow(2);
    if samples > MAX_COMPARE_SAMPLES {
        return Err(RenderError::Invalid(format!(
            "the comparison would trace {samples} samples ({} renders of {w}x{h} at {spp}x{spp} samples per pixel): at most {MAX_COMPARE_SAMPLES}; use a smaller --size, --spp or fewer models",
            models + 1
        )));
    }
    Ok(())
}

/// Per-pixel difference: the mean absolute sRGB difference over the three channels, in [0, 1].
pub fn difference(reference: &[u8], test: &[u8]) -> Vec<f32> {
    reference
        .chunks_exact(3)
        .zip(test.chunks_exact(3))
        .map(|(a, b)| {
            (0..3)
                .map(|k| (a[k] as f32 - b[k] as f32).abs())
                .sum::<f32>()
                / (3.0 * 255.0)
        })
        .collect()
}

fn magma() -> Vec<[u8; 3]> {
    let lut = nv_flip::magma_lut();
    let v = lut.to_vec();
    v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// A heat map of `diff` with `scale` mapping to the top of the colour map.
pub fn heat_map(diff: &[f32], scale: f32) -> Vec<u8> {
    let lut = magma();
    let top = (lut.len() - 1) as f32;
    diff.iter()
        .flat_map(|&d| lut[((d / scale.max(1e-12)).clamp(0.0, 1.0) * top).round() as usize])
        .collect()
}

/// One cell of a grid: a label and an sRGB image.
pub struct Cell {
    pub label: String,
    pub rgb: Vec<u8>,
}

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../analysis/assets/DejaVuSans.ttf");
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// Lays out rows of `w` x `h` cells with a label strip above each, plus an optional colour
/// bar (magma, 0 to `bar_max`) at the right. Returns (rgb, width, height).
pub fn grid(
    rows: &[Vec<Cell>],
    w: u32,
    h: u32,
    bar_max: Option<f32>,
) -> Result<(Vec<u8>, u32, u32)> {
    register_font();
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    let bar_w = if bar_max.is_some() { BAR_W } else { 0 };
    let (gw, gh) = grid_size(rows.len(), cols, w, h, bar_max.is_some());
    if !grid_fits(gw, gh) {
        return Err(RenderError::Invalid(format!(
            "a grid of {gw}x{gh} pixels is too large: at most {MAX_GRID_SIDE} per side and {MAX_GRID_PIXELS} pixels"
        )));
    }
    let (gw, gh) = (gw as u32, gh as u32);
    let mut buf = vec![255u8; (gw * gh * 3) as usize];
    for (r, row) in rows.iter().enumerate() {
        for (c, cell) in row.iter().enumerate() {
            let (ox, oy) = (
                PAD + c as u32 * (w + PAD),
                PAD + r as u32 * (h + LABEL_H + PAD) + LABEL_H,
            );
            for y in 0..h {
                let src = &cell.rgb[(y * w * 3) as usize..((y + 1) * w * 3) as usize];
                let dst = (((oy + y) * gw + ox) * 3) as usize;
                buf[dst..dst + (w * 3) as usize].copy_from_slice(src);
            }
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (gw, gh)).into_drawing_area();
        let err = |e: String| RenderError::Output {
            file: "<grid>".into(),
            message: e,
        };
        for (r, row) in rows.iter().enumerate() {
            for (c, cell) in row.iter().enumerate() {
                let (ox, oy) = (
                    PAD + c as u32 * (w + PAD),
                    PAD + r as u32 * (h + LABEL_H + PAD),
                );
                let size = if w < 220 { 14 } else { 20 };
                // Keep the label inside its cell (DejaVu Sans averages ~0.55 em per glyph).
                let max_chars = (w as f32 / (size as f32 * 0.56)) as usize;
                let label: String = if cell.label.chars().count() > max_chars {
                    cell.label
                        .chars()
                        .take(max_chars.saturating_sub(3))
                        .chain("...".chars())
                        .collect()
                } else {
                    cell.label.clone()
                };
                root.draw_text(
                    &label,
                    &("sans-serif", size).into_font().color(&BLACK),
                    (ox as i32, oy as i32 + 6),
                )
                .map_err(|e| err(e.to_string()))?;
            }
        }
        if let Some(max) = bar_max {
            let lut = magma();
            let (bx, by, bh) = (
                gw - bar_w + 20,
                PAD + LABEL_H,
                (gh - 2 * PAD - LABEL_H).min(400),
            );
            for i in 0..bh {
                let c = lut
                    [((1.0 - i as f32 / (bh - 1).max(1) as f32) * (lut.len() - 1) as f32) as usize];
                root.draw(&Rectangle::new(
                    [
                        (bx as i32, (by + i) as i32),
                        (bx as i32 + 28, (by + i + 1) as i32),
                    ],
                    RGBColor(c[0], c[1], c[2]).filled(),
                ))
                .map_err(|e| err(e.to_string()))?;
            }
            let font = ("sans-serif", 16).into_font().color(&BLACK);
            for (frac, text) in [
                (0.0, format!("{max:.3}")),
                (0.5, format!("{:.3}", max / 2.0)),
                (1.0, "0".to_string()),
            ] {
                let y = by as f32 + frac * (bh - 1) as f32;
                root.draw_text(&text, &font, (bx as i32 + 34, y as i32 - 8))
                    .map_err(|e| err(e.to_string()))?;
            }
            root.draw_text("|difference|", &font, (bx as i32 - 10, PAD as i32 + 6))
                .map_err(|e| err(e.to_string()))?;
            root.draw_text("(sRGB)", &font, (bx as i32 - 10, (by + bh) as i32 + 6))
                .map_err(|e| err(e.to_string()))?;
        }
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok((buf, gw, gh))
}

/// Mean FLIP of two 8-bit sRGB pictures (NVIDIA's metric at 67 pixels per degree); 0 when
/// they are identical.
fn mean_flip(reference: &[u8], test: &[u8], w: u32, h: u32) -> f64 {
    if reference == test {
        return 0.0;
    }
    let err = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, reference),
        nv_flip::FlipImageRgb8::with_data(w, h, test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&err).mean() as f64
}

/// Whether a composed comparison picture of `gw` x `gh` pixels is within the caps.
fn grid_fits(gw: u64, gh: u64) -> bool {
    gw <= MAX_GRID_SIDE && gh <= MAX_GRID_SIDE && gw * gh <= MAX_GRID_PIXELS
}
