//! Film: linear HDR RGB accumulation; sRGB PNG output with exposure, linear EXR output; sizes
//! checked against a memory cap; files written to a temporary name and renamed.

use crate::error::{RenderError, Result};
use crate::texture::linear_to_srgb;
use glam::Vec3;
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
            (u64::from(w) * u64::from(h) * 12) >> 20
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

    /// The pixel at (x, y).
    pub fn at(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// sRGB 8-bit RGB bytes after multiplying by `exposure` and clamping.
    pub fn to_srgb8(&self, exposure: f32) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| {
                (*p * exposure)
                    .to_array()
                    .map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)
            })
            .collect()
    }

    /// Writes `.png` (sRGB, exposure applied) or `.exr` (linear, exposure applied) by the
    /// file's extension.
    pub fn save(&self, path: &Path, exposure: f32) -> Result<()> {
        let out = |m: String| RenderError::Output {
            file: path.display().to_string(),
            message: m,
        };
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("png") => {
                let mut bytes = Vec::new();
                image::codecs::png::PngEncoder::new(&mut bytes)
                    .write_image_rgb8(&self.to_srgb8(exposure), self.width, self.height)
                    .map_err(|e| out(e.to_string()))?;
                write_atomic(path, &bytes)
            }
            Some("exr") => {
                let data: Vec<f32> = self
                    .pixels
                    .iter()
                    .flat_map(|p| (*p * exposure).to_array())
                    .collect();
                let img =
                    image::Rgb32FImage::from_raw(self.width, self.height, data).expect("sized");
                let mut cursor = std::io::Cursor::new(Vec::new());
                image::DynamicImage::ImageRgb32F(img)
                    .write_to(&mut cursor, image::ImageFormat::OpenExr)
                    .map_err(|e| out(e.to_string()))?;
                write_atomic(path, cursor.get_ref())
            }
            _ => Err(RenderError::Invalid(format!(
                "--out {}: the file must end in .png or .exr",
                path.display()
            ))),
        }
    }
}

trait Rgb8 {
    fn write_image_rgb8(self, rgb: &[u8], w: u32, h: u32) -> image::ImageResult<()>;
}

impl<W: std::io::Write> Rgb8 for image::codecs::png::PngEncoder<W> {
    fn write_image_rgb8(self, rgb: &[u8], w: u32, h: u32) -> image::ImageResult<()> {
        use image::ImageEncoder;
        self.write_image(rgb, w, h, image::ExtendedColorType::Rgb8)
    }
}

/// Encodes 8-bit RGB as PNG.
pub fn png_bytes(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image_rgb8(rgb, w, h)
        .map_err(|e| RenderError::Output {
            file: "<png>".into(),
            message: e.to_string(),
        })?;
    Ok(bytes)
}

/// Writes `bytes` atomically (see `fastbrdf_io::write_atomic`): a failure leaves neither a
/// half-written file nor a temporary one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    fastbrdf_io::write_atomic(path, bytes).map_err(RenderError::from)
}
