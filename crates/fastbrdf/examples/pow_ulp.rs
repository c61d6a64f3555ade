//! The measurement behind `math::fast::pow_fma`'s stated accuracy: the largest relative error
//! of the FMA kernels' `pow` (`math::fast::fma::pow`, double-f32 `log2` and `EXP2_C6`) over
//! every normal f32 `x` in (0, 1] at the exponents listed, against f64 `powf`, in f32
//! epsilons; results below 2^-126 (0 by the documented rule) are skipped. About two minutes
//! on two cores; needs a CPU with FMA (AVX2+FMA or AVX-512).
//! Run: `cargo run --release -p fastbrdf --example pow_ulp`.

use fastbrdf::batch::Isa;
use fastbrdf::math::fast::fma;
use rayon::prelude::*;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn pow_all(x: &[f32], y: f32, out: &mut [f32]) {
    for (o, &v) in out.iter_mut().zip(x) {
        *o = fma::pow(v, y);
    }
}

fn main() {
    if !Isa::best().fma() {
        eprintln!("this CPU has no FMA: fma::pow is not what its kernels run");
        std::process::exit(2);
    }
    let (lo, hi) = (f32::MIN_POSITIVE.to_bits(), 1.0f32.to_bits());
    let starts: Vec<u32> = (lo..=hi).step_by(4096).collect();
    println!("max relative error of fma::pow over every normal x in (0, 1], in f32 epsilons");
    for y in [1.0f32, 2.0, 20.0, 200.0, 1234.5, 1e4, 99999.0, 1e5] {
        let worst = starts
            .par_iter()
            .map(|&start| {
                let x: Vec<f32> = (start..(start + 4096).min(hi + 1))
                    .map(f32::from_bits)
                    .collect();
                let mut out = vec![0f32; x.len()];
                // SAFETY: `Isa::best().fma()` above: the CPU has AVX2 and FMA.
                #[cfg(target_arch = "x86_64")]
                unsafe {
                    pow_all(&x, y, &mut out)
                };
                x.iter()
                    .zip(&out)
                    .filter_map(|(&x, &v)| {
                        let want = (x as f64).powf(y as f64);
                        (want >= f32::MIN_POSITIVE as f64).then(|| (v as f64 - want).abs() / want)
                    })
                    .fold(0.0, f64::max)
            })
            .reduce(|| 0.0, f64::max);
        println!("y = {y:>8}: {:.3}", worst / f32::EPSILON as f64);
    }
}
