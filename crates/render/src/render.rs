//! The renderer: rayon over 16x16 tiles; per tile, primary rays with N x N stratified
//! supersampling, then shading. Shading evaluates the specular BRDF through the batch kernel
//! (`Shading::Batch`, default): per tile, object and light, the local `wi`/`wo` of every sample
//! go into structure-of-arrays buffers and one `Kernel::eval` call; `Shading::Scalar` calls
//! the scalar model per sample instead (kept to measure what the batch path buys:
//! `cargo bench -p fastbrdf-render`).
//! A coloured specular model (`Specular::channels`: three, R, G, B) costs three evaluations,
//! each channel weighting its colour channel; a grey one costs one, as before.

use crate::error::Result;
use crate::film::{Film, check_size};
use crate::geometry::Ray;
use crate::scene::{Rays, Scene};
use fastbrdf::batch::Input;
use glam::Vec3;
use rayon::prelude::*;

/// How the specular term is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    Batch,
    Scalar,
}

/// Where the environment light's random numbers come from (direct light uses none: its
/// primary rays lie on a fixed N x N grid per pixel).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sampler {
    /// Owen-scrambled Sobol points (Burley 2020, the `sobol_burley` crate): per primary sample,
    /// pass `k` of the environment light takes point `k` of a sequence seeded by the sample, so
    /// that its passes are stratified in every pair of dimensions they use.
    #[default]
    Sobol,
    /// Independent uniforms (a PCG hash of the sample and the pass): the renderer before
    /// issue 30, kept to measure what stratification buys.
    Independent,
}

impl Sampler {
    /// `sobol` or `independent`.
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Sobol => "sobol",
            Sampler::Independent => "independent",
        }
    }
}

/// Render options.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel along each axis (N x N per pixel), 1..=16.
    pub spp: u32,
    pub shading: Shading,
    /// The environment light's sampler.
    pub sampler: Sampler,
}

const TILE: u32 = 16;

struct Sample {
    pixel: u32,
    /// Object index, or none for background.
    object: Option<usize>,
    p: Vec3,
    /// The shading normal (bump-perturbed), facing the viewer.
    n: Vec3,
    /// The surface normal before the bump, facing the viewer: shadow rays leave along it.
    g: Vec3,
    v: Vec3,
    base: Vec3,
}

/// Per-worker buffers of [`render_tile`], reused from tile to tile (allocating them per tile
/// made the thread heaps grow and shrink: page faults and `mprotect` calls were 10% of a
/// render).
#[derive(Default)]
struct Scratch {
    /// The tile's primary rays, sample by sample.
    rays: Vec<Ray>,
    samples: Vec<Sample>,
    radiance: Vec<Vec3>,
    /// The samples lit by the current object and light, with the light's radiance scale.
    idx: Vec<usize>,
    li: Vec<Vec3>,
    /// Specular inputs (`wi`, `wo` in the local frame) as structure of arrays.
    cols: [Vec<f32>; 6],
    /// The specular values per channel (only the first for a grey model).
    out: [Vec<f32>; 3],
}

/// Renders `scene`; `progress(done, total)` is called after each tile.
pub fn render(
    scene: &Scene,
    opts: &Options,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Film> {
    render_until(scene, opts, progress, &|| false)?
        .ok_or_else(|| crate::RenderError::Invalid("the render was stopped".into()))
}

/// [`render`], asking `stop` before each tile: once it says true, the tiles not started are
/// skipped and the render returns `None` (the Python package stops a render on Ctrl-C so).
pub fn render_until(
    scene: &Scene,
    opts: &Options,
    progress: &(dyn Fn(usize, usize) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Film>> {
    check_size(opts.width, opts.height)?;
    if !(1..=16).contains(&opts.spp) {
        return Err(crate::RenderError::Invalid(format!(
            "--spp {}: must be 1 to 16 (N x N samples per pixel)",
            opts.spp
        )));
    }
    let (w, h) = (opts.width, opts.height);
    let tiles_x = w.div_ceil(TILE);
    let rays = scene.camera.rays(w, h);
    let done = std::sync::atomic::AtomicUsize::new(0);
    // Progressive: with an environment, one pass per environment sample, each adding its
    // share to the film (pass 0 also holds the direct light and the background); the
    // progress counts tiles over all passes.
    let passes = scene.environment.as_ref().map_or(1, |e| e.samples.max(1));
    let total = (tiles_x * h.div_ceil(TILE) * passes) as usize;
    let mut film = Film::try_new(w, h)?;
    let stopped = std::sync::atomic::AtomicBool::new(false);
    for pass in 0..passes {
        // Parallel over bands of TILE rows and, inside each, over its tiles; each band copies
        // its tiles into the film itself, so assembling the film is parallel too.
        film.pixels
            .par_chunks_mut((w * TILE) as usize)
            .enumerate()
            .for_each(|(ty, band)| {
                let tiles: Vec<Vec<Vec3>> = (0..tiles_x)
                    .into_par_iter()
                    .map_init(Scratch::default, |scratch, tx| {
                        if stop() {
                            stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                            return Vec::new();
                        }
                        let px = render_tile(scene, opts, &rays, tx, ty as u32, pass, scratch);
                        progress(
                            done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                            total,
                        );
                        px
                    })
                    .collect();
                if tiles.iter().any(Vec::is_empty) {
                    return; // stopped: the render is dropped
                }
                for (row, line) in band.chunks_mut(w as usize).enumerate() {
                    for (tx, px) in tiles.iter().enumerate() {
                        let x0 = tx * TILE as usize;
                        let tw = (TILE as usize).min(w as usize - x0);
                        let src = &px[row * tw..(row + 1) * tw];
                        if pass == 0 {
                            line[x0..x0 + tw].copy_from_slice(src);
                        } else {
                            line[x0..x0 + tw]
                                .iter_mut()
                                .zip(src)
                                .for_each(|(d, s)| *d += *s);
                        }
                    }
                }
            });
        if stopped.load(std::sync::atomic::Ordering::Relaxed) {
            return Ok(None);
        }
    }
    Ok(Some(film))
}

fn render_tile(
    scene: &Scene,
    opts: &Options,
    rays: &Rays,
    tx: u32,
    ty: u32,
    pass: u32,
    scratch: &mut Scratch,
) -> Vec<Vec3> {
    let (w, h, n) = (opts.width, opts.height, opts.spp);
    let (x0, y0) = (tx * TILE, ty * TILE);
    let (tw, th) = (TILE.min(w - x0), TILE.min(h - y0));
    let Scratch {
        rays: tile_rays,
        samples,
        radiance,
        idx,
        li: lis,
        cols,
        out,
    } = scratch;
    // All the tile's rays first, then hits and samples: a ray (two divisions, a square root
    // and a division) and an intersection (a square root, a division) form one chain of
    // long-latency operations; in one long loop body the processor could not overlap the
    // chains of successive samples (the tile loop was latency-bound), in a short loop it does.
    // A separate loop for the intersections was slower (the hits go through memory). Same
    // operations, same values.
    tile_rays.clear();
    for py in 0..th {
        for px in 0..tw {
            for sy in 0..n {
                for sx in 0..n {
                    let x = (x0 + px) as f32 + (sx as f32 + 0.5) / n as f32;
                    let y = (y0 + py) as f32 + (sy as f32 + 0.5) / n as f32;
                    tile_rays.push(rays.ray(x, y));
                }
            }
        }
    }
    samples.clear();
    for (i, ray) in tile_rays.iter().enumerate() {
        let pixel = i as u32 / (n * n);
        samples.push(match scene.intersect_shading(ray) {
            None => Sample {
                pixel,
                object: None,
                p: Vec3::ZERO,
                n: Vec3::Z,
                g: Vec3::Z,
                v: -ray.d,
                base: Vec3::ZERO,
            },
            Some(hit) => {
                let m = &scene.objects[hit.object].material;
                let v = -ray.d;
                // Two-sided shading: face the viewer, then perturb; a perturbed
                // normal that turns away from the viewer (at silhouettes) falls
                // back to the smooth one rather than flipping.
                let smooth = if hit.n.dot(v) < 0.0 { -hit.n } else { hit.n };
                let nrm = match m.bump {
                    Some(b) => Some(b.perturb(hit.p, smooth))
                        .filter(|n| n.dot(v) > 0.0)
                        .unwrap_or(smooth),
                    None => smooth,
                };
                let albedo = m
                    .texture
                    .as_ref()
                    .map_or(m.albedo, |t| m.albedo * t.sample(hit.uv));
                Sample {
                    pixel,
                    object: Some(hit.object),
                    p: hit.p,
                    n: nrm,
                    g: smooth,
                    v,
                    base: albedo * m.kd,
                }
            }
        });
    }
    radiance.clear();
    if pass > 0 {
        radiance.resize(samples.len(), Vec3::ZERO);
    } else {
        let env = scene.environment.as_ref().map(|e| &e.map);
        radiance.extend(samples.iter().map(|s| match (s.object, env) {
            (Some(_), _) => scene.ambient * s.base,
            (None, Some(map)) => map.radiance(-s.v),
            (None, None) => scene.background,
        }));
        direct(scene, opts, samples, radiance, idx, lis, cols, out);
    }
    if let Some(env) = &scene.environment {
        let at = Tile {
            x0,
            y0,
            tw,
            w,
            n,
            pass,
        };
        env_pass(
            scene, env, opts, &at, samples, radiance, idx, lis, cols, out,
        );
    }
    let mut px = vec![Vec3::ZERO; (tw * th) as usize];
    for (s, r) in samples.iter().zip(radiance.iter()) {
        px[s.pixel as usize] += *r;
    }
    let inv = 1.0 / (n * n) as f32;
    px.iter_mut().for_each(|p| *p *= inv);
    px
}

/// The direct light: per object and light, the diffuse term and the specular term through one
/// batch kernel call (shadow rays when `scene.shadows`).
#[allow(clippy::too_many_arguments)]
fn direct(
    scene: &Scene,
    opts: &Options,
    samples: &[Sample],
    radiance: &mut [Vec3],
    idx: &mut Vec<usize>,
    lis: &mut Vec<Vec3>,
    cols: &mut [Vec<f32>; 6],
    out: &mut [Vec<f32>; 3],
) {
    for (oi, obj) in scene.objects.iter().enumerate() {
        let m = &obj.material;
        for light in &scene.lights {
            idx.clear();
            lis.clear();
            cols.iter_mut().for_each(Vec::clear);
            for (i, s) in samples.iter().enumerate() {
                if s.object != Some(oi) {
                    continue;
                }
                let (l, li, dist) = light.towards(s.p);
                let cos_i = s.n.dot(l);
                if cos_i <= 0.0 {
                    continue;
                }
                // The shadow ray leaves along the unbumped normal. Where only the bumped
                // normal faces the light (the band beyond a bumpy object's terminator), the
                // ray would start inside the object and always hit it, a hard black line (the
                // "shadow terminator problem" of shading normals): no shadow ray there, the
                // light reaches as without shadows.
                if scene.shadows && s.g.dot(l) > 0.0 && scene.shadowed(s.p, s.g, l, dist) {
                    continue;
                }
                radiance[i] += li * s.base * (cos_i / std::f32::consts::PI);
                if m.ks > 0.0 {
                    let (t, b) = s.n.any_orthonormal_pair();
                    let wi = [l.dot(t), l.dot(b), cos_i];
                    let wo = [s.v.dot(t), s.v.dot(b), s.v.dot(s.n)];
                    idx.push(i);
                    lis.push(li);
                    for k in 0..3 {
                        cols[k].push(wi[k]);
                        cols[k + 3].push(wo[k]);
                    }
                }
            }
            if idx.is_empty() {
                continue;
            }
            add_specular(m, opts.shading, idx, lis, cols, out, radiance);
        }
    }
}

/// Adds `lis[j] * ks * f(wi, wo) * cos` to `radiance[idx[j]]`, the specular values `f` of
/// material `m` evaluated for the local directions in `cols` (one batch kernel call per
/// channel, or the scalar model).
fn add_specular(
    m: &crate::scene::Material,
    shading: Shading,
    idx: &[usize],
    lis: &[Vec3],
    cols: &[Vec<f32>; 6],
    out: &mut [Vec<f32>; 3],
    radiance: &mut [Vec3],
) {
    if let Some(rgb) = &m.specular.rgb {
        // An RGB BRDF (measured data, a fitted model): scalar lookups, one per direction pair,
        // weighted as the coloured path weights its three channels.
        for (j, (&i, &li)) in idx.iter().zip(lis.iter()).enumerate() {
            let [r, g, b] = rgb.eval_rgb(
                [cols[0][j], cols[1][j], cols[2][j]],
                [cols[3][j], cols[4][j], cols[5][j]],
            );
            let (ks, cos) = (m.ks, cols[2][j]);
            radiance[i] += li * Vec3::new(ks * r * cos, ks * g * cos, ks * b * cos);
        }
        return;
    }
    let chans = &m.specular.channels;
    for (ch, out) in chans.iter().zip(out.iter_mut()) {
        out.resize(idx.len(), 0.0);
        match shading {
            Shading::Batch => {
                let input =
                    Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
                ch.kernel
                    .eval(input, out)
                    .expect("SoA buffers have equal lengths");
            }
            Shading::Scalar => {
                for (j, o) in out.iter_mut().enumerate() {
                    *o = ch.scalar.eval(
                        [cols[0][j], cols[1][j], cols[2][j]],
                        [cols[3][j], cols[4][j], cols[5][j]],
                    );
                }
            }
        }
    }
    if chans.len() == 3 {
        // Coloured: each channel's value weights its own colour channel, with the
        // grey path's operations in its order, so that channel c of a coloured
        // render equals channel c of the grey render of that channel's model.
        let [r, g, b] = &*out;
        for (j, (&i, &li)) in idx.iter().zip(lis.iter()).enumerate() {
            let (ks, cos) = (m.ks, cols[2][j]);
            radiance[i] += li * Vec3::new(ks * r[j] * cos, ks * g[j] * cos, ks * b[j] * cos);
        }
    } else {
        let out = &out[0];
        for (j, (&i, &li)) in idx.iter().zip(lis.iter()).enumerate() {
            radiance[i] += li * (m.ks * out[j] * cols[2][j]);
        }
    }
}

/// Where a tile lies, for the environment's sample seeds.
struct Tile {
    x0: u32,
    y0: u32,
    tw: u32,
    w: u32,
    n: u32,
    pass: u32,
}

/// Whether light from `l` reaches sample `s` (see the shadow rule in [`direct`]).
fn visible(scene: &Scene, s: &Sample, l: Vec3) -> bool {
    !scene.shadows || s.g.dot(l) <= 0.0 || !scene.shadowed(s.p, s.g, l, f32::INFINITY)
}

/// One progressive pass of the environment light: per primary hit, one direction drawn from
/// the map (`EnvMap::sample`), one cosine-weighted about the shading normal and, where the
/// material has a specular term, one drawn from the specular BRDF (`Brdf::sample`, its
/// default strategy: VNDF for GGX and Beckmann, the closed-form lobe or its twin for
/// Phong-like models), each times `1 / samples`. The diffuse term combines the map and cosine
/// directions by the balance heuristic, so each contribution is
/// `L kd albedo cos / pi / (pdf_map + cos / pi)`. The specular term combines the map and BRDF
/// directions by the power heuristic (Veach 1997): the map's direction weighted by
/// `power(pdf_map, pdf_brdf) / pdf_map`, the BRDF's by `power(pdf_brdf, pdf_map) / pdf_brdf`,
/// both evaluated through the batch kernels as for direct light. The BRDF's density does not
/// depend on the Fresnel term, so a coloured model samples and weighs with its first channel.
/// Seeds: `env::Rng::new(sample id, pass)`, the sample id being
/// `(pixel y * width + pixel x) * N^2 + subsample`: deterministic, whatever the threads.
#[allow(clippy::too_many_arguments)]
fn env_pass(
    scene: &Scene,
    env: &crate::env::Environment,
    opts: &Options,
    at: &Tile,
    samples: &[Sample],
    radiance: &mut [Vec3],
    idx: &mut Vec<usize>,
    lis: &mut Vec<Vec3>,
    cols: &mut [Vec<f32>; 6],
    out: &mut [Vec<f32>; 3],
) {
    use crate::env::{Rng, cosine_sample, power_heuristic, specular_light_weight};
    use fastbrdf::sample::Strategy;
    use std::f32::consts::PI;
    let map = &env.map;
    let inv = 1.0 / env.samples as f32;
    let nn = at.n * at.n;
    for (oi, obj) in scene.objects.iter().enumerate() {
        let m = &obj.material;
        idx.clear();
        lis.clear();
        cols.iter_mut().for_each(Vec::clear);
        for (i, s) in samples.iter().enumerate() {
            if s.object != Some(oi) {
                continue;
            }
            let (px, py) = (at.x0 + s.pixel % at.tw, at.y0 + s.pixel / at.tw);
            let id = (py.wrapping_mul(at.w).wrapping_add(px))
                .wrapping_mul(nn)
                .wrapping_add(i as u32 % nn);
            let mut rng = Rng::new(id, at.pass);
            let (u1, u2, u3, u4) = (rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
            // The specular term's local frame and view direction, once per hit.
            let frame = (m.ks > 0.0).then(|| {
                let (t, b) = s.n.any_orthonormal_pair();
                (t, b, [s.v.dot(t), s.v.dot(b), s.v.dot(s.n)])
            });
            // An RGB BRDF (no channels) has no sampling: the map's directions only.
            let brdf = m.specular.channels.first().map(|c| &c.scalar);
            let mut push = |wi: [f32; 3], wo: [f32; 3], li: Vec3| {
                idx.push(i);
                lis.push(li);
                for k in 0..3 {
                    cols[k].push(wi[k]);
                    cols[k + 3].push(wo[k]);
                }
            };
            // The map's direction: diffuse (MIS with the cosine strategy) and specular.
            let (l, le, pdf_l) = map.sample(u1, u2);
            let cos_i = s.n.dot(l);
            if pdf_l > 0.0 && cos_i > 0.0 && le != Vec3::ZERO && visible(scene, s, l) {
                radiance[i] += le * s.base * (cos_i / PI / (pdf_l + cos_i / PI) * inv);
                if let Some((t, b, wo)) = frame {
                    let wi = [l.dot(t), l.dot(b), cos_i];
                    let pdf_b = brdf.map(|b| b.pdf(wo, wi, Strategy::Auto));
                    let w = specular_light_weight(pdf_l, pdf_b);
                    push(wi, wo, le * (w / pdf_l * inv));
                }
            }
            // The BRDF's direction: specular only (MIS with the map's direction).
            if let (Some((t, b, wo)), Some(brdf)) = (frame, brdf) {
                let (u5, u6) = (rng.uniform(), rng.uniform());
                if let Some(smp) = brdf.sample(wo, [u5, u6], Strategy::Auto) {
                    let wi = smp.wi;
                    let l = t * wi[0] + b * wi[1] + s.n * wi[2];
                    let (le, pdf_l) = map.lookup(l);
                    if smp.pdf > 0.0 && le != Vec3::ZERO && visible(scene, s, l) {
                        let w = power_heuristic(smp.pdf, pdf_l);
                        push(wi, wo, le * (w / smp.pdf * inv));
                    }
                }
            }
            // The cosine-weighted direction: diffuse only.
            if s.base != Vec3::ZERO {
                let l = cosine_sample(s.n, u3, u4);
                let cos_i = s.n.dot(l);
                if cos_i > 0.0 {
                    let (le, pdf_l) = map.lookup(l);
                    if le != Vec3::ZERO && visible(scene, s, l) {
                        radiance[i] += le * s.base * (cos_i / PI / (pdf_l + cos_i / PI) * inv);
                    }
                }
            }
        }
        if !idx.is_empty() {
            add_specular(m, opts.shading, idx, lis, cols, out, radiance);
        }
    }
}
