//! Albedo textures: PNG, JPEG or EXR, read once with capped size and dimensions, decoded from sRGB to linear, sampled bilinearly with wrapping; and the built-in procedural skin ([`skin`], `--texture skin`).

use crate::decode::decode_limited;
use crate::error::Result;
use crate::hash::pcg;
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
        let img = decode_limited(
            path,
            MAX_TEXTURE_BYTES,
            "a texture",
            "the texture",
            |_| Ok(()),
            check_texture_size,
            (MAX_TEXTURE_SIDE, MAX_TEXTURE_SIDE, MAX_TEXTURE_PIXELS * 16),
        )?;
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

/// Side of the built-in skin texture ([`skin`]), in texels.
pub const SKIN_SIDE: u32 = 1024;

/// A hash of a lattice point and a seed, uniform in [0, 1).
fn lattice(i: u32, j: u32, seed: u32) -> f32 {
    let h = pcg(i ^ pcg(j ^ pcg(seed)));
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Value noise in [0, 1) on a `period` x `period` lattice over the unit square, periodic
/// (the texture wraps without a seam), smoothstep-interpolated.
fn periodic_noise(u: f32, v: f32, period: u32, seed: u32) -> f32 {
    let (x, y) = (u * period as f32, v * period as f32);
    let (x0, y0) = (x.floor(), y.floor());
    let s = |t: f32| t * t * (3.0 - 2.0 * t);
    let (fx, fy) = (s(x - x0), s(y - y0));
    let (i, j) = (x0 as u32 % period, y0 as u32 % period);
    let (i1, j1) = ((i + 1) % period, (j + 1) % period);
    let top = lattice(i, j, seed) + (lattice(i1, j, seed) - lattice(i, j, seed)) * fx;
    let bottom = lattice(i, j1, seed) + (lattice(i1, j1, seed) - lattice(i, j1, seed)) * fx;
    top + (bottom - top) * fy
}

/// Pore depth in [0, 1] at texel position (`x`, `y`): at most one round pore per `cell` x
/// `cell` cell (with probability `p`), jittered inside it, of radius 0.15 to 0.3 cells and a
/// smooth (1 - d^2)^2 profile. `cell` divides [`SKIN_SIDE`], so the pattern wraps.
fn pore(x: f32, y: f32, cell: u32, p: f32, seed: u32) -> f32 {
    let c = cell as f32;
    let (cx, cy) = ((x / c).floor(), (y / c).floor());
    let (i, j) = (cx as u32, cy as u32);
    if lattice(i, j, seed) >= p {
        return 0.0;
    }
    let jitter = |k: u32| 0.3 + 0.4 * lattice(i, j, seed.wrapping_add(k));
    let (px, py) = ((cx + jitter(1)) * c, (cy + jitter(2)) * c);
    let radius = c * (0.15 + 0.15 * lattice(i, j, seed.wrapping_add(3)));
    let d2 = ((x - px).powi(2) + (y - py).powi(2)) / (radius * radius);
    if d2 >= 1.0 {
        return 0.0;
    }
    let depth = 0.5 + 0.5 * lattice(i, j, seed.wrapping_add(4));
    (1.0 - d2).powi(2) * depth
}

/// One texel of [`skin`] at texel position (`x`, `y`) (row `y` from the top).
fn skin_texel(x: u32, y: u32) -> Vec3 {
    let side = SKIN_SIDE as f32;
    let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
    let (u, v) = (fx / side, fy / side);
    // Low-frequency tone (blotches a few centimetres across on a face), a fine mottle, and
    // an independent redness field (flushed cheeks, capillaries).
    let tone = (periodic_noise(u, v, 4, 11)
        + 0.5 * periodic_noise(u, v, 9, 12)
        + 0.25 * periodic_noise(u, v, 19, 13))
        / 1.75;
    let mottle = periodic_noise(u, v, 128, 14);
    let red = (periodic_noise(u, v, 5, 15) + 0.5 * periodic_noise(u, v, 23, 16)) / 1.5;
    // A light skin tone in linear RGB (sRGB about 205, 160, 138).
    let base = Vec3::new(0.61, 0.35, 0.25);
    let bright = 1.0 + 0.18 * (tone - 0.5) + 0.08 * (mottle - 0.5);
    let r = 2.0 * (red - 0.5);
    let tint = Vec3::new(1.0 + 0.08 * r, 1.0 - 0.07 * r, 1.0 - 0.05 * r);
    // Pores at three scales: dense fine ones, sparser larger ones.
    let pores = pore(fx, fy, 4, 0.35, 21)
        .max(pore(fx, fy, 8, 0.3, 22))
        .max(pore(fx, fy, 16, 0.12, 23));
    let dark = Vec3::new(1.0 - 0.38 * pores, 1.0 - 0.45 * pores, 1.0 - 0.48 * pores);
    base * bright * tint * dark
}

/// The built-in skin albedo (`--texture skin`): [`SKIN_SIDE`]^2 linear RGB texels of a light
/// skin tone with low-frequency brightness and redness variation, a fine mottle and pores (small
/// dark dots at three scales). Procedural and deterministic (PCG-hashed value noise, fixed
/// seeds): the same texels on every machine and run. Periodic, so it wraps without a seam.
/// Texels lie in [0.1, 0.75]; red > green > blue everywhere.
pub fn skin() -> Texture {
    use rayon::prelude::*;
    let n = SKIN_SIDE;
    let texels = (0..n * n)
        .into_par_iter()
        .map(|k| skin_texel(k % n, k / n))
        .collect();
    Texture::from_linear(n, n, texels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skin_is_deterministic_in_range_and_varied() {
        let t0 = std::time::Instant::now();
        let a = skin();
        let secs = t0.elapsed().as_secs_f64();
        let b = skin();
        assert_eq!((a.width, a.height), (SKIN_SIDE, SKIN_SIDE));
        assert!(a.texels() == b.texels(), "the same texels every time");
        let mut lo = Vec3::splat(f32::MAX);
        let mut hi = Vec3::splat(f32::MIN);
        let mut mean = Vec3::ZERO;
        for &t in a.texels() {
            assert!(t.is_finite() && t.x > t.y && t.y > t.z, "{t}");
            lo = lo.min(t);
            hi = hi.max(t);
            mean += t;
        }
        mean /= a.texels().len() as f32;
        assert!(
            lo.min_element() >= 0.1 && hi.max_element() <= 0.75,
            "{lo} {hi}"
        );
        assert!(
            (mean - Vec3::new(0.6, 0.34, 0.24)).abs().max_element() < 0.04,
            "{mean}"
        );
        // Pores: a visible share of texels are well darker than their surroundings' tone.
        let lum = |t: Vec3| t.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        let dark = a
            .texels()
            .iter()
            .filter(|&&t| lum(t) < 0.8 * lum(mean))
            .count() as f64
            / a.texels().len() as f64;
        assert!((0.01..0.3).contains(&dark), "pore share {dark}");
        // Wraps without a seam: the first and last columns differ like neighbours do.
        let n = SKIN_SIDE as usize;
        let seam: f32 = (0..n)
            .map(|y| lum(a.texels()[y * n]) - lum(a.texels()[y * n + n - 1]))
            .map(f32::abs)
            .sum::<f32>()
            / n as f32;
        let inner: f32 = (0..n)
            .map(|y| lum(a.texels()[y * n + 1]) - lum(a.texels()[y * n]))
            .map(f32::abs)
            .sum::<f32>()
            / n as f32;
        assert!(seam < 2.0 * inner + 1e-3, "seam {seam} vs {inner}");
        // Cheap: well under a second even in a debug build on 2 busy cores.
        assert!(secs < 5.0, "{secs} s");
    }
}
