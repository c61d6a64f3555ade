//! `Kernel::eval` of GGX Cook-Torrance (alpha 0.3, the Python package's and the renderer's main
//! case) on one thread, best instruction set, over `direction_pairs` (about N pairs): the
//! median of R calls in ns per evaluation and M evaluations/s. What issue 30's `rsqrt64` pair
//! set-up was measured with: run it on two builds, interleaved.
//! Run: `cargo run --release -p fastbrdf --example eval_speed [N] [R]` (default 65536, 300).

use fastbrdf::ModelSpec;
use fastbrdf::batch::{Input, Isa, Kernel};
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
    let times: Vec<f64> = (0..rounds.max(1))
        .map(|_| {
            let t = Instant::now();
            k.eval(input, &mut out).unwrap();
            t.elapsed().as_secs_f64()
        })
        .collect();
    let m = common::median(times);
    println!(
        "{spec}, {} pairs, {}: {:.2} ns per evaluation, {:.1} M/s (checksum {})",
        n,
        Isa::best().name(),
        m / n as f64 * 1e9,
        n as f64 / m / 1e6,
        out.iter().map(|&x| x as f64).sum::<f64>()
    );
}
