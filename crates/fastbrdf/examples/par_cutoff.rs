//! Where `Kernel::eval_par`'s pool starts to pay: for a cheap and an expensive kernel, the
//! single-thread `eval` and a forced parallel split (`rayon` over 16384-element chunks, what
//! `eval_par` does above its cut-off) are timed interleaved at growing sizes; the output is the
//! single-thread time at which the split starts to win, the number behind `PAR_MIN_WORK`.
//! Run: `cargo run --release -p fastbrdf --example par_cutoff`.

use fastbrdf::ModelSpec;
use fastbrdf::batch::{Input, Isa, Kernel};
use rayon::prelude::*;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let threads = rayon::current_num_threads();
    println!("threads: {threads}, isa: {}", Isa::best().name());
    for (id, given) in [("power16", vec![("n", "200")]), ("cook-torrance", vec![])] {
        let k = Kernel::new(&ModelSpec::parse(id, &given).unwrap()).unwrap();
        for log2 in 14..=22 {
            let n = 1usize << log2;
            let mut seed = 7u64;
            let mut next = || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 40) as f32 / (1u64 << 24) as f32
            };
            let cols: Vec<Vec<f32>> = (0..6).map(|_| (0..n).map(|_| next()).collect()).collect();
            let input = if id == "cook-torrance" {
                Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]])
            } else {
                Input::Cos(&cols[0])
            };
            let mut out = vec![0.0f32; n];
            let (mut seq, mut par) = (vec![], vec![]);
            for _ in 0..15 {
                let t = Instant::now();
                k.eval(input, &mut out).unwrap();
                seq.push(t.elapsed().as_secs_f64());
                let t = Instant::now();
                out.par_chunks_mut(16384).enumerate().for_each(|(i, o)| {
                    let lo = i * 16384;
                    k.eval(input.slice(lo, lo + o.len()), o).unwrap();
                });
                par.push(t.elapsed().as_secs_f64());
            }
            let (s, p) = (median(seq), median(par));
            println!(
                "{id:14} n = 2^{log2:2}: one thread {:9.1} us, split {:9.1} us, split/one {:.2}",
                s * 1e6,
                p * 1e6,
                p / s
            );
        }
    }
}
