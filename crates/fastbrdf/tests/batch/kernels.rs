//! Every model's kernel against its scalar model (awkward inputs, tails), on every
//! instruction set and across threads; shapes, the denormal policy and the operation counts.

use super::*;

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
            let k = Kernel::new(&cfg).unwrap();
            let m = cfg.model::<f32>().unwrap();
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
                no_simd.push(cfg.clone());
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
    // Only Cook-Torrance and gltf-pbr with an energy compensation, gltf-pbr with its sheen
    // albedo table (table gathers), and the quadrature reference env-brdf lack a SIMD kernel (the exact Beckmann Smith terms have one since
    // issue 30: `math::fast::erfc`).
    let choice = |s: &ModelSpec, name: &str| match s.get(name) {
        Some(Given::Choice(c)) => c.clone(),
        _ => String::new(),
    };
    assert!(
        no_simd.iter().all(|s| s.id() == "env-brdf"
            || s.id() == "env-brdf-table" // table gathers
            // The sheen albedo rows: a quadrature, table gathers, and fits kept scalar.
            || s.id().starts_with("sheen-albedo")
            || s.id() == "cook-torrance"
                && matches!(choice(s, "ms").as_str(), "kulla-conty" | "filament")
            // gltf-pbr's sheen albedo table (gathers), when its sheen is on, its energy
            // compensation (the same table gathers as Cook-Torrance's) and its specular
            // albedo scaling (a split-sum row per direction: scalar).
            || s.id() == "gltf-pbr"
                && (choice(s, "sheen_albedo") == "table"
                    && !matches!(s.get("sheen_color"), Some(Given::Num(x)) if *x == 0.0)
                    || matches!(choice(s, "ms").as_str(), "kulla-conty" | "filament")
                    || !matches!(choice(s, "spec_albedo").as_str(), "" | "fresnel"))),
        "{no_simd:?}"
    );
}

#[test]
fn kernels_reject_bad_shapes() {
    let k = kernel("pow", &[]).unwrap();
    let mut out = vec![0.0; 3];
    assert!(k.eval(Input::Cos(&[0.5, 0.6]), &mut out).is_err());
    let z = [0.0f32; 3];
    assert!(
        k.eval(Input::Dirs([&z, &z, &z, &z, &z, &z]), &mut out)
            .is_err()
    );
    assert!(kernel("smith", &[]).is_err());
    assert!(kernel("pow", &[("n", "0")]).is_err());
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
        let m32 = build::<f32>(e.info.id, &[]).unwrap();
        let m64 = build::<f64>(e.info.id, &[]).unwrap();
        let k = kernel(e.info.id, &[]).unwrap();
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

/// Blocks whose directions are all of unit length normalise them by the series alone (issue
/// 30, `vec3::inv_len`); the others choose per direction. Neither may change a
/// value: a pair evaluates to the same bits whether or not its block holds a direction of
/// another length (here every 97th `wi` doubled: exact in f32, the same direction, whose value
/// must be the unit one's to within rounding), on every instruction set, for every BRDF's
/// kernel. (`vec3`'s tests check the two set-ups against each other in f64.)
#[test]
fn a_pairs_value_does_not_depend_on_the_lengths_in_its_block() {
    let pairs = direction_pairs(700, 17);
    let cols = |scale: bool| -> [Vec<f32>; 6] {
        let mut c: [Vec<f32>; 6] = Default::default();
        for (i, (wi, wo)) in pairs.iter().enumerate() {
            let s = if scale && i % 97 == 5 { 2.0 } else { 1.0 };
            for k in 0..3 {
                c[k].push((wi[k] * s) as f32);
                c[k + 3].push(wo[k] as f32);
            }
        }
        c
    };
    let (unit, mixed) = (cols(false), cols(true));
    fn dirs(c: &[Vec<f32>; 6]) -> Input<'_> {
        Input::Dirs([
            &c[0][..],
            &c[1][..],
            &c[2][..],
            &c[3][..],
            &c[4][..],
            &c[5][..],
        ])
    }
    let n = pairs.len();
    let mut checked = 0;
    for e in registry::all().iter().filter(|e| e.info.kind == Kind::Brdf) {
        for cfg in configs(&e.info, true) {
            let k = Kernel::new(&cfg).unwrap();
            for &isa in Isa::available() {
                let (mut a, mut b) = (vec![0.0f32; n], vec![0.0f32; n]);
                k.eval_with(isa, dirs(&unit), &mut a).unwrap();
                k.eval_with(isa, dirs(&mixed), &mut b).unwrap();
                for i in (0..n).filter(|i| i % 97 == 5) {
                    // The doubled direction, normalised by the general path: the same value
                    // to within its rounding (a block let through the test by mistake would
                    // scale it by the series at `|wi|^2 = 4`).
                    let tol = 1e-5 * a[i].abs().max(1.0);
                    assert!(
                        (a[i] - b[i]).abs() <= tol,
                        "{cfg:?} ({}) pair {i}: {} unit, {} doubled",
                        isa.name(),
                        a[i],
                        b[i]
                    );
                }
                for i in (0..n).filter(|i| i % 97 != 5) {
                    assert_eq!(
                        a[i].to_bits(),
                        b[i].to_bits(),
                        "{cfg:?} ({}) pair {i}: {} in an all-unit block, {} beside a doubled wi",
                        isa.name(),
                        a[i],
                        b[i]
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 20, "{checked} kernels checked");
}

/// `eval_par` gives `eval`'s bits on both sides of its cut-off: a cheap lobe on a batch that
/// stays on one thread, and Cook-Torrance (tens of ns per element, so 2^17 elements are
/// milliseconds of work, far above `PAR_MIN_WORK`) on the pool; odd lengths test the tails.
#[test]
fn eval_par_matches_eval_on_both_sides_of_its_cutoff() {
    for (id, n) in [("power16", 50_001usize), ("cook-torrance", (1 << 17) + 7)] {
        let k = kernel(id, &[]).unwrap();
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

/// The denormal policy: a value the scalar model gives as a subnormal number is 0 from the
/// kernel (power16 at n = 20 near its zero at c = 0.2: its base is clamped at `base_min`;
/// a Beckmann lobe far in its tail: flushed by the MXCSR switch), and the caller's
/// floating-point state is restored afterwards.
#[test]
fn kernels_flush_subnormal_results_to_zero_and_restore_the_callers_state() {
    let k = kernel("power16", &[("n", "20")]).unwrap();
    let Model::Lobe(m) = build::<f32>("power16", &[("n", "20")]).unwrap() else {
        panic!()
    };
    let c = [0.202f32; 37];
    let scalar = m.eval(c[0]);
    assert!(scalar > 0.0 && !scalar.is_normal(), "scalar {scalar:e}");
    // A flushing kernel: Beckmann at alpha = 0.05 where exp(-tan^2 / alpha^2) / cos^4 is
    // subnormal in f32 (found by scanning down from the peak).
    let kb = kernel("beckmann", &[("alpha", "0.05")]).unwrap();
    assert!(kb.flush_to_zero());
    let Model::Distribution(mb) = build::<f32>("beckmann", &[("alpha", "0.05")]).unwrap() else {
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
    let ftz = |id: &str, n: &str| kernel(id, &[("n", n)]).unwrap().flush_to_zero();
    assert!(!ftz("power16", "20") && !ftz("power16", "200") && !ftz("power8", "1"));
    assert!(!ftz("power4", "200") && !ftz("power8", "200") && !ftz("power4", "20"));
    assert!(!ftz("cubic", "200") && !ftz("schlick", "200"));
    assert!(!ftz("sg", "200") && !ftz("ue4-phong-approx", "20") && ftz("pow", "200"));
    assert!(kernel("beckmann", &[]).unwrap().flush_to_zero());
    for alpha in ["0.005", "0.3", "1"] {
        let k = kernel("ggx", &[("alpha", alpha)]).unwrap();
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
    let k = kernel("schlick", &[("n", "200")]).unwrap();
    let Model::Lobe(m) = build::<f32>("schlick", &[("n", "200")]).unwrap() else {
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
                let k = kernel("cook-torrance", &given).unwrap();
                let m = build::<f32>("cook-torrance", &given).unwrap();
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
    let ops = |id: &str, p: &str, v: &str| kernel(id, &[(p, v)]).unwrap().pipe_ops();
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
