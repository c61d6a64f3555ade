//! Question (issue 15): what does the environment light cost against direct light alone?
//! 512x512, 16 samples per pixel (`spp` 4: 4 x 4 primary rays per pixel), shadows on,
//! seed 000's Cook-Torrance (alpha 0.3, V-cavity, Schlick): the built-in sky with one
//! environment sample per primary ray (a map-sampled and a cosine-sampled direction, their
//! shadow rays and the batch BRDF evaluation) against the default key light with its shadow
//! ray; on the embedded face mesh (`--mesh face`: MediaPipe's canonical face) and on the
//! sphere; all threads and one. Each environment sample is three directions (the map's, a
//! cosine one and the BRDF's own, combined by MIS) with their shadow rays.
//! Run: `cargo bench -p fastbrdf-render --bench envlight`; the ratio is env / direct of the
//! same row.

use fastbrdf_render::render::{Options, Shading, render};
use fastbrdf_render::scene::{Scene, Specular};
use fastbrdf_render::setup::{self, SceneSpec};
use std::path::PathBuf;
use std::sync::Arc;

fn main() {
    divan::main();
}

fn scene(subject: &str, env: bool) -> Scene {
    let mut spec = SceneSpec::new();
    if subject == "face" {
        spec.mesh = Some(PathBuf::from(setup::BUILTIN_MESH));
    }
    if env {
        spec.env = Some("sky".into());
        spec.env_samples = 1;
    }
    let loaded = setup::load(&spec).unwrap();
    let model = fastbrdf::ModelSpec::parse(
        "cook-torrance",
        &[("alpha", "0.3"), ("g", "v-cavity"), ("f", "schlick")],
    )
    .unwrap();
    setup::scene(&spec, &loaded, Arc::new(Specular::new(&model).unwrap()))
}

fn run(bencher: divan::Bencher, subject: &str, env: bool, threads: usize) {
    let s = scene(subject, env);
    let opts = Options {
        width: 512,
        height: 512,
        spp: 4,
        shading: Shading::Batch,
        sampler: fastbrdf_render::render::Sampler::default(),
        aa: fastbrdf_render::render::Antialias::default(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    bencher
        .bench_local(|| pool.install(|| divan::black_box(render(&s, &opts, &|_, _| {}).unwrap())));
}

#[divan::bench(args = ["face", "sphere"], sample_count = 3)]
fn env_sky_all_threads(bencher: divan::Bencher, subject: &str) {
    run(bencher, subject, true, rayon::current_num_threads());
}

#[divan::bench(args = ["face", "sphere"], sample_count = 3)]
fn direct_all_threads(bencher: divan::Bencher, subject: &str) {
    run(bencher, subject, false, rayon::current_num_threads());
}

#[divan::bench(args = ["face", "sphere"], sample_count = 3)]
fn env_sky_one_thread(bencher: divan::Bencher, subject: &str) {
    run(bencher, subject, true, 1);
}

#[divan::bench(args = ["face", "sphere"], sample_count = 3)]
fn direct_one_thread(bencher: divan::Bencher, subject: &str) {
    run(bencher, subject, false, 1);
}
