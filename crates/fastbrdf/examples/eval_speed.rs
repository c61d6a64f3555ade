//! `Kernel::eval` of GGX Cook-Torrance (alpha 0.3, the Python package's and the renderer's main
//! case) on one thread, best instruction set, over `direction_pairs` (about N pairs): the
//! median of R calls in ns per evaluation and M evaluations/s; then the batched sampler's `pdf`
//! (visible normals) over the same pairs. What issue 30's `rsqrt64` pair set-up, the series
//! near unit length and the fused `pdf` unit tier were measured with: run it on two builds,
//! interleaved.
//! Run: `cargo run --release -p fastbrdf --example eval_speed [N] [R]` (default 65536, 300).

use fastbrdf::ModelSpec;
use fastbrdf::batch::sample::Sampler;
use fastbrdf::batch::{Input, Isa, Kernel};
use fastbrdf::sample::Strategy;
use std::time::Instant;

mod common;

fn main() {
    let arg = |k: usize, default: usize| {
        std::env::args()
            .nth(k)
            .and_then(|a| a.parse().ok())
            .unwrap_or(default)
    };
    let (n, rounds) = (arg(1, 1 << 16), arg(2, 300));
    let cols = common::pair_columns(n, 3);
    let n = cols[0].len();
    let input = Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
    let spec = ModelSpec::parse("cook-torrance", &[("d", "ggx"), ("alpha", "0.3")]).unwrap();
    let k = Kernel::new(&spec).unwrap();
    let mut out = vec![0.0f32; n];
    let time = |f: &mut dyn FnMut()| {
        let times: Vec<f64> = (0..rounds.max(1))
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .collect();
        common::median(times)
    };
    let report = |what: &str, m: f64, out: &[f32]| {
        println!(
            "{spec}, {} pairs, {}: {:.2} ns per {what}, {:.1} M/s (checksum {})",
            n,
            Isa::best().name(),
            m / n as f64 * 1e9,
            n as f64 / m / 1e6,
            out.iter().map(|&x| x as f64).sum::<f64>()
        )
    };
    let m = time(&mut || k.eval(input, &mut out).unwrap());
    report("evaluation", m, &out);
    // The density of wi given wo by the default strategy (GGX's visible normals): the
    // batched sampler's `pdf`, whose unit tier these unit pairs take.
    let sampler = Sampler::new(&spec).unwrap();
    let (wi, wo) = (
        [&cols[0][..], &cols[1], &cols[2]],
        [&cols[3][..], &cols[4], &cols[5]],
    );
    let m = time(&mut || sampler.pdf(Strategy::Auto, wo, wi, &mut out).unwrap());
    report("density", m, &out);
}
