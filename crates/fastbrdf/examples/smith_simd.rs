//! The exact Beckmann Smith terms in Cook-Torrance's kernels (issue 30): the fused kernel
//! (the rule of `batch::cook_torrance`), the generic path and the plan's parts per element,
//! timed interleaved on the same 4096 direction pairs, best instruction set, one thread.
//! Medians of 41 rounds, ns per evaluation.
//! Run: `cargo run --release -p fastbrdf --example smith_simd`.

use fastbrdf::ModelSpec;
use fastbrdf::batch::{CtPath, Input, Isa, Kernel};
use std::time::Instant;

mod common;
use common::median;

fn main() {
    let cols = common::pair_columns(4096, 3);
    let n = cols[0].len();
    let input = Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
    println!(
        "isa: {}, {n} pairs, ns per evaluation (median of 41): fused / generic / per element",
        Isa::best().name()
    );
    let configs: [&[(&str, &str)]; 4] = [
        &[],
        &[("g", "smith-beckmann-correlated")],
        &[("f", "schlick")],
        &[("g", "smith-rational")],
    ];
    for given in configs {
        let spec = ModelSpec::parse("cook-torrance", given).unwrap();
        let plan = *spec.plan().unwrap();
        let ks = [CtPath::Rule, CtPath::Generic, CtPath::PerElement]
            .map(|p| Kernel::from_plan_path("cook-torrance", &plan, p).unwrap());
        let mut out = vec![0.0f32; n];
        let mut t = [vec![], vec![], vec![]];
        for _ in 0..41 {
            for (k, t) in ks.iter().zip(t.iter_mut()) {
                let s = Instant::now();
                for _ in 0..20 {
                    k.eval_with(Isa::best(), input, &mut out).unwrap();
                }
                t.push(s.elapsed().as_secs_f64() * 1e9 / (20 * n) as f64);
            }
        }
        let [a, b, c] = t.map(median);
        println!(
            "{given:?} (simd {}): {a:.2} / {b:.2} / {c:.2}",
            ks.iter()
                .map(|k| k.simd().to_string())
                .collect::<Vec<_>>()
                .join(",")
        );
    }
}
