//! Batched sampling (`batch::sample::Sampler`) against the scalar sampler
//! (`Brdf::<f32>::sample` / `pdf`): every BRDF id with default and a few other parameters,
//! every strategy it supports (and `auto`), random `wo` and `u` with grazing, below-horizon,
//! zero, NaN and infinite directions and `u` outside [0, 1); the threaded calls against the
//! sequential ones; the errors.

use fastbrdf::batch::sample::{SampleOut, Sampler};
use fastbrdf::sample::{Rng, Strategy};
use fastbrdf::{Brdf, Kind, Model, ModelSpec, registry};

/// A BRDF's spec, scalar f32 model and batch sampler.
fn build(id: &str, p: &[(&str, &str)]) -> (Box<dyn Brdf<f32>>, Sampler) {
    let spec = ModelSpec::parse(id, p).unwrap();
    let Model::Brdf(b) = spec.model::<f32>().unwrap() else {
        panic!("{id} is not a BRDF")
    };
    (b, Sampler::new(&spec).unwrap())
}

/// The cases: every BRDF id with its defaults, plus the renderer's and Python's main case
/// (GGX at 0.3), narrow and wide slopes, anisotropy, an energy compensation, a Fresnel term,
/// a non-exact distribution and both lobe BRDFs with a closed-form and a twin lobe.
fn cases() -> Vec<(&'static str, Vec<(&'static str, &'static str)>)> {
    let mut out: Vec<_> = registry::ids_of(Kind::Brdf)
        .into_iter()
        .map(|id| (id, vec![]))
        .collect();
    let ct = "cook-torrance";
    for p in [
        vec![("d", "ggx"), ("alpha", "0.3")],
        vec![("d", "ggx"), ("alpha", "0.005")],
        vec![("d", "ggx"), ("alpha", "1")],
        vec![("d", "ggx"), ("alpha_x", "0.1"), ("alpha_y", "0.4")],
        vec![("d", "beckmann"), ("alpha", "0.05")],
        vec![("d", "beckmann-pow"), ("alpha", "0.3")],
        vec![("d", "beckmann-power16"), ("alpha", "0.3")],
        vec![("d", "ggx"), ("f", "schlick"), ("alpha", "0.2")],
        vec![
            ("d", "ggx"),
            ("g", "smith-ggx-correlated"),
            ("ms", "kulla-conty"),
        ],
    ] {
        out.push((ct, p));
    }
    for b in ["phong", "blinn-phong"] {
        out.push((b, vec![("lobe", "pow"), ("n", "50")]));
        out.push((b, vec![("lobe", "cubic"), ("n", "20")]));
    }
    out.push(("ward", vec![("alpha_x", "0.1"), ("alpha_y", "0.4")]));
    out
}

/// `n` random `wo` (a third in the upper hemisphere, a third anywhere, a third grazing),
/// scaled by random lengths, then the special directions; `u` in [0, 1) with the ends and
/// out-of-range values mixed in.
fn inputs(seed: u64, n: usize) -> ([Vec<f32>; 3], [Vec<f32>; 2]) {
    let mut r = Rng::new(seed);
    let mut wo: [Vec<f32>; 3] = Default::default();
    let mut u: [Vec<f32>; 2] = Default::default();
    let mut push = |w: [f32; 3], uu: [f32; 2]| {
        for k in 0..3 {
            wo[k].push(w[k]);
        }
        u[0].push(uu[0]);
        u[1].push(uu[1]);
    };
    for i in 0..n {
        let phi = std::f64::consts::TAU * r.uniform();
        let z = match i % 3 {
            0 => r.uniform(),
            1 => 2.0 * r.uniform() - 1.0,
            _ => {
                [1e-7, 9.5e-7, 1e-6, 1e-5, 1e-3, 0.02][(r.uniform() * 6.0) as usize]
                    * (0.5 + r.uniform())
            }
        };
        let s = (1.0 - z * z).max(0.0).sqrt();
        let len = 10f64.powf(6.0 * r.uniform() - 3.0);
        let w = [s * phi.cos(), s * phi.sin(), z].map(|c| (c * len) as f32);
        push(w, [r.uniform() as f32, r.uniform() as f32]);
    }
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let specials = [
        [0.0, 0.0, 0.0],
        [nan, 0.0, 1.0],
        [0.0, nan, 1.0],
        [0.0, 0.0, inf],
        [inf, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.3, 0.2, 0.0],
        [1.0, 0.0, 9.536743e-7],
        [1.0, 0.0, 9.5e-7],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1e-30],
        [1e-30, 0.0, 1e-30],
    ];
    let us = [
        [0.0, 0.0],
        [1.0, 1.0],
        [0.999_999_94, 0.999_999_94],
        [-0.5, 0.3],
        [0.3, 1.5],
        [nan, 0.5],
        [0.5, nan],
        [inf, -inf],
        [0.5, 0.25],
    ];
    for w in specials {
        for uu in us {
            push(w, uu);
        }
    }
    // Good directions with the odd u values.
    for uu in us {
        push([0.2, -0.1, 0.9], uu);
    }
    (wo, u)
}

fn refs<const N: usize>(v: &[Vec<f32>; N]) -> [&[f32]; N] {
    std::array::from_fn(|k| v[k].as_slice())
}

/// Output buffers of `n` elements, filled with a marker the sampler must overwrite.
struct Outs {
    wi: [Vec<f32>; 3],
    weight: Vec<f32>,
    pdf: Vec<f32>,
}

impl Outs {
    fn new(n: usize) -> Self {
        Self {
            wi: std::array::from_fn(|_| vec![-7.0; n]),
            weight: vec![-7.0; n],
            pdf: vec![-7.0; n],
        }
    }
    fn out(&mut self) -> SampleOut<'_> {
        let [x, y, z] = &mut self.wi;
        SampleOut {
            wi: [x, y, z],
            weight: &mut self.weight,
            pdf: &mut self.pdf,
        }
    }
    fn bits(&self) -> Vec<[u32; 5]> {
        (0..self.pdf.len())
            .map(|i| {
                [
                    self.wi[0][i],
                    self.wi[1][i],
                    self.wi[2][i],
                    self.weight[i],
                    self.pdf[i],
                ]
                .map(f32::to_bits)
            })
            .collect()
    }
}

/// The strategies to run: `auto` and every one the BRDF supports.
fn strategies(s: &Sampler) -> Vec<Strategy> {
    std::iter::once(Strategy::Auto)
        .chain(s.strategies().iter().copied())
        .collect()
}

#[test]
fn sample_and_pdf_are_the_scalar_models_bit_for_bit() {
    let mut checked = 0;
    for (case, (id, p)) in cases().into_iter().enumerate() {
        let (b, sampler) = build(id, &p);
        assert_eq!(sampler.strategies(), b.strategies(), "{id} {p:?}");
        let (wo, u) = inputs(case as u64, 600);
        let n = wo[0].len();
        for s in strategies(&sampler) {
            let mut o = Outs::new(n);
            sampler.sample(s, refs(&wo), refs(&u), o.out()).unwrap();
            // The density at the drawn directions and at the next element's `wo` (random
            // pairs, many out of the domain).
            let wi_rand: [Vec<f32>; 3] = std::array::from_fn(|k| {
                let mut v = wo[k].clone();
                v.rotate_left(1);
                v
            });
            let mut pdf_drawn = vec![-7.0; n];
            let mut pdf_rand = vec![-7.0; n];
            sampler
                .pdf(s, refs(&wo), refs(&o.wi), &mut pdf_drawn)
                .unwrap();
            sampler
                .pdf(s, refs(&wo), refs(&wi_rand), &mut pdf_rand)
                .unwrap();
            let got_all = o.bits();
            for i in 0..n {
                let w = [wo[0][i], wo[1][i], wo[2][i]];
                let want = match b.sample(w, [u[0][i], u[1][i]], s) {
                    Some(r) => [r.wi[0], r.wi[1], r.wi[2], r.weight, r.pdf],
                    None => [0.0; 5],
                };
                let got = got_all[i];
                assert_eq!(
                    got,
                    want.map(f32::to_bits),
                    "{id} {p:?} {s} wo {w:?} u {:?}: {:?} != {want:?}",
                    [u[0][i], u[1][i]],
                    got.map(f32::from_bits)
                );
                let wi = [o.wi[0][i], o.wi[1][i], o.wi[2][i]];
                assert_eq!(
                    pdf_drawn[i].to_bits(),
                    b.pdf(w, wi, s).to_bits(),
                    "{id} {s} pdf at {w:?} {wi:?}"
                );
                let wr = [wi_rand[0][i], wi_rand[1][i], wi_rand[2][i]];
                assert_eq!(
                    pdf_rand[i].to_bits(),
                    b.pdf(w, wr, s).to_bits(),
                    "{id} {s} pdf at {w:?} {wr:?}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 50_000, "{checked}");
}

#[test]
fn out_of_domain_wo_gives_zeros() {
    let (_, sampler) = build("cook-torrance", &[("d", "ggx")]);
    let nan = f32::NAN;
    let wo = [
        vec![0.0, nan, 0.0, 0.3, 1.0, 0.0],
        vec![0.0, 0.0, 0.0, 0.2, 0.0, 0.0],
        vec![0.0, 1.0, -1.0, 0.0, 9.0e-7, f32::INFINITY],
    ];
    let u = [vec![0.5; 6], vec![0.5; 6]];
    for s in strategies(&sampler) {
        let mut o = Outs::new(6);
        sampler.sample(s, refs(&wo), refs(&u), o.out()).unwrap();
        assert!(o.bits().iter().all(|b| *b == [0; 5]), "{s}: {:?}", o.bits());
        let mut p = vec![-7.0; 6];
        let wi = [vec![0.0; 6], vec![0.0; 6], vec![1.0; 6]];
        sampler.pdf(s, refs(&wo), refs(&wi), &mut p).unwrap();
        assert!(p.iter().all(|x| x.to_bits() == 0), "{s}: {p:?}");
    }
}

#[test]
fn threaded_calls_give_the_sequential_values() {
    for (id, p) in [
        ("cook-torrance", vec![("d", "ggx"), ("alpha", "0.3")]),
        ("phong", vec![]),
    ] {
        let (_, sampler) = build(id, &p);
        // Over three chunks, with a partial last one.
        let (wo, u) = inputs(99, 3 * 4096 + 17);
        let n = wo[0].len();
        for s in strategies(&sampler) {
            let (mut a, mut b) = (Outs::new(n), Outs::new(n));
            sampler.sample(s, refs(&wo), refs(&u), a.out()).unwrap();
            sampler.sample_par(s, refs(&wo), refs(&u), b.out()).unwrap();
            assert!(a.bits() == b.bits(), "{id} {s}");
            let (mut pa, mut pb) = (vec![-7.0; n], vec![-7.0; n]);
            sampler.pdf(s, refs(&wo), refs(&a.wi), &mut pa).unwrap();
            sampler.pdf_par(s, refs(&wo), refs(&a.wi), &mut pb).unwrap();
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&pa), bits(&pb), "{id} {s}");
        }
    }
}

#[test]
fn errors_name_the_problem() {
    let (_, sampler) = build("cook-torrance", &[("d", "ggx")]);
    let v = vec![0.5f32; 4];
    let short = vec![0.5f32; 3];
    let mut o = Outs::new(4);
    // Unequal lengths: an input, an output; sequential and threaded.
    let e = sampler
        .sample(Strategy::Auto, [&v, &v, &short], [&v, &v], o.out())
        .unwrap_err();
    assert!(e.to_string().contains("lengths differ"), "{e}");
    let mut o3 = Outs::new(3);
    let e = sampler
        .sample_par(Strategy::Auto, [&v, &v, &v], [&v, &v], o3.out())
        .unwrap_err();
    assert!(e.to_string().contains("lengths differ"), "{e}");
    let mut p = vec![0.0f32; 4];
    let e = sampler
        .pdf(Strategy::Auto, [&v, &v, &v], [&v, &short, &v], &mut p)
        .unwrap_err();
    assert!(e.to_string().contains("lengths differ"), "{e}");
    let e = sampler
        .pdf_par(Strategy::Auto, [&v, &v, &v], [&v, &v, &v], &mut p[..2])
        .unwrap_err();
    assert!(e.to_string().contains("lengths differ"), "{e}");
    // A strategy the BRDF lacks: the scalar model's message.
    let (b, _) = build("cook-torrance", &[("d", "ggx")]);
    let want = b.resolve(Strategy::Twin).unwrap_err();
    let e = sampler
        .sample(Strategy::Twin, [&v, &v, &v], [&v, &v], o.out())
        .unwrap_err();
    assert!(e.to_string().contains(&want), "{e} / {want}");
    let e = sampler
        .pdf_par(Strategy::Twin, [&v, &v, &v], [&v, &v, &v], &mut p)
        .unwrap_err();
    assert!(e.to_string().contains(&want), "{e} / {want}");
    // Outputs untouched by a refused call.
    assert!(o.weight.iter().all(|x| *x == -7.0));
    // Not a BRDF.
    let e = Sampler::new(&ModelSpec::parse("ggx", &[]).unwrap())
        .err()
        .unwrap();
    assert!(e.to_string().contains("distribution"), "{e}");
}
