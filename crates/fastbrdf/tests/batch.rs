//! Batch kernels: the vector math's documented accuracy, every model's kernel against its
//! scalar model (including NaN, infinities, out-of-range and back-facing inputs, and lengths
//! that leave tails), and bit-identical results across instruction sets and threads.

mod common;

use common::{as_refs, configs, direction_pairs};
use fastbrdf::accuracy::lobe_samples;
use fastbrdf::batch::{Input, Isa, Kernel, math};
use fastbrdf::{Kind, Model, registry};

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

/// Inputs for a kernel: domain samples plus the awkward values, with a length that leaves a
/// tail for every vector width.
fn cos_inputs(n: f64) -> Vec<f32> {
    let mut v: Vec<f32> = lobe_samples(n).into_iter().map(|c| c as f32).collect();
    v.extend([
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -0.5,
        -0.0,
        0.0,
        1.0,
        1.5,
        1e-7,
        1e-30,
        0.5,
    ]);
    v.truncate(v.len() / 16 * 16 + 13);
    v
}

fn dir_inputs() -> [Vec<f32>; 6] {
    let mut cols: [Vec<f32>; 6] = Default::default();
    let mut push = |wi: [f32; 3], wo: [f32; 3]| {
        for k in 0..3 {
            cols[k].push(wi[k]);
            cols[k + 3].push(wo[k]);
        }
    };
    for (wi, wo) in direction_pairs(400, 9) {
        push(wi.map(|x| x as f32), wo.map(|x| x as f32));
    }
    let up = [0.0, 0.0, 1.0];
    for bad in [
        [0.0, 0.0, 0.0],
        [f32::NAN, 0.0, 1.0],
        [0.3, 0.2, -0.9],
        [1.0, 0.0, 0.0],
        [f32::INFINITY, 0.0, 1.0],
        [0.0, 0.0, 1e-9],
    ] {
        push(bad, up);
        push(up, bad);
    }
    push([3.0, 1.0, 5.0], [-2.0, 0.5, 4.0]); // unnormalised
    // Tiny, huge and subnormal lengths (issue 11: normalised scale-safely, like f64).
    for (i, (wi, wo)) in direction_pairs(12, 21).into_iter().enumerate() {
        let (a, b) = [(1e-30, 1e30), (3e38, 1e-42), (1e-42, 1.0), (1e-20, 1e20)][i % 4];
        push(wi.map(|x| (x * a) as f32), wo.map(|x| (x * b) as f32));
    }
    for c in cols.iter_mut() {
        c.truncate(c.len() / 16 * 16 + 7);
    }
    cols
}

/// Split-sum inputs `(cos_v, alpha)`: a grid over the domain and the awkward values in both
/// columns (the quadrature reference is slow in the scalar loop: a small set).
fn env_inputs() -> [Vec<f32>; 2] {
    let odd = [f32::NAN, f32::INFINITY, -0.5, 0.0, 1.0, 1.5, 1e-30];
    let mut cols: [Vec<f32>; 2] = Default::default();
    for v in [0.0f32, 1e-3, 0.05, 0.3, 0.7, 0.99, 1.0]
        .into_iter()
        .chain(odd)
    {
        for a in [0.005f32, 0.02, 0.1, 0.4, 1.0].into_iter().chain(odd) {
            cols[0].push(v);
            cols[1].push(a);
        }
    }
    cols
}

fn scalar(m: &Model<f32>, input: &Input, i: usize) -> f32 {
    match *input {
        Input::Cos(x) => m.eval_row(&[Some(x[i])]),
        Input::Dirs(w) => m.eval_row(&w.map(|s| Some(s[i]))),
        Input::Env(x) => m.eval_row(&x.map(|s| Some(s[i]))),
    }
}

#[test]
fn every_kernel_matches_its_scalar_model_on_every_isa() {
    let dirs = dir_inputs();
    let env = env_inputs();
    let mut no_simd = vec![];
    for e in registry::all()
        .iter()
        .filter(|e| e.info.kind != Kind::Shadowing)
    {
        let mut worst: f64 = 0.0;
        for cfg in configs(&e.info, true) {
            let given = as_refs(&cfg);
            let k = Kernel::new(e.info.id, &given).unwrap();
            let m = registry::build::<f32>(e.info.id, &given).unwrap();
            let cos;
            let input = if e.info.kind == Kind::Env {
                Input::Env([&env[0][..], &env[1]])
            } else if e.info.kind == Kind::Brdf {
                Input::Dirs([
                    &dirs[0][..],
                    &dirs[1],
                    &dirs[2],
                    &dirs[3],
                    &dirs[4],
                    &dirs[5],
                ])
            } else {
                cos = cos_inputs(common::get(&cfg, "n").unwrap_or(50.0));
                Input::Cos(&cos)
            };
            let len = input.len();
            // The rule (issue 13): the FMA instruction sets (AVX2+FMA, AVX-512) give identical
            // bits; SSE2 (no FMA: two roundings where they fuse) and each of them is held to
            // the scalar model's tolerance below.
            let mut outputs: Vec<(Isa, Vec<f32>)> = vec![];
            for &isa in Isa::available() {
                let mut out = vec![0.0f32; len];
                k.eval_with(isa, input, &mut out).unwrap();
                outputs.push((isa, out));
            }
            let fma: Vec<&(Isa, Vec<f32>)> = outputs.iter().filter(|(i, _)| i.fma()).collect();
            for (isa, out) in fma.iter().skip(1) {
                assert!(
                    out.iter()
                        .zip(&fma[0].1)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "{} {cfg:?}: {} differs from {}",
                    e.info.id,
                    isa.name(),
                    fma[0].0.name()
                );
            }
            let mut par = vec![0.0f32; len];
            k.eval_par(input, &mut par).unwrap();
            let mut best = vec![0.0f32; len];
            k.eval(input, &mut best).unwrap();
            assert!(
                par.iter()
                    .zip(&best)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{}: eval_par differs",
                e.info.id
            );
            if !k.simd() {
                no_simd.push(format!("{} {cfg:?}", e.info.id));
            }
            for (isa, out) in &outputs {
                for (i, &b) in out.iter().enumerate() {
                    let s = scalar(&m, &input, i);
                    assert!(
                        b.is_finite() && b >= 0.0,
                        "{} {cfg:?} #{i} ({}): batch gave {b}",
                        e.info.id,
                        isa.name()
                    );
                    // Zero by a domain rule in the scalar model (NaN, back-facing, zero
                    // vectors, below a cut) must be zero here too; elsewhere the fast
                    // exp2/log2 and the fused multiply-adds may move the value by a few ulp,
                    // amplified like the f32 path itself.
                    if s == 0.0 && scalar_zero_by_rule(&input, i) {
                        assert_eq!(b, 0.0, "{} {cfg:?} #{i}", e.info.id);
                    }
                    let err = (b as f64 - s as f64).abs() / (s as f64).abs().max(1.0);
                    worst = worst.max(err);
                    let tol = 2.0 * e.info.f32_bound + 3e-6;
                    assert!(
                        err <= tol,
                        "{} {cfg:?} #{i} ({}): batch {b} vs scalar {s} (err {err:.2e} > {tol:.1e})",
                        e.info.id,
                        isa.name()
                    );
                }
            }
        }
        println!(
            "{:<24} batch vs scalar f32: max mixed error {worst:.2e}",
            e.info.id
        );
    }
    println!("scalar fallbacks: {}", no_simd.len());
    // Only Cook-Torrance with an exact (erf) Beckmann Smith term (separable or
    // height-correlated) or with an energy compensation (table gathers) and the quadrature
    // reference env-brdf lack a SIMD kernel.
    assert!(
        no_simd.iter().all(|s| s.starts_with("env-brdf ")
            || s.starts_with("cook-torrance")
                && (s.contains("\"smith\"")
                    || s.contains("\"smith-beckmann-correlated\"")
                    || s.contains("\"kulla-conty\"")
                    || s.contains("\"filament\""))),
        "{no_simd:?}"
    );
}

/// Inputs where the scalar models return 0 by a documented rule (not by underflow).
fn scalar_zero_by_rule(input: &Input, i: usize) -> bool {
    match *input {
        Input::Cos(x) => x[i].is_nan(),
        // The split-sum terms clamp their inputs: no zero by rule.
        Input::Env(_) => false,
        Input::Dirs(w) => {
            let (a, b) = ([w[0][i], w[1][i], w[2][i]], [w[3][i], w[4][i], w[5][i]]);
            // The scalar models' own cut (COS_MIN decided in f64 on the given components),
            // not an approximation of it: a valid pair just above the cut whose value is 0
            // by clipping (a cubic's max(0, p)) may be a few ulp above 0 with fused
            // multiply-adds, within the tolerance.
            let bad = |v: [f32; 3]| {
                v.iter().any(|x| !x.is_finite())
                    || !fastbrdf::vec3::above_cos_min(v)
                    || (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
            };
            bad(a) || bad(b)
        }
    }
}

#[test]
fn kernels_reject_bad_shapes() {
    let k = Kernel::new("pow", &[]).unwrap();
    let mut out = vec![0.0; 3];
    assert!(k.eval(Input::Cos(&[0.5, 0.6]), &mut out).is_err());
    let z = [0.0f32; 3];
    assert!(
        k.eval(Input::Dirs([&z, &z, &z, &z, &z, &z]), &mut out)
            .is_err()
    );
    assert!(Kernel::new("smith", &[]).is_err());
    assert!(Kernel::new("pow", &[("n", "0")]).is_err());
}

/// issue 11: finite non-zero directions of any length have a direction. In f32, (1e-30, 0,
/// 1e-30) squared underflows to a zero length and was rejected as "zero-length" (and gave 0),
/// while f64 evaluated it. Every BRDF, scalar f32 and f64, `try_eval_row` and the batch
/// kernel: a scaled pair evaluates as the unit pair does.
#[test]
fn tiny_huge_and_subnormal_directions_evaluate_like_unit_ones() {
    let scales: [f64; 8] = [1e-30, 1e30, 3e38, 1e-38, 1e-42, 1e-45, 1e-20, 1e20];
    let pairs = direction_pairs(30, 33);
    for e in registry::all().iter().filter(|e| e.info.kind == Kind::Brdf) {
        let m32 = registry::build::<f32>(e.info.id, &[]).unwrap();
        let m64 = registry::build::<f64>(e.info.id, &[]).unwrap();
        let k = Kernel::new(e.info.id, &[]).unwrap();
        for (wi, wo) in &pairs {
            let (wi32, wo32) = (wi.map(|x| x as f32), wo.map(|x| x as f32));
            let unit32 = m32.eval_row(&opt(&[wi32, wo32].concat()));
            let unit64 = m64.eval_row(&opt(&[wi32.map(f64::from), wo32.map(f64::from)].concat()));
            for &a in &scales {
                for &b in &[1.0, a, 1.0 / a.max(1e-38)] {
                    // f32 inputs: the scaled components as f32 (subnormal ones lose bits,
                    // so compare with the direction they actually have).
                    let si = wi.map(|x| (x * a) as f32);
                    let so = wo.map(|x| (x * b) as f32);
                    if si.iter().chain(&so).any(|x| !x.is_finite())
                        || si.iter().all(|x| *x == 0.0)
                        || so.iter().all(|x| *x == 0.0)
                    {
                        continue;
                    }
                    // Rounding a subnormal component may leave a grazing direction.
                    let grazing = |v: [f32; 3]| {
                        let m = v.iter().fold(0f64, |m, x| m.max((*x as f64).abs()));
                        let l = v
                            .iter()
                            .map(|x| (*x as f64 / m).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        (v[2] as f64 / m) / l < 2e-6
                    };
                    if grazing(si) || grazing(so) {
                        continue;
                    }
                    let row32: Vec<Option<f32>> = [si, so].concat().into_iter().map(Some).collect();
                    let row64: Vec<Option<f64>> = row32.iter().map(|x| x.map(f64::from)).collect();
                    let v32 = m32.try_eval_row(&row32).unwrap_or_else(|err| {
                        panic!("{} f32 rejects {si:?} {so:?}: {err}", e.info.id)
                    });
                    let v64 = m64.try_eval_row(&row64).unwrap_or_else(|err| {
                        panic!("{} f64 rejects {si:?} {so:?}: {err}", e.info.id)
                    });
                    // The f64 value of the direction the f32 components have.
                    let dir = |v: [f32; 3]| {
                        let m = v.iter().fold(0f64, |m, x| m.max((*x as f64).abs()));
                        v.map(|x| x as f64 / m)
                    };
                    let exact = m64.eval_row(&opt(&[dir(si), dir(so)].concat()));
                    let tol = 1e-6 + 2.0 * e.info.f32_bound;
                    let close = |x: f64, y: f64| (x - y).abs() / y.abs().max(1.0) <= tol;
                    assert!(
                        close(v64, exact) && close(v32 as f64, exact),
                        "{} a={a} b={b}: f32 {v32}, f64 {v64}, unit-length f64 {exact}",
                        e.info.id
                    );
                    if a.max(b) < 1e37 && a.min(b) > 1e-37 {
                        // Normal components: the direction is exactly the unit pair's.
                        assert!(close(v64, unit64) && close(v32 as f64, unit32 as f64));
                    }
                    let cols: Vec<Vec<f32>> =
                        (0..6).map(|j| vec![[si, so].concat()[j]; 9]).collect();
                    let mut out = vec![0.0f32; 9];
                    let input =
                        Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
                    k.eval(input, &mut out).unwrap();
                    let ok = |x: f32| {
                        close(x as f64, v32 as f64)
                            || (x as f64 - v32 as f64).abs() <= 3e-6 * (v32 as f64).abs().max(1.0)
                    };
                    assert!(
                        out.iter().all(|&x| ok(x)),
                        "{} batch {:?} vs scalar {v32}",
                        e.info.id,
                        out[0]
                    );
                }
            }
        }
    }
}

fn opt<T: Copy>(v: &[T]) -> Vec<Option<T>> {
    v.iter().copied().map(Some).collect()
}

/// `eval_par` gives `eval`'s bits on both sides of its cut-off: a cheap lobe on a batch that
/// stays on one thread, and Cook-Torrance (tens of ns per element, so 2^17 elements are
/// milliseconds of work, far above `PAR_MIN_WORK`) on the pool; odd lengths test the tails.
#[test]
fn eval_par_matches_eval_on_both_sides_of_its_cutoff() {
    for (id, n) in [("power16", 50_001usize), ("cook-torrance", (1 << 17) + 7)] {
        let k = Kernel::new(id, &[]).unwrap();
        let mut s = 11u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 0.5
        };
        let cols: Vec<Vec<f32>> = (0..6).map(|_| (0..n).map(|_| next()).collect()).collect();
        let input = if id == "cook-torrance" {
            Input::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]])
        } else {
            Input::Cos(&cols[0])
        };
        let (mut a, mut b) = (vec![0.0f32; n], vec![0.0f32; n]);
        k.eval(input, &mut a).unwrap();
        k.eval_par(input, &mut b).unwrap();
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{id}: eval_par differs from eval"
        );
    }
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

/// The denormal policy: a value the scalar model gives as a subnormal number is 0 from the
/// kernel (power16 at n = 20 near its zero at c = 0.2: its base is clamped at `base_min`;
/// a Beckmann lobe far in its tail: flushed by the MXCSR switch), and the caller's
/// floating-point state is restored afterwards.
#[test]
fn kernels_flush_subnormal_results_to_zero_and_restore_the_callers_state() {
    let k = Kernel::new("power16", &[("n", "20")]).unwrap();
    let Model::Lobe(m) = registry::build::<f32>("power16", &[("n", "20")]).unwrap() else {
        panic!()
    };
    let c = [0.202f32; 37];
    let scalar = m.eval(c[0]);
    assert!(scalar > 0.0 && !scalar.is_normal(), "scalar {scalar:e}");
    // A flushing kernel: Beckmann at alpha = 0.05 where exp(-tan^2 / alpha^2) / cos^4 is
    // subnormal in f32 (found by scanning down from the peak).
    let kb = Kernel::new("beckmann", &[("alpha", "0.05")]).unwrap();
    assert!(kb.flush_to_zero());
    let Model::Distribution(mb) = registry::build::<f32>("beckmann", &[("alpha", "0.05")]).unwrap()
    else {
        panic!()
    };
    let cb = (0..100_000)
        .map(|i| 1.0 - i as f32 * 1e-5)
        .find(|&c| {
            let v = mb.eval(c);
            v > 0.0 && !v.is_normal()
        })
        .expect("a cosine with a subnormal Beckmann value");
    let cb = [cb; 37];
    #[cfg(target_arch = "x86_64")]
    let mxcsr = || {
        let mut v = 0u32;
        // SAFETY: stmxcsr stores the 32-bit MXCSR into a valid u32.
        unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut v, options(nostack)) };
        v
    };
    #[cfg(target_arch = "x86_64")]
    let before = mxcsr();
    for &isa in Isa::available() {
        let mut out = [1.0f32; 37];
        k.eval_with(isa, Input::Cos(&c), &mut out).unwrap();
        assert!(out.iter().all(|v| *v == 0.0), "{}: {out:?}", isa.name());
        let mut out = [1.0f32; 37];
        kb.eval_with(isa, Input::Cos(&cb), &mut out).unwrap();
        #[cfg(target_arch = "x86_64")]
        assert!(out.iter().all(|v| *v == 0.0), "{}: {out:?}", isa.name());
    }
    #[cfg(target_arch = "x86_64")]
    assert_eq!(mxcsr(), before, "MXCSR not restored");
    // The caller's own arithmetic still produces subnormals.
    assert!(!(std::hint::black_box(1e-30f32) * 1e-10).is_normal());
}

/// The denormal policy's choice per kernel (`Kernel::flush_to_zero`): the power forms never
/// flush (power16 clamps its base at `base_min`, checked in the test above; the others'
/// subnormal bands are under 1.5e-4 of [0, 1]); `cubic` and `schlick` never (subnormals only from tiny inputs: a plain kernel
/// then returns the subnormal value the scalar model gives), nor the spherical Gaussians
/// (their `exp2` is built from bits), nor `ggx` (no subnormal step: every output 0 or normal,
/// checked here on the awkward inputs); the others always. A plain kernel leaves the caller's
/// MXCSR alone too.
#[test]
fn the_flush_to_zero_switch_is_decided_per_kernel() {
    // The band's edge: the least base whose 2^k-th power by squarings is normal.
    for k in 2..=4u32 {
        let t = fastbrdf::lobes::power::base_min(k);
        let sq = |mut x: f32| {
            for _ in 0..k {
                x *= x;
            }
            x
        };
        assert!(
            sq(t) >= f32::MIN_POSITIVE && sq(f32::from_bits(t.to_bits() - 1)) < f32::MIN_POSITIVE
        );
    }
    let ftz = |id: &str, n: &str| Kernel::new(id, &[("n", n)]).unwrap().flush_to_zero();
    assert!(!ftz("power16", "20") && !ftz("power16", "200") && !ftz("power8", "1"));
    assert!(!ftz("power4", "200") && !ftz("power8", "200") && !ftz("power4", "20"));
    assert!(!ftz("cubic", "200") && !ftz("schlick", "200"));
    assert!(!ftz("sg", "200") && !ftz("ue4-phong-approx", "20") && ftz("pow", "200"));
    assert!(Kernel::new("beckmann", &[]).unwrap().flush_to_zero());
    for alpha in ["0.005", "0.3", "1"] {
        let k = Kernel::new("ggx", &[("alpha", alpha)]).unwrap();
        assert!(!k.flush_to_zero());
        let mut x = cos_inputs(50.0);
        x.extend([1e-38f32, 1e-40, f32::MIN_POSITIVE, 1.0 - f32::EPSILON, 1e-6]);
        for &isa in Isa::available() {
            let mut out = vec![0.0f32; x.len()];
            k.eval_with(isa, Input::Cos(&x), &mut out).unwrap();
            assert!(
                out.iter().all(|v| *v == 0.0 || v.is_normal()),
                "ggx alpha={alpha} ({}): {:?}",
                isa.name(),
                out.iter()
                    .zip(&x)
                    .find(|(v, _)| **v != 0.0 && !v.is_normal())
            );
        }
    }
    let k = Kernel::new("schlick", &[("n", "200")]).unwrap();
    let Model::Lobe(m) = registry::build::<f32>("schlick", &[("n", "200")]).unwrap() else {
        panic!()
    };
    let c = [1e-37f32; 21];
    let want = m.eval(c[0]);
    assert!(want > 0.0 && !want.is_normal(), "scalar {want:e}");
    for &isa in Isa::available() {
        let mut out = [0.0f32; 21];
        k.eval_with(isa, Input::Cos(&c), &mut out).unwrap();
        // The FMA form's denominator rounds differently from the scalar one: within 1%.
        assert!(
            out.iter().all(|v| (v / want - 1.0).abs() < 1e-2),
            "{}: {out:?} vs {want:e}",
            isa.name()
        );
    }
    // Forcing the switch on gives the flushed 0 instead.
    let mut k = k;
    k.set_flush_to_zero(true);
    let mut out = [1.0f32; 21];
    k.eval(Input::Cos(&c), &mut out).unwrap();
    #[cfg(target_arch = "x86_64")]
    assert!(out.iter().all(|v| *v == 0.0), "{out:?}");
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

/// issue 14: anisotropic `cook-torrance` (`alpha_x`, `alpha_y`: the registry-wide test above
/// gives them equal) in the batch kernels on every ISA against the scalar f32 model, every
/// allowed D and G, slopes to their extremes, within twice the anisotropic f32 bound.
#[test]
fn anisotropic_cook_torrance_kernels_match_the_scalar_model() {
    let dirs = dir_inputs();
    let input = Input::Dirs([
        &dirs[0][..],
        &dirs[1],
        &dirs[2],
        &dirs[3],
        &dirs[4],
        &dirs[5],
    ]);
    let tol = 2.0 * fastbrdf::brdf::cook_torrance::ANISO_F32 + 3e-6;
    let mut worst: f64 = 0.0;
    for &d in fastbrdf::brdf::cook_torrance::ANISO_D {
        for &g in fastbrdf::brdf::cook_torrance::ANISO_G {
            for (ax, ay) in [("0.005", "1"), ("0.5", "0.02"), ("0.3", "0.1")] {
                let given = [
                    ("d", d),
                    ("g", g),
                    ("f", "schlick"),
                    ("alpha_x", ax),
                    ("alpha_y", ay),
                ];
                let k = Kernel::new("cook-torrance", &given).unwrap();
                let m = registry::build::<f32>("cook-torrance", &given).unwrap();
                for &isa in Isa::available() {
                    let mut out = vec![0.0f32; input.len()];
                    k.eval_with(isa, input, &mut out).unwrap();
                    for (i, &b) in out.iter().enumerate() {
                        let s = scalar(&m, &input, i);
                        let err = (b as f64 - s as f64).abs() / (s as f64).abs().max(1.0);
                        worst = worst.max(err);
                        assert!(
                            b.is_finite() && err <= tol,
                            "{given:?} #{i} ({}): batch {b} vs scalar {s}",
                            isa.name()
                        );
                    }
                }
            }
        }
    }
    println!("anisotropic cook-torrance batch vs scalar f32: max mixed error {worst:.2e}");
}

/// `Kernel::pipe_ops` (issue 13: `fastbrdf bench` states the fraction of the machine's limit
/// for kernels whose vectorised `exp2` the registry's counts cannot see): on an instruction
/// set with FMA the families that count their kernels report them (`sg` at rates below and
/// above 127, where its batch forms differ); the others, and every kernel without FMA,
/// report nothing.
#[test]
fn kernels_count_their_multiply_pipe_operations_where_the_registry_cannot() {
    use fastbrdf::PipeOps;
    use fastbrdf::math::fast::{EXP2_C6, EXP2_NONPOS_TIMES_MULS};
    // Horner over EXP2_C6: one fused multiply-add a degree.
    assert_eq!(usize::from(EXP2_NONPOS_TIMES_MULS), EXP2_C6.len() - 1);
    let ops = |id: &str, p: &str, v: &str| Kernel::new(id, &[(p, v)]).unwrap().pipe_ops();
    let fma = Isa::best().fma();
    let want = |mul, div| fma.then_some(PipeOps { mul, div });
    assert_eq!(ops("sg", "n", "200"), want(7, 0));
    assert_eq!(ops("ue4-phong-approx", "n", "200"), want(7, 0));
    assert_eq!(ops("sg", "n", "20"), want(7, 0));
    assert_eq!(ops("beckmann", "alpha", "0.3"), want(11, 1));
    assert_eq!(ops("beckmann-ct", "alpha", "0.005"), want(11, 1));
    for (id, p, v) in [
        ("power16", "n", "200"),
        ("schlick", "n", "20"),
        ("ggx", "alpha", "0.3"),
    ] {
        assert_eq!(ops(id, p, v), None, "{id}");
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
