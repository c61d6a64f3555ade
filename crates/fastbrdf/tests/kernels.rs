//! Cook-Torrance's kernels (issue 28): which (D, G, F) combinations get a specialised kernel
//! (the rule of `batch::cook_torrance`), and that the generic path gives the specialised
//! kernels' values bit for bit, on every instruction set (but GGX's closed forms,
//! `tests/ggx_closed.rs`).

mod common;

use common::direction_pairs;
use fastbrdf::batch::{CtPath, Input, Isa, Kernel};
use fastbrdf::model::Kind;
use fastbrdf::plan::{BrdfPlan, Plan};
use fastbrdf::{ModelSpec, registry};
use std::collections::BTreeSet;
use std::mem::discriminant;

/// Direction pairs over several blocks of the generic path and a tail, with the invalid and
/// awkward inputs of `tests/batch/`.
fn dirs() -> [Vec<f32>; 6] {
    let mut cols: [Vec<f32>; 6] = Default::default();
    let mut push = |wi: [f32; 3], wo: [f32; 3]| {
        for k in 0..3 {
            cols[k].push(wi[k]);
            cols[k + 3].push(wo[k]);
        }
    };
    let up = [0.0, 0.0, 1.0];
    for (i, (wi, wo)) in direction_pairs(780, 5).into_iter().enumerate() {
        push(wi.map(|x| x as f32), wo.map(|x| x as f32));
        // Invalid pairs inside blocks, not only at the end.
        if i % 97 == 0 {
            push([0.3, 0.2, -0.9], up);
            push(up, [f32::NAN, 0.0, 1.0]);
        }
    }
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
    push([3.0, 1.0, 5.0], [-2.0, 0.5, 4.0]);
    push([1e-30, 0.0, 1e-30], [0.0, 1e-42, 1e-42]);
    cols
}

fn ids(kind: Kind) -> Vec<&'static str> {
    registry::ids_of(kind)
}

/// The plan of `cook-torrance` with `given`.
fn plan(given: &[(&str, &str)]) -> Plan {
    *ModelSpec::parse("cook-torrance", given)
        .unwrap()
        .plan()
        .unwrap()
}

fn is_scalar_g(g: &str) -> bool {
    match ModelSpec::parse(g, &[])
        .and_then(|s| s.plan().copied())
        .unwrap()
    {
        Plan::Shadowing(p) => !p.simd(),
        _ => panic!("{g} is not a shadowing term"),
    }
}

/// A Smith term (a function of the slope distribution's `alpha^2 tan^2 theta`).
fn is_smith(g: &str) -> bool {
    match ModelSpec::parse(g, &[])
        .and_then(|s| s.plan().copied())
        .unwrap()
    {
        Plan::Shadowing(p) => p.aniso(),
        _ => panic!("{g} is not a shadowing term"),
    }
}

/// The rule, stated independently of the kernels' match: each distribution's own Smith terms
/// (by the exact one its family names, `DistForm::smith`), the D-free terms with `none` and
/// `schlick`. A new distribution or Smith term must be placed here (the test panics on one it
/// cannot place), and the kernels then follow or this test fails.
fn expected(d: &str, g: &str, f: &str) -> bool {
    const OWN: &[(&str, &[&str])] = &[
        (
            "smith",
            &["smith", "smith-rational", "smith-beckmann-correlated"],
        ),
        (
            "smith-ggx",
            &[
                "smith-ggx",
                "smith-ggx-correlated",
                "smith-ggx-correlated-fast",
                "smith-ggx-correlated-fast-tuned",
                "smith-ggx-joint-approx",
                "schlick-ggx",
            ],
        ),
    ];
    let Plan::Distribution(dp) = ModelSpec::parse(d, &[])
        .and_then(|s| s.plan().copied())
        .unwrap()
    else {
        panic!("{d} is not a distribution")
    };
    use fastbrdf::plan::DistForm;
    let own = OWN
        .iter()
        .find(|(s, _)| *s == dp.smith())
        .unwrap_or_else(|| panic!("{d}'s Smith term {} is not placed in the rule", dp.smith()))
        .1;
    if is_smith(g) {
        assert!(
            OWN.iter().any(|(_, gs)| gs.contains(&g)),
            "Smith term {g} is not placed in the rule"
        );
    }
    // Not vectorised, or the exact Beckmann Smith terms (vectorised, but no faster fused
    // than on the generic path: `batch::cook_torrance`'s header, issue 30).
    if is_scalar_g(g) || matches!(g, "smith" | "smith-beckmann-correlated") {
        return false;
    }
    if is_smith(g) {
        own.contains(&g)
    } else {
        matches!(f, "none" | "schlick")
    }
}

/// Every registered D x G x F: specialised exactly where the rule says, and then SIMD; the
/// generic ones SIMD exactly when G vectorises. Prints the count of specialised (D, G, F)
/// family combinations (ids of one family, `beckmann` and `beckmann-ct`, share a kernel).
#[test]
fn cook_torrance_kernels_follow_the_rule() {
    let mut fams = BTreeSet::new();
    let mut all = BTreeSet::new();
    let mut generic = 0;
    for d in ids(Kind::Distribution) {
        for g in ids(Kind::Shadowing) {
            for f in ids(Kind::Fresnel) {
                let f = f.strip_prefix("fresnel-").unwrap();
                let given = [("d", d), ("g", g), ("f", f)];
                let p = plan(&given);
                let k = Kernel::from_plan("cook-torrance", &p).unwrap();
                let want = expected(d, g, f);
                assert_eq!(k.specialised(), want, "{given:?}");
                assert_eq!(k.simd(), !is_scalar_g(g), "{given:?}");
                let Plan::Brdf(BrdfPlan::CookTorrance(ct)) = p else {
                    unreachable!()
                };
                let key = format!(
                    "{:?}",
                    (
                        discriminant(&ct.d),
                        discriminant(&ct.g),
                        discriminant(&ct.f)
                    )
                );
                all.insert(key.clone());
                if want {
                    fams.insert(key);
                } else {
                    generic += 1;
                }
            }
        }
    }
    println!(
        "cook-torrance: {} of {} (D, G, F) family combinations specialised ({generic} id \
         combinations generic)",
        fams.len(),
        all.len()
    );
    // Energy compensation: the plan's parts per element, not specialised.
    let k = Kernel::new(
        &ModelSpec::parse(
            "cook-torrance",
            &[
                ("d", "ggx"),
                ("g", "smith-ggx-correlated"),
                ("ms", "kulla-conty"),
            ],
        )
        .unwrap(),
    )
    .unwrap();
    assert!(!k.specialised() && !k.simd());
    // Every other model's kernel is specialised.
    for e in registry::all() {
        if e.info.kind != Kind::Shadowing && e.info.id != "cook-torrance" {
            let k = Kernel::new(&ModelSpec::parse(e.info.id, &[]).unwrap()).unwrap();
            assert!(k.specialised(), "{}", e.info.id);
        }
    }
}

fn same_bits(a: &[f32], b: &[f32]) -> Option<usize> {
    a.iter()
        .zip(b)
        .position(|(x, y)| x.to_bits() != y.to_bits() && !(x.is_nan() && y.is_nan()))
}

/// The three paths (the rule's, the generic passes, the plan's parts per element) give the
/// same bits on every instruction set for every D x G x F, isotropic (with each denominator)
/// and anisotropic, but the rule's closed forms of GGX (`batch::ggx_closed`); and the generic
/// path and the rule's stay within the registry-wide tolerance of the scalar f32 model.
#[test]
fn generic_path_gives_the_specialised_kernels_bits() {
    let w = dirs();
    let input = Input::Dirs([&w[0][..], &w[1], &w[2], &w[3], &w[4], &w[5]]);
    let n = input.len();
    let tol = 2.0 * registry::find("cook-torrance").unwrap().info.f32_bound + 3e-6;
    let aniso_d = fastbrdf::brdf::cook_torrance::ANISO_D;
    let aniso_g = fastbrdf::brdf::cook_torrance::ANISO_G;
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for d in ids(Kind::Distribution) {
        for g in ids(Kind::Shadowing) {
            for f in ids(Kind::Fresnel) {
                let f = f.strip_prefix("fresnel-").unwrap();
                let mut cases: Vec<Vec<(&str, &str)>> = vec![
                    vec![("alpha", "0.3")],
                    vec![("alpha", "0.05"), ("denominator", "seed-000")],
                    vec![("alpha", "0.85"), ("denominator", "seed-001")],
                ];
                if aniso_d.contains(&d) && aniso_g.contains(&g) {
                    cases.push(vec![("alpha_x", "0.5"), ("alpha_y", "0.02")]);
                }
                for mut given in cases {
                    given.extend([("d", d), ("g", g), ("f", f)]);
                    let p = plan(&given);
                    let spec = ModelSpec::parse("cook-torrance", &given).unwrap();
                    let Ok(fastbrdf::Model::Brdf(m)) = spec.model::<f32>() else {
                        unreachable!()
                    };
                    let paths = [CtPath::Rule, CtPath::Generic, CtPath::PerElement]
                        .map(|c| Kernel::from_plan_path("cook-torrance", &p, c).unwrap());
                    for &isa in Isa::available() {
                        let outs: Vec<Vec<f32>> = paths
                            .iter()
                            .map(|k| {
                                let mut out = vec![0.0f32; n];
                                k.eval_with(isa, input, &mut out).unwrap();
                                out
                            })
                            .collect();
                        // GGX with its own Smith term and no Fresnel term or Schlick's,
                        // isotropic: the rule's kernel is the closed form (`batch::ggx_closed`,
                        // held to the f64 model by `tests/ggx_closed.rs`), within the
                        // tolerance below rather than of the parts' bits.
                        let closed = d == "ggx"
                            && ["smith-ggx", "smith-ggx-correlated"].contains(&g)
                            && ["none", "schlick"].contains(&f)
                            && !given.iter().any(|(k, _)| *k == "alpha_x");
                        let same: &[(&str, &Vec<f32>)] = if closed {
                            &[("per element", &outs[2])]
                        } else {
                            &[("specialised", &outs[0]), ("per element", &outs[2])]
                        };
                        if closed {
                            // Both within a few 1e-7 to 2.5e-6 of f64 (Schlick's f0 = 0.04
                            // adds at most 5.4e-7): 5e-6 of each other, the same zeros.
                            for (i, (&a, &b)) in outs[0].iter().zip(&outs[1]).enumerate() {
                                let e = (a as f64 - b as f64).abs() / (b as f64).abs();
                                assert!(
                                    a == b || e <= 5e-6,
                                    "{given:?} ({}) #{i}: closed form {a} vs parts {b}",
                                    isa.name()
                                );
                            }
                        }
                        for &(name, other) in same {
                            if let Some(i) = same_bits(&outs[1], other) {
                                panic!(
                                    "{given:?} ({}) #{i}: generic {} vs {name} {}",
                                    isa.name(),
                                    outs[1][i],
                                    other[i]
                                );
                            }
                        }
                        for (i, (&b, &r)) in outs[1].iter().zip(&outs[0]).enumerate() {
                            let s =
                                m.eval([w[0][i], w[1][i], w[2][i]], [w[3][i], w[4][i], w[5][i]]);
                            for (name, b) in [("generic", b), ("the rule's", r)] {
                                let err = (b as f64 - s as f64).abs() / (s as f64).abs().max(1.0);
                                worst = worst.max(err);
                                assert!(
                                    b.is_finite() && b >= 0.0 && err <= tol,
                                    "{given:?} ({}) #{i}: {name} {b} vs scalar {s}",
                                    isa.name()
                                );
                            }
                        }
                    }
                    checked += 1;
                }
            }
        }
    }
    println!(
        "{checked} configurations: generic = specialised = per element; vs scalar f32 {worst:.2e}"
    );
}

/// The generic path on inputs shorter than a block, of one element and empty, and through
/// `eval_par` over many blocks, against `eval`.
#[test]
fn generic_path_handles_any_length() {
    let w = dirs();
    let p = plan(&[("d", "beckmann"), ("g", "smith-ggx"), ("f", "conductor")]);
    let k = Kernel::from_plan("cook-torrance", &p).unwrap();
    assert!(!k.specialised());
    let full = {
        let input = Input::Dirs([&w[0][..], &w[1], &w[2], &w[3], &w[4], &w[5]]);
        let mut out = vec![0.0f32; input.len()];
        k.eval(input, &mut out).unwrap();
        out
    };
    for len in [0, 1, 7, 255, 256, 257, 513] {
        let input = Input::Dirs([0, 1, 2, 3, 4, 5].map(|c| &w[c][..len]));
        let mut out = vec![-1.0f32; len];
        k.eval(input, &mut out).unwrap();
        assert_eq!(same_bits(&out, &full[..len]), None, "length {len}");
    }
    // Many chunks of `eval_par` (16384 each), so its pool may run.
    let big: Vec<Vec<f32>> = w.iter().map(|c| c.repeat(60)).collect();
    let input = Input::Dirs([&big[0][..], &big[1], &big[2], &big[3], &big[4], &big[5]]);
    let (mut a, mut b) = (vec![0.0f32; input.len()], vec![0.0f32; input.len()]);
    k.eval(input, &mut a).unwrap();
    k.eval_par(input, &mut b).unwrap();
    assert_eq!(same_bits(&a, &b), None);
    assert_eq!(same_bits(&a[..full.len()], &full), None);
}
