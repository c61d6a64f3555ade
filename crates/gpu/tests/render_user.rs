//! The GPU renderer shading with a user's shader (`fastbrdf_gpu::render::render_user`, issue
//! 31) against the CPU renderer shading the same model as an RGB BRDF
//! (`fastbrdf_render::user::UserRgb` of the shader's compute evaluator, `GpuBrdf`): the whole
//! BRDF, weights kd 0, ks 1.
//!
//! Tolerance: `tests/render.rs`'s (8-bit sRGB: PSNR >= 45 dB, every channel within 2/255 but
//! on at most 0.1% of the pixels; on a software adapter also 1e-4 relative in linear radiance
//! on 99.9% of the pixels), and, as there, each comparison must fail against a CPU render with
//! its first light 5% brighter. Both sides evaluate the user's function in f32 on the same
//! directions (the CPU's f32 directions, widened to f64 and back by `UserRgb`), so they differ
//! only where the renderers themselves do.

mod common;
use common::{data, owned};

use fastbrdf::user::UserBrdf;
use fastbrdf_gpu::Gpu;
use fastbrdf_gpu::render::{render as gpu_render, render_user};
use fastbrdf_gpu::user::{GpuBrdf, UserShader};
use fastbrdf_render::compare;
use fastbrdf_render::film::Film;
use fastbrdf_render::render::{Antialias, Options, Sampler, Shading, render as cpu_render};
use fastbrdf_render::scene::{Light, LightKind, Scene, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use fastbrdf_render::user::UserRgb;
use glam::Vec3;
use std::sync::Arc;

fn opts() -> Options {
    Options {
        width: 96,
        height: 96,
        spp: 2,
        shading: Shading::Batch,
        sampler: Sampler::default(),
        aa: Antialias::Grid,
    }
}

/// The sphere over the floor, a directional and a point light (white; shadows on), the
/// whole-BRDF weights 0, 1.
fn scene_spec() -> SceneSpec {
    let mut spec = SceneSpec::new();
    spec.floor = true;
    (spec.kd, spec.ks) = (0.0, 1.0);
    spec
}

fn scene_with(specular: Specular) -> Scene {
    let spec = scene_spec();
    let loaded = setup::load(&spec).unwrap();
    let mut scene = setup::scene(&spec, &loaded, Arc::new(specular));
    scene.lights.push(Light {
        kind: LightKind::Point {
            position: Vec3::new(-1.5, 2.5, 2.0),
        },
        color: Vec3::ONE,
        intensity: 12.0,
    });
    scene
}

/// A user's model loaded for both renderers: the shader, its values, and the scene whose
/// specular term is its CPU-side RGB BRDF.
struct Model {
    shader: UserShader,
    given: Vec<(String, String)>,
}

impl Model {
    fn load(file: &str, given: &[(&str, &str)]) -> Self {
        let shader = UserShader::load(&data(file)).unwrap_or_else(|e| panic!("{e}"));
        Self {
            shader,
            given: owned(given),
        }
    }

    fn scene(&self, gpu: &Gpu) -> Scene {
        let brdf = GpuBrdf::new(&gpu.device, &gpu.queue, self.shader.clone(), &self.given)
            .unwrap_or_else(|e| panic!("{e}"));
        let rgb = UserRgb::new(Arc::new(brdf) as Arc<dyn UserBrdf>);
        scene_with(Specular::rgb(&self.shader.name(), Arc::new(rgb)))
    }

    fn gpu_film(&self, gpu: &Gpu, scene: &Scene) -> Film {
        let values = self.shader.values(&self.given).unwrap();
        render_user(
            &gpu.device,
            &gpu.queue,
            scene,
            &opts(),
            &self.shader,
            &values,
            &|_, _| {},
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }
}

/// How two 8-bit renders differ (`tests/render.rs`'s measure).
struct Diff {
    psnr: f64,
    max: u8,
    over2: f64,
    linear: f32,
}

impl std::fmt::Display for Diff {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "PSNR {:.1} dB, max {}/255, {:.3}% of pixels over 2/255, linear {:.2e}",
            self.psnr, self.max, self.over2, self.linear
        )
    }
}

impl Diff {
    fn of(a: &Film, b: &Film) -> Self {
        let (x, y) = (a.to_srgb8(1.0), b.to_srgb8(1.0));
        let m = compare::metrics("gpu", &x, &y, a.width, a.height);
        let px: Vec<u8> = x
            .chunks_exact(3)
            .zip(y.chunks_exact(3))
            .map(|(p, q)| (0..3).map(|k| p[k].abs_diff(q[k])).max().unwrap())
            .collect();
        let mut rel: Vec<f32> = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(c, g)| ((*g - *c).abs() / c.max(Vec3::ONE)).max_element())
            .collect();
        rel.sort_by(f32::total_cmp);
        Diff {
            psnr: m.psnr,
            max: px.iter().copied().max().unwrap(),
            over2: 100.0 * px.iter().filter(|&&d| d > 2).count() as f64 / px.len() as f64,
            linear: rel[(rel.len() - 1) * 999 / 1000],
        }
    }

    fn passes(&self) -> bool {
        self.psnr >= 45.0 && self.over2 <= 0.1
    }

    fn passes_software(&self) -> bool {
        self.passes() && self.linear <= 1e-4
    }
}

/// The GPU render of `m` against the CPU's (and the CPU's with a 5% brighter light, which
/// must miss); returns the GPU's film.
fn matches_the_cpu(label: &str, gpu: &Gpu, m: &Model) -> Film {
    let scene = m.scene(gpu);
    let g = m.gpu_film(gpu, &scene);
    let c = cpu_render(&scene, &opts(), &|_, _| {}).unwrap();
    if let Some(e) = scene.objects[0]
        .material
        .specular
        .rgb
        .as_ref()
        .unwrap()
        .failure()
    {
        panic!("{label}: the CPU's evaluator failed: {e}");
    }
    let d = Diff::of(&c, &g);
    eprintln!("{label}, GPU against CPU: {d}");
    assert!(d.passes(), "{label}: {d}");
    if gpu.is_software() {
        assert!(d.passes_software(), "{label} (software adapter): {d}");
    }
    let mut brighter = scene;
    brighter.lights[0].intensity *= 1.05;
    let far = Diff::of(&cpu_render(&brighter, &opts(), &|_, _| {}).unwrap(), &g);
    assert!(
        !far.passes(),
        "{label}: a 5% brighter light passes too: {far}"
    );
    g
}

/// walter.brdf (GGX, Smith, no Fresnel; Ks = 1, Kd = 0) on the GPU: the CPU's picture of the
/// same file, and the GPU's picture of the registry's cook-torrance d=ggx g=smith-ggx f=none,
/// the same model (`tests/user_shaders.rs`: within 5e-5 of the peak), shaded grey.
#[test]
fn walter_matches_the_cpu_and_the_registry_model() {
    let Some(gpu) = common::gpu() else { return };
    let walter = Model::load(
        "brdf-explorer/walter.brdf",
        &[("Kd", "0"), ("Ks", "1"), ("alphaG", "0.1")],
    );
    let g = matches_the_cpu("walter.brdf", gpu, &walter);
    let film_max = g.pixels.iter().map(|p| p.max_element()).fold(0.0, f32::max);
    assert!(film_max > 0.5, "the highlight is missing: max {film_max}");

    let spec = common::spec(
        "cook-torrance",
        &[
            ("alpha", "0.1"),
            ("d", "ggx"),
            ("g", "smith-ggx"),
            ("f", "none"),
        ],
    );
    let registry = scene_with(Specular::new(&spec).unwrap());
    let r = gpu_render(&gpu.device, &gpu.queue, &registry, &opts()).unwrap();
    let d = Diff::of(&r, &g);
    eprintln!("walter.brdf against cook-torrance, both on the GPU: {d}");
    assert!(d.passes(), "walter.brdf against cook-torrance: {d}");
}

/// A coloured model with parameters (blinn_phong.glsl: colours kd and ks, float n, switch
/// diffuse) matches the CPU in R, G and B, and other values give another picture, the one the
/// CPU renders with them.
#[test]
fn parameters_and_colours_reach_the_render() {
    let Some(gpu) = common::gpu() else { return };
    let defaults = Model::load("user/blinn_phong.glsl", &[]);
    let a = matches_the_cpu("blinn_phong.glsl, defaults", gpu, &defaults);
    // kd = 0.5, 0.25, 0.125 by default: the picture is reddest (the background and the white
    // ks are grey).
    let sum = a.pixels.iter().fold(Vec3::ZERO, |s, p| s + *p);
    assert!(sum.x > sum.y && sum.y > sum.z, "not kd's hue: {sum}");

    let other = Model::load(
        "user/blinn_phong.glsl",
        &[("n", "400"), ("kd", "0.1,0.3,0.6")],
    );
    let b = matches_the_cpu("blinn_phong.glsl, n=400 kd=0.1,0.3,0.6", gpu, &other);
    let d = Diff::of(&a, &b);
    eprintln!("blinn_phong.glsl, defaults against other values: {d}");
    assert!(!d.passes(), "other parameter values, the same picture: {d}");
    let sum = b.pixels.iter().fold(Vec3::ZERO, |s, p| s + *p);
    assert!(sum.z > sum.y && sum.y > sum.x, "not kd's hue: {sum}");
}

/// Values that are not one per parameter are an input error naming the shader; a scene with
/// an RGB BRDF given to the plain renderer is refused, naming it.
#[test]
fn wrong_values_and_rgb_without_a_shader_are_errors() {
    let Some(gpu) = common::gpu() else { return };
    let m = Model::load("brdf-explorer/walter.brdf", &[]);
    let scene = m.scene(gpu);
    let Err(e) = render_user(
        &gpu.device,
        &gpu.queue,
        &scene,
        &opts(),
        &m.shader,
        &[],
        &|_, _| {},
    ) else {
        panic!("no values for five parameters rendered");
    };
    let msg = e.to_string();
    assert!(
        msg.contains("walter.brdf") && msg.contains("0 parameter values for its 5"),
        "{msg}"
    );
    let Err(e) = gpu_render(&gpu.device, &gpu.queue, &scene, &opts()) else {
        panic!("an RGB BRDF without a shader rendered");
    };
    let msg = e.to_string();
    assert!(
        msg.contains("walter.brdf") && msg.contains("RGB BRDF"),
        "{msg}"
    );
}
