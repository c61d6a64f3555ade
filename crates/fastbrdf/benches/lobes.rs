//! Question: how many lobe evaluations per second, scalar against SIMD, and against the
//! naive `powf` loop? Batch of 4096 cosines (L1-resident), one thread, n = 200.
//! Run: `cargo bench -p fastbrdf --bench lobes` (throughput is printed as items/s).

use divan::{Bencher, counter::ItemsCount};
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::{Given, Model, ModelSpec};

const N: usize = 4096;

fn main() {
    divan::main();
}

fn cosines() -> Vec<f32> {
    (0..N).map(|i| (i as f32 + 0.5) / N as f32).collect()
}

#[divan::bench]
fn powf_loop(b: Bencher) {
    let x = cosines();
    let mut out = vec![0.0f32; N];
    let n = divan::black_box(200.0f32);
    b.counter(ItemsCount::new(N)).bench_local(|| {
        for (o, &c) in out.iter_mut().zip(&x) {
            *o = c.powf(n);
        }
        divan::black_box(&out);
    });
}

#[divan::bench(args = ["pow", "schlick", "flog", "cubic", "cubic-rational", "power16", "sg", "ue4-phong-approx"])]
fn simd(b: Bencher, id: &str) {
    let x = cosines();
    let mut out = vec![0.0f32; N];
    let k = Kernel::new(&lobe(id)).unwrap();
    b.counter(ItemsCount::new(N))
        .bench_local(|| k.eval(Input::Cos(&x), &mut out).unwrap());
}

#[divan::bench(args = ["pow", "schlick", "flog", "cubic", "cubic-rational", "power16", "sg", "ue4-phong-approx"])]
fn scalar(b: Bencher, id: &str) {
    let x = cosines();
    let mut out = vec![0.0f32; N];
    let Model::Lobe(l) = lobe(id).model::<f32>().unwrap() else {
        unreachable!()
    };
    b.counter(ItemsCount::new(N)).bench_local(|| {
        for (o, &c) in out.iter_mut().zip(&x) {
            *o = l.eval(c);
        }
        divan::black_box(&out);
    });
}

/// Lobe `id` at n = 200.
fn lobe(id: &str) -> ModelSpec {
    ModelSpec::new(id, &[("n", Given::Num(200.0))]).unwrap()
}
