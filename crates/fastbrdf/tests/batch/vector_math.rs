//! The vector math the kernels are built from (`fastbrdf::batch::math`): each function's
//! documented accuracy, in its plain and fused-multiply-add variants, over the range it
//! serves.

use super::*;

#[test]
fn exp2_is_within_2_ulp() {
    let mut worst: f64 = 0.0;
    for i in 0..=2_000_000 {
        let x = -126.0 + 253.0 * i as f32 / 2_000_000.0;
        let (got, want) = (math::exp2(x) as f64, (x as f64).exp2());
        worst = worst.max((got - want).abs() / want);
    }
    println!(
        "exp2 max relative error {worst:.3e} ({:.2} ulp)",
        worst / f32::EPSILON as f64
    );
    assert!(worst <= 2.0 * f32::EPSILON as f64, "{worst}");
    assert_eq!(math::exp2(-130.0), 0.0);
    assert_eq!(math::exp2(-126.0), f32::MIN_POSITIVE);
    for x in [-126.2f32, -126.6, -126.99] {
        assert_eq!(math::exp2(x), 0.0, "exp2({x})");
        assert_eq!(fastbrdf::math::fast::fma::exp2(x), 0.0, "fma::exp2({x})");
    }
    assert_eq!(math::exp2(f32::NEG_INFINITY), 0.0);
    assert_eq!(math::exp2(200.0), f32::INFINITY);
    assert!(math::exp2(f32::NAN).is_nan());
    assert_eq!(math::exp2(0.0), 1.0);
}

#[test]
fn log2_and_pow_and_acos_are_within_their_documented_bounds() {
    let mut worst_log: f64 = 0.0;
    let mut x = f32::MIN_POSITIVE;
    while x < 4.0 {
        let (got, want) = (math::log2(x) as f64, (x as f64).log2());
        worst_log = worst_log.max((got - want).abs() / want.abs().max(1.0));
        x *= 1.000_01;
    }
    println!("log2 max error {worst_log:.3e}");
    assert!(worst_log <= 6e-8, "{worst_log}");
    let mut x = f32::MIN_POSITIVE;
    while x < 4.0 {
        assert!(
            (math::log2_wide(x) - (x as f64).log2()).abs() <= 1e-12,
            "log2_wide({x})"
        );
        x *= 1.000_1;
    }
    let worst_exp = (0..=1_000_000)
        .map(|i| -87.0 + 175.0 * i as f32 / 1_000_000.0)
        .map(|x| ((math::exp(x) as f64) - (x as f64).exp()).abs() / (x as f64).exp())
        .fold(0.0, f64::max);
    println!("exp max relative error {worst_exp:.3e}");
    assert!(worst_exp <= 2.0 * f32::EPSILON as f64, "{worst_exp}");
    assert_eq!(math::log2(0.0), f32::NEG_INFINITY);
    assert!(math::log2(-1.0).is_nan());
    let mut worst_pow: f64 = 0.0;
    // Up to 1e5: lobe exponents n and Ward's and seed 000's 2/alpha^2 (8e4 at alpha = 0.005).
    for y in [1.0f32, 1.5, 7.0, 20.0, 100.0, 1000.0, 10000.0, 100000.0] {
        // Uniform in [0, 1], and dense below 1 where c^y with a large y is not negligible.
        for i in 1..=400_000 {
            let x = if i <= 200_000 {
                i as f32 / 200_000.0
            } else {
                1.0 - (i - 200_000) as f32 * 1e-9 * (1.0 + y.min(1000.0))
            };
            let want = (x as f64).powf(y as f64);
            if want < 1e-9 {
                continue;
            }
            let rel = (math::pow(x, y) as f64 - want).abs() / want;
            worst_pow = worst_pow.max(rel / (2.0 * f32::EPSILON as f64));
        }
    }
    println!("pow max error = {worst_pow:.3} x 2 ulp");
    assert!(worst_pow <= 1.0);
    assert_eq!(math::pow(0.0, 3.0), 0.0);
    let worst_acos = (0..=100_000)
        .map(|i| i as f32 / 100_000.0)
        .map(|x| (math::acos(x) as f64 - (x as f64).acos()).abs())
        .fold(0.0, f64::max);
    println!("acos max abs error {worst_acos:.3e}");
    assert!(worst_acos <= 3e-7, "{worst_acos}");
}

/// The fused-multiply-add variants of the vector functions (the AVX2+FMA and AVX-512
/// kernels') keep the same bounds as the plain ones (here `mul_add` runs as libm's `fmaf`:
/// same results, slower, so the grids are smaller).
#[test]
fn fma_variants_of_the_vector_functions_keep_their_bounds() {
    use fastbrdf::math::fast::fma;
    let eps = f32::EPSILON as f64;
    let worst = |f: &dyn Fn(f32) -> f64, g: &dyn Fn(f64) -> f64, xs: Vec<f32>| {
        xs.into_iter()
            .map(|x| (f(x) - g(x as f64)).abs() / g(x as f64).abs().max(1e-300))
            .fold(0.0, f64::max)
    };
    let e2 = worst(
        &|x| fma::exp2(x) as f64,
        &|x| x.exp2(),
        (0..=200_000)
            .map(|i| -126.0 + 253.0 * i as f32 / 2e5)
            .collect(),
    );
    let e = worst(
        &|x| fma::exp(x) as f64,
        &|x| x.exp(),
        (0..=200_000)
            .map(|i| -87.0 + 175.0 * i as f32 / 2e5)
            .collect(),
    );
    let ac = worst(
        &|x| fma::acos(x) as f64,
        &|x| x.acos(),
        (0..=100_000).map(|i| i as f32 / 1e5).collect(),
    );
    println!("fma: exp2 {e2:.2e}, exp {e:.2e}, acos {ac:.2e}");
    assert!(e2 <= 2.0 * eps && e <= 2.0 * eps, "{e2} {e}");
    assert!(ac <= 4.0 * eps, "{ac}");
    let mut x = f32::MIN_POSITIVE;
    while x < 4.0 {
        assert!(
            (fma::log2_wide(x) - (x as f64).log2()).abs() <= 1e-12,
            "{x}"
        );
        x *= 1.001;
    }
    // fma::log2 is f32 arithmetic (flog's kernels): one epsilon, mixed absolute/relative, over the
    // normal floats up to 2^24 and every f32 within 4096 ulp of 1, its hardest neighbourhood.
    let mut worst_log: f64 = 0.0;
    let mut x = f32::MIN_POSITIVE;
    let near_one = (-4096..=4096).map(|k| f32::from_bits((1.0f32.to_bits() as i32 + k) as u32));
    let mut grid = vec![];
    while x < 16_777_216.0 {
        grid.push(x);
        x *= 1.000_03;
    }
    for x in grid.into_iter().chain(near_one) {
        let want = (x as f64).log2();
        worst_log = worst_log.max((fma::log2(x) as f64 - want).abs() / want.abs().max(1.0));
    }
    println!("fma::log2 max error {worst_log:.3e}");
    assert!(worst_log <= eps, "fma::log2: {worst_log:.3e}");
    assert_eq!(fma::log2(0.0), f32::NEG_INFINITY);
    assert_eq!(fma::log2(1.0), 0.0);
    assert!(fma::log2(-1.0).is_nan() && fma::log2(f32::NAN).is_nan());
    // fma::pow is double-f32 (not the f64 form): the same grid as `math::pow`'s test, and
    // every f32 in the interval edges' neighbourhoods of its three reduction centres.
    for y in [
        1.0f32, 1.5, 7.0, 20.0, 200.0, 1234.5, 10000.0, 99999.0, 100000.0,
    ] {
        let dense = (1..=200_000).map(|i| 1.0 - i as f32 * 1e-9 * (1.0 + y.min(1000.0)));
        let edges = [0.890_898_7f32, 1.122_462 / 2.0, 0.707_106_77, 0.5]
            .into_iter()
            .flat_map(|x0| {
                (-2000..=2000).map(move |k| f32::from_bits((x0.to_bits() as i32 + k) as u32))
            });
        for x in (1..=200_000)
            .map(|i| i as f32 / 200_000.0)
            .chain(dense)
            .chain(edges)
        {
            let want = (x as f64).powf(y as f64);
            if want >= 1e-30 {
                let rel = (fma::pow(x, y) as f64 - want).abs() / want;
                assert!(rel <= 2.0 * eps, "pow({x}, {y}): {rel:.2e}");
                // The clamped lobe's form: the same bits wherever the result is normal.
                assert_eq!(fma::pow_unit(x, y).to_bits(), fma::pow(x, y).to_bits());
            } else if want < f64::from(f32::MIN_POSITIVE) {
                // Below the normal range: 0 or a value under 2^-126, never more.
                let u = fma::pow_unit(x, y);
                assert!(
                    (0.0..=f32::MIN_POSITIVE).contains(&u),
                    "pow_unit({x}, {y}) = {u:e}"
                );
            } else if want >= 2.0 * f64::from(f32::MIN_POSITIVE) {
                assert_eq!(fma::pow_unit(x, y).to_bits(), fma::pow(x, y).to_bits());
            }
        }
    }
    for y in [1.0f32, 1.5, 200.0, 1e5] {
        // x = 0, subnormal and the smallest normals: 0, or at most 2^-126 (y = 1).
        for x in [
            0.0f32,
            1e-45,
            1e-40,
            f32::MIN_POSITIVE,
            2.0 * f32::MIN_POSITIVE,
        ] {
            let u = fma::pow_unit(x, y);
            assert!(
                (0.0..=f32::MIN_POSITIVE).contains(&u) || x.powf(y) >= f32::MIN_POSITIVE,
                "pow_unit({x:e}, {y}) = {u:e}"
            );
        }
        assert_eq!(fma::pow_unit(1.0, y), 1.0);
    }
    assert_eq!(fma::pow(0.0, 3.0), 0.0);
    assert_eq!(fma::pow(1.0, 1e5), 1.0);
    assert!(fma::pow(f32::NAN, 2.0).is_nan() && fma::pow(-0.5, 2.0).is_nan());
}

/// The non-positive-argument exponentials (sg, gauss, Beckmann, Ward): the plain and fused
/// variants keep `exp2`'s and `exp`'s 2-ulp bound on the whole range they serve, give 0 below
/// it, and 0 or NaN for NaN (the kernels' final max(0, .) makes that 0).
#[test]
fn nonpositive_exponentials_keep_the_bounds() {
    use fastbrdf::math::fast::{self, fma};
    let eps = f32::EPSILON as f64;
    for (name, f, g, lo) in [
        (
            "exp2_nonpos",
            fast::exp2_nonpos as fn(f32) -> f32,
            f64::exp2 as fn(f64) -> f64,
            -126.0f32,
        ),
        ("exp_nonpos", fast::exp_nonpos, f64::exp, -87.0),
        ("fma::exp2_nonpos", fma::exp2_nonpos, f64::exp2, -126.0),
        ("fma::exp_nonpos", fma::exp_nonpos, f64::exp, -87.0),
    ] {
        let steps = 400_000;
        let worst = (0..=steps)
            .map(|i| lo * i as f32 / steps as f32)
            .map(|x| ((f(x) as f64) - g(x as f64)).abs() / g(x as f64))
            .fold(0.0, f64::max);
        println!("{name}: {worst:.2e}");
        assert!(worst <= 2.0 * eps, "{name}: {worst:.3e}");
        assert_eq!(f(-200.0), 0.0, "{name}");
        assert_eq!(f(0.0), 1.0, "{name}");
        if name.contains("exp2") {
            // 2^-126 is the last normal result; below it 0 (the exponent addition cannot
            // build subnormals, and used to return wrong ones there).
            assert_eq!(f(-126.0), f32::MIN_POSITIVE, "{name}");
            for x in [-126.001f32, -126.3, -126.5, -126.7, -126.999] {
                assert_eq!(f(x), 0.0, "{name}({x})");
            }
        }
        let nan = f(f32::NAN);
        assert!(nan == 0.0 || nan.is_nan(), "{name}: {nan}");
    }
}

/// The split-sum terms' argument rule has two spellings (generic selects for the scalar
/// models, concrete ones for the kernels: `plan::env_args`, `env_args_batch`): the same bits
/// on every awkward and ordinary input.
#[test]
fn env_args_forms_agree_bit_for_bit() {
    let [v, a] = env_inputs();
    let mut extra = vec![
        -0.0f32,
        f32::NEG_INFINITY,
        f32::MIN_POSITIVE,
        1e-40,
        0.999_999_9,
        1.000_000_1,
    ];
    extra.extend((0..=200).map(|i| i as f32 / 200.0));
    for (&x, &y) in v
        .iter()
        .zip(&a)
        .chain(extra.iter().flat_map(|x| extra.iter().map(move |y| (x, y))))
    {
        let (g, b) = (
            fastbrdf::plan::env_args::<f32>(x, y),
            fastbrdf::plan::env_args_batch(x, y),
        );
        assert_eq!(
            (g.0.to_bits(), g.1.to_bits()),
            (b.0.to_bits(), b.1.to_bits()),
            "({x:e}, {y:e}): {g:?} vs {b:?}"
        );
    }
}

/// `exp2_nonpos_times` (Beckmann's batch form): `s 2^x` within 3 ulp on [-123, 0] for scales
/// across the documented [1/4, 2^64] (Beckmann's and Cook-Torrance's at alpha 1 and 0.005
/// among them), exactly `s` at 0, and 0 below -123 and for NaN.
#[test]
fn scaled_exponential_keeps_its_bound() {
    use fastbrdf::math::fast::{self, fma};
    let eps = f32::EPSILON as f64;
    for (name, f) in [
        (
            "exp2_nonpos_times",
            fast::exp2_nonpos_times as fn(f32, f32) -> f32,
        ),
        ("fma::exp2_nonpos_times", fma::exp2_nonpos_times),
    ] {
        for s in [
            0.25f32,
            1.0 / std::f32::consts::PI,
            1.0,
            3.5368,
            1e4,
            1.2732e4,
            2f32.powi(64),
        ] {
            let steps = 200_000;
            let mut worst: f64 = 0.0;
            for i in 0..=steps {
                let x = -123.0 * i as f32 / steps as f32;
                let want = s as f64 * (x as f64).exp2();
                let got = f(x, s);
                assert!(got.is_normal(), "{name}({x}, {s}) = {got:e}");
                let got = got as f64;
                worst = worst.max((got - want).abs() / want);
            }
            println!("{name} s = {s:e}: {worst:.2e}");
            assert!(worst <= 3.0 * eps, "{name} s = {s}: {worst:.3e}");
            assert_eq!(f(0.0, s), s, "{name}");
            for x in [
                -123.01f32,
                -126.0,
                -127.5,
                -1e30,
                f32::NEG_INFINITY,
                f32::NAN,
            ] {
                assert_eq!(f(x, s), 0.0, "{name}({x}, {s})");
            }
        }
    }
}

/// `exp2_nonpos_tail` (the spherical Gaussians' kernels, no final select): within 3 ulp of
/// `2^x` down to -125.5, off by at most 2^-126 below (where the exact value is under
/// 2^-125.5), never negative or NaN, and exactly 0 for NaN, -inf and everything at or below
/// -127 (every f32 of the tail [-127, -125.5] is checked).
#[test]
fn exponential_without_the_select_keeps_its_tail_bound() {
    use fastbrdf::math::fast::{self, fma};
    let eps = f32::EPSILON as f64;
    for (name, f) in [
        ("exp2_nonpos_tail", fast::exp2_nonpos_tail as fn(f32) -> f32),
        ("fma::exp2_nonpos_tail", fma::exp2_nonpos_tail),
    ] {
        let mut worst: f64 = 0.0;
        let steps = 400_000;
        for i in 0..=steps {
            let x = -125.5 * i as f32 / steps as f32;
            let want = (x as f64).exp2();
            let got = f(x);
            assert!(got.is_normal(), "{name}({x}) = {got:e}");
            let got = got as f64;
            worst = worst.max((got - want).abs() / want);
        }
        println!("{name}: {:.2} f32 epsilons down to -125.5", worst / eps);
        assert!(worst <= 3.0 * eps, "{name}: {worst:.3e}");
        assert_eq!(f(0.0), 1.0, "{name}");
        // Every f32 between -127 and -125.5: the tail.
        let (lo, hi) = ((-127.0f32).to_bits(), (-125.5f32).to_bits());
        let mut tail: f64 = 0.0;
        for b in hi..=lo {
            let x = f32::from_bits(b);
            let got = f(x);
            assert!(got >= 0.0 && got.is_finite(), "{name}({x}) = {got:e}");
            tail = tail.max((got as f64 - (x as f64).exp2()).abs());
        }
        assert!(tail <= 2f64.powi(-126), "{name}: tail error {tail:e}");
        for x in [-127.0f32, -128.0, -1e30, f32::NEG_INFINITY, f32::NAN] {
            assert_eq!(f(x).to_bits(), 0, "{name}({x})");
        }
    }
}
