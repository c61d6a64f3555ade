//! Albedo textures: PNG, JPEG or EXR, read once with capped size and dimensions, decoded from sRGB to linear, sampled bilinearly with wrapping.

use crate::error::{RenderError, Result};
use glam::{Vec2, Vec3};
use std::path::Path;

/// Largest texture file read: 256 MiB.
pub const MAX_TEXTURE_BYTES: u64 = 256 << 20;
/// Largest texture side: 16384 pixels.
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Largest texture: 2^25 pixels (32 Mpixel; 384 MiB of linear texels).
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 25;

/// Checks a texture's declared size against the caps; the message says why.
pub fn check_texture_size(w: u32, h: u32) -> std::result::Result<(), String> {
    if w == 0 || h == 0 {
        return Err(format!("the texture is empty ({w}x{h})"));
    }
    if w > MAX_TEXTURE_SIDE
        || h > MAX_TEXTURE_SIDE
        || u64::from(w) * u64::from(h) > MAX_TEXTURE_PIXELS
    {
        return Err(format!(
            "the texture declares {w}x{h} pixels: at most {MAX_TEXTURE_SIDE} per side and {MAX_TEXTURE_PIXELS} pixels are accepted (nothing was decoded)"
        ));
    }
    Ok(())
}

/// A linear RGB texture.
#[derive(Clone, Debug)]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    texels: Vec<Vec3>,
}

/// The sRGB transfer function, decoded.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB transfer function, encoded.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl Texture {
    /// Loads a PNG, JPEG or EXR file: read once (at most [`MAX_TEXTURE_BYTES`]), its declared
    /// size checked against [`MAX_TEXTURE_SIDE`] and [`MAX_TEXTURE_PIXELS`] before anything is
    /// decoded, and the decoder's allocations capped.
    pub fn load(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let bad = |m: String| RenderError::Input {
            file: file.clone(),
            line: None,
            message: m,
        };
        let f =
            std::fs::File::open(path).map_err(|e| bad(format!("cannot read the texture: {e}")))?;
        let bytes = fastbrdf_io::read_reader_bounded(f, path, MAX_TEXTURE_BYTES, "a texture")?;
        let reader = || {
            image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
                .with_guessed_format()
                .map_err(|e| bad(format!("cannot read the texture: {e}")))
        };
        let (w, h) = reader()?
            .into_dimensions()
            .map_err(|e| bad(format!("cannot read the texture: {e}")))?;
        check_texture_size(w, h).map_err(bad)?;
        let mut r = reader()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE);
        limits.max_alloc = Some(MAX_TEXTURE_PIXELS * 16);
        r.limits(limits);
        let img = r
            .decode()
            .map_err(|e| bad(format!("cannot read the texture: {e}")))?;
        let rgb = img.to_rgb8();
        // Not empty: check_texture_size refused a zero side before decoding.
        let (w, h) = rgb.dimensions();
        let lut: Vec<f32> = (0..256).map(|i| srgb_to_linear(i as f32 / 255.0)).collect();
        let texels = rgb
            .pixels()
            .map(|p| Vec3::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]))
            .collect();
        Ok(Self {
            width: w,
            height: h,
            texels,
        })
    }

    /// A texture from linear texels (row-major, top row first).
    pub fn from_linear(width: u32, height: u32, texels: Vec<Vec3>) -> Self {
        assert_eq!(texels.len(), (width * height) as usize, "texel count");
        Self {
            width,
            height,
            texels,
        }
    }

    /// The linear texels (row-major, top row first), for renderers that filter themselves
    /// (the GPU renderer uploads them).
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Bilinear sample at `uv` (v = 0 at the bottom, as OBJ), wrapping.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width as f32, self.height as f32);
        let x = uv.x.rem_euclid(1.0) * w - 0.5;
        let y = (1.0 - uv.y.rem_euclid(1.0)) * h - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |xi: f32, yi: f32| {
            let xi = (xi as i64).rem_euclid(self.width as i64) as usize;
            let yi = (yi as i64).rem_euclid(self.height as i64) as usize;
            self.texels[yi * self.width as usize + xi]
        };
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}
