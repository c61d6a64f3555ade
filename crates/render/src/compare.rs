//! Comparing renders: RMSE and PSNR on sRGB values in [0, 1], FLIP (NVIDIA's perceptual
//! metric, `nv-flip` bindings to the reference implementation, default 67 pixels per degree),
//! heat maps of the per-pixel difference (magma colour map, shared scale, with a colour bar),
//! and a labelled grid.

use crate::error::{RenderError, Result};
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
    let flip = if reference == test {
        0.0
    } else {
        let r = nv_flip::FlipImageRgb8::with_data(w, h, reference);
        let t = nv_flip::FlipImageRgb8::with_data(w, h, test);
        let err = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
        nv_flip::FlipPool::from_image(&err).mean() as f64
    };
    Metrics {
        model: model.into(),
        rmse,
        psnr,
        flip,
    }
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
    let label_h = 34;
    let pad = 8;
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0) as u32;
    let bar_w = if bar_max.is_some() { 150 } else { 0 };
    let (gw, gh) = (
        pad + cols * (w + pad) + bar_w,
        pad + rows.len() as u32 * (h + label_h + pad),
    );
    let mut buf = vec![255u8; (gw * gh * 3) as usize];
    for (r, row) in rows.iter().enumerate() {
        for (c, cell) in row.iter().enumerate() {
            let (ox, oy) = (
                pad + c as u32 * (w + pad),
                pad + r as u32 * (h + label_h + pad) + label_h,
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
                    pad + c as u32 * (w + pad),
                    pad + r as u32 * (h + label_h + pad),
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
                pad + label_h,
                (gh - 2 * pad - label_h).min(400),
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
            root.draw_text("|difference|", &font, (bx as i32 - 10, pad as i32 + 6))
                .map_err(|e| err(e.to_string()))?;
            root.draw_text("(sRGB)", &font, (bx as i32 - 10, (by + bh) as i32 + 6))
                .map_err(|e| err(e.to_string()))?;
        }
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok((buf, gw, gh))
}
