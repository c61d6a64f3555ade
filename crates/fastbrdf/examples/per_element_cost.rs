//! Times `batch::per_element` (grouped per-element parameters) against the scalar-parameter
//! kernel on GGX, f32, single call per case: `cargo run --release -p fastbrdf --example
//! per_element_cost [n] [count]`. Prints M elements/s for 1, 256 and all-distinct alpha values.

use fastbrdf::ModelSpec;
use fastbrdf::batch::per_element::{PerElement, Rows};
use fastbrdf::batch::{Input, Kernel};
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1 << 20);
    let spec = ModelSpec::parse("ggx", &[]).unwrap();
    let mut seed = 1u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 40) as f64 / (1u64 << 24) as f64
    };
    let cos: Vec<f32> = (0..n).map(|_| rnd() as f32).collect();
    let mut out = vec![0.0f32; n];
    let k = Kernel::new(&spec).unwrap();
    let best = |f: &mut dyn FnMut()| {
        (0..5)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let t = best(&mut || k.eval(Input::Cos(&cos), &mut out).unwrap());
    println!("scalar alpha (one thread)   {:9.2} M/s", n as f64 / t / 1e6);
    let pe = PerElement::new(&spec, &["alpha"]).unwrap();
    let only: Option<usize> = std::env::args().nth(2).and_then(|a| a.parse().ok());
    for (label, count) in [
        ("1 value", 1usize),
        ("256 values", 256),
        ("all distinct", 0),
    ] {
        if only.is_some_and(|o| o != count) {
            continue;
        }
        let m = if count == 0 { n.min(1 << 16) } else { n };
        let alpha: Vec<f64> = (0..m)
            .map(|i| {
                if count == 0 {
                    0.01 + 0.98 * (i as f64 / m as f64)
                } else {
                    f64::from((0.05 + 0.9 * (rnd() * count as f64).floor() / count as f64) as f32)
                }
            })
            .collect();
        let t = best(&mut || {
            pe.eval_f32(&[&alpha], Rows::Cols(&[&cos[..m]]), &mut out[..m])
                .unwrap()
        });
        println!("per element, {label:14} {:9.2} M/s", m as f64 / t / 1e6);
    }
}
