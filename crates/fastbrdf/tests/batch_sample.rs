//! Batched sampling (`batch::sample::Sampler`) against the scalar sampler
//! (`Brdf::<f32>::sample` / `pdf`): every BRDF id with default and a few other parameters,
//! every strategy it supports (and `auto`), random `wo` and `u` with grazing, below-horizon,
//! zero, NaN and infinite directions and `u` outside [0, 1); the threaded calls against the
//! sequential ones; the errors.

mod common;

use common::Outs;
use fastbrdf::batch::sample::{NEAR, Sampler};
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

/// The strategies to run: `auto` and every one the BRDF supports.
fn strategies(s: &Sampler) -> Vec<Strategy> {
    std::iter::once(Strategy::Auto)
        .chain(s.strategies().iter().copied())
        .collect()
}

fn row(v: &[Vec<f32>; 3], i: usize) -> [f32; 3] {
    [v[0][i], v[1][i], v[2][i]]
}

/// Whether `v`'s squared length is within the unit tier's `NEAR` of 1.
fn near_unit(v: [f32; 3]) -> bool {
    ((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - 1.0).abs() <= NEAR
}

/// A density of the batch sampler (`got`) against the scalar one (`want`): the same bits,
/// but where the SIMD path's unit tier may have decided it (both directions near unit
/// length), there zero where it is zero and else within 1e-4 relative
/// (`tests/batch_sample_unit.rs` holds the tier to its tighter bound).
fn same_pdf(got: f32, want: f32, [wo, wi]: [[f32; 3]; 2], sampler: &Sampler, s: Strategy) {
    if sampler.simd(s) && near_unit(wo) && near_unit(wi) {
        assert_eq!(
            got == 0.0,
            want == 0.0,
            "pdf at {wo:?} {wi:?}: {got} {want}"
        );
        let rel = (got - want).abs() / want.abs().max(f32::MIN_POSITIVE);
        assert!(rel <= 1e-4, "pdf at {wo:?} {wi:?}: {got} {want}");
    } else {
        assert_eq!(
            got.to_bits(),
            want.to_bits(),
            "pdf at {wo:?} {wi:?}: {got} {want}"
        );
    }
}

#[test]
fn sample_and_pdf_are_the_scalar_models_bit_for_bit() {
    let mut checked = 0;
    for (case, (id, p)) in cases().into_iter().enumerate() {
        let (b, simd) = build(id, &p);
        let (_, mut sampler) = build(id, &p);
        sampler.set_simd(false);
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
            // The densities of the SIMD path too: the scalar values bit for bit.
            simd.pdf(s, refs(&wo), refs(&o.wi), &mut pdf_drawn).unwrap();
            let mut pdf_generic = vec![-7.0; n];
            sampler
                .pdf(s, refs(&wo), refs(&wi_rand), &mut pdf_generic)
                .unwrap();
            simd.pdf(s, refs(&wo), refs(&wi_rand), &mut pdf_rand)
                .unwrap();
            for i in 0..n {
                let pair = [row(&wo, i), row(&wi_rand, i)];
                same_pdf(pdf_rand[i], pdf_generic[i], pair, &simd, s);
            }
            let got_all = o.bits();
            // No value of `u` (NaN, infinite, out of [0, 1)) gives a NaN or infinity.
            assert!(
                got_all
                    .iter()
                    .flatten()
                    .all(|b| f32::from_bits(*b).is_finite()),
                "{id} {s}"
            );
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
                same_pdf(pdf_drawn[i], b.pdf(w, wi, s), [w, wi], &simd, s);
                let wr = [wi_rand[0][i], wi_rand[1][i], wi_rand[2][i]];
                same_pdf(pdf_rand[i], b.pdf(w, wr, s), [w, wr], &simd, s);
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

/// Cook-Torrance with GGX: the SIMD path of `vndf`.
fn ggx_cases() -> Vec<Vec<(&'static str, &'static str)>> {
    vec![
        vec![("d", "ggx"), ("alpha", "0.3")],
        vec![("d", "ggx"), ("alpha", "0.005")],
        vec![("d", "ggx"), ("alpha", "1")],
        vec![("d", "ggx"), ("alpha_x", "0.1"), ("alpha_y", "0.4")],
        vec![("d", "ggx"), ("f", "schlick"), ("alpha", "0.2")],
        vec![
            ("d", "ggx"),
            ("g", "smith-ggx-correlated"),
            ("ms", "kulla-conty"),
        ],
    ]
}

fn brdf_plan(spec: &ModelSpec) -> fastbrdf::plan::BrdfPlan {
    match spec.plan().unwrap() {
        fastbrdf::plan::Plan::Brdf(b) => *b,
        _ => panic!("not a BRDF"),
    }
}

/// The SIMD path draws where the scalar f32 sampler draws; its density is the scalar density
/// at its own `wi` bit for bit (within 1e-4 relative where `wo` is near unit length: the unit
/// tier, `tests/batch_sample_unit.rs`), its weight `f cos_i / pdf` there within the eval kernel's
/// few ulp (1e-5, mixed); its directions and weights are as close to the f64 sampler's as
/// the scalar f32 sampler's are (within 3 times its largest error plus 2e-6 / 2e-5: the
/// polynomial `sincos_2pi` in place of libm's, amplified as the f32 path amplifies its own
/// rounding near the edge of the visible-normal disk).
#[test]
fn ggx_vndf_simd_tracks_the_scalar_sampler() {
    use fastbrdf::plan::BrdfForm;
    for p in ggx_cases() {
        let spec = ModelSpec::parse("cook-torrance", &p).unwrap();
        let (b, sampler) = build("cook-torrance", &p);
        let Model::Brdf(b64) = spec.model::<f64>().unwrap() else {
            panic!()
        };
        let plan = brdf_plan(&spec);
        assert!(
            sampler.simd(Strategy::Auto) && sampler.simd(Strategy::Vndf),
            "{p:?}"
        );
        assert!(!sampler.simd(Strategy::DCos) && !sampler.simd(Strategy::Cosine));
        let (wo, u) = inputs(5, 60_000);
        let n = wo[0].len();
        let mut o = Outs::new(n);
        sampler
            .sample(Strategy::Auto, refs(&wo), refs(&u), o.out())
            .unwrap();
        // Largest errors against f64: directions and weights, SIMD and scalar f32.
        let mut worst = [0f64; 4];
        let mut drawn = 0;
        for i in 0..n {
            let w = [wo[0][i], wo[1][i], wo[2][i]];
            let uu = [u[0][i], u[1][i]];
            let got = [o.wi[0][i], o.wi[1][i], o.wi[2][i]];
            let r = b.sample(w, uu, Strategy::Vndf);
            assert_eq!(
                r.is_some(),
                o.pdf[i] != 0.0,
                "{p:?} wo {w:?} u {uu:?}: {r:?}"
            );
            let Some(r) = r else {
                assert_eq!([got[0], got[1], got[2], o.weight[i]], [0.0; 4]);
                continue;
            };
            drawn += 1;
            let won = fastbrdf::vec3::normalize(w).unwrap();
            let pdf = plan.pdf_wi(won, got, Strategy::Vndf);
            if near_unit(w) {
                // The unit tier (`tests/batch_sample_unit.rs` bounds it).
                let rel = (o.pdf[i] - pdf).abs() / pdf;
                assert!(rel <= 1e-4, "{p:?} wo {w:?} u {uu:?}: {} {pdf}", o.pdf[i]);
            } else {
                assert_eq!(o.pdf[i].to_bits(), pdf.to_bits(), "{p:?} wo {w:?} u {uu:?}");
            }
            let want = b.eval(got, won) * got[2] / pdf;
            let err = (o.weight[i] - want).abs() / want.abs().max(1.0);
            assert!(
                err <= 1e-5,
                "{p:?} wo {w:?} u {uu:?}: weight {} vs {want}",
                o.weight[i]
            );
            let r64 = b64
                .sample(w.map(f64::from), uu.map(f64::from), Strategy::Vndf)
                .unwrap();
            let dir = |x: [f32; 3]| {
                (0..3)
                    .map(|k| (x[k] as f64 - r64.wi[k]).abs())
                    .fold(0.0, f64::max)
            };
            for (k, e) in [
                dir(got),
                dir(r.wi),
                (o.weight[i] as f64 - r64.weight).abs(),
                (r.weight as f64 - r64.weight).abs(),
            ]
            .into_iter()
            .enumerate()
            {
                worst[k] = worst[k].max(e);
            }
        }
        assert!(drawn > n / 3, "{p:?}: {drawn} of {n}");
        let [dir_simd, dir32, w_simd, w32] = worst;
        assert!(
            dir_simd <= 3.0 * dir32 + 2e-6,
            "{p:?}: directions {dir_simd:.2e} vs scalar f32 {dir32:.2e}"
        );
        assert!(
            w_simd <= 3.0 * w32 + 2e-5,
            "{p:?}: weights {w_simd:.2e} vs scalar f32 {w32:.2e}"
        );
    }
}

/// The vectorised `sin(2 pi u)`, `cos(2 pi u)` against f64 on [0, 1].
#[test]
fn sincos_2pi_is_within_its_bound() {
    let mut worst = 0f64;
    let n = 1 << 20;
    let mut us: Vec<f32> = (0..=n).map(|i| i as f32 / n as f32).collect();
    us.extend([
        0.125,
        0.25,
        0.375,
        0.5,
        0.625,
        0.75,
        0.875,
        1.0,
        0.999_999_94,
        1e-30,
    ]);
    us.extend((1..1000).map(|i| 0.25 * (i % 5) as f32 + (i as f32) * 1e-9));
    for u in us {
        let (s, c) = fastbrdf::batch::sample::sincos_2pi(u);
        let (s64, c64) = (std::f64::consts::TAU * u as f64).sin_cos();
        worst = worst
            .max((s as f64 - s64).abs())
            .max((c as f64 - c64).abs());
        if (4.0 * u).fract() == 0.0 {
            // Quarter turns are exact.
            assert!(
                s == s64.round() as f32 && c == c64.round() as f32,
                "{u}: {s} {c}"
            );
        }
    }
    println!("sincos_2pi: largest error {worst:.2e}");
    assert!(worst <= 1.2e-7, "{worst:e}");
}

/// The SIMD path's draws follow its density: chi-square against the f64 model's `pdf`
/// (`chi2::run`, the CI sizes of `tests/sampling.rs`), draws made in one batch.
#[test]
fn ggx_vndf_simd_passes_chi_square() {
    use fastbrdf::chi2::{self, Config};
    use std::cell::Cell;
    let cfg = Config::ci();
    let runs: Vec<(Vec<(&str, &str)>, f64)> = vec![
        (vec![("d", "ggx"), ("alpha", "0.3")], 0.0),
        (vec![("d", "ggx"), ("alpha", "0.3")], 45.0),
        (vec![("d", "ggx"), ("alpha", "0.3")], 80.0),
        (vec![("d", "ggx"), ("alpha", "0.05")], 45.0),
        (vec![("d", "ggx"), ("alpha", "1")], 80.0),
        (
            vec![("d", "ggx"), ("alpha_x", "0.1"), ("alpha_y", "0.4")],
            60.0,
        ),
    ];
    let tests = runs.len();
    for (p, theta) in runs {
        let spec = ModelSpec::parse("cook-torrance", &p).unwrap();
        let sampler = Sampler::new(&spec).unwrap();
        let Model::Brdf(b64) = spec.model::<f64>().unwrap() else {
            panic!()
        };
        let t = f64::to_radians(theta);
        let wo64 = [t.sin() * 0.5f64.cos(), t.sin() * 0.5f64.sin(), t.cos()];
        // The same uniform pairs `chi2::run` would pass, in its order.
        let mut rng = Rng::new(cfg.seed);
        let n = cfg.samples;
        let mut u: [Vec<f32>; 2] = [vec![], vec![]];
        for _ in 0..n {
            let [a, b] = rng.pair();
            u[0].push(a as f32);
            u[1].push(b as f32);
        }
        let wo = wo64.map(|c| vec![c as f32; n]);
        let mut o = Outs::new(n);
        sampler
            .sample(Strategy::Vndf, refs(&wo), refs(&u), o.out())
            .unwrap();
        let next = Cell::new(0);
        let out = chi2::run(
            |_| {
                let i = next.get();
                next.set(i + 1);
                (o.pdf[i] > 0.0).then(|| [0, 1, 2].map(|k| o.wi[k][i] as f64))
            },
            |w| b64.pdf(wo64, w, Strategy::Vndf),
            &cfg,
            tests,
        );
        assert!(
            out.passed,
            "{p:?} at {theta} degrees: p = {:.3e}",
            out.p_value
        );
    }
}

/// The SIMD path's fast steps (f32 horizon test with a margin, direct normalisation; the
/// exact steps redone for a block where one element is outside their ranges): directions
/// whose cosine sweeps `COS_MIN` within 64 ulp (the margin is 1e-5 relative, about 84 ulp;
/// the f32 cosine's error a few ulp), at lengths around the direct range's ends (`|v|^2` near 2^-100
/// and 2^100) and ordinary ones, as `wo` and as `wi`: the density is the generic path's bit
/// for bit, and a draw exists exactly where the scalar sampler's does.
#[test]
fn ggx_vndf_simd_fast_steps_keep_the_exact_answers() {
    let p = [("d", "ggx"), ("alpha", "0.3")];
    let (b, simd) = build("cook-torrance", &p);
    let (_, mut generic) = build("cook-torrance", &p);
    generic.set_simd(false);
    let cos_min = fastbrdf::vec3::COS_MIN as f32;
    let mut edge: [Vec<f32>; 3] = Default::default();
    // z within 64 f32 ulp of COS_MIN (a power of 2), x and y of about unit length: the f64
    // cosine falls on both sides of COS_MIN within the f32 cosine's error.
    // One length after the other: a block of the fast path (128 elements) with one element
    // outside the direct range (2^-51) is redone whole on the exact steps.
    for len in [1.0, 0.3, 0.7, 2f64.powi(-50), 2f64.powi(-51), 2f64.powi(50)] {
        for k in -64..=64 {
            let z = cos_min * (1.0 + k as f32 * f32::EPSILON / 2.0);
            for j in 0..50 {
                let phi = j as f64 * 0.1234;
                let v = [phi.cos() * len, phi.sin() * len, z as f64 * len].map(|x| x as f32);
                for (e, x) in edge.iter_mut().zip(v) {
                    e.push(x);
                }
            }
        }
    }
    let n = edge[0].len();
    let good: [Vec<f32>; 3] = [vec![0.3; n], vec![-0.2; n], vec![0.8; n]];
    for (wo, wi) in [(&edge, &good), (&good, &edge), (&edge, &edge)] {
        let (mut got, mut want) = (vec![-7.0; n], vec![-7.0; n]);
        simd.pdf(Strategy::Vndf, refs(wo), refs(wi), &mut got)
            .unwrap();
        generic
            .pdf(Strategy::Vndf, refs(wo), refs(wi), &mut want)
            .unwrap();
        for i in 0..n {
            assert_eq!(got[i].to_bits(), want[i].to_bits(), "element {i}");
        }
    }
    let u: [Vec<f32>; 2] = [
        (0..n).map(|i| (i % 97) as f32 / 97.0).collect(),
        (0..n).map(|i| (i % 89) as f32 / 89.0).collect(),
    ];
    let mut o = Outs::new(n);
    simd.sample(Strategy::Vndf, refs(&edge), refs(&u), o.out())
        .unwrap();
    for i in 0..n {
        let w = [edge[0][i], edge[1][i], edge[2][i]];
        let r = b.sample(w, [u[0][i], u[1][i]], Strategy::Vndf);
        assert_eq!(r.is_some(), o.pdf[i] != 0.0, "wo {w:?}: {r:?}");
    }
}
