//! `batch::per_element`: every element equals the model built for its values (its kernel in
//! f32, its scalar model in f64), bit for bit, across blocks, groups and parameters; checks
//! name the first refused element.

use fastbrdf::batch::per_element::{BLOCK, PerElement, Rows};
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::{Given, Model, ModelSpec};

/// A small deterministic generator in [0, 1).
fn uniform(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

#[test]
fn cosines_in_f32_and_f64_equal_a_model_per_value() {
    let spec = ModelSpec::parse("ggx", &[]).unwrap();
    let pe = PerElement::new(&spec, &["alpha"]).unwrap();
    let mut s = 7;
    let n = 2 * BLOCK + 123;
    let alpha: Vec<f64> = (0..n)
        .map(|_| f64::from((0.01 + (uniform(&mut s) * 37.0).floor() / 40.0) as f32))
        .collect();
    let cos: Vec<f32> = (0..n).map(|_| uniform(&mut s) as f32 * 1.2 - 0.1).collect();
    let cos64: Vec<f64> = cos.iter().map(|&c| f64::from(c)).collect();
    let (mut o32, mut o64) = (vec![0.0f32; n], vec![0.0f64; n]);
    pe.eval_f32(&[&alpha], Rows::Cols(&[&cos]), &mut o32)
        .unwrap();
    pe.eval_f64(&[&alpha], Rows::Cols(&[&cos64]), &mut o64)
        .unwrap();
    for i in (0..n).step_by(97) {
        let one = spec.with("alpha", Given::Num(alpha[i])).unwrap();
        let mut r = [0.0f32];
        Kernel::new(&one)
            .unwrap()
            .eval(Input::Cos(&cos[i..i + 1]), &mut r)
            .unwrap();
        assert_eq!(o32[i].to_bits(), r[0].to_bits(), "f32 element {i}");
        let Model::Distribution(d) = one.model::<f64>().unwrap() else {
            panic!()
        };
        assert_eq!(
            o64[i].to_bits(),
            d.eval(cos64[i]).to_bits(),
            "f64 element {i}"
        );
    }
}

#[test]
fn directions_with_two_parameters_equal_a_model_per_value() {
    let spec = ModelSpec::parse("cook-torrance", &[("d", "ggx"), ("f", "schlick")]).unwrap();
    let pe = PerElement::new(&spec, &["alpha", "f0"]).unwrap();
    let mut s = 11;
    let n = BLOCK + 500;
    let alpha: Vec<f64> = (0..n)
        .map(|_| [0.1, 0.3, 0.7][(uniform(&mut s) * 3.0) as usize])
        .collect();
    let f0: Vec<f64> = (0..n)
        .map(|_| [0.04, 0.9][(uniform(&mut s) * 2.0) as usize])
        .collect();
    let w: Vec<f32> = (0..6 * n)
        .map(|_| uniform(&mut s) as f32 * 2.0 - 0.5)
        .collect();
    let (wi, wo) = w.split_at(3 * n);
    let mut out = vec![0.0f32; n];
    pe.eval_f32(&[&alpha, &f0], Rows::Dirs(wi, wo), &mut out)
        .unwrap();
    for i in (0..n).step_by(61) {
        let one = spec
            .with("alpha", Given::Num(alpha[i]))
            .and_then(|x| x.with("f0", Given::Num(f0[i])))
            .unwrap();
        let mut r = [0.0f32];
        let c: [&[f32]; 6] = std::array::from_fn(|a| {
            if a < 3 {
                &wi[3 * i + a..3 * i + a + 1]
            } else {
                &wo[3 * i + a - 3..3 * i + a - 2]
            }
        });
        Kernel::new(&one)
            .unwrap()
            .eval(Input::Dirs(c), &mut r)
            .unwrap();
        assert_eq!(out[i].to_bits(), r[0].to_bits(), "element {i}");
    }
}

#[test]
fn checks_name_the_first_refused_element_and_the_parameter() {
    let spec = ModelSpec::parse("flog", &[]).unwrap();
    let pe = PerElement::new(&spec, &["n"]).unwrap();
    assert!(pe.check(0, &[1.0, 50.0, 3.0]).is_ok());
    let (i, e) = pe.check(0, &[1.0, f64::NAN, 0.0]).unwrap_err();
    assert_eq!(i, 1);
    assert!(
        e.to_string().contains("parameter n = NaN is invalid"),
        "{e}"
    );
    let (i, _) = pe.check(0, &[1.0, 2.0, 0.0]).unwrap_err();
    assert_eq!(i, 2);
    let ct = ModelSpec::parse("cook-torrance", &[]).unwrap();
    assert!(PerElement::new(&ct, &["d"]).is_err());
    assert!(PerElement::new(&ct, &["nope"]).is_err());
    // Lengths are checked.
    let mut out = [0.0f32; 2];
    assert!(
        pe.eval_f32(&[&[1.0]], Rows::Cols(&[&[0.5, 0.5]]), &mut out)
            .is_err()
    );
}

#[test]
fn each_model_visits_every_element_with_its_values_model() {
    let spec = ModelSpec::parse("flog", &[]).unwrap();
    let pe = PerElement::new(&spec, &["n"]).unwrap();
    let n = BLOCK + 10;
    let vals: Vec<f64> = (0..n).map(|i| [2.0, 20.0, 200.0][i % 3]).collect();
    let mut seen = 0;
    pe.each_model::<f64, fastbrdf::Error>(&[&vals], n, |i, m| {
        let Model::Lobe(l) = m else { panic!() };
        let one = spec.with("n", Given::Num(vals[i])).unwrap();
        let Model::Lobe(r) = one.model::<f64>().unwrap() else {
            panic!()
        };
        assert_eq!(l.eval(0.7).to_bits(), r.eval(0.7).to_bits(), "element {i}");
        seen += 1;
        Ok(())
    })
    .unwrap();
    assert_eq!(seen, n);
    assert!(
        pe.each_model::<f64, fastbrdf::Error>(&[&vals[..3]], n, |_, _| Ok(()))
            .is_err()
    );
}
