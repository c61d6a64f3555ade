//! Environment light: a latitude-longitude map of radiance (Radiance `.hdr` or OpenEXR, 2:1),
//! a built-in procedural sky or a constant white map, importance-sampled by a piecewise-
//! constant 2D distribution (rows by their sin theta-weighted luminance, then columns).
//!
//! Directions: y up. A direction `d` maps to `u = atan2(d.x, -d.z) / 2 pi + 1/2` (columns, left
//! to right) and `v = acos(d.y) / pi` (rows, top = straight up): the map's centre column lies
//! along -z, behind the default camera's subject. Radiance is constant over a texel (nearest
//! lookup), the same function the sampling distribution is built from, so a sampled texel's
//! contribution has no lookup bias.
//!
//! Multiple importance sampling: [`balance_heuristic`] and [`power_heuristic`] weight two
//! strategies; the renderer combines the map's samples with cosine-weighted hemisphere
//! samples for the diffuse term (balance heuristic), and the map's samples with the specular
//! BRDF's own (`fastbrdf::Brdf::sample`) for the specular term (power heuristic,
//! [`specular_light_weight`] for the map's side).

use crate::error::{RenderError, Result};
pub use crate::hash::pcg;
use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;
use std::sync::Arc;

pub(crate) mod sobol;
mod trig;
pub mod wave;

/// Largest environment map file read: 512 MiB.
pub const MAX_ENV_BYTES: u64 = 512 << 20;
/// Largest environment map width (the height is half of it): 8192 x 4096.
pub const MAX_ENV_WIDTH: u32 = 8192;
/// Largest `--env-samples`.
pub const MAX_ENV_SAMPLES: u32 = 4096;
/// The largest radiance a texel may hold (any channel); a map with a larger one is refused at
/// load, naming the file and the texel.
///
/// Why 1e12. The brightest thing an environment map shows is the Sun: 1.6e9 cd/m^2, so a map
/// in absolute photometric units with the Sun unclipped stays below about 1e10, and captures
/// in relative units are far lower (Poly Haven's unclipped suns read 1e4 to 1e6). 1e12 leaves
/// a factor 100 over the Sun and keeps a path's product, radiance x BRDF x cos / pdf (a
/// measured BRDF is at most 1e8 sr^-1, `fastbrdf::measured::MAX_VALUE`), far below f32's
/// 3.4e38. A map of 3e38 texels (finite in f32) made the render overflow and the error blame
/// the model.
pub const MAX_ENV_RADIANCE: f32 = 1e12;

/// The built-in sky's sun: the direction towards it (the default key light's) and its
/// angular radius in degrees.
pub const SUN_DIR: [f32; 3] = [-0.45, 0.55, 0.7];
pub const SUN_RADIUS_DEG: f32 = 2.0;
/// The sun disc's irradiance at normal incidence (the default key light's intensity).
pub const SUN_IRRADIANCE: f32 = 3.0;

/// An environment light for a scene: the map and the samples per primary hit.
#[derive(Clone, Debug)]
pub struct Environment {
    pub map: Arc<EnvMap>,
    /// Light samples per primary hit (each a map sample and a cosine sample), taken in as
    /// many progressive passes.
    pub samples: u32,
}

/// A latitude-longitude radiance map with its sampling distribution.
#[derive(Clone, Debug)]
pub struct EnvMap {
    pub width: u32,
    pub height: u32,
    /// Per texel (row-major), its radiance and its probability mass (the masses sum to 1),
    /// side by side: a look-up or a draw reads one 16-byte cell (two arrays cost two cache
    /// misses per sample on a large map).
    cells: Vec<Cell>,
    /// Cumulative distribution over rows (height + 1 entries, 0 to 1).
    marginal: Vec<f32>,
    /// Per row, the cumulative distribution over its columns (width + 1 entries each).
    conditional: Vec<f32>,
    /// Guide tables ([`guide_of`]) of `marginal` (four buckets per row: 32 KB at most, in
    /// cache, and the search after it reads one or two entries) and of each row of
    /// `conditional` ([`row_guide`] buckets per row, about one per 4 columns, so that the
    /// search after the guide reads one or two cache lines of the row: on a large map the
    /// rows are not in cache, and each line a search reads is a miss on the draw's path).
    /// Entries are u16: a map is at most [`MAX_ENV_WIDTH`] wide.
    marginal_guide: Vec<u16>,
    conditional_guide: Vec<u16>,
    /// Per row, the last entry of its cumulative distribution (1, or 0 for a black row): a
    /// draw scales its uniform number by it before it has read the row ([`wave`]).
    row_total: Vec<f32>,
}

/// A texel's radiance and probability mass.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct Cell {
    rgb: Vec3,
    mass: f32,
}

/// Buckets of the guide table of a row `w` texels wide: one per 4 columns (at least one).
fn row_guide(w: usize) -> usize {
    (w / 4).max(1)
}

fn lum(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The map position (u, v) in [0, 1]^2 of unit direction `d` (the fast `atan2` and `acos`
/// of [`trig`]: within a few 1e-7 rad of f64's).
#[inline(always)]
pub fn dir_to_uv(d: Vec3) -> (f32, f32) {
    let u = trig::atan2(d.x, -d.z) / (2.0 * PI) + 0.5;
    let v = trig::acos(d.y) / PI;
    (u, v)
}

/// The unit direction at map position (u, v), and sin theta ([`trig::sin_cos`]).
#[inline(always)]
pub fn uv_to_dir(u: f32, v: f32) -> (Vec3, f32) {
    let (phi, theta) = ((u - 0.5) * 2.0 * PI, v * PI);
    let (st, ct) = trig::sin_cos(theta);
    let (sp, cp) = trig::sin_cos(phi);
    (Vec3::new(st * sp, ct, -st * cp), st)
}

/// The index in `cdf` (n + 1 entries from 0 to 1) of the bin holding `u`, and where in it.
/// `guide` ([`guide_of`] of `cdf`) narrows the binary search to the few entries around `u`:
/// the same index as a search of the whole table, to the bit.
fn sample_cdf(cdf: &[f32], guide: &[u16], u: f32) -> (usize, f32) {
    let n = cdf.len() - 1;
    let u = u.clamp(0.0, 1.0 - f32::EPSILON) * cdf[n];
    bin_of(cdf, search(cdf, guide, u), u)
}

/// The bin of `cdf` and the place in it of `u` (already scaled by the table's total) from its
/// partition point `p` ([`search`]): [`sample_cdf`]'s second half, shared with the staged
/// draws of [`wave`].
#[inline(always)]
fn bin_of(cdf: &[f32], p: usize, u: f32) -> (usize, f32) {
    let n = cdf.len() - 1;
    let i = (p.max(1) - 1).min(n - 1);
    let width = cdf[i + 1] - cdf[i];
    let frac = if width > 0.0 {
        ((u - cdf[i]) / width).clamp(0.0, 1.0 - f32::EPSILON)
    } else {
        0.5
    };
    (i, frac)
}

/// `cdf.partition_point(|&c| c <= u)`, searched only between the guide entries of the bucket
/// `u` falls in and its neighbours.
///
/// Why a guide table (Chen and Asau 1974), not an alias table: a binary search of the sky's
/// 512 rows and 1024 columns took 28% of an environment render (19 unpredictable branches per
/// sample). An alias table draws in O(1) too, but it maps neighbouring `u` to unrelated texels,
/// which would undo the stratification of the Sobol sampler; inverting the CDF keeps it, and
/// the guide makes the inversion about as cheap.
#[inline]
fn search(cdf: &[f32], guide: &[u16], u: f32) -> usize {
    let total = cdf[cdf.len() - 1];
    match bucket(total, guide.len() - 1, u) {
        None => cdf.partition_point(|&c| c <= u),
        Some(k) => {
            let (lo, hi) = guide_range(guide, k);
            lo + cdf[lo..hi].partition_point(|&c| c <= u)
        }
    }
}

/// The guide bucket of `u` (scaled by `total`, the table's last entry) in a guide of `g`
/// buckets, or none where the table is empty (a total of 0) or has no guide: search it all.
#[inline(always)]
fn bucket(total: f32, g: usize, u: f32) -> Option<usize> {
    if total.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || g == 0 {
        return None;
    }
    Some(((u as f64 / total as f64) * g as f64) as usize)
}

/// The range of a table holding the partition point of a `u` in bucket `k`: guide[k] = the
/// partition point of k / g x total, and `u` lies in bucket k up to rounding, so the buckets
/// k - 1 to k + 1 hold its partition point for certain.
#[inline(always)]
fn guide_range(guide: &[u16], k: usize) -> (usize, usize) {
    let g = guide.len() - 1;
    let lo = guide[k.saturating_sub(1).min(g)] as usize;
    let hi = guide[(k + 2).min(g)] as usize;
    (lo, hi)
}

/// The guide table of `cdf` (n + 1 entries, non-decreasing) with `g` buckets: g + 1 entries,
/// entry k the partition point of `k / g x cdf[n]` (compared in f64, so that each entry
/// bounds the f32 searches of its bucket).
fn guide_of(cdf: &[f32], g: usize) -> Vec<u16> {
    let n = cdf.len() - 1;
    let total = cdf[n] as f64;
    (0..=g)
        .map(|k| cdf.partition_point(|&c| c as f64 <= k as f64 / g as f64 * total) as u16)
        .collect()
}

impl EnvMap {
    /// A map from linear texels (row-major, top row = straight up). Errors name the problem:
    /// not 2:1, too large, a NaN, infinite, negative or implausibly bright (above
    /// [`MAX_ENV_RADIANCE`]) texel.
    pub fn from_texels(
        width: u32,
        height: u32,
        texels: Vec<Vec3>,
    ) -> std::result::Result<Self, String> {
        check_env_size(width, height)?;
        assert_eq!(texels.len(), (width * height) as usize, "texel count");
        if let Some(i) = texels.iter().position(|t| {
            !t.is_finite() || t.min_element() < 0.0 || t.max_element() > MAX_ENV_RADIANCE
        }) {
            let t = texels[i];
            let what = if t.is_nan() {
                "NaN"
            } else if !t.is_finite() {
                "infinite"
            } else if t.min_element() < 0.0 {
                "negative"
            } else {
                "implausibly bright (above 1e12, a hundred times the Sun's luminance)"
            };
            return Err(format!(
                "texel ({}, {}) is {what} ({}, {}, {}): an environment map holds finite, non-negative radiance up to {MAX_ENV_RADIANCE:e}",
                i as u32 % width,
                i as u32 / width,
                t.x,
                t.y,
                t.z
            ));
        }
        let (w, h) = (width as usize, height as usize);
        // Weights: luminance times sin theta at the row's centre (a texel's solid angle); a
        // black map falls back to sin theta alone, so sampling stays defined.
        let black = texels.iter().all(|t| lum(*t) <= 0.0);
        let mut weights = vec![0.0f64; w * h];
        for r in 0..h {
            let st = (PI * (r as f32 + 0.5) / h as f32).sin() as f64;
            for c in 0..w {
                let l = if black {
                    1.0
                } else {
                    lum(texels[r * w + c]) as f64
                };
                weights[r * w + c] = l * st;
            }
        }
        let total: f64 = weights.iter().sum();
        let mut marginal = Vec::with_capacity(h + 1);
        let mut conditional = Vec::with_capacity(h * (w + 1));
        let mut acc = 0.0f64;
        marginal.push(0.0);
        for r in 0..h {
            let row = &weights[r * w..(r + 1) * w];
            let sum: f64 = row.iter().sum();
            let mut a = 0.0f64;
            conditional.push(0.0);
            for &x in row {
                a += x;
                conditional.push(if sum > 0.0 { (a / sum) as f32 } else { 0.0 });
            }
            acc += sum;
            marginal.push((acc / total) as f32);
        }
        let cells = texels
            .iter()
            .zip(&weights)
            .map(|(&rgb, x)| Cell {
                rgb,
                mass: (x / total) as f32,
            })
            .collect();
        let marginal_guide = guide_of(&marginal, 4 * h);
        let conditional_guide = conditional
            .chunks_exact(w + 1)
            .flat_map(|row| guide_of(row, row_guide(w)))
            .collect();
        let row_total = conditional.chunks_exact(w + 1).map(|r| r[w]).collect();
        Ok(Self {
            width,
            height,
            cells,
            marginal,
            conditional,
            marginal_guide,
            conditional_guide,
            row_total,
        })
    }

    /// Per texel (row-major), its radiance and probability mass (the masses sum to 1): the
    /// distribution [`EnvMap::sample`] draws from, for a GPU twin (`fastbrdf_gpu::render::env`).
    pub fn texels(&self) -> impl Iterator<Item = (Vec3, f32)> + '_ {
        self.cells.iter().map(|c| (c.rgb, c.mass))
    }

    /// The sampling tables: the cumulative distribution over rows (height + 1 entries), and
    /// per row the one over its columns (width + 1 entries each), as [`EnvMap::sample`] reads
    /// them.
    pub fn tables(&self) -> (&[f32], &[f32]) {
        (&self.marginal, &self.conditional)
    }

    /// A constant map of radiance `c` (the furnace: `c` = 1).
    pub fn constant(c: Vec3) -> Self {
        Self::from_texels(16, 8, vec![c; 128]).expect("a valid constant map")
    }

    /// The built-in sky, 1024 x 512, evaluated at texel centres. Above the horizon (y >= 0)
    /// `mix(horizon, zenith, sqrt(y))` with horizon (0.85, 0.9, 1.0) and zenith
    /// (0.2, 0.35, 0.75); below it a ground of (0.2, 0.18, 0.16); plus a sun disc towards
    /// [`SUN_DIR`] of angular radius [`SUN_RADIUS_DEG`] and radiance (1, 0.95, 0.85) x
    /// [`SUN_IRRADIANCE`] / (its solid angle 2 pi (1 - cos radius)).
    pub fn sky() -> Self {
        let (w, h) = (1024u32, 512u32);
        let sun = Vec3::from(SUN_DIR).normalize();
        let cos_r = SUN_RADIUS_DEG.to_radians().cos();
        let sun_l = Vec3::new(1.0, 0.95, 0.85) * (SUN_IRRADIANCE / (2.0 * PI * (1.0 - cos_r)));
        let (horizon, zenith) = (Vec3::new(0.85, 0.9, 1.0), Vec3::new(0.2, 0.35, 0.75));
        let ground = Vec3::new(0.2, 0.18, 0.16);
        let mut texels = Vec::with_capacity((w * h) as usize);
        for r in 0..h {
            for c in 0..w {
                let (d, _) = uv_to_dir((c as f32 + 0.5) / w as f32, (r as f32 + 0.5) / h as f32);
                let mut l = if d.y >= 0.0 {
                    horizon.lerp(zenith, d.y.sqrt())
                } else {
                    ground
                };
                if d.dot(sun) >= cos_r {
                    l += sun_l;
                }
                texels.push(l);
            }
        }
        Self::from_texels(w, h, texels).expect("a valid sky")
    }

    /// `sky`, `white` (a constant map of 1) or a file (Radiance `.hdr` or OpenEXR).
    pub fn from_spec(spec: &str) -> Result<Self> {
        match spec {
            "sky" => Ok(Self::sky()),
            "white" => Ok(Self::constant(Vec3::ONE)),
            _ => Self::load(Path::new(spec)),
        }
    }

    /// Loads a Radiance `.hdr` or OpenEXR map: read once (at most [`MAX_ENV_BYTES`]), its
    /// declared size checked (2:1, at most [`MAX_ENV_WIDTH`] wide) before anything is
    /// decoded, every texel finite and non-negative.
    pub fn load(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let bad = |m: String| RenderError::Input {
            file: file.clone(),
            line: None,
            message: m,
        };
        let accept = |format: Option<image::ImageFormat>| match format {
            Some(image::ImageFormat::Hdr | image::ImageFormat::OpenExr) => Ok(()),
            other => {
                let found = other.map_or("not an image format this reads".to_string(), |f| {
                    format!("{f:?}")
                });
                Err(format!(
                    "not an HDR environment map (a Radiance .hdr or OpenEXR file is needed; found {found})"
                ))
            }
        };
        let img = crate::decode::decode_limited(
            path,
            MAX_ENV_BYTES,
            "an environment map",
            "the environment map",
            accept,
            check_env_size,
            (
                MAX_ENV_WIDTH,
                MAX_ENV_WIDTH / 2,
                u64::from(MAX_ENV_WIDTH) * u64::from(MAX_ENV_WIDTH / 2) * 16,
            ),
        )?
        .to_rgb32f();
        let (w, h) = img.dimensions();
        let texels = img.pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        Self::from_texels(w, h, texels).map_err(bad)
    }

    /// The texel at map position (u, v), in i32 (a map is at most [`MAX_ENV_WIDTH`] wide; a
    /// NaN goes to 0 as it would in usize) and by `max` and `min` rather than `clamp` (whose
    /// check of its bounds kept the loops of [`wave`] from vectorising).
    #[inline(always)]
    fn texel(&self, u: f32, v: f32) -> usize {
        let (w, h) = (self.width as i32, self.height as i32);
        let c = ((u * self.width as f32) as i32).max(0).min(w - 1);
        let r = ((v * self.height as f32) as i32).max(0).min(h - 1);
        (r * w + c) as usize
    }

    /// The radiance arriving from unit direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (u, v) = dir_to_uv(d);
        self.cells[self.texel(u, v)].rgb
    }

    /// The solid-angle density of [`EnvMap::sample`] at unit direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.lookup(d).1
    }

    /// The radiance from unit direction `d` and [`EnvMap::sample`]'s density there, from one
    /// map position (one `atan2` and one `acos`).
    pub fn lookup(&self, d: Vec3) -> (Vec3, f32) {
        let (i, st) = self.texel_of(d);
        self.cell_at(i, st)
    }

    /// The texel of unit direction `d` and its sin theta (`sqrt(1 - y^2)`, without a sin of
    /// the acos): [`EnvMap::lookup`]'s first half.
    #[inline(always)]
    fn texel_of(&self, d: Vec3) -> (usize, f32) {
        let (u, v) = dir_to_uv(d);
        (self.texel(u, v), (1.0 - d.y * d.y).max(0.0).sqrt())
    }

    /// Texel `i`'s radiance and the solid-angle density there, `sin theta` = `st` (density 0
    /// at the poles): the second half of [`EnvMap::lookup`] and [`EnvMap::sample`].
    #[inline(always)]
    fn cell_at(&self, i: usize, st: f32) -> (Vec3, f32) {
        let Cell { rgb, mass } = self.cells[i];
        if st <= 0.0 {
            return (rgb, 0.0);
        }
        let m = mass * (self.width * self.height) as f32;
        (rgb, m / (2.0 * PI * PI * st))
    }

    /// A direction drawn from the map's distribution by two uniform numbers in [0, 1):
    /// (unit direction, radiance, solid-angle density); density 0 at the poles (skip it).
    pub fn sample(&self, u1: f32, u2: f32) -> (Vec3, Vec3, f32) {
        let (r, fr) = sample_cdf(&self.marginal, &self.marginal_guide, u1);
        let w = self.width as usize;
        let g = row_guide(w) + 1;
        let (c, fc) = sample_cdf(
            &self.conditional[r * (w + 1)..(r + 1) * (w + 1)],
            &self.conditional_guide[r * g..(r + 1) * g],
            u2,
        );
        self.drawn(r, fr, c, fc)
    }

    /// The draw of texel (column `c`, row `r`) at (`fc`, `fr`) within it: [`EnvMap::sample`]'s
    /// last step, shared with the staged draws of [`wave`].
    #[inline(always)]
    fn drawn(&self, r: usize, fr: f32, c: usize, fc: f32) -> (Vec3, Vec3, f32) {
        let (d, st) = self.drawn_dir(r, fr, c, fc);
        let (rgb, pdf) = self.cell_at(r * self.width as usize + c, st);
        (d, rgb, pdf)
    }

    /// The direction and sin theta of [`EnvMap::drawn`].
    #[inline(always)]
    fn drawn_dir(&self, r: usize, fr: f32, c: usize, fc: f32) -> (Vec3, f32) {
        let u = (c as f32 + fc) / self.width as f32;
        let v = (r as f32 + fr) / self.height as f32;
        uv_to_dir(u, v)
    }
}

/// Checks an environment map's declared size: 2:1, at most [`MAX_ENV_WIDTH`] wide.
pub fn check_env_size(w: u32, h: u32) -> std::result::Result<(), String> {
    if w == 0 || h == 0 {
        return Err(format!("the environment map is empty ({w}x{h})"));
    }
    if w > MAX_ENV_WIDTH || h > MAX_ENV_WIDTH / 2 {
        return Err(format!(
            "the environment map declares {w}x{h} pixels: at most {MAX_ENV_WIDTH}x{} are accepted (nothing was decoded)",
            MAX_ENV_WIDTH / 2
        ));
    }
    if w != 2 * h {
        return Err(format!(
            "the environment map is {w}x{h}: a latitude-longitude map is twice as wide as high (2:1)"
        ));
    }
    Ok(())
}

/// The balance heuristic: the weight of strategy a's sample, `pa / (pa + pb)`.
pub fn balance_heuristic(pa: f32, pb: f32) -> f32 {
    if pa + pb > 0.0 { pa / (pa + pb) } else { 0.0 }
}

/// The power heuristic (exponent 2): `pa^2 / (pa^2 + pb^2)`, formed from the ratio of the
/// smaller density to the larger so that narrow lobes' large densities cannot overflow f32.
pub fn power_heuristic(pa: f32, pb: f32) -> f32 {
    if pa + pb > 0.0 {
        if pa >= pb {
            let r = pb / pa;
            1.0 / (1.0 + r * r)
        } else {
            let r = pa / pb;
            r * r / (1.0 + r * r)
        }
    } else {
        0.0
    }
}

/// The MIS weight of a map sample for the specular term, whose density is `pdf_light`:
/// `power_heuristic(pdf_light, brdf_pdf)` against the BRDF's own sample of the same pass (the
/// renderer's environment pass, `render.rs`), or 1 when no BRDF density is given (a map-only
/// estimate).
pub fn specular_light_weight(pdf_light: f32, brdf_pdf: Option<f32>) -> f32 {
    brdf_pdf.map_or(1.0, |b| power_heuristic(pdf_light, b))
}

/// A small deterministic generator (PCG hash, 24-bit uniforms).
#[derive(Clone, Copy, Debug)]
pub struct Rng(u32);

impl Rng {
    /// The generator of sample `id` in pass `pass`.
    pub fn new(id: u32, pass: u32) -> Self {
        Self(pcg(id ^ pcg(pass.wrapping_add(0x9e37_79b9))))
    }

    /// A uniform number in [0, 1).
    pub fn uniform(&mut self) -> f32 {
        self.0 = pcg(self.0);
        (self.0 >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// A cosine-weighted direction about unit normal `n` (density `cos / pi`).
#[inline(always)]
pub fn cosine_sample(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let (t, b) = n.any_orthonormal_pair();
    let r = u1.sqrt();
    let (s, c) = trig::sin_cos(2.0 * PI * u2);
    (t * (r * c) + b * (r * s) + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A 64 x 32 test map of grey texels spread over four decades, with every fifth row
    /// black (empty rows of the sampling tables), drawn by `Rng::new(id, pass)`.
    pub(crate) fn rough_map(id: u32, pass: u32) -> EnvMap {
        let mut rng = Rng::new(id, pass);
        let texels = (0..64 * 32)
            .map(|i| {
                let x = rng.uniform();
                if i / 64 % 5 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::splat(x * x * x * 100.0)
                }
            })
            .collect();
        EnvMap::from_texels(64, 32, texels).unwrap()
    }

    #[test]
    fn directions_and_map_positions_invert() {
        for &(u, v) in &[(0.1f32, 0.2f32), (0.5, 0.5), (0.9, 0.8), (0.3, 0.05)] {
            let (d, _) = uv_to_dir(u, v);
            let (u2, v2) = dir_to_uv(d);
            assert!((u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5, "{u},{v}");
        }
        assert!((uv_to_dir(0.5, 0.5).0 - Vec3::NEG_Z).length() < 1e-6);
        assert!((uv_to_dir(0.5, 0.0).0 - Vec3::Y).length() < 1e-6);
    }

    /// The density integrates to 1 over the sphere and matches what `sample` returns.
    #[test]
    fn the_sampling_density_is_normalised_and_consistent() {
        let map = EnvMap::sky();
        let n = 400;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..2 * n {
                let (u, v) = (
                    (j as f32 + 0.5) / (2 * n) as f32,
                    (i as f32 + 0.5) / n as f32,
                );
                let (d, st) = uv_to_dir(u, v);
                let dw = (2.0 * PI / (2 * n) as f32) * (PI / n as f32) * st;
                sum += (map.pdf(d) * dw) as f64;
            }
        }
        assert!((sum - 1.0).abs() < 0.02, "{sum}");
        let mut rng = Rng::new(7, 0);
        for _ in 0..1000 {
            let (d, l, p) = map.sample(rng.uniform(), rng.uniform());
            if p > 0.0 {
                assert!((map.pdf(d) - p).abs() <= 1e-3 * p, "{} vs {p}", map.pdf(d));
                assert_eq!(map.radiance(d), l);
            }
        }
    }

    /// Toy MIS: integral of x^2 over [0, 1] (1/3) from a uniform strategy and a linear one
    /// (density 2x), one sample of each per estimate, by the balance and power heuristics:
    /// the weights sum to 1 and the estimate is unbiased.
    #[test]
    fn mis_heuristics_combine_two_strategies_without_bias() {
        for h in [balance_heuristic, power_heuristic] {
            let mut rng = Rng::new(1, 2);
            let n = 200_000;
            let mut sum = 0.0f64;
            for _ in 0..n {
                let xa = rng.uniform();
                let xb = rng.uniform().sqrt();
                let (pa_a, pb_a) = (1.0, 2.0 * xa);
                let (pa_b, pb_b) = (1.0, 2.0 * xb);
                assert!((h(pa_a, pb_a) + h(pb_a, pa_a) - 1.0).abs() < 1e-6);
                let fa = xa * xa * h(pa_a, pb_a) / pa_a;
                let fb = if pb_b > 0.0 {
                    xb * xb * h(pb_b, pa_b) / pb_b
                } else {
                    0.0
                };
                sum += (fa + fb) as f64;
            }
            let est = sum / n as f64;
            assert!((est - 1.0 / 3.0).abs() < 3e-3, "{est}");
        }
        // Narrow lobes' densities: no overflow (squares of 1e20 and 1e30 are infinite in f32).
        assert_eq!(power_heuristic(1e30, 1e20), 1.0);
        assert!(power_heuristic(1e20, 1e30) < 1e-19);
        assert!((power_heuristic(3e25, 3e25) - 0.5).abs() < 1e-7);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(specular_light_weight(2.0, None), 1.0);
        assert!((specular_light_weight(1.0, Some(1.0)) - 0.5).abs() < 1e-7);
    }

    /// The guided search finds the index a search of the whole table finds, to the bit, on
    /// the sky (a tiny bright sun: long flat stretches and a steep step), a random map and a
    /// map with black rows, for uniform numbers everywhere including the ends.
    #[test]
    fn the_guide_tables_change_no_sample() {
        let plain = |cdf: &[f32], u: f32| {
            let n = cdf.len() - 1;
            let u = u.clamp(0.0, 1.0 - f32::EPSILON) * cdf[n];
            cdf.partition_point(|&c| c <= u)
        };
        let mut rng = Rng::new(3, 2);
        for map in [EnvMap::sky(), rough_map(3, 1)] {
            let w = map.width as usize;
            let mut tables = vec![(&map.marginal[..], &map.marginal_guide[..])];
            let g = row_guide(w) + 1;
            for r in (0..map.height as usize).step_by(7) {
                tables.push((
                    &map.conditional[r * (w + 1)..(r + 1) * (w + 1)],
                    &map.conditional_guide[r * g..(r + 1) * g],
                ));
            }
            for (cdf, guide) in tables {
                let mut us: Vec<f32> = (0..20_000).map(|_| rng.uniform()).collect();
                us.extend([0.0, 1.0 - f32::EPSILON, 0.5, 1e-9]);
                us.extend(cdf.iter().copied()); // bin edges
                for u in us {
                    let n = cdf.len() - 1;
                    let uu = u.clamp(0.0, 1.0 - f32::EPSILON) * cdf[n];
                    assert_eq!(search(cdf, guide, uu), plain(cdf, u), "u = {u}");
                }
            }
        }
    }

    #[test]
    fn bad_maps_are_refused() {
        assert!(
            EnvMap::from_texels(4, 4, vec![Vec3::ONE; 16])
                .unwrap_err()
                .contains("2:1")
        );
        let mut t = vec![Vec3::ONE; 8];
        t[5] = Vec3::new(0.0, f32::NAN, 0.0);
        assert!(
            EnvMap::from_texels(4, 2, t.clone())
                .unwrap_err()
                .contains("NaN")
        );
        t[5] = Vec3::new(-1.0, 0.0, 0.0);
        assert!(
            EnvMap::from_texels(4, 2, t.clone())
                .unwrap_err()
                .contains("negative")
        );
        t[5] = Vec3::new(f32::INFINITY, 0.0, 0.0);
        assert!(
            EnvMap::from_texels(4, 2, t.clone())
                .unwrap_err()
                .contains("infinite")
        );
        // Finite in f32 but no radiance a map can hold (issue 27: 3e38 overflowed the render,
        // whose error blamed the model); the bound itself is accepted.
        t[5] = Vec3::new(1.0, 3e38, 1.0);
        let e = EnvMap::from_texels(4, 2, t.clone()).unwrap_err();
        assert!(
            e.contains("implausibly bright") && e.contains("(1, 1)"),
            "{e}"
        );
        t[5] = Vec3::splat(MAX_ENV_RADIANCE);
        assert!(EnvMap::from_texels(4, 2, t).is_ok());
        assert!(check_env_size(16384, 8192).unwrap_err().contains("at most"));
        // A black map still samples (sin theta alone).
        let m = EnvMap::from_texels(4, 2, vec![Vec3::ZERO; 8]).unwrap();
        assert!(m.sample(0.3, 0.6).2 > 0.0);
    }
}
