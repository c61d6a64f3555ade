//! Albedo textures: PNG or JPEG, decoded from sRGB to linear, sampled bilinearly with wrapping.

use crate::error::{RenderError, Result};
use glam::{Vec2, Vec3};
use std::path::Path;

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
    /// Loads a PNG or JPEG file.
    pub fn load(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let img = image::open(path).map_err(|e| RenderError::Input {
            file: file.clone(),
            line: None,
            message: format!("cannot read the texture: {e}"),
        })?;
        let rgb = img.to_rgb8();
        let (w, h) = rgb.dimensions();
        if w == 0 || h == 0 {
            return Err(RenderError::Input {
                file,
                line: None,
                message: "the texture is empty".into(),
            });
        }
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
