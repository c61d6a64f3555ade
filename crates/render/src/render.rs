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
use crate::scene::{Rays, Scene, Views};
use fastbrdf::batch::Input;
use glam::Vec3;
use rayon::prelude::*;

mod environment;
mod mapped;
mod primary;
use environment::{EnvScratch, env_pass};
use primary::primary;

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

/// Where a pixel's primary samples go (`--aa`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Antialias {
    /// Adaptive: first one sample at each pixel's centre; N x N samples (on a rotated grid,
    /// `primary::subpixel`) only where the 3 x 3 neighbourhood of centre samples shows an edge
    /// (`primary::edge`: a normal turning, a depth step, an albedo or direct-light contrast),
    /// 2N x 2N at an object's outline (another object or the background) without an
    /// environment, where most of the error lies (`primary::OUTLINE`). A pixel left at its
    /// centre sample keeps it (without an environment, a pixel refined on an even rotated
    /// grid keeps it too: N x N + 1 samples); with an environment it takes N x N times the
    /// passes, so it gets as many environment samples as a grid pixel (on one hit point,
    /// stratified over all of them). Measured on the default scenes (`tools/equal_error.py`): all of a grid render's
    /// error against its converged reference lies in 2-6% of the pixels, at edges. A bumped
    /// object (`--bump`) always takes N x N (axis-aligned): its relief varies inside a pixel.
    /// The refined pixels depend on the whole picture's colours, so channel c of a coloured
    /// render equals the grey render of channel c's model only with `Grid`.
    #[default]
    Adaptive,
    /// N x N samples in every pixel (the renderer before issue 30; the GPU renderer's).
    Grid,
}

impl Antialias {
    /// `adaptive` or `grid`.
    pub fn name(self) -> &'static str {
        match self {
            Antialias::Adaptive => "adaptive",
            Antialias::Grid => "grid",
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
    /// Where the primary samples go.
    pub aa: Antialias,
}

/// Tile side with an environment (a tile's passes then keep its wavefront's arrays in cache).
const TILE: u32 = 16;
/// Tile width and height without an environment. Adaptive antialiasing probes a ring of
/// pixels around each tile for its edge test: 16 x 16 tiles traced 27% more primary rays
/// than pixels, 64 x 32 ones 10%, and a directly lit render is little more than its primary
/// rays.
const TILE_DIRECT: (u32, u32) = (64, 32);

#[derive(Clone, Copy)]
struct Sample {
    pixel: u32,
    /// Which of the pixel's N x N grid positions (0 for a centre sample).
    sub: u32,
    /// Its environment passes: `samples`, or N x N times that for a pixel's only sample.
    passes: u32,
    /// Object index, or none for background.
    object: Option<usize>,
    p: Vec3,
    /// The shading normal (bump-perturbed), facing the viewer.
    n: Vec3,
    /// The surface normal before the bump, facing the viewer: shadow rays leave along it.
    g: Vec3,
    v: Vec3,
    base: Vec3,
    /// The specular term's texel (`Specular::tint`), one elsewhere.
    tint: Vec3,
    /// The specular term's local frame (x, y) about `n`: the mesh's tangent frame where it
    /// has tangents (a glTF mesh: anisotropy, normal textures; `maps::frame`), else
    /// `n.any_orthonormal_pair()`.
    t: Vec3,
    b: Vec3,
    /// A metallic-roughness texture's metallic and roughness level (`maps::MetallicRoughness`),
    /// else 0.
    metal: f32,
    level: u32,
    /// The occlusion of the light that is not punctual (the environment, the ambient term):
    /// one without an occlusion texture.
    ao: f32,
    /// Emitted radiance (a glTF material's emission), added once per primary sample.
    emit: Vec3,
}

/// Per-worker buffers of [`render_tile`], reused from tile to tile (allocating them per tile
/// made the thread heaps grow and shrink: page faults and `mprotect` calls were 10% of a
/// render); one set per worker thread for the whole render ([`render_until`]).
#[derive(Default)]
struct Scratch {
    /// The tile's primary rays, sample by sample.
    rays: Vec<Ray>,
    samples: Vec<Sample>,
    radiance: Vec<Vec3>,
    spec: Spec,
    env: EnvScratch,
    /// Per pixel of the tile, its number of samples.
    count: Vec<u32>,
    /// Adaptive antialiasing: the centre samples of the tile and its ring, their pass-0
    /// radiance (then that of the kept ones), and per pixel the grid it takes.
    probe: Vec<Sample>,
    probe_radiance: Vec<Vec3>,
    /// The probe's direct light alone, and its samples' edge-test inputs.
    probe_direct: Vec<Vec3>,
    probe_keys: Vec<primary::EdgeKey>,
    /// Per probe sample, `primary::edge`'s verdict on its right (bits 0-1) and lower (bits
    /// 2-3) neighbour.
    edges: Vec<u8>,
    /// Per pixel, the side of the grid it takes (0: its centre sample alone) and whether
    /// the grid is rotated (`primary::subpixel`).
    refine: Vec<(u32, bool)>,
    /// Without an environment, the pixels that keep their centre sample (their radiance is
    /// `probe_radiance`, in order); their samples are not in `samples`.
    kept_px: Vec<u32>,
    /// Per refined ray, its (pixel, grid position) (`primary::refined_rays`).
    sub_px: Vec<(u32, u32)>,
    /// The tile's pixels for one pass, and their sum over passes (with an environment).
    px: Vec<Vec3>,
    acc: Vec<Vec3>,
}

impl Scratch {
    /// Buffers sized for a tile of `tw` x `th` pixels and its probe ring, so that they do not
    /// grow by doubling through the first tiles: each size they pass through is fresh memory,
    /// whose first touch (a page fault, the kernel zeroing the page) cost about 0.6 ns a byte
    /// on the 2-core VM (1.2 ms for 2 MB). Capacity never written costs address space only.
    fn sized(tw: u32, th: u32) -> Self {
        let (px, probe) = ((tw * th) as usize, ((tw + 2) * (th + 2)) as usize);
        let mut s = Self::default();
        s.rays.reserve(probe);
        s.samples.reserve(probe);
        s.radiance.reserve(probe);
        s.count.reserve(px);
        s.probe.reserve(probe);
        s.probe_radiance.reserve(probe);
        s.probe_keys.reserve(probe);
        s.edges.reserve(probe);
        s.refine.reserve(px);
        s.kept_px.reserve(px);
        s.px.reserve(px);
        s.sub_px.reserve(probe);
        s.spec.reserve(probe);
        s
    }
}

/// The specular terms to evaluate for one object: which sample each adds to, the light's
/// radiance scale, the local `wi`, `wo` as structure of arrays, and the values per channel.
#[derive(Default)]
struct Spec {
    idx: Vec<usize>,
    li: Vec<Vec3>,
    /// `wi` x, y, z, `wo` x, y, z.
    cols: [Vec<f32>; 6],
    /// The specular values per channel (only the first for a grey model).
    out: [Vec<f32>; 3],
}

impl Spec {
    fn clear(&mut self) {
        self.idx.clear();
        self.li.clear();
        self.cols.iter_mut().for_each(Vec::clear);
    }

    /// Room for `n` entries, written by index: `idx`, `li` and the six columns as slices of
    /// length `n`; [`Spec::close`] then keeps the first `k`.
    fn open(&mut self, n: usize) -> (&mut [usize], &mut [Vec3], [&mut [f32]; 6]) {
        self.clear();
        self.idx.resize(n, 0);
        self.li.resize(n, Vec3::ZERO);
        self.cols.iter_mut().for_each(|c| c.resize(n, 0.0));
        (
            &mut self.idx,
            &mut self.li,
            self.cols.each_mut().map(Vec::as_mut_slice),
        )
    }

    /// Room for `n` entries in every buffer (see [`Scratch::sized`]).
    fn reserve(&mut self, n: usize) {
        self.idx.reserve(n);
        self.li.reserve(n);
        self.cols.iter_mut().for_each(|c| c.reserve(n));
        self.out.iter_mut().for_each(|c| c.reserve(n));
    }

    fn close(&mut self, k: usize) {
        self.idx.truncate(k);
        self.li.truncate(k);
        self.cols.iter_mut().for_each(|c| c.truncate(k));
    }

    #[inline(always)]
    fn push(&mut self, i: usize, wi: [f32; 3], wo: [f32; 3], li: Vec3) {
        self.idx.push(i);
        self.li.push(li);
        for k in 0..3 {
            self.cols[k].push(wi[k]);
            self.cols[k + 3].push(wo[k]);
        }
    }
}

/// Renders `scene`; `progress(done, total)` is called after each tile and pass.
pub fn render(
    scene: &Scene,
    opts: &Options,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Film> {
    render_until(scene, opts, progress, &|| false)?
        .ok_or_else(|| crate::RenderError::Invalid("the render was stopped".into()))
}

/// [`render`], asking `stop` before each tile and pass: once it says true, the work not
/// started is skipped and the render returns `None` (the Python package stops a render on
/// Ctrl-C so).
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
    let (tile_w, tile_h) = if scene.environment.is_some() {
        (TILE, TILE)
    } else {
        TILE_DIRECT
    };
    let tiles_x = w.div_ceil(tile_w);
    let rays = scene.camera.rays(w, h);
    // With an environment, one pass per environment sample, each adding its share to the
    // pixels (pass 0 also holds the direct light and the background). The passes of a tile
    // run one after the other on its primary hits, found once (before issue 30 each pass
    // traced the whole image's primary rays again); the progress counts tiles x passes.
    let passes = scene.environment.as_ref().map_or(1, |e| e.samples.max(1));
    // Adaptive antialiasing gives a pixel left at its centre sample N x N times the passes.
    let passes_max = match opts.aa {
        Antialias::Adaptive if scene.environment.is_some() => passes * opts.spp * opts.spp,
        _ => passes,
    };
    let ctx = Ctx {
        scene,
        opts,
        rays,
        views: scene.views(&rays),
        tile_w,
        tile_h,
        passes_max,
        total: (tiles_x * h.div_ceil(tile_h) * passes_max) as usize,
        done: std::sync::atomic::AtomicUsize::new(0),
        progress,
        stop,
        samplers: samplers(scene)?,
        // Once per render rather than a division per pixel (or a table per tile).
        // Up to an outline pixel's (2N)^2 samples and its centre (`primary::OUTLINE`).
        scale: (0..=4 * opts.spp * opts.spp + 1)
            .map(|c| 1.0 / c as f32)
            .collect(),
    };
    let mut film = Film::try_new(w, h)?;
    // Per worker thread, buffers reused from tile to tile for the whole render (rayon's
    // `map_init` made a set per split of each band's tiles: 9,000 reallocations and their
    // copies were 5% of a directly lit 512 x 512 render's instructions), each made by its
    // worker at its first tile: made here, on this thread, they took 0.45 ms before the
    // first tile (the allocator's first writes into fresh huge pages) with the workers idle.
    let scratch: Vec<std::sync::Mutex<Option<Scratch>>> = (0..rayon::current_num_threads())
        .map(|_| std::sync::Mutex::new(None))
        .collect();
    let stopped = std::sync::atomic::AtomicBool::new(false);
    // Parallel over bands of `tile_h` rows and, inside each, over its tiles; each tile writes
    // its rows of the film from its worker's buffers (a fresh Vec per tile, copied into the
    // film after its band, was fresh memory too; see `Scratch::sized`).
    film.pixels
        .par_chunks_mut((w * tile_h) as usize)
        .enumerate()
        .for_each(|(ty, band)| {
            let mut rows: Vec<Vec<&mut [Vec3]>> = (0..tiles_x).map(|_| Vec::new()).collect();
            for line in band.chunks_mut(w as usize) {
                for (tx, part) in line.chunks_mut(tile_w as usize).enumerate() {
                    rows[tx].push(part);
                }
            }
            rows.into_par_iter().enumerate().for_each(|(tx, mut out)| {
                // The worker's own buffers; a fresh set if they are in use (a tile that
                // waits inside rayon may run another tile on this thread).
                let slot = rayon::current_thread_index().and_then(|i| scratch.get(i));
                let (tx, ty) = (tx as u32, ty as u32);
                let done = match slot.and_then(|m| m.try_lock().ok()) {
                    Some(mut s) => {
                        let s = s.get_or_insert_with(|| Scratch::sized(tile_w, tile_h));
                        render_tile(&ctx, tx, ty, s, &mut out)
                    }
                    None => render_tile(&ctx, tx, ty, &mut Scratch::default(), &mut out),
                };
                if !done {
                    // Stopped: the render is dropped.
                    stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                }
            });
        });
    if stopped.load(std::sync::atomic::Ordering::Relaxed) {
        return Ok(None);
    }
    Ok(Some(film))
}

/// What every tile of one render shares.
struct Ctx<'a> {
    scene: &'a Scene,
    opts: &'a Options,
    rays: Rays,
    /// The meshes' bundles of the camera's and the directional lights' rays.
    views: Views,
    /// Tile width and height ([`TILE`] or [`TILE_DIRECT`]).
    tile_w: u32,
    tile_h: u32,
    /// The most passes a tile runs (the progress counts this many per tile).
    passes_max: u32,
    total: usize,
    done: std::sync::atomic::AtomicUsize,
    progress: &'a (dyn Fn(usize, usize) + Sync),
    stop: &'a (dyn Fn() -> bool + Sync),
    /// Per object, the batch sampler of its specular model's first channel (none for an RGB
    /// BRDF or without an environment).
    samplers: Vec<Option<BrdfSampler>>,
    /// 1 / (a pixel's sample count), by count: 0..=(2 spp)^2.
    scale: Vec<f32>,
}

impl Ctx<'_> {
    /// Counts `k` more tile passes done and reports the progress.
    fn advance(&self, k: usize) {
        let done = self.done.fetch_add(k, std::sync::atomic::Ordering::Relaxed) + k;
        (self.progress)(done, self.total);
    }
}

/// The specular BRDF's sampling for the environment pass, per batch.
type BrdfSampler = fastbrdf::batch::sample::Sampler;

fn samplers(scene: &Scene) -> Result<Vec<Option<BrdfSampler>>> {
    scene
        .objects
        .iter()
        .map(
            |o| match (&scene.environment, o.material.specular.channels.first()) {
                (Some(_), Some(c)) if o.material.ks > 0.0 => Ok(Some(BrdfSampler::new(&c.spec)?)),
                _ => Ok(None),
            },
        )
        .collect()
}

/// One tile, all passes: its primary hits once ([`primary`]), then per pass the direct
/// light (pass 0) and the environment's samples; the pixels are the sum over passes of each
/// pass's average over the pixel's samples, added in pass order, written to `out` (the
/// tile's rows of the film). Without an environment and with N > 1, the refined samples
/// are traced and lit in chunks ([`lit_tile`]). False when `stop` said so.
fn render_tile(
    ctx: &Ctx,
    tx: u32,
    ty: u32,
    scratch: &mut Scratch,
    out: &mut [&mut [Vec3]],
) -> bool {
    let (scene, opts) = (ctx.scene, ctx.opts);
    let (w, h) = (opts.width, opts.height);
    let (x0, y0) = (tx * ctx.tile_w, ty * ctx.tile_h);
    let (tw, th) = (ctx.tile_w.min(w - x0), ctx.tile_h.min(h - y0));
    let at = Tile { x0, y0, tw, w };
    if (ctx.stop)() {
        return false;
    }
    // A tile whose rays (its ring's too) all see the background, without an environment:
    // each pixel is its samples' sum of the background times their share, as below.
    let (lo, hi) = (
        (x0 as f32 - 1.0, y0 as f32 - 1.0),
        ((x0 + tw + 1) as f32, (y0 + th + 1) as f32),
    );
    if scene.environment.is_none() && !ctx.views.may_hit(&ctx.rays, lo, hi) {
        let n = if opts.spp > 1 && opts.aa == Antialias::Adaptive {
            1
        } else {
            opts.spp * opts.spp
        };
        let sum = (0..n).fold(Vec3::ZERO, |a, _| a + scene.background);
        ctx.advance(ctx.passes_max as usize);
        out.iter_mut()
            .for_each(|row| row.fill(sum * ctx.scale[n as usize]));
        return true;
    }
    // The pixels' sample counts and the radiance of pass 0 already known (from the probe).
    let known = primary(ctx, &at, th, scratch);
    if scene.environment.is_none() && opts.spp > 1 {
        lit_tile(ctx, &at, th, scratch, out);
        return true;
    }
    let Scratch {
        samples,
        radiance,
        env: env_scratch,
        spec,
        probe_radiance,
        count,
        kept_px,
        px,
        acc,
        ..
    } = scratch;
    let passes = samples.iter().map(|s| s.passes).max().unwrap_or(1);
    // The sum over passes; with one pass (no environment) the pass's pixels themselves.
    px.resize((tw * th) as usize, Vec3::ZERO);
    for pass in 0..passes {
        if (ctx.stop)() {
            return false;
        }
        radiance.clear();
        if pass > 0 {
            radiance.resize(samples.len(), Vec3::ZERO);
        } else {
            radiance.extend_from_slice(&probe_radiance[..known]);
            let env = scene.environment.as_ref().map(|e| &e.map);
            radiance.extend(samples[known..].iter().map(|s| initial(scene, env, s)));
            direct(ctx, &samples[known..], &mut radiance[known..], spec);
        }
        if let Some(env) = &scene.environment {
            env_pass(ctx, env, &at, pass, samples, radiance, env_scratch, spec);
        }
        px.fill(Vec3::ZERO);
        add_samples(px, samples, radiance);
        // Without an environment (one pass), the pixels left at their centre sample.
        average(ctx, px, kept_px, probe_radiance, count);
        if pass == 0 {
            if passes > 1 {
                acc.clone_from(px);
            }
        } else {
            acc.iter_mut().zip(px.iter()).for_each(|(a, p)| *a += *p);
        }
        ctx.advance(1);
    }
    // A tile whose pixels all took the grid ran fewer passes than the progress counts.
    let skipped = ctx.passes_max.saturating_sub(passes) as usize;
    if skipped > 0 {
        ctx.advance(skipped);
    }
    let sum = if passes > 1 { acc } else { px };
    for (row, part) in out.iter_mut().zip(sum.chunks_exact(tw as usize)) {
        row.copy_from_slice(part);
    }
    true
}

/// Samples traced and lit per chunk without an environment ([`lit_tile`]): the chunk's
/// samples (152 bytes each) stay in the core's L2 cache, and a worker's buffers stay at the
/// probe's size. Tracing a tile's refined samples at once grew them to a tile's worth (up to
/// 35k samples, 5 MB, at `--spp 2` on 64 x 32 pixels of outline), each size they passed
/// through fresh memory from the kernel; in chunks the face rendered about 1.04x faster at
/// `--spp 2` (`tools/render_speed.sh`; 256 and 2048 timed as 1024).
const LIT_CHUNK: usize = 1024;

/// The rest of a tile without an environment (one pass, N > 1), after [`primary`]: the
/// refined (or grid) samples traced and lit [`LIT_CHUNK`] rays at a time and summed into
/// their pixels, then the pixels that kept their centre sample, then each pixel scaled by
/// its count: the same sums in the same order as tracing them all at once, so the same
/// image to the bit.
fn lit_tile(ctx: &Ctx, at: &Tile, th: u32, scratch: &mut Scratch, out: &mut [&mut [Vec3]]) {
    let Scratch {
        rays,
        samples,
        radiance,
        spec,
        probe_radiance,
        count,
        kept_px,
        refine,
        sub_px,
        px,
        ..
    } = scratch;
    px.clear();
    px.resize((at.tw * th) as usize, Vec3::ZERO);
    let mut next = 0;
    while next < refine.len() {
        rays.clear();
        sub_px.clear();
        next = primary::refined_rays(&ctx.rays, at, refine, next, LIT_CHUNK, rays, sub_px);
        samples.clear();
        primary::trace(ctx, rays, |i| sub_px[i], 1, samples);
        radiance.clear();
        radiance.extend(samples.iter().map(|s| initial(ctx.scene, None, s)));
        direct(ctx, samples, radiance, spec);
        add_samples(px, samples, radiance);
    }
    average(ctx, px, kept_px, probe_radiance, count);
    ctx.advance(1);
    for (row, part) in out.iter_mut().zip(px.chunks_exact(at.tw as usize)) {
        row.copy_from_slice(part);
    }
}

/// Adds each sample's radiance to its pixel's.
fn add_samples(px: &mut [Vec3], samples: &[Sample], radiance: &[Vec3]) {
    for (s, r) in samples.iter().zip(radiance) {
        px[s.pixel as usize] += *r;
    }
}

/// The pixels' sums finished: the radiance of those that kept their centre sample added
/// (`kept_px`, in the order of `kept`), then each divided by its sample count.
fn average(ctx: &Ctx, px: &mut [Vec3], kept_px: &[u32], kept: &[Vec3], count: &[u32]) {
    for (&p, r) in kept_px.iter().zip(kept) {
        px[p as usize] += *r;
    }
    px.iter_mut()
        .zip(count)
        .for_each(|(p, &c)| *p *= ctx.scale[c as usize]);
}

/// A sample's radiance before any light: the ambient term on an object, the environment or
/// the background elsewhere.
fn initial(scene: &Scene, env: Option<&std::sync::Arc<crate::env::EnvMap>>, s: &Sample) -> Vec3 {
    match (s.object, env) {
        (Some(_), _) => scene.ambient * s.base * s.ao + s.emit,
        (None, Some(map)) => map.radiance(-s.v),
        (None, None) => scene.background,
    }
}

/// The direct light: per object and light, the diffuse term and the specular term through one
/// batch kernel call (shadow rays when `scene.shadows`).
fn direct(ctx: &Ctx, samples: &[Sample], radiance: &mut [Vec3], spec: &mut Spec) {
    let (scene, opts) = (ctx.scene, ctx.opts);
    for (oi, obj) in scene.objects.iter().enumerate() {
        let m = &obj.material;
        let search = scene.shadows && scene.may_shadow(oi);
        for (li, light) in scene.lights.iter().enumerate() {
            let along = ctx.views.light(li);
            // The specular terms go into columns sized for every sample and written by
            // index (eight pushes' capacity checks per lit sample were 4% of a directly lit
            // render's instructions), then cut to the `k` written.
            let mut k = 0;
            let (idx, lis, mut cols) = spec.open(samples.len());
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
                if search && s.g.dot(l) > 0.0 && scene.shadowed_in(oi, s.p, s.g, l, dist, along) {
                    continue;
                }
                radiance[i] += li * s.base * (cos_i / std::f32::consts::PI);
                if m.ks > 0.0 {
                    let (t, b) = (s.t, s.b);
                    let d = [
                        l.dot(t),
                        l.dot(b),
                        cos_i,
                        s.v.dot(t),
                        s.v.dot(b),
                        s.v.dot(s.n),
                    ];
                    idx[k] = i;
                    lis[k] = li;
                    for (c, x) in cols.iter_mut().zip(d) {
                        c[k] = x;
                    }
                    k += 1;
                }
            }
            spec.close(k);
            if !spec.idx.is_empty() {
                add_specular(m, opts.shading, spec, radiance, samples);
            }
        }
    }
}

/// Adds `li[j] * ks * f(wi, wo) * cos` to `radiance[idx[j]]` for every entry of `spec`, the
/// specular values `f` of material `m` evaluated for its local directions (one batch kernel
/// call per channel, or the scalar model). A tinted term (`Specular::tint`) adds
/// `f_zero + t * (f - f_zero)`, `t` the texel of `samples[idx[j]]`: both models evaluated.
fn add_specular(
    m: &crate::scene::Material,
    shading: Shading,
    spec: &mut Spec,
    radiance: &mut [Vec3],
    samples: &[Sample],
) {
    if let Some(mr) = m.maps.as_ref().and_then(|x| x.metallic_roughness.as_ref()) {
        mapped::add_specular_mapped(m, mr, shading, spec, radiance, samples);
        return;
    }
    if let Some(tint) = &m.specular.tint {
        let zero = crate::scene::Material {
            kd: m.kd,
            ks: m.ks,
            albedo: m.albedo,
            texture: None,
            bump: None,
            specular: tint.zero.clone(),
            maps: None,
        };
        let mut f0 = vec![Vec3::ZERO; radiance.len()];
        let mut f1 = vec![Vec3::ZERO; radiance.len()];
        add_specular_untinted(&zero, shading, spec, &mut f0);
        add_specular_untinted(m, shading, spec, &mut f1);
        // A sample may hold several entries: its sums are added once, then cleared.
        for &i in &spec.idx {
            radiance[i] += f0[i] + samples[i].tint * (f1[i] - f0[i]);
            (f0[i], f1[i]) = (Vec3::ZERO, Vec3::ZERO);
        }
        return;
    }
    add_specular_untinted(m, shading, spec, radiance);
}

/// [`add_specular`] of the material's own model, its tint left out.
fn add_specular_untinted(
    m: &crate::scene::Material,
    shading: Shading,
    spec: &mut Spec,
    radiance: &mut [Vec3],
) {
    let Spec {
        idx,
        li: lis,
        cols,
        out,
    } = spec;
    if let Some(rgb) = &m.specular.rgb {
        // An RGB BRDF (measured data, a fitted model, a user's model): one batch call (scalar
        // lookups by default), weighted as the coloured path weights its three channels.
        let mut values = Vec::new();
        rgb.eval_rgb_batch(
            [&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]],
            &mut values,
        );
        for (j, ((&i, &li), &[r, g, b])) in idx.iter().zip(lis.iter()).zip(&values).enumerate() {
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
}
