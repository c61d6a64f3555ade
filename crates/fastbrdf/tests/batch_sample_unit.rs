//! The unit tier of the GGX `vndf` SIMD path (`batch::sample`'s `ggx` header): inputs of
//! near unit length (`|v|^2` within `NEAR` of 1, what renderers and numpy callers pass) take
//! closed forms (no normalisation, one square root and one division for `pdf`; the weight
//! `4 k G2 / G1` for `sample`) whose values are the exact tiers' (the scalar model's) within
//! the bounds below, tested here; elsewhere the exact tiers, bit for bit
//! (`tests/batch_sample.rs`).

// Elements are compared by index across several parallel arrays.
#![allow(clippy::needless_range_loop)]

mod common;

use common::Outs;
use fastbrdf::batch::sample::Sampler;
use fastbrdf::sample::{Rng, Strategy};
use fastbrdf::{Brdf, Model, ModelSpec};

/// The unit tier's `pdf` against the scalar model's, relative: `PDF_REL (1 + 1 / (alpha
/// |wo + wi|))` (the half vector's direction, rounded differently in the two, moves `D` by
/// up to about `2 / alpha` times its angle; `|wo + wi|` divides that angle).
pub const PDF_REL: f64 = 1e-6;
/// `sample`'s weight against the f64 model's `f cos_i / pdf` at the drawn direction (mixed:
/// relative above 1, absolute below).
pub const WEIGHT_ERR: f64 = 1e-5;

fn build(p: &[(&str, &str)]) -> (Box<dyn Brdf<f32>>, Sampler, Sampler) {
    let spec = ModelSpec::parse("cook-torrance", p).unwrap();
    let Model::Brdf(b) = spec.model::<f32>().unwrap() else {
        panic!()
    };
    let mut generic = Sampler::new(&spec).unwrap();
    generic.set_simd(false);
    (b, Sampler::new(&spec).unwrap(), generic)
}

fn cases() -> Vec<(Vec<(&'static str, &'static str)>, f64)> {
    vec![
        (vec![("d", "ggx"), ("alpha", "0.3")], 0.3),
        (vec![("d", "ggx"), ("alpha", "0.005")], 0.005),
        (vec![("d", "ggx"), ("alpha", "1")], 1.0),
        (
            vec![("d", "ggx"), ("alpha_x", "0.1"), ("alpha_y", "0.4")],
            0.1,
        ),
        (vec![("d", "ggx"), ("f", "schlick"), ("alpha", "0.2")], 0.2),
        (
            vec![
                ("d", "ggx"),
                ("g", "smith-ggx-correlated"),
                ("alpha", "0.3"),
            ],
            0.3,
        ),
        (
            vec![
                ("d", "ggx"),
                ("g", "smith-ggx-correlated"),
                ("ms", "kulla-conty"),
            ],
            0.3,
        ),
    ]
}

/// `n` unit directions (f64, rounded to f32) over the upper hemisphere, a quarter grazing.
fn unit_dirs(r: &mut Rng, n: usize) -> [Vec<f32>; 3] {
    let mut v: [Vec<f32>; 3] = Default::default();
    for i in 0..n {
        let z = if i % 4 == 3 {
            1e-3 * r.uniform() + 2e-6
        } else {
            r.uniform()
        };
        let phi = std::f64::consts::TAU * r.uniform();
        let s = (1.0 - z * z).sqrt();
        for (k, c) in [s * phi.cos(), s * phi.sin(), z].into_iter().enumerate() {
            v[k].push(c as f32);
        }
    }
    v
}

fn refs<const N: usize>(v: &[Vec<f32>; N]) -> [&[f32]; N] {
    std::array::from_fn(|k| v[k].as_slice())
}

fn row(v: &[Vec<f32>; 3], i: usize) -> [f32; 3] {
    [v[0][i], v[1][i], v[2][i]]
}

/// The unit tier's densities of random unit pairs against the scalar model's: zero where it
/// is zero, else within `PDF_REL (1 + 1 / (alpha |wo + wi|))`; and the tier runs (values
/// that differ in their bits exist).
#[test]
fn unit_tier_pdf_tracks_the_scalar_model() {
    for (p, alpha) in cases() {
        let (b, simd, _) = build(&p);
        let mut r = Rng::new(11);
        let n = 40_000;
        let (wo, wi) = (unit_dirs(&mut r, n), unit_dirs(&mut r, n));
        let mut got = vec![-7.0; n];
        simd.pdf(Strategy::Vndf, refs(&wo), refs(&wi), &mut got)
            .unwrap();
        let (mut worst, mut differ) = (0f64, 0);
        for i in 0..n {
            let (o, w) = (row(&wo, i), row(&wi, i));
            let want = b.pdf(o, w, Strategy::Vndf);
            assert_eq!(
                want == 0.0,
                got[i] == 0.0,
                "{p:?} {o:?} {w:?}: {} {want}",
                got[i]
            );
            if want == 0.0 {
                continue;
            }
            differ += usize::from(got[i].to_bits() != want.to_bits());
            let h = (0..3)
                .map(|k| (o[k] as f64 + w[k] as f64).powi(2))
                .sum::<f64>()
                .sqrt();
            let rel = (got[i] as f64 - want as f64).abs() / want as f64;
            let scaled = rel / (1.0 + 1.0 / (alpha * h));
            worst = worst.max(scaled);
            assert!(
                scaled <= PDF_REL,
                "{p:?} wo {o:?} wi {w:?}: {} vs {want} ({rel:.2e})",
                got[i]
            );
        }
        println!("{p:?}: worst scaled relative error {worst:.2e}, {differ} of {n} differ in bits");
        assert!(
            differ > n / 100,
            "{p:?}: the unit tier did not run ({differ})"
        );
    }
}

/// The unit tier's draws against the scalar sampler's (unit `wo`, random `u`): a draw exactly
/// where the scalar sampler draws; the density at the drawn `wi` within the pdf bound of
/// [`unit_tier_pdf_tracks_the_scalar_model`]; the weight, `4 k G2 / G1` where the model has
/// it in closed form, no further from the f64 model's `f cos_i / pdf` at that `wi` than the
/// scalar f32 sampler's weight plus `WEIGHT_ERR` (times the pdf bound's conditioning factor
/// where the weight is the eval kernel's `f cos_i / pdf`; elements the exact tiers decide, `wo.h`
/// below 1e-3 at grazing `wo`, keep the eval kernel's weight and its error).
#[test]
fn unit_tier_sample_tracks_the_scalar_model() {
    for (p, alpha) in cases() {
        let (b, simd, _) = build(&p);
        // The weight in closed form: no Fresnel term, no energy compensation.
        let closed = !p.iter().any(|(k, _)| *k == "f" || *k == "ms");
        let spec = ModelSpec::parse("cook-torrance", &p).unwrap();
        let Model::Brdf(b64) = spec.model::<f64>().unwrap() else {
            panic!()
        };
        let mut r = Rng::new(12);
        let n = 40_000;
        let wo = unit_dirs(&mut r, n);
        let u: [Vec<f32>; 2] =
            std::array::from_fn(|_| (0..n).map(|_| r.uniform() as f32).collect());
        let mut o = Outs::new(n);
        simd.sample(Strategy::Vndf, refs(&wo), refs(&u), o.out())
            .unwrap();
        let (mut worst_p, mut worst_w, mut worst_scalar, mut drawn) = (0f64, 0f64, 0f64, 0);
        for i in 0..n {
            let w = row(&wo, i);
            let got = row(&o.wi, i);
            let s = b.sample(w, [u[0][i], u[1][i]], Strategy::Vndf);
            assert_eq!(
                s.is_some(),
                o.pdf[i] != 0.0,
                "{p:?} wo {w:?}: {s:?} {}",
                o.pdf[i]
            );
            if s.is_none() {
                assert_eq!([got[0], got[1], got[2], o.weight[i]], [0.0; 4]);
                continue;
            }
            drawn += 1;
            let pdf = b.pdf(w, got, Strategy::Vndf);
            let h = (0..3)
                .map(|k| (w[k] as f64 + got[k] as f64).powi(2))
                .sum::<f64>()
                .sqrt();
            let rel = (o.pdf[i] as f64 - pdf as f64).abs() / pdf as f64 / (1.0 + 1.0 / (alpha * h));
            worst_p = worst_p.max(rel);
            assert!(rel <= PDF_REL, "{p:?} wo {w:?}: pdf {} vs {pdf}", o.pdf[i]);
            // The f64 model's weight at the drawn `wi` (its D cancels between f and pdf,
            // so the rounding of `wi` does not move it as it moves f32's D).
            let (w64, g64) = (w.map(f64::from), got.map(f64::from));
            let want = b64.eval(g64, w64) * g64[2] / b64.pdf(w64, g64, Strategy::Vndf);
            // Without a closed form the weight is the eval kernel's `f` at `wi` (its `D` at
            // the half vector of `wo` and the rounded `wi`) over the unit tier's density (its
            // `D` at the drawn normal): they no longer cancel, and the weight moves as the
            // density does, by the pdf bound's conditioning factor.
            let err = (o.weight[i] as f64 - want).abs() / want.abs().max(1.0);
            let err = if closed {
                err
            } else {
                err / (1.0 + 1.0 / (alpha * h))
            };
            let scalar = f64::from(s.unwrap().weight);
            let err32 = (scalar - want).abs() / want.abs().max(1.0);
            worst_w = worst_w.max(err);
            worst_scalar = worst_scalar.max(err32);
            assert!(
                err - err32 <= WEIGHT_ERR,
                "{p:?} wo {w:?} wi {got:?}: weight {} vs {want} (scalar {scalar})",
                o.weight[i]
            );
        }
        println!(
            "{p:?}: {drawn} drawn, worst pdf {worst_p:.2e} (scaled), weight {worst_w:.2e} \
             (the scalar f32 sampler's: {worst_scalar:.2e})"
        );
        assert!(drawn > n / 2, "{p:?}: {drawn}");
    }
}

/// Each element's value depends on its own inputs alone: unit-length elements sharing a
/// block with one that is not (which the exact tiers decide) get the values they get in an
/// all-unit batch, bit for bit, in `sample` and `pdf`.
#[test]
fn unit_tier_values_do_not_depend_on_the_neighbours() {
    let (_, simd, _) = build(&[("d", "ggx"), ("alpha", "0.3")]);
    let mut r = Rng::new(13);
    let n = 1000;
    let (wo, wi) = (unit_dirs(&mut r, n), unit_dirs(&mut r, n));
    let u: [Vec<f32>; 2] = std::array::from_fn(|_| (0..n).map(|_| r.uniform() as f32).collect());
    let mut odd = wo.clone();
    for i in (0..n).step_by(97) {
        for c in &mut odd {
            c[i] *= 3.0; // not near unit length: the exact tiers
        }
    }
    let (mut a, mut b) = (vec![-7.0; n], vec![-7.0; n]);
    simd.pdf(Strategy::Vndf, refs(&wo), refs(&wi), &mut a)
        .unwrap();
    simd.pdf(Strategy::Vndf, refs(&odd), refs(&wi), &mut b)
        .unwrap();
    let (mut sa, mut sb) = (Outs::new(n), Outs::new(n));
    simd.sample(Strategy::Vndf, refs(&wo), refs(&u), sa.out())
        .unwrap();
    simd.sample(Strategy::Vndf, refs(&odd), refs(&u), sb.out())
        .unwrap();
    let mut exact_differ = 0;
    for i in 0..n {
        let (x, y) = (sa.bits_at(i), sb.bits_at(i));
        if i % 97 == 0 {
            exact_differ += usize::from(a[i].to_bits() != b[i].to_bits() || x != y);
        } else {
            assert_eq!(a[i].to_bits(), b[i].to_bits(), "pdf {i}");
            assert_eq!(x, y, "sample {i}");
        }
    }
    // The scaled elements took the exact tiers: their values differ from the unit tier's.
    assert!(exact_differ > 0);
}
