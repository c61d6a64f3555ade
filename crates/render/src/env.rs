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
//! strategies. The renderer's light strategy draws one direction per pass from the map or,
//! where the map has a compact bright part (a sun), one from the bright texels
//! ([`EnvMap::sample_bright`]) and one from the rest ([`EnvMap::sample_rest`]), whose
//! densities do not overlap ([`EnvMap::light_pdf`]). It combines them with cosine-weighted
//! hemisphere samples for the diffuse term (balance heuristic), and with the specular BRDF's
//! own (`fastbrdf::Brdf::sample`) for the specular term (power heuristic,
//! [`power_weight_over_pdf`]).

use crate::error::{RenderError, Result};
pub use crate::hash::pcg;
use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;
use std::sync::Arc;

mod bright;
pub(crate) mod sobol;
mod trig;
pub mod wave;
pub use bright::BrightTables;
pub use bright::{BRIGHT_FACTOR, BRIGHT_MAX_TEXELS, BRIGHT_MIN_SHARE};
use bright::{Bright, bright_part, cdf_of};

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
    /// The bright texels as a strategy of their own ([`EnvMap::sample_bright`]), where the map
    /// has a compact bright part (a sun); `None` otherwise or when turned off
    /// ([`EnvMap::without_bright`]).
    bright: Option<Bright>,
}

/// What a draw reads: the whole map, or the rest without the bright texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    Whole,
    Rest,
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
        let row_sums: Vec<f64> = weights.chunks_exact(w).map(|r| r.iter().sum()).collect();
        let total: f64 = row_sums.iter().sum();
        let marginal = cdf_of(&row_sums);
        let mut conditional: Vec<f32> = weights.chunks_exact(w).flat_map(cdf_of).collect();
        // The bright part, and the rest's rows after the map's.
        let bright = if black {
            None
        } else {
            bright_part(&texels, &weights, total, w, &mut conditional)
        };
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
            bright,
        })
    }

    /// The map without its bright strategy: the renderer then draws one direction per pass
    /// from the whole map, as the GPU renderer does (its Lambert pictures equal the CPU's to
    /// rounding only so; `fastbrdf-gpu`'s `tests/render_env.rs`).
    pub fn without_bright(mut self) -> Self {
        let (w, h) = (self.width as usize, self.height as usize);
        self.bright = None;
        self.conditional.truncate(h * (w + 1));
        self.conditional_guide.truncate(h * (row_guide(w) + 1));
        self.row_total.truncate(h);
        self
    }

    /// Whether the map has a bright strategy ([`EnvMap::sample_bright`]): how many texels,
    /// and their share of the map's weight.
    pub fn bright(&self) -> Option<(usize, f32)> {
        self.bright
            .as_ref()
            .map(|b| (b.texels.len(), 1.0 / b.ratio))
    }

    /// The bright strategy's tables, as a GPU twin reads them (`fastbrdf_gpu::render::env`,
    /// `shaders/env.wgsl`): `None` without a bright part.
    pub fn bright_tables(&self) -> Option<BrightTables<'_>> {
        let b = self.bright.as_ref()?;
        let rows = self.height as usize * (self.width as usize + 1);
        Some(BrightTables {
            texels: &b.texels,
            cdf: &b.cdf,
            rest_marginal: &b.rest_marginal,
            rest_row: &b.rest_row,
            rest_rows: &self.conditional[rows..],
            axis: b.axis,
            below: b.below,
        })
    }

    /// A direction drawn from the bright texels alone, in proportion to their weight, by two
    /// uniform numbers in [0, 1): (unit direction, radiance, this strategy's density there);
    /// `None` without a bright part. Uniform within the texel in longitude and latitude, as
    /// [`EnvMap::sample`]: its density is the map's times the bright part's `ratio` (one over
    /// its share of the weight).
    pub fn sample_bright(&self, u1: f32, u2: f32) -> Option<(Vec3, Vec3, f32)> {
        let b = self.bright.as_ref()?;
        let u = u1.clamp(0.0, 1.0 - f32::EPSILON);
        let (k, fr) = bin_of(&b.cdf, b.cdf.partition_point(|&c| c <= u), u);
        let i = b.texels[k] as usize;
        let w = self.width as usize;
        let (d, rgb, pdf) = self.drawn(i / w, fr, i % w, u2.clamp(0.0, 1.0 - f32::EPSILON));
        Some((d, rgb, pdf * b.ratio))
    }

    /// Whether a surface of shading normal `n` may see a bright texel above its horizon (else
    /// every direction of the bright strategy has a zero cosine there and adds nothing).
    #[inline]
    pub fn bright_faces(&self, n: Vec3) -> bool {
        self.bright
            .as_ref()
            .is_some_and(|b| n.dot(b.axis) > b.below)
    }

    /// The density of the renderer's light strategies together, one draw of each per pass
    /// ([`EnvMap::sample_rest`] and [`EnvMap::sample_bright`], whose texels do not overlap), at
    /// a direction whose look-up gave radiance `rgb` and the whole map's density `pdf`: a
    /// bright texel's (one whose radiance is bright) under the bright strategy, any other's
    /// under the rest's; without a bright part, the map's own.
    #[inline]
    pub fn light_pdf(&self, rgb: Vec3, pdf: f32) -> f32 {
        match &self.bright {
            Some(b) if lum(rgb) > b.threshold => pdf * b.ratio,
            Some(b) => pdf * b.rest_ratio,
            None => pdf,
        }
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
        let rows = self.height as usize * (self.width as usize + 1);
        (&self.marginal, &self.conditional[..rows])
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
        self.draw(Part::Whole, u1, u2)
    }

    /// A direction drawn from the rest of the map, without its bright texels
    /// ([`EnvMap::sample_bright`]; the whole map where it has none), as [`EnvMap::sample`]:
    /// its density is the map's times the rest's ratio (one over its share of the weight), 0
    /// on the bright texels.
    pub fn sample_rest(&self, u1: f32, u2: f32) -> (Vec3, Vec3, f32) {
        self.draw(Part::Rest, u1, u2)
    }

    /// [`EnvMap::sample`] or [`EnvMap::sample_rest`].
    fn draw(&self, part: Part, u1: f32, u2: f32) -> (Vec3, Vec3, f32) {
        let (marginal, guide, rows, scale) = self.part(part);
        let (r, fr) = sample_cdf(marginal, guide, u1);
        let t = rows.map_or(r, |rows| rows[r] as usize);
        let w = self.width as usize;
        let g = row_guide(w) + 1;
        let (c, fc) = sample_cdf(
            &self.conditional[t * (w + 1)..(t + 1) * (w + 1)],
            &self.conditional_guide[t * g..(t + 1) * g],
            u2,
        );
        let (d, rgb, pdf) = self.drawn(r, fr, c, fc);
        (d, rgb, pdf * scale)
    }

    /// The tables a draw from `part` reads: the distribution over rows and its guide, per row
    /// the row of the conditional tables (`None`: the row itself), and the factor from the
    /// map's density to the part's.
    #[inline(always)]
    fn part(&self, part: Part) -> (&[f32], &[u16], Option<&[u32]>, f32) {
        match &self.bright {
            Some(b) if part == Part::Rest => (
                &b.rest_marginal,
                &b.rest_marginal_guide,
                Some(&b.rest_row),
                b.rest_ratio,
            ),
            _ => (&self.marginal, &self.marginal_guide, None, 1.0),
        }
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

/// The power heuristic's weight of a strategy's sample divided by that strategy's density
/// `p`, against another strategy of density `q` there: `p / (p^2 + q^2)`, which multiplies
/// the integrand. Formed from the ratio `q / p`, so that narrow lobes' large densities cannot
/// overflow f32; 0 when `p` is 0 (the sample cannot occur).
pub fn power_weight_over_pdf(p: f32, q: f32) -> f32 {
    if p > 0.0 {
        let r = q / p;
        1.0 / (p * (1.0 + r * r))
    } else {
        0.0
    }
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
pub(crate) mod tests;
