//! Batched sampling against the scalar sampler, in one run, rounds interleaved: `sample` and
//! `pdf` of Cook-Torrance (GGX, alpha 0.3, its default `vndf`; the renderer's and the Python
//! package's main case, and Beckmann's generic path beside it) over 2^20 random `wo` (upper
//! hemisphere) and `u`, as
//! - `scalar-dyn`: `Box<dyn Brdf<f32>>::sample` / `pdf` per element (what callers did);
//! - `generic`: `batch::sample::Sampler` with the SIMD path off (the scalar code per element,
//!   monomorphised, bit for bit);
//! - `batch`: `Sampler::sample` / `pdf` (the SIMD path where it applies), one thread;
//! - `batch_par`: `Sampler::sample_par` / `pdf_par`, rayon's threads.
//!
//! Prints the median of 9 rounds in M elements/s. Run:
//! `cargo run --release -p fastbrdf --example sample_speed`.

use fastbrdf::batch::Isa;
use fastbrdf::batch::sample::{SampleOut, Sampler};
use fastbrdf::sample::{Rng, Strategy};
use fastbrdf::{Model, ModelSpec};
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

struct Bufs {
    wi: [Vec<f32>; 3],
    weight: Vec<f32>,
    pdf: Vec<f32>,
}

impl Bufs {
    fn out(&mut self) -> SampleOut<'_> {
        let [x, y, z] = &mut self.wi;
        SampleOut {
            wi: [x, y, z],
            weight: &mut self.weight,
            pdf: &mut self.pdf,
        }
    }
}

fn main() {
    let n = 1usize << 20;
    println!(
        "threads: {}, isa: {}, n = {n}",
        rayon::current_num_threads(),
        Isa::best().name()
    );
    let mut rng = Rng::new(3);
    let mut wo: [Vec<f32>; 3] = Default::default();
    let mut u: [Vec<f32>; 2] = Default::default();
    for _ in 0..n {
        let z = rng.uniform();
        let phi = std::f64::consts::TAU * rng.uniform();
        let s = (1.0 - z * z).sqrt();
        for (k, c) in [s * phi.cos(), s * phi.sin(), z].into_iter().enumerate() {
            wo[k].push(c as f32);
        }
        u[0].push(rng.uniform() as f32);
        u[1].push(rng.uniform() as f32);
    }
    let wo_r: [&[f32]; 3] = [&wo[0], &wo[1], &wo[2]];
    let u_r: [&[f32]; 2] = [&u[0], &u[1]];
    for given in [
        vec![("d", "ggx"), ("alpha", "0.3")],
        vec![("d", "beckmann"), ("alpha", "0.3")],
    ] {
        let spec = ModelSpec::parse("cook-torrance", &given).unwrap();
        let Model::Brdf(b) = spec.model::<f32>().unwrap() else {
            unreachable!()
        };
        let sampler = Sampler::new(&spec).unwrap();
        let mut generic = Sampler::new(&spec).unwrap();
        generic.set_simd(false);
        let s = Strategy::Auto;
        let mut bufs = Bufs {
            wi: Default::default(),
            weight: vec![0.0; n],
            pdf: vec![0.0; n],
        };
        bufs.wi = std::array::from_fn(|_| vec![0.0; n]);
        // The directions the densities are evaluated at: one batch of draws.
        sampler.sample(s, wo_r, u_r, bufs.out()).unwrap();
        let wi: [Vec<f32>; 3] = bufs.wi.clone();
        let wi_r: [&[f32]; 3] = [&wi[0], &wi[1], &wi[2]];
        let names = [
            "sample scalar-dyn",
            "sample generic",
            "sample batch",
            "sample batch_par",
            "pdf scalar-dyn",
            "pdf generic",
            "pdf batch",
            "pdf batch_par",
        ];
        let mut times: Vec<Vec<f64>> = vec![vec![]; names.len()];
        let mut sink = 0.0f32;
        for _ in 0..9 {
            for (k, t) in times.iter_mut().enumerate() {
                let t0 = Instant::now();
                match k {
                    0 => {
                        for i in 0..n {
                            let r = b.sample([wo[0][i], wo[1][i], wo[2][i]], [u[0][i], u[1][i]], s);
                            let (w, f, p) =
                                r.map_or(([0.0; 3], 0.0, 0.0), |r| (r.wi, r.weight, r.pdf));
                            bufs.wi[0][i] = w[0];
                            bufs.wi[1][i] = w[1];
                            bufs.wi[2][i] = w[2];
                            bufs.weight[i] = f;
                            bufs.pdf[i] = p;
                        }
                    }
                    1 => generic.sample(s, wo_r, u_r, bufs.out()).unwrap(),
                    2 => sampler.sample(s, wo_r, u_r, bufs.out()).unwrap(),
                    3 => sampler.sample_par(s, wo_r, u_r, bufs.out()).unwrap(),
                    4 => {
                        for i in 0..n {
                            bufs.pdf[i] = b.pdf(
                                [wo[0][i], wo[1][i], wo[2][i]],
                                [wi[0][i], wi[1][i], wi[2][i]],
                                s,
                            );
                        }
                    }
                    5 => generic.pdf(s, wo_r, wi_r, &mut bufs.pdf).unwrap(),
                    6 => sampler.pdf(s, wo_r, wi_r, &mut bufs.pdf).unwrap(),
                    _ => sampler.pdf_par(s, wo_r, wi_r, &mut bufs.pdf).unwrap(),
                }
                t.push(t0.elapsed().as_secs_f64());
                sink += bufs.pdf[n / 2] + bufs.weight[n / 3];
            }
        }
        println!("cook-torrance {given:?} (simd path: {})", sampler.simd(s));
        let base = [median(times[0].clone()), median(times[4].clone())];
        for (k, name) in names.iter().enumerate() {
            let t = median(times[k].clone());
            println!(
                "  {name:<18} {:8.1} M/s  ({:.1}x scalar-dyn)",
                n as f64 / t / 1e6,
                base[k / 4] / t
            );
        }
        std::hint::black_box(sink);
    }
}
