//! The environment light's pass ([`env_pass`]): per object a wavefront of map, cosine and
//! BRDF directions, the BRDF's densities and draws batched, every specular term evaluated in
//! one batch; and the random numbers of each primary sample and pass ([`uniforms`]).

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
    /// The stages ([`env_pass`]): per hit of the object in this pass, its sample, seed id, six
    /// uniform numbers, map draw, shading normal and cosine direction with its cosine; per
    /// cosine direction kept, its hit (index in `hit`), direction, cosine and look-up; per
    /// BRDF draw with a density, its direction and look-up.
    hit: Vec<usize>,
    id: Vec<u32>,
    u: [Vec<f32>; 6],
    drawn: Vec<(Vec3, Vec3, f32)>,
    normal: Vec<Vec3>,
    cos_all: (Vec<Vec3>, Vec<f32>),
    cos_hit: Vec<usize>,
    cos_dir: Vec<Vec3>,
    cos_cos: Vec<f32>,
    cos_le: Vec<(Vec3, f32)>,
    draw_dir: Vec<Vec3>,
    draw_le: Vec<(Vec3, f32)>,
    wave: crate::env::wave::Wave,
    /// Per map direction: its sample, radiance x 1 / (pdf x samples), density; then `wo`
    /// x, y, z, `wi` x, y, z and the BRDF's density there.
    map_i: Vec<usize>,
    map_le: Vec<Vec3>,
    map_pdf: Vec<f32>,
    map_dirs: [Vec<f32>; 6],
    map_brdf_pdf: Vec<f32>,
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
        self.cos_hit.clear();
        self.cos_dir.clear();
        self.cos_cos.clear();
        self.draw_dir.clear();
        self.cos_le.clear();
        self.draw_le.clear();
        self.map_i.clear();
        self.map_le.clear();
        self.map_pdf.clear();
        self.map_dirs.iter_mut().for_each(Vec::clear);
        self.draw_i.clear();
        self.draw_frame.clear();
        self.draw_in.iter_mut().for_each(Vec::clear);
    }
}

/// The six uniform numbers of each primary sample of `ids` in `pass`, appended to `u` column
/// by column: (map direction), (cosine direction), (BRDF direction).
fn uniforms(sampler: Sampler, ids: &[u32], pass: u32, u: &mut [Vec<f32>; 6]) {
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
        // seed, the first two again (the BRDF's pair), so that each pair the pass uses is
        // stratified over the passes and the pairs are independent. The crate holds 2^16
        // points per seed: passes beyond (at most 4096 x 256 with adaptive antialiasing)
        // continue in sequences of further seeds. All the wavefront's at once
        // (`env::sobol::fill`: `sobol_burley::sample_4d`'s numbers, vectorised over the hits).
        Sampler::Sobol => crate::env::sobol::fill(ids, pass, u),
    }
}

/// One progressive pass of the environment light: per primary hit, one direction drawn from
/// the map (`EnvMap::sample`), one cosine-weighted about the shading normal and, where the
/// material has a specular term, one drawn from the specular BRDF (its default strategy:
/// VNDF for GGX and Beckmann, the closed-form lobe or its twin for Phong-like models), each
/// times `1 / samples`. The diffuse term combines the map and cosine directions by the
/// balance heuristic, so each contribution is `L kd albedo cos / pi / (pdf_map + cos / pi)`.
/// The specular term combines the map and BRDF directions by the power heuristic (Veach
/// 1997): the map's direction weighted by `power(pdf_map, pdf_brdf) / pdf_map`, the BRDF's by
/// `power(pdf_brdf, pdf_map) / pdf_brdf`, both evaluated through the batch kernels as for
/// direct light. The BRDF's density does not depend on the Fresnel term, so a coloured model
/// samples and weighs with its first channel.
///
/// A wavefront per object, in stages over all its hits (issue 30: one hit at a time, the
/// cache misses of the map's cells and tables came one after another, and the trigonometry
/// and the Sobol points ran scalar; staged, the misses overlap and the arithmetic vectorises):
/// the uniform numbers (`env::sobol::fill`); the map's draws (`EnvMap::sample_many`); the
/// cosine directions (`env::wave::cosine_many`) and their look-ups (`EnvMap::lookup_many`);
/// then a loop over the hits adds the diffuse terms (shadow rays) and collects the specular
/// queries; the BRDF's densities at the map's directions and its own draws go through the
/// batch sampler (`fastbrdf::batch::sample`) in one call each; the drawn directions are looked
/// up at once; a last loop traces their shadow rays and queues every specular term, in the
/// order of the hits (map direction first), for one batch evaluation. Each stage computes what
/// the one-hit-at-a-time loop did, to the bit, in the same order of additions.
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
    use crate::env::wave::cosine_many;
    use crate::env::{power_heuristic, specular_light_weight};
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
        // The map's directions, all at once (`EnvMap::sample_many`: their cache misses
        // overlap).
        map.sample_many(&es.u[0], &es.u[1], &mut es.wave, &mut es.drawn);
        // The cosine-weighted directions (diffuse only: every hit's drawn in one vectorised
        // loop, those with a diffuse term and a positive cosine kept) and their look-ups.
        es.normal.clear();
        es.normal.extend(es.hit.iter().map(|&i| samples[i].n));
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
            // The map's direction: diffuse (MIS with the cosine strategy) and specular.
            let (l, le, pdf_l) = es.drawn[j];
            // Occlusion scales the environment's light (times one without a texture: exact).
            let le = le * s.ao;
            let cos_i = s.n.dot(l);
            if pdf_l > 0.0 && cos_i > 0.0 && le != Vec3::ZERO && visible(scene, oi, s, l) {
                radiance[i] += le * s.base * (cos_i / PI / (pdf_l + cos_i / PI) * inv);
                if let Some((t, b, wo)) = frame {
                    let wi = [l.dot(t), l.dot(b), cos_i];
                    es.map_i.push(i);
                    es.map_le.push(le);
                    es.map_pdf.push(pdf_l);
                    for k in 0..3 {
                        es.map_dirs[k].push(wo[k]);
                        es.map_dirs[k + 3].push(wi[k]);
                    }
                }
            }
            // The BRDF's direction: specular only (MIS with the map's direction); drawn below.
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
                let le = le * s.ao;
                if le != Vec3::ZERO && visible(scene, oi, s, l) {
                    radiance[i] += le * s.base * (cos_i / PI / (pdf_l + cos_i / PI) * inv);
                }
            }
        }
        if es.map_i.is_empty() && es.draw_i.is_empty() {
            continue;
        }
        // The BRDF's densities at the map's directions, and its own draws: one batch each.
        let nm = es.map_i.len();
        es.map_brdf_pdf.resize(nm, 0.0);
        let nd = es.draw_i.len();
        es.draw_out.iter_mut().for_each(|c| c.resize(nd, 0.0));
        if let Some(sm) = sampler {
            let d = &es.map_dirs;
            sm.pdf(
                Strategy::Auto,
                [&d[0], &d[1], &d[2]],
                [&d[3], &d[4], &d[5]],
                &mut es.map_brdf_pdf,
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
        // Every specular term in the order of the hits, each hit's map direction first.
        spec.clear();
        let (mut a, mut b) = (0, 0);
        while a < nm || b < nd {
            if a < nm && (b >= nd || es.map_i[a] <= es.draw_i[b]) {
                let d = &es.map_dirs;
                let wo = [d[0][a], d[1][a], d[2][a]];
                let wi = [d[3][a], d[4][a], d[5][a]];
                let inv = 1.0 / samples[es.map_i[a]].passes as f32;
                let pdf_b = sampler.map(|_| es.map_brdf_pdf[a]);
                let w = specular_light_weight(es.map_pdf[a], pdf_b);
                spec.push(
                    es.map_i[a],
                    wi,
                    wo,
                    es.map_le[a] * (w / es.map_pdf[a] * inv),
                );
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
                    let le = le * s.ao;
                    if le != Vec3::ZERO && visible(scene, oi, s, l) {
                        let w = power_heuristic(pdf, pdf_l);
                        let di = &es.draw_in;
                        spec.push(i, wi, [di[0][b], di[1][b], di[2][b]], le * (w / pdf * inv));
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
