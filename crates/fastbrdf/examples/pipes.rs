//! Which vector operations share the multiply pipes (the reasoning behind the C-peer parity
//! of the power forms in README's "Speed"): loops over 4096 floats (L1-resident) doing 4 or
//! 8 dependent operations per element, timed with the best instruction set. If `mul4max4`
//! (4 multiplies and 4 `max`) runs about as fast as `mul4`, the clamps run on other pipes
//! and cost no multiply slot; `mul8` against `mul4` shows the multiply pipes' own limit.
//! Timing only; no model is involved.
//! Run: `cargo run --release -p fastbrdf --example pipes`.

use fastbrdf::batch::Isa;
use std::hint::black_box;
use std::time::Instant;

#[inline(always)]
fn mx(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

type Loop = fn(Isa, &[f32; 8], &[f32], &mut [f32]);

/// One timed loop: the element body compiled inside `#[target_feature]` functions for
/// AVX-512 and AVX2+FMA (as the library's kernels are) and plainly for the baseline.
macro_rules! timed_loop {
    ($name:ident, |$c:ident, $k:ident| $e:expr) => {
        fn $name(isa: Isa, k: &[f32; 8], x: &[f32], out: &mut [f32]) {
            #[inline(always)]
            fn body($k: &[f32; 8], x: &[f32], out: &mut [f32]) {
                for (o, &$c) in out.iter_mut().zip(x) {
                    *o = $e;
                }
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
            unsafe fn avx512(k: &[f32; 8], x: &[f32], out: &mut [f32]) {
                body(k, x, out)
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma")]
            unsafe fn avx2(k: &[f32; 8], x: &[f32], out: &mut [f32]) {
                body(k, x, out)
            }
            match isa {
                // SAFETY: `isa` is `Isa::best()`, which detected these features on this CPU.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx512 => unsafe { avx512(k, x, out) },
                // SAFETY: as above.
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2Fma => unsafe { avx2(k, x, out) },
                _ => body(k, x, out),
            }
        }
    };
}

timed_loop!(mul4, |c, k| c * k[0] * k[1] * k[2] * k[3]);
timed_loop!(mul8, |c, k| c
    * k[0]
    * k[1]
    * k[2]
    * k[3]
    * k[4]
    * k[5]
    * k[6]
    * k[7]);
timed_loop!(max4, |c, k| mx(mx(mx(mx(c, k[4]), k[5]), k[6]), k[7]));
timed_loop!(add4, |c, k| c + k[4] + k[5] + k[6] + k[7]);
timed_loop!(mul4max4, |c, k| mx(
    mx(mx(mx(c * k[0] * k[1] * k[2] * k[3], k[4]), k[5]), k[6]),
    k[7]
));
timed_loop!(mul4add4, |c, k| c * k[0] * k[1] * k[2] * k[3]
    + k[4]
    + k[5]
    + k[6]
    + k[7]);

fn main() {
    let isa = Isa::best();
    println!(
        "isa: {} ({} lanes); best of 15 rounds of 20000 calls on 4096 floats",
        isa.name(),
        isa.lanes()
    );
    println!("{:<10} {:>10} {:>14}", "loop", "G elem/s", "ns per vector");
    let loops: [(&str, Loop); 6] = [
        ("mul4", mul4),
        ("mul8", mul8),
        ("max4", max4),
        ("add4", add4),
        ("mul4max4", mul4max4),
        ("mul4add4", mul4add4),
    ];
    let n = 4096;
    let x: Vec<f32> = (0..n).map(|i| (i as f32 + 0.5) / n as f32).collect();
    let mut out = vec![0.0f32; n];
    // Multipliers near 1 (no overflow or subnormals), the mul8 tail too; the clamps and
    // addends are runtime values, so nothing folds.
    let k = [1.0001f32, 0.9999, 1.0002, 0.9998, -3.0, -2.0, -1.5, -1.0];
    let mut best = [0.0f64; 6];
    for _ in 0..15 {
        for (i, (_, f)) in loops.iter().enumerate() {
            let reps = 20_000;
            let t = Instant::now();
            for _ in 0..reps {
                f(isa, black_box(&k), black_box(&x), black_box(&mut out));
            }
            best[i] = best[i].max((reps * n) as f64 / t.elapsed().as_secs_f64());
        }
    }
    for (i, (name, _)) in loops.iter().enumerate() {
        println!(
            "{name:<10} {:>10.2} {:>14.3}",
            best[i] / 1e9,
            isa.lanes() as f64 / best[i] * 1e9
        );
    }
}
