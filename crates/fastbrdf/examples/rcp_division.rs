//! Why the divider-bound kernels keep their division (README's "Speed"): `schlick`'s form
//! `c / fma(c, 1 - n, n)` on 4096 cosines (L1-resident, 64-byte aligned), once with the
//! division (`vdivps`, as the library's kernel) and once with AVX-512's reciprocal estimate
//! (`vrcp14ps`, 14 bits), the quotient `q = c r` and Markstein's correction
//! `q + r (c - d q)` (three multiply-pipe operations more, within about 1 ulp), timed in
//! interleaved rounds. If the estimate is not clearly faster, the division costs no more
//! than the multiply-pipe work that would replace it. Prints both rates, their ratio and
//! both forms' largest relative error against f64. Needs AVX-512 (exit 2 without).
//! Run: `cargo run --release -p fastbrdf --example rcp_division`.

#[cfg(target_arch = "x86_64")]
use fastbrdf::batch::Isa;
#[cfg(target_arch = "x86_64")]
use std::hint::black_box;
#[cfg(target_arch = "x86_64")]
use std::time::Instant;

#[cfg(target_arch = "x86_64")]
mod imp {
    use std::arch::x86_64::*;

    /// The library kernel's form: one division.
    #[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
    pub unsafe fn divide(x: &[f32], out: &mut [f32], n: f32) {
        let a = 1.0 - n;
        for (o, &c) in out.iter_mut().zip(x) {
            let c = if c < 1.0 { c } else { 1.0 };
            let v = c / c.mul_add(a, n);
            *o = if v > 0.0 { v } else { 0.0 };
        }
    }

    /// The reciprocal estimate with the quotient's correction.
    #[target_feature(enable = "avx512f,avx512vl,avx2,fma")]
    pub unsafe fn estimate(x: &[f32], out: &mut [f32], n: f32) {
        let a = _mm512_set1_ps(1.0 - n);
        let nn = _mm512_set1_ps(n);
        let one = _mm512_set1_ps(1.0);
        let zero = _mm512_setzero_ps();
        for (o, c) in out.chunks_exact_mut(16).zip(x.chunks_exact(16)) {
            // SAFETY: both chunks hold exactly 16 f32s.
            unsafe {
                let c = _mm512_min_ps(_mm512_loadu_ps(c.as_ptr()), one);
                let d = _mm512_fmadd_ps(c, a, nn);
                let r = _mm512_rcp14_ps(d);
                let q = _mm512_mul_ps(c, r);
                let e = _mm512_fnmadd_ps(d, q, c);
                let q = _mm512_max_ps(_mm512_fmadd_ps(r, e, q), zero);
                _mm512_storeu_ps(o.as_mut_ptr(), q);
            }
        }
    }
}

/// A timed form: `out = f(x)` at the index `n`.
#[cfg(target_arch = "x86_64")]
type Form = unsafe fn(&[f32], &mut [f32], f32);

#[cfg(target_arch = "x86_64")]
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

#[cfg(target_arch = "x86_64")]
fn main() {
    if Isa::best() != Isa::Avx512 {
        eprintln!("this CPU has no AVX-512: vrcp14ps is not available");
        std::process::exit(2);
    }
    const N: usize = 4096;
    let n = 20.0f32;
    // 64-byte aligned input and output inside over-allocated vectors.
    let mut xb = vec![0f32; N + 16];
    let mut ob = vec![0f32; N + 16];
    let off = |p: *const f32| (16 - (p as usize % 64) / 4) % 16;
    let (xo, oo) = (off(xb.as_ptr()), off(ob.as_ptr()));
    for (i, x) in xb[xo..xo + N].iter_mut().enumerate() {
        *x = (i as f32 + 0.5) / N as f32;
    }
    let x = &xb[xo..xo + N];
    let out = &mut ob[oo..oo + N];
    let forms: [(&str, Form); 2] = [("division", imp::divide), ("estimate", imp::estimate)];
    let mut errors = [0f64; 2];
    for (k, (_, f)) in forms.iter().enumerate() {
        // SAFETY: the CPU has AVX-512 (checked above).
        unsafe { f(x, out, n) };
        for (&c, &v) in x.iter().zip(out.iter()) {
            let want = c as f64 / (n as f64 - (n as f64 - 1.0) * c as f64);
            errors[k] = errors[k].max((v as f64 - want).abs() / want);
        }
    }
    let mut rates = [vec![], vec![]];
    for _ in 0..301 {
        for (k, (_, f)) in forms.iter().enumerate() {
            let t = Instant::now();
            for _ in 0..50 {
                // SAFETY: as above.
                unsafe { f(black_box(x), out, n) };
                black_box(&*out);
            }
            rates[k].push((50 * N) as f64 / t.elapsed().as_secs_f64());
        }
    }
    let [d, e] = rates.map(median);
    println!("schlick form, n = {n}, 4096 cosines, median of 301 interleaved rounds:");
    for (k, (name, _)) in forms.iter().enumerate() {
        let rate = if k == 0 { d } else { e };
        let eps = errors[k] / f32::EPSILON as f64;
        println!(
            "  {name:<9} {:6.2} G/s  max error {eps:.2} f32 epsilons",
            rate / 1e9
        );
    }
    println!("  estimate / division: {:.3}", e / d);
}

#[cfg(not(target_arch = "x86_64"))]
fn main() {
    eprintln!("x86-64 only (AVX-512's vrcp14ps)");
    std::process::exit(2);
}
