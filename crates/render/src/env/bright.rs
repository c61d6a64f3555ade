//! A map's bright texels (a sun) as a light strategy of its own, and the rest of the map
//! without them: how they are chosen and the tables that draw them.

use super::{guide_of, lum, uv_to_dir};
use glam::Vec3;
use std::f32::consts::PI;

/// A map's bright texels (luminance above `threshold`), drawn in proportion to their weight
/// (luminance times sin theta, as the whole map's distribution weighs them), and the rest of the
/// map: the renderer's two light strategies, one direction of each per pass.
///
/// Why split. The built-in sky's sun is 39% of its weight in 122 texels: drawn from the whole
/// map, the number of a pixel's draws that hit it is what fluctuates (half the sky scenes'
/// error). One draw from the sun and one from the rest each pass, the sun's share is exact.
#[derive(Clone, Debug)]
pub(super) struct Bright {
    pub(super) threshold: f32,
    /// The whole map's weight over the bright texels' (one over their share): under this
    /// strategy a bright texel's density is the map's density there times `ratio` ...
    pub(super) ratio: f32,
    /// ... and under the rest's, a texel's that is not bright times `rest_ratio` (one over
    /// the rest's share).
    pub(super) rest_ratio: f32,
    /// The bright texels (row-major indices) and the cumulative distribution of their weights
    /// (one more entry, 0 to 1).
    pub(super) texels: Vec<u32>,
    pub(super) cdf: Vec<f32>,
    /// The rest's distribution over rows (height + 1 entries) with its guide, and per row the
    /// row of `EnvMap::conditional` holding its distribution over columns: the row itself, or
    /// for a row holding bright texels one appended after the map's rows without them.
    pub(super) rest_marginal: Vec<f32>,
    pub(super) rest_marginal_guide: Vec<u16>,
    pub(super) rest_row: Vec<u32>,
    /// A cone holding every bright texel: its axis and `-sin` of its half-angle (a surface
    /// whose normal has `n . axis <= below` sees none of them above its horizon).
    pub(super) axis: Vec3,
    pub(super) below: f32,
}

/// A map's bright strategy as plain tables ([`super::EnvMap::bright_tables`]), for a GPU twin
/// of [`super::EnvMap::sample_bright`] and [`super::EnvMap::sample_rest`].
#[derive(Clone, Copy, Debug)]
pub struct BrightTables<'a> {
    /// The bright texels (row-major indices) and the cumulative distribution of their weights
    /// (one more entry, 0 to 1), drawn without scaling the uniform number by its last entry.
    pub texels: &'a [u32],
    pub cdf: &'a [f32],
    /// The rest's distribution over rows (height + 1 entries) and, per row, the row of the
    /// conditional tables holding its distribution over columns: below the map's height the
    /// map's own row, else row `height + k` = the `k`-th of `rest_rows`.
    pub rest_marginal: &'a [f32],
    pub rest_row: &'a [u32],
    /// The rest's rows that differ from the map's (width + 1 entries each).
    pub rest_rows: &'a [f32],
    /// The cone holding every bright texel: a normal `n` with `n . axis <= below` sees none
    /// of them above its horizon ([`super::EnvMap::bright_faces`]).
    pub axis: Vec3,
    pub below: f32,
}

/// A texel is bright when its luminance exceeds this many times the map's mean (over solid
/// angle): the built-in sky's sun is 1,200 times its mean, a captured sun 10^3 to 10^6 times.
pub const BRIGHT_FACTOR: f32 = 64.0;
/// The bright texels form a strategy of their own only when they carry at least this share of
/// the map's weight (below it, the extra direction costs more than the noise it removes) ...
pub const BRIGHT_MIN_SHARE: f64 = 0.05;
/// ... and are at most one texel in this many (a compact light, not half the sky).
pub const BRIGHT_MAX_TEXELS: usize = 256;

/// The cumulative distribution of weights `xs`: n + 1 entries from 0 to 1, all 0 where the
/// weights sum to 0.
pub(super) fn cdf_of(xs: &[f64]) -> Vec<f32> {
    let sum: f64 = xs.iter().sum();
    let mut acc = 0.0f64;
    let running = xs.iter().map(|&x| {
        acc += x;
        if sum > 0.0 { (acc / sum) as f32 } else { 0.0 }
    });
    std::iter::once(0.0).chain(running).collect()
}

/// The bright part of a map of `texels` (row-major, `w` wide) whose weights are `weights`
/// (summing to `total`), per [`BRIGHT_FACTOR`], [`BRIGHT_MIN_SHARE`] and
/// [`BRIGHT_MAX_TEXELS`], with the rest of the map's distribution: the distributions over
/// columns of the rows that hold bright texels, without them, are appended to `conditional`
/// (the map's, `w + 1` entries a row).
pub(super) fn bright_part(
    texels: &[Vec3],
    weights: &[f64],
    total: f64,
    w: usize,
    conditional: &mut Vec<f32>,
) -> Option<Bright> {
    let h = texels.len() / w;
    let area: f64 = (0..h)
        .map(|r| (PI * (r as f32 + 0.5) / h as f32).sin() as f64 * w as f64)
        .sum();
    let threshold = (BRIGHT_FACTOR as f64 * total / area) as f32;
    let chosen: Vec<u32> = (0..texels.len())
        .filter(|&i| lum(texels[i]) > threshold)
        .map(|i| i as u32)
        .collect();
    if chosen.is_empty() || chosen.len() > texels.len() / BRIGHT_MAX_TEXELS {
        return None;
    }
    let sum: f64 = chosen.iter().map(|&i| weights[i as usize]).sum();
    if sum < BRIGHT_MIN_SHARE * total {
        return None;
    }
    let cdf = cdf_of(
        &chosen
            .iter()
            .map(|&i| weights[i as usize])
            .collect::<Vec<_>>(),
    );
    // The rest: per row its weight without its bright texels (none left: the map is its
    // bright texels, drawn whole); a row holding some gets a distribution over its columns
    // without them, after the map's rows.
    let mut is_bright = vec![false; texels.len()];
    chosen.iter().for_each(|&i| is_bright[i as usize] = true);
    let rest_of = |r: usize| -> Vec<f64> {
        let rest = |i: usize| if is_bright[i] { 0.0 } else { weights[i] };
        (r * w..(r + 1) * w).map(rest).collect()
    };
    let rest_sums: Vec<f64> = (0..h).map(|r| rest_of(r).iter().sum()).collect();
    let rest_total: f64 = rest_sums.iter().sum();
    if rest_total <= 0.0 {
        return None;
    }
    let rest_marginal = cdf_of(&rest_sums);
    let mut rest_row: Vec<u32> = (0..h as u32).collect();
    for (r, row) in rest_row.iter_mut().enumerate() {
        if is_bright[r * w..(r + 1) * w].contains(&true) {
            *row = (conditional.len() / (w + 1)) as u32;
            conditional.extend(cdf_of(&rest_of(r)));
        }
    }
    // The cone: the axis along the texels' mean direction, the half-angle the largest angle
    // to a texel's centre plus the texel's half-diagonal (its widest extent from the centre).
    let centre = |i: u32| {
        let (r, c) = (i as usize / w, i as usize % w);
        uv_to_dir((c as f32 + 0.5) / w as f32, (r as f32 + 0.5) / h as f32).0
    };
    let axis = chosen
        .iter()
        .fold(Vec3::ZERO, |a, &i| a + centre(i))
        .normalize_or(Vec3::Y);
    let half_diagonal = |i: u32| {
        let r = i as usize / w;
        let st = (PI * (r as f32 + 1.0) / h as f32)
            .sin()
            .max((PI * r as f32 / h as f32).sin());
        0.5 * ((PI / h as f32).powi(2) + (2.0 * PI * st / w as f32).powi(2)).sqrt()
    };
    let half_angle = chosen
        .iter()
        .map(|&i| axis.dot(centre(i)).clamp(-1.0, 1.0).acos() + half_diagonal(i))
        .fold(0.0f32, f32::max);
    Some(Bright {
        threshold,
        ratio: (total / sum) as f32,
        rest_ratio: (total / rest_total) as f32,
        texels: chosen,
        cdf,
        rest_marginal_guide: guide_of(&rest_marginal, 4 * h),
        rest_marginal,
        rest_row,
        axis,
        below: if half_angle < PI / 2.0 {
            -half_angle.sin()
        } else {
            -1.0
        },
    })
}
