//! The tile's primary samples ([`primary`]): the grid, or adaptive antialiasing's probe of
//! centre samples with its edge test ([`edge`]), and the hits they trace ([`trace`]).

use super::{Antialias, Ctx, Sample, Scratch, Tile, direct, initial, mapped};
use crate::geometry::Ray;
use crate::scene::Rays;
use glam::Vec3;

/// The tile's primary samples (`scratch.samples`) and each pixel's sample count
/// (`scratch.count`). Grid: N x N per pixel, in pixel order (without an environment only
/// `scratch.refine`, N for every pixel: the caller traces them). Adaptive (N > 1): one sample at
/// the centre of each pixel and of the ring of pixels around the tile (the probe), with its
/// direct light; a pixel with an [`edge`] among its four neighbours then takes N x N samples
/// at [`subpixel`]'s positions (2N x 2N at an [`OUTLINE`] without an environment), the others
/// keep their centre sample (with an environment first in `samples`, without
/// one only their pixels, in `scratch.kept_px`; their pass-0 radiance in
/// `scratch.probe_radiance`); without an environment a pixel refined on an even rotated
/// lattice keeps it too, and the refined samples are left to the caller, which traces and
/// lights them in chunks from `scratch.refine` ([`refined_rays`]). Returns how many samples
/// lead `samples` with a known pass-0 radiance.
pub(super) fn primary(ctx: &Ctx, at: &Tile, th: u32, scratch: &mut Scratch) -> usize {
    let (opts, n) = (ctx.opts, ctx.opts.spp);
    let (x0, y0, tw) = (at.x0, at.y0, at.tw);
    let e = ctx
        .scene
        .environment
        .as_ref()
        .map_or(1, |e| e.samples.max(1));
    let Scratch {
        rays,
        samples,
        count,
        probe,
        probe_radiance,
        probe_direct,
        probe_keys,
        edges,
        refine,
        spec,
        kept_px,
        sub_px,
        ..
    } = scratch;
    samples.clear();
    kept_px.clear();
    count.clear();
    count.resize((tw * th) as usize, n * n);
    if n == 1 {
        // One sample per pixel: a row of rays at a time.
        rays.clear();
        let xs: Vec<f32> = (0..tw).map(|px| (x0 + px) as f32 + 0.5).collect();
        for py in 0..th {
            ctx.rays.extend_row(&xs, (y0 + py) as f32 + 0.5, rays);
        }
        trace(ctx, rays, |i| (i as u32, 0), e, samples);
        probe_radiance.clear();
        return 0;
    }
    if opts.aa == Antialias::Grid {
        // Every pixel on the axis-aligned grid ([`refined_rays`]); the counts are N x N
        // already. Without an environment the caller traces and lights them in chunks.
        refine.clear();
        refine.resize((tw * th) as usize, (n, false));
        probe_radiance.clear();
        if ctx.scene.environment.is_some() {
            rays.clear();
            sub_px.clear();
            refined_rays(&ctx.rays, at, refine, 0, usize::MAX, rays, sub_px);
            trace(ctx, rays, |i| sub_px[i], e, samples);
        }
        return 0;
    }
    // The probe: centre samples of the tile and the ring around it (clamped to the image).
    let (pw, ph) = (tw + 2, th + 2);
    rays.clear();
    let xs: Vec<f32> = (0..pw)
        .map(|px| (x0 + px).saturating_sub(1).min(opts.width - 1) as f32 + 0.5)
        .collect();
    for py in 0..ph {
        let y = (y0 + py).saturating_sub(1).min(opts.height - 1);
        ctx.rays.extend_row(&xs, y as f32 + 0.5, rays);
    }
    probe.clear();
    let kept_passes = if ctx.scene.environment.is_some() {
        e * n * n
    } else {
        1
    };
    trace(ctx, rays, |_| (0, 0), kept_passes, probe);
    let env = ctx.scene.environment.as_ref().map(|e| &e.map);
    let eye = ctx.scene.camera.eye;
    probe_radiance.clear();
    probe_radiance.extend(probe.iter().map(|s| initial(ctx.scene, env, s)));
    // The direct light of the probe: for the edge test and, where the centre sample stays,
    // as its pass-0 radiance. With an environment apart (its share is added per pass, and the
    // edge test reads the direct light alone); without one straight into the radiance, which
    // the edge test reads (a copy each way per tile before).
    let light: &[Vec3] = if env.is_some() {
        let direct_only = probe_direct;
        direct_only.clear();
        direct_only.resize(probe_radiance.len(), Vec3::ZERO);
        direct(ctx, probe, direct_only, spec);
        probe_radiance
            .iter_mut()
            .zip(direct_only.iter())
            .for_each(|(r, d)| *r += *d);
        direct_only
    } else {
        direct(ctx, probe, probe_radiance, spec);
        probe_radiance
    };
    // Each probe sample's edge-test inputs, once (the test reads each sample up to four
    // times): 4% of a directly lit render's instructions went to reading them from the
    // samples and taking the maxima again per pair.
    probe_keys.clear();
    probe_keys.extend(probe.iter().zip(light.iter()).map(|(s, &light)| EdgeKey {
        object: s.object.map_or(u32::MAX, |o| o as u32),
        depth: (s.p - eye).length(),
        n: s.n,
        base: s.base,
        base_max: s.base.max_element(),
        light,
        light_max: light.max_element(),
    }));
    // The four neighbours: an edge that passes between diagonal neighbours passes between two
    // of them too (the eight refined a third more pixels for no less error on the default
    // scenes). [`edge`] is symmetric, so each pair of the probe is tested once: `edges[c]`
    // bit 0 for (c, c + 1), bit 1 for (c, c + pw).
    let keys = &probe_keys[..];
    let pwu = pw as usize;
    edges.clear();
    edges.resize(probe.len(), 0);
    for py in 0..ph as usize {
        for px in 0..pwu {
            let c = py * pwu + px;
            // Only the pairs that touch the tile's pixels (probe rows and columns 1..=th,
            // 1..=tw; the ring is 0 and th + 1, tw + 1).
            let (row, col) = (
                (1..=th as usize).contains(&py),
                (1..=tw as usize).contains(&px),
            );
            let right = if row && px <= tw as usize {
                edge(&keys[c], &keys[c + 1])
            } else {
                0
            };
            let down = if col && py <= th as usize {
                edge(&keys[c], &keys[c + pwu])
            } else {
                0
            };
            edges[c] = right | (down << 2);
        }
    }
    // Per pixel, the side of its grid: 0 to keep the centre sample, N at an edge, and 2N at
    // an outline without an environment ([`OUTLINE`]).
    refine.clear();
    let with_centre = |(m, rotated): (u32, bool)| env.is_none() && keeps_centre(m, rotated);
    let any_bump = ctx.scene.objects.iter().any(|o| o.material.bump.is_some());
    let outline_side = if env.is_some() { n } else { 2 * n };
    for py in 0..th {
        for px in 0..tw {
            let c = ((py + 1) * pw + px + 1) as usize;
            // The strongest of the four pairs: right and down of `c`, right of its left
            // neighbour, down of its upper one.
            let level = (edges[c] & 3)
                .max(edges[c] >> 2)
                .max(edges[c - 1] & 3)
                .max(edges[c - pwu] >> 2);
            // A bumped surface varies inside a pixel more than its neighbours show: always
            // N x N there (the sample's object read only where a material has a bump), on
            // the axis-aligned grid ([`subpixel`]).
            let bumped = any_bump
                && probe[c]
                    .object
                    .is_some_and(|o| ctx.scene.objects[o].material.bump.is_some());
            let side = match level {
                OUTLINE => outline_side,
                EDGE => n,
                _ if bumped => n,
                _ => 0,
            };
            refine.push((side, !bumped));
        }
    }
    // The pixels that keep their centre sample first (their pass-0 radiance is known). With
    // an environment their samples lead `samples` (the passes shade them again); without
    // one their radiance is final, so only their pixels are kept (`kept_px`): copying the
    // sample (152 bytes) was 8% of a directly lit render's instructions.
    let mut kept = 0;
    for py in 0..th {
        for px in 0..tw {
            let p = (py * tw + px) as usize;
            if refine[p].0 > 0 && !with_centre(refine[p]) {
                continue;
            }
            let c = ((py + 1) * pw + px + 1) as usize;
            if env.is_some() {
                samples.push(Sample {
                    pixel: p as u32,
                    ..probe[c]
                });
            } else {
                kept_px.push(p as u32);
            }
            probe_radiance[kept] = probe_radiance[c];
            // A refined pixel's count is set with its grid below.
            if refine[p].0 == 0 {
                count[p] = 1;
            }
            kept += 1;
        }
    }
    probe_radiance.truncate(kept);
    for (c, &r) in count.iter_mut().zip(refine.iter()) {
        if r.0 > 0 {
            *c = r.0 * r.0 + u32::from(with_centre(r));
        }
    }
    if env.is_none() {
        // The refined samples are traced and lit in chunks by the caller ([`refined_rays`]).
        return 0;
    }
    rays.clear();
    sub_px.clear();
    refined_rays(&ctx.rays, at, refine, 0, usize::MAX, rays, sub_px);
    trace(ctx, rays, |i| sub_px[i], e, samples);
    kept
}

/// The rays of the tile's refined pixels from pixel `from` on (`refine`: per pixel the side
/// of its grid, 0 for none, and whether it is rotated; [`subpixel`]'s positions), appended
/// to `rays` with each one's (pixel, grid position) in `pixels`, whole pixels at a time until
/// there are at least `limit` rays or the tile ends. Returns the pixel to go on from
/// (`refine.len()` at the end). Rays come in pixel order, each pixel's in grid order.
pub(super) fn refined_rays(
    camera: &Rays,
    at: &Tile,
    refine: &[(u32, bool)],
    from: usize,
    limit: usize,
    rays: &mut Vec<Ray>,
    pixels: &mut Vec<(u32, u32)>,
) -> usize {
    let tw = at.tw as usize;
    for (p, &(m, rotated)) in refine.iter().enumerate().skip(from) {
        if rays.len() >= limit {
            return p;
        }
        let (px, py) = ((p % tw) as u32, (p / tw) as u32);
        for sy in 0..m {
            for sx in 0..m {
                let (dx, dy) = subpixel(sx, sy, m, rotated);
                rays.push(camera.ray((at.x0 + px) as f32 + dx, (at.y0 + py) as f32 + dy));
                pixels.push((p as u32, sy * m + sx));
            }
        }
    }
    refine.len()
}

/// Which edge, if any, two neighbouring centre samples (sample, direct light, distance from
/// the eye) straddle: [`OUTLINE`] where they see another object or the background, else
/// [`EDGE`] for normals more than ~25 degrees apart, a depth step of more than 5%, or a
/// contrast in albedo or direct light of more than 5% (with a floor of 0.01 for dark
/// pixels), else 0. The thresholds err towards refining: a refined pixel costs
/// N x N samples, a missed edge aliases.
#[inline]
fn edge(a: &EdgeKey, b: &EdgeKey) -> u8 {
    // `x.max(y).max_element()` is the larger of the two maxima.
    let contrast = |x: Vec3, y: Vec3, xm: f32, ym: f32| {
        (x - y).abs().max_element() > 0.01 + 0.05 * if xm > ym { xm } else { ym }
    };
    if a.object != b.object {
        OUTLINE
    } else if (a.object != u32::MAX
        && (a.n.dot(b.n) < 0.9
            || (a.depth - b.depth).abs() > 0.05 * a.depth.min(b.depth)
            || contrast(a.base, b.base, a.base_max, b.base_max)))
        || contrast(a.light, b.light, a.light_max, b.light_max)
    {
        EDGE
    } else {
        0
    }
}

/// [`edge`]'s verdicts: an edge inside an object's picture (a normal, depth, albedo or light
/// step), and an outline (the samples see different objects, or one sees the background).
/// Without an environment an outline pixel takes 2N x 2N samples: on the face at 512 x 512
/// with N = 2, 69% of the adaptive render's error against its converged reference (relMSE,
/// `tools/equal_error.py`'s metric) lay in its 1,812 outline pixels, a fifth of the refined
/// ones, where a sample's radiance jumps from the object's to the background's. There 4 x 4
/// took the error from 1.15e-4 (rotated 2 x 2) to 4.2e-5 for 7% more render time. With an
/// environment every sample takes its passes, so extra positions would multiply them.
const EDGE: u8 = 1;
const OUTLINE: u8 = 2;

/// The offset inside a pixel of a refined pixel's sample (`sx`, `sy`) of `n` x `n`. Rotated:
/// a square lattice rotated by atan(1/n) (for `n` = 2, the rotated-grid pattern of GPUs' 4x
/// antialiasing), whose `n`^2 points lie in distinct rows and columns of the n^2 x n^2
/// subgrid, one in each cell of the n x n grid. An edge near the horizontal or vertical,
/// which crosses the axis-aligned grid's `n` samples of a row or column at once, crosses
/// these one at a time: on the face at 512 x 512 the adaptive 2 x 2 render's error against
/// its converged reference fell from 1.62e-4 to 1.15e-4 (relMSE, `tools/equal_error.py`'s
/// metric), and with outlines at 4 x 4 from 7.6e-5 (axis-aligned) to 4.2e-5. Else the
/// axis-aligned grid, for a bumped object's pixels: the lattice's first alias frequency is
/// sqrt(1 + 1/n^2) times lower, and on a relief finer than the pixels (`--bump 160,0.6` at
/// 256 x 256) the rotated 2 x 2 had 1.36x the grid's error. `n` = 1 is the centre. `--aa
/// grid` keeps the axis-aligned grid: the GPU renderer rasterises it (one fragment per
/// sample at (W N) x (H N)), and grid renders are its twin.
#[inline]
pub(super) fn subpixel(sx: u32, sy: u32, n: u32, rotated: bool) -> (f32, f32) {
    let nf = n as f32;
    if !rotated {
        return ((sx as f32 + 0.5) / nf, (sy as f32 + 0.5) / nf);
    }
    (
        (sx as f32 + (sy as f32 + 0.5) / nf) / nf,
        (sy as f32 + ((n - 1 - sx) as f32 + 0.5) / nf) / nf,
    )
}

/// Whether a pixel refined on [`subpixel`]'s `m` x `m` grid (`rotated` or not) also keeps its
/// centre sample, without an environment (traced and shaded in the probe: N x N + 1 samples):
/// on a rotated lattice of even side, where no point of the lattice lies at the centre. On
/// the face at 512 x 512, `--spp 2`, the error against the converged reference (relMSE) fell
/// from 4.27e-5 to 4.02e-5, the sphere's from 1.39e-5 to 1.31e-5, at the same render time.
/// Not on a bumped pixel's axis-aligned grid: the bumped sphere of `tests/sampling.rs` had
/// 1.15x the error with it.
fn keeps_centre(m: u32, rotated: bool) -> bool {
    rotated && m > 0 && m.is_multiple_of(2)
}

/// What [`edge`] reads of a probe sample: its object (`u32::MAX` for the background), its
/// distance from the eye, shading normal, diffuse colour and direct light, with the two
/// colours' largest channels.
#[derive(Clone, Copy)]
pub(super) struct EdgeKey {
    object: u32,
    depth: f32,
    n: Vec3,
    base: Vec3,
    base_max: f32,
    light: Vec3,
    light_max: f32,
}

/// Appends the samples of `rays` (ray `i` belongs to `pixel(i)` = (pixel, grid position)),
/// each taking `passes` environment passes.
pub(super) fn trace(
    ctx: &Ctx,
    rays: &[Ray],
    pixel: impl Fn(usize) -> (u32, u32),
    passes: u32,
    samples: &mut Vec<Sample>,
) {
    let scene = ctx.scene;
    for (i, ray) in rays.iter().enumerate() {
        let (pixel, sub) = pixel(i);
        samples.push(match scene.intersect_shading_in(ray, &ctx.views.eye) {
            None => {
                let (t, b) = Vec3::Z.any_orthonormal_pair();
                Sample {
                    pixel,
                    sub,
                    passes,
                    object: None,
                    p: Vec3::ZERO,
                    n: Vec3::Z,
                    g: Vec3::Z,
                    v: -ray.d,
                    base: Vec3::ZERO,
                    tint: Vec3::ONE,
                    t,
                    b,
                    metal: 0.0,
                    level: 0,
                    ao: 1.0,
                    emit: Vec3::ZERO,
                }
            }
            Some(hit) => {
                let m = &scene.objects[hit.object].material;
                let v = -ray.d;
                // Two-sided shading: face the viewer, then perturb; a perturbed
                // normal that turns away from the viewer (at silhouettes) falls
                // back to the smooth one rather than flipping.
                let back = hit.n.dot(v) < 0.0;
                let smooth = if back { -hit.n } else { hit.n };
                let (nrm, t, b) = match m.bump {
                    Some(b) => {
                        let n = Some(b.perturb(hit.p, smooth))
                            .filter(|n| n.dot(v) > 0.0)
                            .unwrap_or(smooth);
                        let (t, b) = n.any_orthonormal_pair();
                        (n, t, b)
                    }
                    // The mesh's tangent frame and the normal texture, where there are.
                    None => crate::maps::frame(
                        smooth,
                        hit.tangent,
                        back,
                        v,
                        m.maps.as_ref().and_then(|x| x.normal.as_ref()),
                        hit.uv,
                    ),
                };
                let (metal, level, ao, emit) = m
                    .maps
                    .as_ref()
                    .map_or((0.0, 0, 1.0, Vec3::ZERO), |x| mapped::texels(x, hit.uv));
                let albedo = m
                    .texture
                    .as_ref()
                    .map_or(m.albedo, |t| m.albedo * t.sample(hit.uv));
                Sample {
                    pixel,
                    sub,
                    passes,
                    object: Some(hit.object),
                    p: hit.p,
                    n: nrm,
                    g: smooth,
                    v,
                    base: albedo * m.kd,
                    tint: m
                        .specular
                        .tint
                        .as_ref()
                        .map_or(Vec3::ONE, |t| t.texture.sample(hit.uv)),
                    t,
                    b,
                    metal,
                    level,
                    ao,
                    emit,
                }
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::{keeps_centre, refined_rays, subpixel};
    use crate::render::Tile;
    use crate::scene::Camera;
    use glam::Vec3;

    /// Refined rays made in chunks (as `lit_tile` traces them) are the rays made at once, in
    /// the same order; each chunk ends at a pixel's end, with at least the limit's rays but
    /// for the last.
    #[test]
    fn refined_rays_in_chunks_are_the_rays_at_once() {
        let camera = Camera {
            eye: Vec3::new(0.0, 0.0, 4.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 30.0,
        }
        .rays(40, 30);
        let at = Tile {
            x0: 8,
            y0: 4,
            tw: 13,
            w: 40,
        };
        let refine: Vec<(u32, bool)> = (0..13 * 7u32)
            .map(|p| ([0, 2, 0, 4, 3, 0, 1][(p * 5 % 7) as usize], p % 3 != 0))
            .collect();
        let (mut all, mut all_px) = (Vec::new(), Vec::new());
        let end = refined_rays(&camera, &at, &refine, 0, usize::MAX, &mut all, &mut all_px);
        assert_eq!(end, refine.len());
        let expected: u32 = refine.iter().map(|r| r.0 * r.0).sum();
        assert_eq!(all.len(), expected as usize);
        for limit in [1, 7, 16, 100, 10_000] {
            let (mut next, mut rays, mut px) = (0, Vec::new(), Vec::new());
            while next < refine.len() {
                let (mut r, mut p) = (Vec::new(), Vec::new());
                let from = next;
                next = refined_rays(&camera, &at, &refine, next, limit, &mut r, &mut p);
                assert!(next > from);
                assert!(r.len() >= limit || next == refine.len(), "limit {limit}");
                // Whole pixels: the chunk's last ray is its pixel's last grid position.
                if let Some(&(pixel, sub)) = p.last() {
                    let m = refine[pixel as usize].0;
                    assert_eq!(sub, m * m - 1);
                }
                rays.extend(r);
                px.extend(p);
            }
            assert_eq!(px, all_px, "limit {limit}");
            let same = rays.iter().zip(&all).all(|(a, b)| a.o == b.o && a.d == b.d);
            assert!(same && rays.len() == all.len(), "limit {limit}");
        }
        // Ray i is pixel (x0 + p % tw, y0 + p / tw) at its subpixel position.
        let (p, sub) = all_px[5];
        let m = refine[p as usize].0;
        let (dx, dy) = subpixel(sub % m, sub / m, m, refine[p as usize].1);
        let r = camera.ray((8 + p % 13) as f32 + dx, (4 + p / 13) as f32 + dy);
        assert!(r.o == all[5].o && r.d == all[5].d);
    }

    /// A refined pixel keeps its centre sample exactly where its rotated lattice has no point
    /// there (even sides); an odd lattice has one, which would count the centre twice.
    #[test]
    fn the_centre_sample_is_kept_where_no_lattice_point_lies_there() {
        for m in 1..=32u32 {
            let at_centre = (0..m)
                .flat_map(|sy| (0..m).map(move |sx| subpixel(sx, sy, m, true)))
                .any(|(x, y)| (x - 0.5).abs() < 1e-6 && (y - 0.5).abs() < 1e-6);
            assert_eq!(keeps_centre(m, true), !at_centre, "m {m}");
            assert!(!keeps_centre(m, false), "m {m}: the axis-aligned grid");
        }
        assert!(!keeps_centre(0, true));
    }

    /// The rotated lattice: every point inside the pixel, one in each cell of the n x n grid,
    /// in its own row and column of the n^2 x n^2 subgrid (so an axis-aligned edge meets the
    /// points one at a time), and the points' mean at the pixel's centre; the axis-aligned
    /// grid at the cells' centres; n = 1 the centre.
    #[test]
    fn the_rotated_lattice_takes_each_cell_row_and_column_once() {
        for n in 1..=32u32 {
            let nn = (n * n) as usize;
            let (mut cell, mut col, mut row) = (vec![0; nn], vec![0; nn], vec![0; nn]);
            let mut mean = [0.0f64; 2];
            for sy in 0..n {
                for sx in 0..n {
                    let (x, y) = subpixel(sx, sy, n, true);
                    assert!(
                        x > 0.0 && x < 1.0 && y > 0.0 && y < 1.0,
                        "n {n}: ({x}, {y})"
                    );
                    let nf = n as f32;
                    cell[(y * nf) as usize * n as usize + (x * nf) as usize] += 1;
                    col[(x * nf * nf) as usize] += 1;
                    row[(y * nf * nf) as usize] += 1;
                    mean[0] += f64::from(x) / nn as f64;
                    mean[1] += f64::from(y) / nn as f64;
                    let (gx, gy) = subpixel(sx, sy, n, false);
                    assert_eq!((gx, gy), ((sx as f32 + 0.5) / nf, (sy as f32 + 0.5) / nf));
                }
            }
            assert!(
                cell.iter().chain(&col).chain(&row).all(|&k| k == 1),
                "n {n}"
            );
            assert!((mean[0] - 0.5).abs() < 1e-5 && (mean[1] - 0.5).abs() < 1e-5);
        }
        assert_eq!(subpixel(0, 0, 1, true), (0.5, 0.5));
        // n = 2: the rotated-grid pattern of 4x antialiasing, at eighths.
        let four: Vec<_> = (0..4).map(|k| subpixel(k % 2, k / 2, 2, true)).collect();
        assert_eq!(
            four,
            [
                (0.125, 0.375),
                (0.625, 0.125),
                (0.375, 0.875),
                (0.875, 0.625)
            ]
        );
    }
}
