//! Question: how long does a 1024x1024 sphere with one light and 1 sample per pixel take, do
//! threads scale, and what does shading through the batch kernels buy over the scalar model?
//! Specular models: pow (n = 200, one exp2/log2 per sample) and seed 000's Cook-Torrance.
//! Run: `cargo bench -p fastbrdf-render --bench render`.

use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::Specular;
use fastbrdf_render::setup::{self, SceneSpec};
use std::sync::Arc;

fn main() {
    divan::main();
}

fn scene(id: &str) -> fastbrdf_render::scene::Scene {
    let spec = SceneSpec::new();
    let loaded = setup::load(&spec).unwrap();
    let params: &[(&str, &str)] = if id == "pow" {
        &[("n", "200")]
    } else {
        &[("alpha", "0.3"), ("g", "v-cavity"), ("f", "schlick")]
    };
    let model = fastbrdf::ModelSpec::parse(id, params).unwrap();
    setup::scene(&spec, &loaded, Arc::new(Specular::new(&model).unwrap()))
}

fn run(id: &str, shading: Shading, threads: usize) {
    let s = scene(id);
    let opts = Options {
        width: 1024,
        height: 1024,
        spp: 1,
        shading,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| divan::black_box(render(&s, &opts, &|_, _| {}).unwrap()));
}

#[divan::bench(args = ["pow", "cook-torrance"], sample_count = 10)]
fn sphere_1024_batch_all_threads(id: &str) {
    run(id, Shading::Batch, rayon::current_num_threads());
}

#[divan::bench(args = ["pow", "cook-torrance"], sample_count = 10)]
fn sphere_1024_batch_one_thread(id: &str) {
    run(id, Shading::Batch, 1);
}

#[divan::bench(args = ["pow", "cook-torrance"], sample_count = 10)]
fn sphere_1024_scalar_all_threads(id: &str) {
    run(id, Shading::Scalar, rayon::current_num_threads());
}
