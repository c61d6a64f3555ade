//! Shading with a glTF material's textures beyond its base colour ([`crate::maps`]): the
//! texels at a hit, and the specular term of a metallic-roughness texture, evaluated per
//! roughness level with the batch kernels of that level's two models (metallic 0 and 1).

use super::{Sample, Shading, Spec, add_specular};
use crate::maps::{MetallicRoughness, SurfaceMaps};
use crate::scene::Material;
use glam::{Vec2, Vec3};

/// A hit's textured values: (metallic, roughness level, occlusion, emitted radiance); without
/// a texture, (0, 0, 1, the emissive factor or zero).
pub(super) fn texels(maps: &SurfaceMaps, uv: Vec2) -> (f32, u32, f32, Vec3) {
    let (metal, level) = maps
        .metallic_roughness
        .as_ref()
        .map_or((0.0, 0), |mr| mr.at(uv));
    let ao = maps.occlusion.as_ref().map_or(1.0, |o| {
        1.0 + o.strength * (o.texture.sample(uv).x.clamp(0.0, 1.0) - 1.0)
    });
    let emit = maps.emissive.as_ref().map_or(Vec3::ZERO, |e| {
        e.texture
            .as_ref()
            .map_or(e.factor, |t| e.factor * t.sample(uv))
    });
    (metal, level, ao, emit)
}

/// [`add_specular`] for a material with a metallic-roughness texture: the entries of `spec`
/// grouped by their samples' roughness levels; per level, the models at metallic 0 and 1
/// (each tinted by the base colour texture, as the material's own model) evaluated in one
/// batch each and mixed per sample, `(1 - m) f0 + m f1`.
pub(super) fn add_specular_mapped(
    m: &Material,
    mr: &MetallicRoughness,
    shading: Shading,
    spec: &Spec,
    radiance: &mut [Vec3],
    samples: &[Sample],
) {
    let level = |j: usize| samples[spec.idx[j]].level;
    let mut order: Vec<usize> = (0..spec.idx.len()).collect();
    order.sort_by_key(|&j| level(j));
    let mut sub = Spec::default();
    let mut f = [
        vec![Vec3::ZERO; radiance.len()],
        vec![Vec3::ZERO; radiance.len()],
    ];
    let mut k = 0;
    while k < order.len() {
        let lv = level(order[k]);
        let end = k + order[k..].iter().take_while(|&&j| level(j) == lv).count();
        sub.clear();
        for &j in &order[k..end] {
            let c = &spec.cols;
            sub.push(
                spec.idx[j],
                [c[0][j], c[1][j], c[2][j]],
                [c[3][j], c[4][j], c[5][j]],
                spec.li[j],
            );
        }
        let metal = |i: &usize| samples[*i].metal;
        let need = [
            sub.idx.iter().any(|i| metal(i) < 1.0),
            sub.idx.iter().any(|i| metal(i) > 0.0),
        ];
        for (c, model) in mr.models(lv).iter().enumerate() {
            if need[c] {
                let corner = Material {
                    kd: m.kd,
                    ks: m.ks,
                    albedo: m.albedo,
                    texture: None,
                    bump: None,
                    specular: model.clone(),
                    maps: None,
                };
                add_specular(&corner, shading, &mut sub, &mut f[c], samples);
            }
        }
        // A sample may hold several entries (all at its level): its sums are added once,
        // then cleared.
        for &i in &sub.idx {
            let mm = samples[i].metal;
            radiance[i] += f[0][i] * (1.0 - mm) + f[1][i] * mm;
            (f[0][i], f[1][i]) = (Vec3::ZERO, Vec3::ZERO);
        }
        k = end;
    }
}
