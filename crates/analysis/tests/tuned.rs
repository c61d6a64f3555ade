//! The fitted models' targets: at identical operation count, the tuned max abs error over the
//! whole lobe is at most half the untuned one for every n in [8, 1000] where the untuned form
//! is not exact, and no worse for n in [1, 8); sg-tuned (the same single exp2 as UE4's
//! approximation) beats `ue4-phong-approx` at every n >= 8; no published lobe dominates a tuned
//! one in (operation cost, max abs error over n in [8, 1000]).

use fastbrdf::accuracy::worst_at;
use fastbrdf::{ErrorBound, Kind, Metric, Zone, registry};
use rayon::prelude::*;

fn abs_err(id: &str, n: f64) -> f64 {
    let b = ErrorBound {
        reference: "pow",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("n", n, n),
        bound: 0.0,
    };
    worst_at(id, &b, n).unwrap().err
}

const PAIRS: [(&str, &str, f64); 5] = [
    ("power4-tuned", "power4", 4.0),
    ("power8-tuned", "power8", 8.0),
    ("power16-tuned", "power16", 16.0),
    ("sg-tuned", "sg", 0.0),
    ("cubic-rational-tuned", "cubic-rational", 0.0),
];

#[test]
fn tuned_families_halve_the_error_for_n_from_8_and_are_no_worse_below() {
    for (tuned, untuned, exact_at) in PAIRS {
        let worst = (1..=1000)
            .into_par_iter()
            .map(|n| {
                let n = f64::from(n);
                let (t, u) = (abs_err(tuned, n), abs_err(untuned, n));
                if n == exact_at {
                    // Both compute (1 + (c - 1))^g = c^g up to one rounding.
                    assert!(
                        t <= u && u < 1e-15,
                        "{tuned} at n = {n}: the power form is exact, tuned {t}, untuned {u}"
                    );
                    return 0.0;
                }
                if n < 8.0 {
                    assert!(t <= u + 1e-12, "{tuned} at n = {n}: {t} > untuned {u}");
                    return 0.0;
                }
                assert!(
                    t <= 0.5 * u,
                    "{tuned} at n = {n}: {t} > half of untuned {u}"
                );
                t / u
            })
            .reduce(|| 0.0, f64::max);
        println!("{tuned}: worst tuned / untuned over n = 8..1000: {worst:.4}");
    }
}

#[test]
fn sg_tuned_beats_ue4_at_the_same_cost_for_every_n_from_8() {
    let (a, b) = (
        &registry::find("sg-tuned").unwrap().info.ops,
        &registry::find("ue4-phong-approx").unwrap().info.ops,
    );
    assert_eq!(
        (a.mul, a.add, a.div, a.sqrt, a.transcendental),
        (b.mul, b.add, b.div, b.sqrt, b.transcendental)
    );
    (8..=1000).into_par_iter().for_each(|n| {
        let n = f64::from(n);
        let (t, u) = (abs_err("sg-tuned", n), abs_err("ue4-phong-approx", n));
        assert!(t < u, "n = {n}: sg-tuned {t} >= ue4 {u}");
    });
}

/// A cost model from the registry's operation counts (no timing in tests): an exp2/log2/pow
/// as 10 multiply-adds, a division or square root as 4.
fn cost(id: &str) -> f64 {
    let o = registry::find(id).unwrap().info.ops;
    f64::from(o.mul)
        + f64::from(o.add)
        + 4.0 * f64::from(o.div + o.sqrt)
        + 10.0 * f64::from(o.transcendental)
}

#[test]
fn no_published_lobe_dominates_a_tuned_one_except_as_documented() {
    let lobes: Vec<&str> = registry::all()
        .iter()
        .filter(|e| {
            e.info.kind == Kind::Lobe
                && !e.info.id.starts_with("flog-normalized")
                && e.info.id != "pow"
        })
        .map(|e| e.info.id)
        .collect();
    let err8 = |id: &str| {
        (8..=1000)
            .step_by(3)
            .map(|n| abs_err(id, f64::from(n)))
            .fold(0.0, f64::max)
    };
    let errs: Vec<(&str, f64, f64)> = lobes
        .par_iter()
        .map(|id| (*id, cost(id), err8(id)))
        .collect();
    for &(t, ct, et) in errs.iter().filter(|e| e.0.ends_with("-tuned")) {
        let dominators: Vec<&str> = errs
            .iter()
            .filter(|&&(p, cp, ep)| {
                !p.ends_with("-tuned") && cp <= ct && ep <= et && (cp < ct || ep < et)
            })
            .map(|e| e.0)
            .collect();
        println!("{t}: cost {ct}, max abs (n 8..1000) {et:.5}, dominated by {dominators:?}");
        if t == "cubic-rational-tuned" {
            // Documented miss: the two-branch family's best max abs error (0.041) stays above
            // the power forms' at lower cost; tuning halves its own error but not enough.
            assert!(dominators.contains(&"power16"), "{dominators:?}");
        } else {
            assert!(dominators.is_empty(), "{t} is dominated by {dominators:?}");
        }
    }
}
