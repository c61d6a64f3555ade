//! The GPU renderer on a glTF scene (issue 33) against the CPU renderer: two coloured `gltf-pbr`
//! spheres (a dielectric and a metal) on a floor with a base colour texture (a coloured
//! material tinted by its texels, `Specular::tint`) and anisotropy (its frame the mesh's
//! MikkTSpace tangents), read from a `.glb` built here by the reader the CLI uses, 32 x 32 at
//! one sample per pixel, shadows on.
//!
//! - Direct light (the file's directional light): the tolerance of `tests/render.rs`, every
//!   8-bit channel within 2/255 but on 0.1% of the pixels, PSNR at least 45 dB, and on a
//!   software adapter 1e-4 linear (relative to max(1, value)) on 99.9% of the pixels.
//!   Measured on lavapipe: every 8-bit value equal, linear 99.9th percentile 2.4e-7.
//!   It can fail: the CPU's pictures of the scene without the floor's texture and without its
//!   tangents miss it (the latter: 27% of the pixels over 2/255), and the GPU's picture is
//!   coloured (the spheres' R and B differ).
//! - Environment light (the built-in sky, its sun included): the GPU draws its third direction
//!   from a GGX lobe, the CPU from the model's sampler (`tests/render_env.rs`), so the pictures
//!   agree in the limit: the GPU's 256 passes against the CPU's 512, linear RMSE at most 0.015
//!   and the means within 0.5%. Measured on lavapipe against the CPU's 2048 passes: the GPU's
//!   RMSE 0.0033 at 256 passes and 0.00096 at 1024 (the CPU's own 0.0030 and 0.00091), means
//!   within 1e-4. This is the test that found lavapipe's loop limit (`render/env.rs`,
//!   `PASSES_PER_DRAW`): with every pass in one draw the GPU's picture was 1% dark at 256
//!   passes and a third at 1024. It can fail: the GPU's picture without the floor's texture
//!   misses the mean (by 24%).

mod common;
#[path = "../../render/tests/gltf_build/mod.rs"]
mod gltf_build;

use fastbrdf_gpu::render::render as gpu_render;
use fastbrdf_render::compare;
use fastbrdf_render::env::EnvMap;
use fastbrdf_render::film::Film;
use fastbrdf_render::geometry::TriMesh;
use fastbrdf_render::gltf::{self, GltfScene};
use fastbrdf_render::render::{Antialias, Options, Sampler, Shading, render as cpu_render};
use fastbrdf_render::scene::{Scene, Shape};
use fastbrdf_render::setup::SceneSpec;
use glam::Vec3;
use gltf_build::Doc;
use serde_json::json;
use std::path::Path;
use std::sync::Arc;

const SIZE: u32 = 32;

fn opts() -> Options {
    Options {
        width: SIZE,
        height: SIZE,
        spp: 1,
        shading: Shading::Batch,
        sampler: Sampler::Sobol,
        aa: Antialias::Grid,
    }
}

/// A 4 x 4 PNG of the texels `f(x, y)`.
fn png(f: impl Fn(u8, u8) -> [u8; 3]) -> Vec<u8> {
    let rgb: Vec<u8> = (0..16u8).flat_map(|i| f(i % 4, i / 4)).collect();
    fastbrdf_render::film::png_bytes(&rgb, 4, 4).unwrap()
}

/// The data URI of `png`.
fn uri(png: &[u8]) -> String {
    format!("data:image/png;base64,{}", gltf_build::base64(png))
}

/// The floor's textures: base colour (a checker of warm and cool texels of different
/// brightness), normal (tilts of up to about 30 degrees), occlusion (R: 0.3 to 1), emission,
/// metallic-roughness (G: roughness 0.4 to 0.55, B: metallic 0 to 1; a narrow range of
/// roughness keeps the models to build few: one per level of 1/256 and metallic 0 and 1).
fn textures() -> [Vec<u8>; 5] {
    [
        png(|x, y| {
            if (x + y) % 2 == 0 {
                [250, 120 + 30 * x, 40]
            } else {
                [30, 60 + 40 * y, 220]
            }
        }),
        png(|x, y| [68 + 40 * x, 188 - 40 * y, 230]),
        png(|x, y| [80 + 25 * (x + y), 0, 0]),
        png(|x, y| [40 * x, 200, 40 * y]),
        png(|x, y| [0, 102 + 13 * x, 85 * y]),
    ]
}

/// The scene: two coloured spheres and a textured floor, a camera, a directional light.
fn doc() -> Doc {
    let mut d = Doc::new();
    d.uses("KHR_lights_punctual", false);
    d.uses("KHR_materials_anisotropy", false);
    d.json["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "directional", "intensity": 3.0}]}});
    let dielectric = d.push(
        "materials",
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.1, 1.0],
            "metallicFactor": 0.0, "roughnessFactor": 0.4}}),
    );
    let metal = d.push(
        "materials",
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.7, 0.3, 1.0],
            "metallicFactor": 1.0, "roughnessFactor": 0.3}}),
    );
    let floor = d.push(
        "materials",
        json!({"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.6, 1.0],
            "metallicFactor": 1.0, "roughnessFactor": 1.0, "baseColorTexture": {"index": 0},
            "metallicRoughnessTexture": {"index": 4}},
            "normalTexture": {"index": 1, "scale": 0.8},
            "occlusionTexture": {"index": 2, "strength": 0.7},
            "emissiveTexture": {"index": 3}, "emissiveFactor": [0.2, 0.1, 0.05],
            "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.8, "anisotropyRotation": 0.6}}}),
    );
    for (i, t) in textures().iter().enumerate() {
        d.push("images", json!({"uri": uri(t)}));
        d.push("textures", json!({"source": i}));
    }
    let a = d.sphere(16, Some(dielectric));
    let b = d.sphere(16, Some(metal));
    let q = d.quad(true, Some(floor));
    let na = d.push("nodes", json!({"mesh": a, "translation": [-1.1, 0.0, 0.0]}));
    let nb = d.push("nodes", json!({"mesh": b, "translation": [1.1, 0.0, 0.0]}));
    // The floor: the quad turned to face up, then 60 degrees about y, so that its tangents
    // (along its u) differ from any_orthonormal_pair's frame about +y (+x).
    let (h, s, c) = (std::f32::consts::FRAC_1_SQRT_2, 0.5f32, 0.75f32.sqrt());
    let nf = d.push(
        "nodes",
        json!({"mesh": q, "translation": [0.0, -1.0, 0.0], "scale": [6.0, 6.0, 6.0],
               "rotation": [-c * h, s * h, s * h, c * h]}),
    );
    let cam = d.push(
        "cameras",
        json!({"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}),
    );
    let nc = d.push(
        "nodes",
        json!({"camera": cam, "translation": [0.0, 1.0, 6.0], "rotation": [-0.08, 0.0, 0.0, 0.9968]}),
    );
    let nl = d.push(
        "nodes",
        json!({"rotation": [-0.45, 0.25, 0.0, 0.857], "extensions": {"KHR_lights_punctual": {"light": 0}}}),
    );
    d.scene(&[na, nb, nf, nc, nl]);
    d
}

fn read() -> GltfScene {
    gltf::from_bytes("t.glb", &doc().glb(), Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

/// The scene with shadows (and `env` sampled `samples` times); `textured`: the floor's
/// texture kept (else dropped).
fn scene(g: &GltfScene, env: Option<Arc<EnvMap>>, samples: u32, textured: bool) -> Scene {
    let mut spec = SceneSpec::new();
    spec.shadows = true;
    spec.env_samples = samples;
    let mut s = g.scene(&spec, env, &g.specs(&[]).unwrap()).unwrap();
    if !textured {
        for o in &mut s.objects {
            let sp = &o.material.specular;
            if sp.tint.is_some() {
                o.material.specular = Arc::new(
                    fastbrdf_render::scene::Specular::new(sp.brdf.as_ref().unwrap()).unwrap(),
                );
            }
        }
    }
    s
}

/// `s` without its glTF maps (normal, occlusion, emissive and metallic-roughness textures).
fn without_maps(mut s: Scene) -> Scene {
    for o in &mut s.objects {
        o.material.maps = None;
    }
    s
}

/// `s` with its meshes' tangents dropped (the local frame then any_orthonormal_pair's).
fn without_tangents(mut s: Scene) -> Scene {
    for o in &mut s.objects {
        if let Shape::Mesh(m) = &o.shape {
            let plain = TriMesh::new(
                m.positions.clone(),
                m.normals.clone(),
                m.uvs.clone(),
                m.triangles.clone(),
            );
            o.shape = Shape::Mesh(Arc::new(plain));
        }
    }
    s
}

/// 8-bit and linear differences: (PSNR, largest channel difference in 1/255, percent of pixels
/// over 2/255, 99.9th percentile of the linear difference relative to max(1, cpu)).
fn diff(cpu: &Film, gpu: &Film) -> (f64, u8, f64, f32) {
    let (a, b) = (cpu.to_srgb8(1.0), gpu.to_srgb8(1.0));
    let m = compare::metrics("gpu", &a, &b, cpu.width, cpu.height);
    let px: Vec<u8> = a
        .chunks_exact(3)
        .zip(b.chunks_exact(3))
        .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap())
        .collect();
    let mut rel: Vec<f32> = cpu
        .pixels
        .iter()
        .zip(&gpu.pixels)
        .map(|(c, g)| ((*g - *c).abs() / c.max(Vec3::ONE)).max_element())
        .collect();
    rel.sort_by(f32::total_cmp);
    (
        m.psnr,
        px.iter().copied().max().unwrap(),
        100.0 * px.iter().filter(|&&d| d > 2).count() as f64 / px.len() as f64,
        rel[(rel.len() - 1) * 999 / 1000],
    )
}

fn passes(d: (f64, u8, f64, f32), software: bool) -> bool {
    d.0 >= 45.0 && d.2 <= 0.1 && (!software || d.3 <= 1e-4)
}

#[test]
fn coloured_and_textured_materials_render_as_on_the_cpu() {
    let Some(g) = common::gpu() else {
        return;
    };
    let software = g.is_software();
    let gs = read();
    let s = scene(&gs, None, 1, true);
    assert_eq!(s.objects.len(), 3);
    assert!(
        s.objects
            .iter()
            .all(|o| o.material.specular.channels.len() == 3)
    );
    assert_eq!(
        s.objects
            .iter()
            .filter(|o| o.material.specular.tint.is_some())
            .count(),
        1
    );
    assert!(s.objects.iter().any(|o| o.material.maps.is_some()));
    // The floor is anisotropic: its mesh carries tangents (MikkTSpace), its frame theirs.
    assert!(
        s.objects
            .iter()
            .any(|o| matches!(&o.shape, Shape::Mesh(m) if !m.tangents.is_empty()))
    );
    let t = std::time::Instant::now();
    let gpu = gpu_render(&g.device, &g.queue, &s, &opts()).unwrap();
    eprintln!("GPU render: {:.2} s", t.elapsed().as_secs_f64());
    let cpu = cpu_render(&s, &opts(), &|_, _| {}).unwrap();
    let d = diff(&cpu, &gpu);
    eprintln!(
        "glTF scene, direct light: PSNR {:.1} dB, max {}/255, {:.3}% over 2/255, linear {:.2e}",
        d.0, d.1, d.2, d.3
    );
    assert!(passes(d, software), "{d:?}");
    // The GPU's picture is coloured: the dielectric's red over its blue, the floor textured.
    let reddish = gpu.pixels.iter().any(|p| p.x > 2.0 * p.z && p.x > 0.05);
    let bluish = gpu.pixels.iter().any(|p| p.z > 1.5 * p.x && p.z > 0.05);
    assert!(reddish && bluish, "a coloured picture");
    // It can fail: the texture moves the picture beyond the tolerance.
    let plain = cpu_render(&scene(&gs, None, 1, false), &opts(), &|_, _| {}).unwrap();
    let d = diff(&plain, &gpu);
    assert!(!passes(d, software), "without the texture: {d:?}");
    // And the tangent frame turns the anisotropic floor's highlight.
    let turned = cpu_render(
        &without_tangents(scene(&gs, None, 1, true)),
        &opts(),
        &|_, _| {},
    )
    .unwrap();
    let d = diff(&turned, &gpu);
    eprintln!("against the CPU's picture without the tangents: {d:?}");
    assert!(!passes(d, software), "without the tangents: {d:?}");
    // And the normal and emissive textures change it too.
    let bare = cpu_render(
        &without_maps(scene(&gs, None, 1, true)),
        &opts(),
        &|_, _| {},
    )
    .unwrap();
    let d = diff(&bare, &gpu);
    eprintln!("against the CPU's picture without the maps: {d:?}");
    assert!(!passes(d, software), "without the maps: {d:?}");
}

/// RMSE of the linear channels, and the two means.
fn rmse(a: &Film, b: &Film) -> (f64, f64, f64) {
    let (mut s, mut ma, mut mb) = (0.0f64, 0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = *p - *q;
        s += f64::from(d.dot(d));
        ma += f64::from(p.x + p.y + p.z);
        mb += f64::from(q.x + q.y + q.z);
    }
    let n = 3.0 * a.pixels.len() as f64;
    ((s / n).sqrt(), ma / n, mb / n)
}

#[test]
fn under_the_sky_the_gpu_converges_to_the_cpus_picture() {
    let Some(g) = common::gpu() else {
        return;
    };
    let gs = read();
    let sky = Arc::new(EnvMap::from_spec("sky").unwrap());
    let reference = cpu_render(
        &scene(&gs, Some(sky.clone()), 512, true),
        &opts(),
        &|_, _| {},
    )
    .unwrap();
    let t = std::time::Instant::now();
    let gpu = gpu_render(
        &g.device,
        &g.queue,
        &scene(&gs, Some(sky.clone()), 256, true),
        &opts(),
    )
    .unwrap();
    eprintln!("GPU render: {:.2} s", t.elapsed().as_secs_f64());
    gpu.check_finite().unwrap();
    let (e, m, mref) = rmse(&gpu, &reference);
    eprintln!("glTF scene, sky: RMSE {e:.4}, mean {m:.4} vs {mref:.4}");
    assert!(e <= 0.015, "RMSE {e}");
    assert!((m - mref).abs() <= 0.005 * mref, "mean {m} vs {mref}");
    // It can fail: without the floor's texture the mean moves.
    let plain = gpu_render(
        &g.device,
        &g.queue,
        &scene(&gs, Some(sky), 16, false),
        &opts(),
    )
    .unwrap();
    let (_, m, _) = rmse(&plain, &reference);
    assert!(
        (m - mref).abs() > 0.05 * mref,
        "without the texture: {m} vs {mref}"
    );
}

/// The per-scene shader (`fastbrdf_gpu::render::features`: the parts no object uses left out)
/// draws the same bits as the shader with every part on: the glTF scene (tint, every map,
/// tangents, a metallic-roughness texture, meshes and their shadow rays) under its lights
/// and under the sky, the sky without shadow rays, and the scene without its maps.
#[test]
fn the_per_scene_shader_draws_the_same_bits() {
    let Some(g) = common::gpu() else {
        return;
    };
    let gs = read();
    let sky = Arc::new(EnvMap::from_spec("sky").unwrap());
    let o = Options {
        width: 40,
        height: 32,
        ..opts()
    };
    let no_shadows = |mut s: Scene| {
        s.shadows = false;
        s
    };
    let cases = [
        ("direct light", scene(&gs, None, 1, true)),
        ("sky", scene(&gs, Some(sky.clone()), 2, true)),
        (
            "sky, no shadow rays",
            no_shadows(scene(&gs, Some(sky), 2, true)),
        ),
        ("without maps", without_maps(scene(&gs, None, 1, true))),
    ];
    for (label, s) in cases {
        let differ = common::pixels_unlike_every_part_on(g, &s, &o);
        assert_eq!(differ, 0, "{label}: {differ} pixels differ");
    }
}
