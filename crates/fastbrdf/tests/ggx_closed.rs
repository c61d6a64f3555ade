//! Cook-Torrance with GGX, its own Smith term (`smith-ggx` or `smith-ggx-correlated`),
//! no Fresnel term or Schlick's, isotropic: the batch kernel is the closed form of
//! `batch::ggx_closed` (issue 30), not the product of the parts. Its values against the f64
//! model at the same f32 inputs (every slope, denominator and such Fresnel term, unit and
//! non-unit inputs, grazing and back-to-back pairs), the same zeros as the scalar model,
//! the same bits on the FMA instruction sets and whatever the block holds.

mod common;

use common::{Rng, direction_pairs};
use fastbrdf::ModelSpec;
use fastbrdf::batch::{CtPath, Input, Isa, Kernel};

/// The closed form's documented bound (`batch::ggx_closed`, the sum of its roundings' worst
/// cases): relative to the f64 model.
const BOUND: f64 = 2.5e-6;

type Pairs = Vec<([f32; 3], [f32; 3])>;

/// Pairs over the whole domain: the library's (near the mirror direction, uniform, grazing),
/// nearly back-to-back and grazing ones, some at another length, and out-of-domain ones.
fn pairs() -> Pairs {
    let f = |v: [f64; 3]| v.map(|x| x as f32);
    let mut out: Pairs = direction_pairs(6000, 11)
        .into_iter()
        .map(|(a, b)| (f(a), f(b)))
        .collect();
    let mut rng = Rng(7);
    for i in 0..3000 {
        // Grazing: cosines down to 2e-6, azimuths opposite (the half vector's x and y
        // cancel) or near each other.
        let z = |r: &mut Rng| 2e-6 * 10f64.powf(5.0 * r.f64());
        let (zi, zo) = (z(&mut rng), z(&mut rng));
        let (pi, po) = (
            std::f64::consts::TAU * rng.f64(),
            if i % 2 == 0 {
                std::f64::consts::PI
            } else {
                0.3 * rng.f64()
            },
        );
        let d = |z: f64, phi: f64| {
            let r = (1.0 - z * z).sqrt();
            [r * phi.cos(), r * phi.sin(), z]
        };
        out.push((f(d(zi, pi)), f(d(zo, pi + po))));
    }
    // The `COS_MIN` cut (2^-20): cosines on it, an f32 step either side, and directions whose
    // f64 normalised z straddles it (the cut is decided there, not on the f32 components).
    let cut = fastbrdf::vec3::COS_MIN as f32;
    for z in [
        cut,
        f32::from_bits(cut.to_bits() - 1),
        f32::from_bits(cut.to_bits() + 1),
    ] {
        for (len, other) in [(1.0f32, [0.3, -0.2, 0.93]), (1.0 + 3e-7, [-0.6, 0.1, 0.79])] {
            let r = (1.0 - z * z).sqrt() * len;
            let w = [r * 0.6, -r * 0.8, z * len];
            out.push((w, other));
            out.push((other, w));
            out.push((w, [-w[0], -w[1], w[2]]));
        }
    }
    for i in 0..600 {
        // Not of unit length: the general normalisation (its blocks take it).
        let (a, b) = out[i * 7];
        let s = [0.25f32, 3.0, 1e-3, 7e3][i % 4];
        out.push((a.map(|x| x * s), b));
    }
    for bad in [
        [0.0, 0.0, 0.0],
        [f32::NAN, 0.0, 1.0],
        [0.3, 0.2, -0.9],
        [1.0, 0.0, 0.0],
    ] {
        out.push((bad, [0.0, 0.0, 1.0]));
        out.push(([0.0, 0.0, 1.0], bad));
    }
    out
}

fn columns(p: &Pairs) -> [Vec<f32>; 6] {
    let mut c: [Vec<f32>; 6] = Default::default();
    for (wi, wo) in p {
        for k in 0..3 {
            c[k].push(wi[k]);
            c[k + 3].push(wo[k]);
        }
    }
    c
}

fn eval(k: &Kernel, isa: Isa, c: &[Vec<f32>; 6]) -> Vec<f32> {
    let mut out = vec![0.0f32; c[0].len()];
    let input = Input::Dirs([&c[0][..], &c[1], &c[2], &c[3], &c[4], &c[5]]);
    k.eval_with(isa, input, &mut out).unwrap();
    out
}

/// The kernel's value at one pair, alone in its batch.
fn eval_one(k: &Kernel, isa: Isa, wi: [f32; 3], wo: [f32; 3]) -> f32 {
    eval(
        k,
        isa,
        &std::array::from_fn(|j| vec![if j < 3 { wi[j] } else { wo[j - 3] }]),
    )[0]
}

/// The relative error of `wi.h` the closed form may have (`batch::ggx_closed`).
const WIH: f64 = 2.4e-7;

/// The relative change of Schlick's term when `c = wi.h` moves by [`WIH`] (relative), the
/// error it adds to the closed form's (unbounded in relative terms as `F` goes to 0: `f0 = 0`
/// and `c` near 1, where any f32 `wi.h` has it too).
fn schlick_error(wi: [f32; 3], wo: [f32; 3], f0: f64, f90: f64) -> f64 {
    let u = |v: [f32; 3]| {
        let v = v.map(f64::from);
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    };
    let (i, o) = (u(wi), u(wo));
    let h = [i[0] + o[0], i[1] + o[1], i[2] + o[2]];
    let c = ((h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt() / 2.0).min(1.0);
    let f = |c: f64| f0 + (f90 - f0) * (1.0 - c.min(1.0)).powi(5);
    let (lo, hi) = (f(c * (1.0 - WIH)), f(c * (1.0 + WIH)));
    let at = f(c);
    if at > 0.0 {
        ((lo - at).abs().max((hi - at).abs())) / at
    } else {
        0.0
    }
}

/// The relative error of `x` against `exact` (0 must be 0).
fn rel(x: f32, exact: f64) -> f64 {
    if exact == 0.0 {
        if x == 0.0 { 0.0 } else { f64::INFINITY }
    } else {
        (x as f64 - exact).abs() / exact
    }
}

#[test]
fn the_closed_form_is_within_its_bound_of_f64_on_the_whole_domain() {
    let p = pairs();
    let c = columns(&p);
    let mut checked = 0;
    let (mut worst, mut worst_parts) = (0.0f64, 0.0f64);
    for g in ["smith-ggx", "smith-ggx-correlated"] {
        for f in [
            &[("f", "none")][..],
            &[("f", "schlick")],
            &[("f", "schlick"), ("f0", "0"), ("f90", "0.5")],
        ] {
            for (alpha, den) in [
                ("0.005", "4"),
                ("0.05", "seed-000"),
                ("0.3", "4"),
                ("0.3", "seed-001"),
                ("1", "4"),
            ] {
                let mut given = vec![
                    ("d", "ggx"),
                    ("g", g),
                    ("alpha", alpha),
                    ("denominator", den),
                ];
                given.extend_from_slice(f);
                let spec = ModelSpec::parse("cook-torrance", &given).unwrap();
                let Ok(fastbrdf::Model::Brdf(m)) = spec.model::<f64>() else {
                    unreachable!()
                };
                let plan = *spec.plan().unwrap();
                let num = |k: &str, d: f64| {
                    given
                        .iter()
                        .find(|(n, _)| *n == k)
                        .map_or(d, |(_, v)| v.parse().unwrap())
                };
                let (f0, f90) = (num("f0", 0.04), num("f90", 1.0));
                let schlick = f[0].1 == "schlick";
                let closed = Kernel::from_plan_path("cook-torrance", &plan, CtPath::Rule).unwrap();
                let parts =
                    Kernel::from_plan_path("cook-torrance", &plan, CtPath::Generic).unwrap();
                let isas = Isa::available();
                let outs: Vec<Vec<f32>> = isas.iter().map(|&i| eval(&closed, i, &c)).collect();
                let generic = eval(&parts, isas[0], &c);
                // The closed form is what the rule chose: its values are not the parts'.
                assert!(
                    outs[0]
                        .iter()
                        .zip(&generic)
                        .any(|(a, b)| a.to_bits() != b.to_bits()),
                    "{given:?}: the rule's kernel gives the parts' bits"
                );
                for (isa, out) in isas.iter().zip(&outs) {
                    if isa.fma() {
                        let first = isas.iter().position(|i| i.fma()).unwrap();
                        assert!(
                            out.iter()
                                .zip(&outs[first])
                                .all(|(a, b)| a.to_bits() == b.to_bits()),
                            "{given:?}: {} differs from the other FMA instruction set",
                            isa.name()
                        );
                    }
                    for (i, ((wi, wo), &x)) in p.iter().zip(out).enumerate() {
                        let exact = m.eval(wi.map(f64::from), wo.map(f64::from));
                        let fe = if schlick {
                            schlick_error(*wi, *wo, f0, f90)
                        } else {
                            0.0
                        };
                        let e = rel(x, exact) - fe;
                        assert!(
                            x.is_finite() && e <= BOUND,
                            "{given:?} ({}) #{i} {wi:?} {wo:?}: {x} against f64 {exact} ({e:.2e})",
                            isa.name()
                        );
                        worst = worst.max(e);
                        worst_parts = worst_parts.max(rel(generic[i], exact) - fe);
                    }
                }
                checked += 1;
            }
        }
    }
    println!(
        "{checked} configurations, {} pairs: closed form within {worst:.2e} of f64 (the parts' product {worst_parts:.2e}), beyond Schlick's own error for an error of {WIH:.1e} in wi.h",
        p.len()
    );
}

/// A pair's value does not depend on its neighbours (blocks of unit inputs normalise by the
/// series alone): the same bits evaluated alone as in the whole batch.
#[test]
fn a_pairs_closed_form_value_does_not_depend_on_its_block() {
    let p = pairs();
    let c = columns(&p);
    let k = common::kernel(
        "cook-torrance",
        &[("d", "ggx"), ("g", "smith-ggx-correlated")],
    )
    .unwrap();
    for &isa in Isa::available() {
        let all = eval(&k, isa, &c);
        for i in (0..p.len()).step_by(37) {
            assert_eq!(
                eval_one(&k, isa, p[i].0, p[i].1).to_bits(),
                all[i].to_bits(),
                "#{i} ({})",
                isa.name()
            );
        }
    }
}

/// With an energy compensation the rule's kernel is not the closed form: the plan's parts
/// (`batch::cook_torrance::kernel`), the per-element path's bits.
#[test]
fn an_energy_compensation_keeps_the_parts() {
    let p = pairs();
    let c = columns(&p);
    let given = [
        ("d", "ggx"),
        ("g", "smith-ggx-correlated"),
        ("ms", "kulla-conty"),
    ];
    let plan = *ModelSpec::parse("cook-torrance", &given)
        .unwrap()
        .plan()
        .unwrap();
    let rule = Kernel::from_plan_path("cook-torrance", &plan, CtPath::Rule).unwrap();
    let parts = Kernel::from_plan_path("cook-torrance", &plan, CtPath::PerElement).unwrap();
    let isa = Isa::available()[0];
    let (a, b) = (eval(&rule, isa, &c), eval(&parts, isa, &c));
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
}

/// An adversarial search (as `fastbrdf check` runs on the scalar models): from each
/// configuration's 8 worst pairs of [`pairs`], a seeded random walk over the six input
/// components that keeps every step which raises the error against f64 (steps shrinking from
/// 1e-2 to 1e-7 relative), 400 steps each. The worst found stays within the bound.
#[test]
fn a_search_for_the_closed_forms_worst_pair_stays_within_its_bound() {
    let isa = Isa::available()[0];
    let mut rng = Rng(99);
    let mut worst = 0.0f64;
    for g in ["smith-ggx", "smith-ggx-correlated"] {
        for f in ["none", "schlick"] {
            for alpha in ["0.005", "0.05", "0.3", "1"] {
                let given = [("d", "ggx"), ("g", g), ("f", f), ("alpha", alpha)];
                let k = common::kernel("cook-torrance", &given).unwrap();
                let Ok(fastbrdf::Model::Brdf(m)) = common::build::<f64>("cook-torrance", &given)
                else {
                    unreachable!()
                };
                let err = |wi: [f32; 3], wo: [f32; 3]| {
                    let x = eval_one(&k, isa, wi, wo);
                    let exact = m.eval(wi.map(f64::from), wo.map(f64::from));
                    let fe = if f == "schlick" {
                        schlick_error(wi, wo, 0.04, 1.0)
                    } else {
                        0.0
                    };
                    rel(x, exact) - fe
                };
                let mut start: Vec<(f64, [f32; 3], [f32; 3])> = pairs()
                    .into_iter()
                    .map(|(a, b)| (err(a, b), a, b))
                    .collect();
                start.sort_by(|a, b| b.0.total_cmp(&a.0));
                for &(mut e, mut wi, mut wo) in start.iter().take(8) {
                    let mut step = 1e-2;
                    for _ in 0..400 {
                        let mut jitter = |v: [f32; 3]| {
                            v.map(|c| c * (1.0 + step * (2.0 * rng.f64() - 1.0)) as f32)
                        };
                        let (a, b) = (jitter(wi), jitter(wo));
                        let ea = err(a, b);
                        if ea > e {
                            (e, wi, wo) = (ea, a, b);
                        } else {
                            step = (step * 0.9).max(1e-7);
                        }
                    }
                    assert!(
                        e <= BOUND,
                        "{given:?}: {wi:?} {wo:?} off f64 by {e:.2e} (found by the search)"
                    );
                    worst = worst.max(e);
                }
            }
        }
    }
    println!("search: the closed form within {worst:.2e} of f64");
}
