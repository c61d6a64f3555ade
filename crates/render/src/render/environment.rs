//! The environment light's pass ([`env_pass`]): per object a wavefront of light (the map's, or
//! a sun's and the rest's), cosine and BRDF directions, the BRDF's densities and draws
//! batched, every specular term evaluated in one batch; and the random numbers of each
//! primary sample and pass ([`uniforms`]).

use super::{Ctx, Sample, Sampler, Spec, Tile, add_specular};
use crate::scene::Scene;
use glam::Vec3;

/// Whether light from `l` reaches sample `s` of object `from` (see the shadow rule in
/// [`super::direct`]).
fn visible(scene: &Scene, from: usize, s: &Sample, l: Vec3) -> bool {
    !scene.shadows || s.g.dot(l) <= 0.0 || !scene.shadowed_from(from, s.p, s.g, l, f32::INFINITY)
}

/// The environment pass's queries to the specular BRDF, batched per object: the densities of
/// the map's directions (`map_*`) and the draws of the BRDF's own (`draw_*`), each with the
/// sample it belongs to, as structures of arrays for [`BrdfSampler`].
#[derive(Default)]
pub(super) struct EnvScratch {
    /// The stages ([`env_pass`]): per hit of the object in this pass, its sample, seed id,
    /// eight uniform numbers, map draw, bright draw, shading normal and cosine direction with
    /// its cosine; per cosine direction kept, its hit (index in `hit`), direction, cosine and
    /// look-up; per BRDF draw with a density, its direction and look-up.
    hit: Vec<usize>,
    id: Vec<u32>,
    u: [Vec<f32>; 8],
    drawn: Vec<(Vec3, Vec3, f32)>,
    bright: Vec<Option<(Vec3, Vec3, f32)>>,
    normal: Vec<Vec3>,
    cos_all: (Vec<Vec3>, Vec<f32>),
    cos_hit: Vec<usize>,
    cos_dir: Vec<Vec3>,
    cos_cos: Vec<f32>,
    cos_le: Vec<(Vec3, f32)>,
    draw_dir: Vec<Vec3>,
    draw_le: Vec<(Vec3, f32)>,
    wave: crate::env::wave::Wave,
    /// The map's and the bright texels' directions with a specular term to add.
    lights: Lights,
    /// Per BRDF draw: its sample, the frame (t, b) of its shading normal; `wo` x, y, z and
    /// `u` 1, 2; then the drawn `wi` x, y, z, weight (unused) and density.
    draw_i: Vec<usize>,
    draw_frame: Vec<(Vec3, Vec3)>,
    draw_in: [Vec<f32>; 5],
    draw_out: [Vec<f32>; 5],
}

impl EnvScratch {
    fn clear(&mut self) {
        self.hit.clear();
        self.id.clear();
        self.u.iter_mut().for_each(Vec::clear);
        self.drawn.clear();
        self.bright.clear();
        self.cos_hit.clear();
        self.cos_dir.clear();
        self.cos_cos.clear();
        self.draw_dir.clear();
        self.cos_le.clear();
        self.draw_le.clear();
        self.lights.clear();
        self.draw_i.clear();
        self.draw_frame.clear();
        self.draw_in.iter_mut().for_each(Vec::clear);
    }
}

/// Per light direction (the rest of the map's or the bright texels') whose specular term is to
/// be added: its sample, radiance, density; then `wo` x, y, z, `wi` x, y, z and the BRDF's
/// density there.
#[derive(Default)]
struct Lights {
    i: Vec<usize>,
    le: Vec<Vec3>,
    pdf: Vec<f32>,
    dirs: [Vec<f32>; 6],
    brdf_pdf: Vec<f32>,
}

impl Lights {
    fn clear(&mut self) {
        self.i.clear();
        self.le.clear();
        self.pdf.clear();
        self.dirs.iter_mut().for_each(Vec::clear);
    }
}

/// One light direction of hit `s` (sample `i`, `inv` = 1 / its passes, `frame` its specular
/// frame and view direction): `(l, radiance, density)`, the density of the light strategies
/// together (`EnvMap::light_pdf`: the rest's and the bright texels' do not overlap). Its
/// diffuse term goes to `radiance` at once (balance heuristic against the cosine strategy);
/// its specular term is queued in `lights`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn light_direction(
    scene: &Scene,
    oi: usize,
    i: usize,
    s: &Sample,
    inv: f32,
    frame: Option<(Vec3, Vec3, [f32; 3])>,
    (l, le, pdf_l): (Vec3, Vec3, f32),
    radiance: &mut Vec3,
    lights: &mut Lights,
) {
    // Occlusion scales the environment's light (times one without a texture: exact).
    let le = le * s.ao;
    let cos_i = s.n.dot(l);
    if pdf_l > 0.0 && cos_i > 0.0 && le != Vec3::ZERO && visible(scene, oi, s, l) {
        let c = cos_i / std::f32::consts::PI;
        *radiance += le * s.base * (c / (pdf_l + c) * inv);
        if let Some((t, b, wo)) = frame {
            let wi = [l.dot(t), l.dot(b), cos_i];
            lights.i.push(i);
            lights.le.push(le);
            lights.pdf.push(pdf_l);
            for k in 0..3 {
                lights.dirs[k].push(wo[k]);
                lights.dirs[k + 3].push(wi[k]);
            }
        }
    }
}

/// The eight uniform numbers of each primary sample of `ids` in `pass`, appended to `u` column
/// by column: (map direction), (cosine direction), (BRDF direction), (bright direction).
fn uniforms(sampler: Sampler, ids: &[u32], pass: u32, u: &mut [Vec<f32>; 8]) {
    match sampler {
        Sampler::Independent => {
            for &id in ids {
                let mut rng = crate::env::Rng::new(id, pass);
                for col in u.iter_mut() {
                    col.push(rng.uniform());
                }
            }
        }
        // Pass k takes point k of two Owen-scrambled Sobol sequences seeded by the sample:
        // its first four dimensions (the map's pair and the cosine pair) and, from a second
        // seed, its first two again (the BRDF's pair) and its last two (the bright texels'),
        // so that each pair the pass uses is stratified over the passes and the pairs are
        // independent. The crate holds 2^16
        // points per seed: passes beyond (at most 4096 x 256 with adaptive antialiasing)
        // continue in sequences of further seeds. All the wavefront's at once
        // (`env::sobol::fill`: `sobol_burley::sample_4d`'s numbers, vectorised over the hits).
        Sampler::Sobol => crate::env::sobol::fill(ids, pass, u),
    }
}

/// One progressive pass of the environment light: per primary hit, one direction drawn from
/// the map (`EnvMap::sample_rest`: the whole map, or where it has a compact bright part, a
/// sun, the rest without it) and, where the map has one and the hit may see it above its
/// horizon, one from the bright texels (`EnvMap::sample_bright`); one cosine-weighted about
/// the shading normal and, where the material has a specular term, one drawn from the
/// specular BRDF (its default strategy: VNDF for GGX and Beckmann, the closed-form lobe or its
/// twin for Phong-like models), each times `1 / samples`.
///
/// The light strategies' densities do not overlap, so that together they are one light
/// strategy of density `pdf_light` (`EnvMap::light_pdf`) that takes one direction in the sun
/// and one elsewhere each pass: drawn from the whole map, the number of a pixel's directions
/// that hit the sun was what fluctuated (39% of the built-in sky's weight in 122 texels; half
/// of the sky scenes' error). The diffuse term combines the light and cosine directions by the
/// balance heuristic, so each contribution is `L kd albedo cos / pi / (pdf_light + cos / pi)`.
/// The specular term combines the light and BRDF directions by the power heuristic (Veach
/// 1997): a light direction weighted by `power(pdf_light, pdf_brdf) / pdf_light`, the BRDF's by
/// `power(pdf_brdf, pdf_light) / pdf_brdf` (`env::power_weight_over_pdf`), both evaluated
/// through the batch kernels as for direct light. The BRDF's density does not depend on the
/// Fresnel term, so a coloured model samples and weighs with its first channel.
///
/// A wavefront per object, in stages over all its hits (issue 30: one hit at a time, the
/// cache misses of the map's cells and tables came one after another, and the trigonometry
/// and the Sobol points ran scalar; staged, the misses overlap and the arithmetic vectorises):
/// the uniform numbers (`env::sobol::fill`); the map's draws (`EnvMap::sample_rest_many`)
/// and the bright texels'; the cosine directions (`env::wave::cosine_many`) and their
/// look-ups (`EnvMap::lookup_many`); then a loop over the hits adds the diffuse terms (shadow
/// rays) and collects the specular queries; the BRDF's densities at the light directions and
/// its own draws go through the batch sampler (`fastbrdf::batch::sample`) in one call each;
/// the drawn directions are looked up at once; a last loop traces their shadow rays and
/// queues every specular term, in the order of the hits (light directions first), for one
/// batch evaluation. Each stage computes what the one-hit-at-a-time loop did, to the bit, in
/// the same order of additions.
///
/// Random numbers ([`uniforms`]): per primary sample, id `(pixel y * width + pixel x) * N^2 +
/// subsample`, and pass; deterministic whatever the threads.
#[allow(clippy::too_many_arguments)]
pub(super) fn env_pass(
    ctx: &Ctx,
    env: &crate::env::Environment,
    at: &Tile,
    pass: u32,
    samples: &[Sample],
    radiance: &mut [Vec3],
    es: &mut EnvScratch,
    spec: &mut Spec,
) {
    use crate::env::power_weight_over_pdf;
    use crate::env::wave::cosine_many;
    use fastbrdf::sample::Strategy;
    use std::f32::consts::PI;
    let scene = ctx.scene;
    let map = &env.map;
    let nn = ctx.opts.spp * ctx.opts.spp;
    for (oi, obj) in scene.objects.iter().enumerate() {
        let m = &obj.material;
        let sampler = ctx.samplers[oi].as_ref();
        es.clear();
        // The hits of this object in this pass, and their uniform numbers.
        for (i, s) in samples.iter().enumerate() {
            if s.object != Some(oi) || pass >= s.passes {
                continue;
            }
            let (px, py) = (at.x0 + s.pixel % at.tw, at.y0 + s.pixel / at.tw);
            let id = (py.wrapping_mul(at.w).wrapping_add(px))
                .wrapping_mul(nn)
                .wrapping_add(s.sub);
            es.hit.push(i);
            es.id.push(id);
        }
        if es.hit.is_empty() {
            continue;
        }
        uniforms(ctx.opts.sampler, &es.id, pass, &mut es.u);
        // The map's directions (the rest's, where it has a bright part), all at once
        // (`EnvMap::sample_rest_many`: their cache misses overlap).
        map.sample_rest_many(&es.u[0], &es.u[1], &mut es.wave, &mut es.drawn);
        // The cosine-weighted directions (diffuse only: every hit's drawn in one vectorised
        // loop, those with a diffuse term and a positive cosine kept) and their look-ups.
        es.normal.clear();
        es.normal.extend(es.hit.iter().map(|&i| samples[i].n));
        // The bright texels' directions (a small table: in cache), for the hits that may see
        // one above their horizon.
        if map.bright().is_some() {
            let (u6, u7) = (&es.u[6], &es.u[7]);
            let draw = |((&n, &a), &b)| map.bright_faces(n).then(|| map.sample_bright(a, b))?;
            es.bright.extend(es.normal.iter().zip(u6).zip(u7).map(draw));
        }
        let (dirs, coss) = (&mut es.cos_all.0, &mut es.cos_all.1);
        cosine_many(&es.normal, &es.u[2], &es.u[3], dirs, coss);
        for (j, &i) in es.hit.iter().enumerate() {
            if samples[i].base != Vec3::ZERO && coss[j] > 0.0 {
                es.cos_hit.push(j);
                es.cos_dir.push(dirs[j]);
                es.cos_cos.push(coss[j]);
            }
        }
        map.lookup_many(&es.cos_dir, &mut es.wave, &mut es.cos_le);
        let mut next_cos = 0;
        for (j, &i) in es.hit.iter().enumerate() {
            let s = &samples[i];
            let inv = 1.0 / s.passes as f32;
            // The specular term's local frame and view direction, once per hit.
            let frame = (m.ks > 0.0).then(|| {
                let (t, b) = (s.t, s.b);
                (t, b, [s.v.dot(t), s.v.dot(b), s.v.dot(s.n)])
            });
            // The rest of the map's direction, then the bright texels'.
            let r = &mut radiance[i];
            light_direction(scene, oi, i, s, inv, frame, es.drawn[j], r, &mut es.lights);
            if let Some(&Some(bright)) = es.bright.get(j) {
                light_direction(scene, oi, i, s, inv, frame, bright, r, &mut es.lights);
            }
            // The BRDF's direction: specular only (MIS with the light directions); drawn below.
            if let (Some((t, b, wo)), Some(_)) = (frame, sampler) {
                es.draw_i.push(i);
                es.draw_frame.push((t, b));
                let (u5, u6) = (es.u[4][j], es.u[5][j]);
                for (col, x) in es.draw_in.iter_mut().zip([wo[0], wo[1], wo[2], u5, u6]) {
                    col.push(x);
                }
            }
            // The cosine-weighted direction: diffuse only.
            if es.cos_hit.get(next_cos) == Some(&j) {
                let (l, cos_i) = (es.cos_dir[next_cos], es.cos_cos[next_cos]);
                let (le, pdf_l) = es.cos_le[next_cos];
                next_cos += 1;
                let pdf_l = map.light_pdf(le, pdf_l);
                let le = le * s.ao;
                if le != Vec3::ZERO && visible(scene, oi, s, l) {
                    radiance[i] += le * s.base * (cos_i / PI / (pdf_l + cos_i / PI) * inv);
                }
            }
        }
        if es.lights.i.is_empty() && es.draw_i.is_empty() {
            continue;
        }
        // The BRDF's densities at the map's directions, and its own draws: one batch each.
        let nm = es.lights.i.len();
        es.lights.brdf_pdf.resize(nm, 0.0);
        let nd = es.draw_i.len();
        es.draw_out.iter_mut().for_each(|c| c.resize(nd, 0.0));
        if let Some(sm) = sampler {
            let d = &es.lights.dirs;
            sm.pdf(
                Strategy::Auto,
                [&d[0], &d[1], &d[2]],
                [&d[3], &d[4], &d[5]],
                &mut es.lights.brdf_pdf,
            )
            .expect("equal lengths, the default strategy");
            let (di, [wx, wy, wz, weight, pdf]) = (&es.draw_in, &mut es.draw_out);
            sm.sample(
                Strategy::Auto,
                [&di[0], &di[1], &di[2]],
                [&di[3], &di[4]],
                fastbrdf::batch::sample::SampleOut {
                    wi: [wx, wy, wz],
                    weight,
                    pdf,
                },
            )
            .expect("equal lengths, the default strategy");
        }
        // The drawn directions (world space) with a density, and their look-ups, all at once.
        let world = |b: usize| {
            let s = &samples[es.draw_i[b]];
            let (t, bt) = es.draw_frame[b];
            let o = &es.draw_out;
            t * o[0][b] + bt * o[1][b] + s.n * o[2][b]
        };
        let drawn = (0..nd).filter(|&b| es.draw_out[4][b] > 0.0).map(world);
        es.draw_dir.extend(drawn);
        map.lookup_many(&es.draw_dir, &mut es.wave, &mut es.draw_le);
        let mut next_draw = 0;
        // Every specular term in the order of the hits, each hit's light directions first.
        spec.clear();
        let (mut a, mut b) = (0, 0);
        while a < nm || b < nd {
            if a < nm && (b >= nd || es.lights.i[a] <= es.draw_i[b]) {
                let d = &es.lights.dirs;
                let wo = [d[0][a], d[1][a], d[2][a]];
                let wi = [d[3][a], d[4][a], d[5][a]];
                let inv = 1.0 / samples[es.lights.i[a]].passes as f32;
                let pdf_b = sampler.map_or(0.0, |_| es.lights.brdf_pdf[a]);
                let w = power_weight_over_pdf(es.lights.pdf[a], pdf_b);
                spec.push(es.lights.i[a], wi, wo, es.lights.le[a] * (w * inv));
                a += 1;
            } else {
                let i = es.draw_i[b];
                let s = &samples[i];
                let o = &es.draw_out;
                let (wi, pdf) = ([o[0][b], o[1][b], o[2][b]], o[4][b]);
                if pdf > 0.0 {
                    let inv = 1.0 / s.passes as f32;
                    let (l, (le, pdf_l)) = (es.draw_dir[next_draw], es.draw_le[next_draw]);
                    next_draw += 1;
                    let pdf_l = map.light_pdf(le, pdf_l);
                    let le = le * s.ao;
                    if le != Vec3::ZERO && visible(scene, oi, s, l) {
                        let w = power_weight_over_pdf(pdf, pdf_l);
                        let di = &es.draw_in;
                        spec.push(i, wi, [di[0][b], di[1][b], di[2][b]], le * (w * inv));
                    }
                }
                b += 1;
            }
        }
        if !spec.idx.is_empty() {
            add_specular(m, ctx.opts.shading, spec, radiance, samples);
        }
    }
}
