//! The denormal policy's measurement (`Kernel::flush_to_zero`): each lobe (and distribution,
//! at `alpha`) kernel below is
//! timed on 4096 uniform cosines (L1-resident) with the flush-to-zero switch and without it,
//! interleaved round by round; the output gives both rates, their ratio, the width of the band
//! of cosines whose squarings would be subnormal (power forms: `base_min(K) / s`; `power16`
//! zeroes its base there, so it should not care), and what the library chose. A kernel should
//! flush where the switch wins and skip it where it loses or is even.
//! Run: `cargo run --release -p fastbrdf --example ftz_band`.

use fastbrdf::batch::{Input, Isa, Kernel};
use fastbrdf::lobes::power::base_min;
use fastbrdf::{Given, ModelSpec};
use std::hint::black_box;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    println!("isa: {}", Isa::best().name());
    println!(
        "{:<8} {:>5} {:>9} {:>12} {:>12} {:>10}  chosen",
        "model", "n", "band", "flush G/s", "plain G/s", "plain/flush"
    );
    let n = 4096;
    let mut seed = 11u64;
    let cos: Vec<f32> = (0..n)
        .map(|_| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        })
        .collect();
    let mut out = vec![0.0f32; n];
    for (id, exponent) in [
        ("power4", 200.0),
        ("power8", 200.0),
        ("power16", 200.0),
        ("power4", 20.0),
        ("power8", 20.0),
        ("power16", 20.0),
        ("power8", 1.0),
        ("cubic", 200.0),
        ("schlick", 200.0),
        ("sg", 200.0),
        ("ggx", 0.3),
        ("beckmann", 0.3),
    ] {
        let name = if id == "ggx" || id == "beckmann" {
            "alpha"
        } else {
            "n"
        };
        let spec = ModelSpec::new(id, &[(name, Given::Num(exponent))]).unwrap();
        let mut k = Kernel::new(&spec).unwrap();
        let chosen = k.flush_to_zero();
        let band = match id {
            "power4" => Some(base_min(2) as f64 / (exponent / 4.0)),
            "power8" => Some(base_min(3) as f64 / (exponent / 8.0)),
            "power16" => Some(base_min(4) as f64 / (exponent / 16.0)),
            _ => None,
        };
        let rate = |k: &Kernel, out: &mut [f32]| {
            let reps = 2000;
            let t = Instant::now();
            for _ in 0..reps {
                k.eval(Input::Cos(black_box(&cos)), out).unwrap();
            }
            (reps * n) as f64 / t.elapsed().as_secs_f64()
        };
        let (mut on, mut off) = (vec![], vec![]);
        for _ in 0..31 {
            k.set_flush_to_zero(true);
            on.push(rate(&k, &mut out));
            k.set_flush_to_zero(false);
            off.push(rate(&k, &mut out));
        }
        let (on, off) = (median(on), median(off));
        println!(
            "{id:<8} {exponent:>5} {:>9} {:>12.2} {:>12.2} {:>10.3}  {}",
            band.map_or("-".into(), |b| format!("{b:.1e}")),
            on / 1e9,
            off / 1e9,
            off / on,
            if chosen { "flush" } else { "plain" }
        );
    }
}
