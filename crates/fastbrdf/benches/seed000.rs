//! Question: are seed 000's one-function Cook-Torrance and Ward faster, and by how much
//! (the seed claims 4.34x and more than 2x)? Seed 000's Cook-Torrance (V-cavity G, Schlick F,
//! (V.N)(L.N)) with the exp-based D, the one-pow D and D16; isotropic Ward and its two forms.
//! 4096 random direction pairs, one thread, scalar f32 and SIMD.
//! Run: `cargo bench -p fastbrdf --bench seed000`.

use divan::{Bencher, counter::ItemsCount};
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::{Model, ModelSpec};

const N: usize = 4096;

fn main() {
    divan::main();
}

fn pairs() -> [Vec<f32>; 6] {
    let p = fastbrdf::accuracy::direction_pairs(N - 3, 1);
    std::array::from_fn(|k| {
        p.iter()
            .map(|(a, b)| if k < 3 { a[k] } else { b[k - 3] } as f32)
            .collect()
    })
}

const CONFIGS: [&str; 6] = [
    "ct:beckmann-ct",
    "ct:beckmann-pow",
    "ct:beckmann-power16",
    "ward",
    "ward-pow",
    "ward-power16",
];

/// The spec a configuration names: `ct:D` is Cook-Torrance with seed 000's terms and
/// distribution `D`, anything else a model id at its defaults.
fn spec(cfg: &str) -> ModelSpec {
    let (id, given) = match cfg.strip_prefix("ct:") {
        Some(d) => (
            "cook-torrance",
            vec![
                ("d", d),
                ("g", "v-cavity"),
                ("f", "schlick"),
                ("denominator", "seed-000"),
            ],
        ),
        None => (cfg, vec![]),
    };
    ModelSpec::parse(id, &given).unwrap()
}

#[divan::bench(args = CONFIGS)]
fn scalar(b: Bencher, cfg: &str) {
    let w = pairs();
    let mut out = vec![0.0f32; N];
    let Model::Brdf(m) = spec(cfg).model::<f32>().unwrap() else {
        unreachable!()
    };
    b.counter(ItemsCount::new(N)).bench_local(|| {
        for (i, o) in out.iter_mut().enumerate() {
            *o = m.eval([w[0][i], w[1][i], w[2][i]], [w[3][i], w[4][i], w[5][i]]);
        }
        divan::black_box(&out);
    });
}

#[divan::bench(args = CONFIGS)]
fn simd(b: Bencher, cfg: &str) {
    let w = pairs();
    let mut out = vec![0.0f32; N];
    let k = Kernel::new(&spec(cfg)).unwrap();
    b.counter(ItemsCount::new(N)).bench_local(|| {
        k.eval(
            Input::Dirs([&w[0], &w[1], &w[2], &w[3], &w[4], &w[5]]),
            &mut out,
        )
        .unwrap()
    });
}
