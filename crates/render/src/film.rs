//! Film: linear HDR RGB accumulation; sRGB PNG output (sRGB chunk) with exposure, linear EXR
//! output (scanline ZIP, no exposure); sizes checked against a memory cap; non-finite pixels
//! refused before any write; files written to a temporary name and renamed.

use crate::error::{RenderError, Result};
use crate::texture::linear_to_srgb;
use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;

/// Largest image side accepted.
pub const MAX_SIDE: u32 = 8192;
/// Largest pixel count accepted: 2^25 (32 Mpixel; the film then takes 384 MiB).
pub const MAX_PIXELS: u64 = 1 << 25;

/// Checks an image size against the caps.
pub fn check_size(w: u32, h: u32) -> Result<()> {
    if w == 0 || h == 0 {
        return Err(RenderError::Invalid(format!(
            "size {w}x{h}: both sides must be at least 1"
        )));
    }
    if w > MAX_SIDE || h > MAX_SIDE || u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(RenderError::Invalid(format!(
            "size {w}x{h} is too large: at most {MAX_SIDE} per side and {MAX_PIXELS} pixels (the film would need {} MiB)",
            (u64::from(w) * u64::from(h)).saturating_mul(12) >> 20
        )));
    }
    Ok(())
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let bad = || RenderError::Invalid(format!("--size '{s}': expected WIDTHxHEIGHT, e.g. 800x600"));
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    check_size(w, h)?;
    Ok((w, h))
}

/// A linear RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; (width * height) as usize],
        }
    }

    /// A black film, or [`RenderError::Memory`] when its pixels cannot be allocated (the
    /// renderers use this: a size within [`check_size`] may still exceed what the process can
    /// have, and an allocation failure must not abort an embedding interpreter).
    pub fn try_new(width: u32, height: u32) -> Result<Self> {
        let n = width as usize * height as usize;
        // Zeroed by the allocator (fresh pages from the kernel, untouched until the renderer's
        // threads write them): writing the zeros here took a single thread 1.7 ms of page
        // faults on a 512 x 512 film, 14% of a directly lit render.
        let pixels = bytemuck::allocation::try_zeroed_vec::<Vec3>(n).map_err(|_| {
            RenderError::Memory(format!(
                "cannot allocate {} MiB for a {width} x {height} film (out of memory)",
                (n as u64).saturating_mul(12) >> 20
            ))
        })?;
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// The pixel at (x, y).
    pub fn at(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// sRGB 8-bit RGB bytes after multiplying by `exposure` and clamping. Rows in parallel;
    /// a pixel equal to the one before it (the background, flat regions) reuses its bytes
    /// instead of three `powf` (the same function of the same value: the same bytes).
    pub fn to_srgb8(&self, exposure: f32) -> Vec<u8> {
        let w = self.width as usize;
        let mut rgb = vec![0u8; self.pixels.len() * 3];
        rgb.par_chunks_mut(w * 3)
            .zip(self.pixels.par_chunks(w))
            .for_each(|(out, row)| {
                let mut last: Option<(Vec3, [u8; 3])> = None;
                for (o, p) in out.chunks_exact_mut(3).zip(row) {
                    let v = *p * exposure;
                    let bytes = match last {
                        // `==` on floats: NaN never matches, and -0 and +0 encode alike.
                        Some((lv, lb)) if lv == v => lb,
                        _ => {
                            let b = v
                                .to_array()
                                .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8);
                            last = Some((v, b));
                            b
                        }
                    };
                    o.copy_from_slice(&bytes);
                }
            });
        rgb
    }

    /// Errors if any pixel is NaN or infinite (the last guard before a file is written: no
    /// NaN or inf ever reaches a PNG or EXR). The message names the first such pixel.
    pub fn check_finite(&self) -> Result<()> {
        // In chunks of 4096 pixels: `position_first` over single pixels checks a shared
        // bound per item, which showed in a directly lit render's profile.
        let first = self
            .pixels
            .par_chunks(4096)
            .position_first(|c| c.iter().any(|p| !p.is_finite()))
            .and_then(|k| {
                let c = &self.pixels[k * 4096..];
                c.iter().position(|p| !p.is_finite()).map(|i| k * 4096 + i)
            });
        if let Some(i) = first {
            // Counted only on the error path: a finite film is scanned once.
            let bad = self.pixels[i..].iter().filter(|p| !p.is_finite()).count();
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            return Err(RenderError::Invalid(format!(
                "the render has {bad} non-finite pixels (the first at x = {x}, y = {y}: {:?}): the model, its parameters, the lights or the environment map overflow f32; nothing was written",
                self.pixels[i].to_array()
            )));
        }
        Ok(())
    }

    /// Writes `.png` (sRGB with an sRGB chunk, `exposure` applied, clipped to [0, 1]) or
    /// `.exr` (linear radiance, exposure NOT applied, scanline ZIP) by the file's extension,
    /// after [`Film::check_finite`].
    pub fn save(&self, path: &Path, exposure: f32) -> Result<()> {
        self.check_finite()?;
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("png") => write_atomic(
                path,
                &png_bytes(&self.to_srgb8(exposure), self.width, self.height)?,
            ),
            Some("exr") => write_atomic(path, &self.encode_exr()?),
            _ => Err(RenderError::Invalid(format!(
                "--out {}: the file must end in .png or .exr",
                path.display()
            ))),
        }
    }

    /// The film as OpenEXR: linear RGB, 32-bit float, one scanline-block layer with ZIP
    /// compression (16 lines per block; read by every viewer, unlike tiled files).
    pub fn exr_bytes(&self) -> Result<Vec<u8>> {
        self.check_finite()?;
        self.encode_exr()
    }

    /// [`Film::exr_bytes`] without the finiteness check (the caller has made it).
    fn encode_exr(&self) -> Result<Vec<u8>> {
        use exr::prelude::*;
        let (w, h) = (self.width as usize, self.height as usize);
        let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
            let p = self.pixels[y * w + x];
            (p.x, p.y, p.z)
        });
        let encoding = Encoding {
            compression: Compression::ZIP16,
            blocks: Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        };
        let layer = Layer::new((w, h), LayerAttributes::default(), encoding, channels);
        let mut cursor = std::io::Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut cursor)
            .map_err(|e| RenderError::Output {
                file: "<exr>".into(),
                message: e.to_string(),
            })?;
        Ok(cursor.into_inner())
    }
}

/// Encodes 8-bit sRGB RGB as PNG with an sRGB chunk (perceptual intent; the png crate adds
/// the gAMA and cHRM fallbacks), so viewers know the colour space.
pub fn png_bytes(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>> {
    let fail = |e: png::EncodingError| RenderError::Output {
        file: "<png>".into(),
        message: e.to_string(),
    };
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = enc.write_header().map_err(fail)?;
        writer.write_image_data(rgb).map_err(fail)?;
        writer.finish().map_err(fail)?;
    }
    Ok(bytes)
}

/// Writes `bytes` atomically (see `fastbrdf_io::write_atomic`): a failure leaves neither a
/// half-written file nor a temporary one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    fastbrdf_io::write_atomic(path, bytes).map_err(RenderError::from)
}
