//! Lobes against their printed formulas (the seeds' cubics in monomial form, Simpson's
//! rule for normalisation).

use super::*;

/// Seed 003's closed forms for the Hermite cubic (Q = 0.5), with q = 0.5^(1/n).
pub(crate) fn seed_cubic_coefficients(n: f64) -> (f64, f64, f64) {
    let q = 0.5f64.powf(1.0 / n);
    let den = 2.0 * (q - 1.0).powi(2) * q * q;
    let a = ((q - 1.0) * (2.0 * q + n) + 1.0) / den;
    let b = -(q * q * (4.0 * q - 3.0) + n * (q * q - 1.0) + 1.0) / den;
    (a, b, 1.0 - a - b)
}

/// The three-point cubic by Gaussian elimination on the monomial system.
pub(crate) fn three_point_coefficients(n: f64) -> (f64, f64, f64) {
    let (bq, bg): (f64, f64) = (0.5, 1.0 / 18.0);
    let r = bq.powf(1.0 / n);
    let l = bg.powf(1.0 / n);
    let mut m = [
        [r.powi(3), r * r, r, bq],
        [l.powi(3), l * l, l, bg],
        [1.0, 1.0, 1.0, 1.0],
    ];
    for col in 0..3 {
        let piv = (col..3)
            .max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))
            .unwrap();
        m.swap(col, piv);
        for row in 0..3 {
            if row != col {
                let f = m[row][col] / m[col][col];
                let pivot_row = m[col];
                for (x, p) in m[row].iter_mut().zip(pivot_row) {
                    *x -= f * p;
                }
            }
        }
    }
    (m[0][3] / m[0][0], m[1][3] / m[1][1], m[2][3] / m[2][2])
}

/// A monomial cubic, zero below its local minimum in (0, upper) and where negative.
pub(crate) fn clipped_cubic((a, b, c1): (f64, f64, f64), upper: f64, c: f64) -> f64 {
    // p' = 3a c^2 + 2b c + c1; local minimum where p'' = 6a c + 2b > 0.
    let disc = 4.0 * b * b - 12.0 * a * c1;
    let mut cut: f64 = 0.0;
    if a.abs() > 1e-9 && disc >= 0.0 {
        for s in [-1.0, 1.0] {
            let x = (-2.0 * b + s * disc.sqrt()) / (6.0 * a);
            if x > 0.0 && x < upper && 6.0 * a * x + 2.0 * b > 0.0 {
                cut = cut.max(x);
            }
        }
    } else if a.abs() <= 1e-9 && b > 0.0 {
        let x = -c1 / (2.0 * b);
        if x > 0.0 && x < upper {
            cut = x;
        }
    }
    if c < cut {
        0.0
    } else {
        (a * c * c * c + b * c * c + c1 * c).max(0.0)
    }
}

pub(crate) fn ref_lobe(id: &str, n: f64, c: f64) -> f64 {
    let coef = 0.197 * (n + 1.24) + 0.068 / (0.64 + n);
    let flog = || (1.0 - 0.5 * (1.0 - n * c.log2()).log2()).max(0.0);
    let q = 0.5f64.powf(1.0 / n);
    let rational = || c / (2.0 * n * q - (2.0 * n - 2.0) * c);
    let power = |g: i32| (1.0 + n / g as f64 * (c - 1.0)).max(0.0).powi(g);
    match id {
        "pow" => c.powf(n),
        "schlick" => c / (n - n * c + c),
        "schlick-modified" => 2.0 * c / (1.25 * (n - n * c + 1.25 * c).powi(2)),
        "gauss" => (-n * c.acos().powi(2) / 2.0).exp(),
        "flog" => flog(),
        "flog-normalized" => coef * flog(),
        "flog-normalized-clamped" => (coef * flog()).clamp(0.0, 1.0),
        "cubic" => clipped_cubic(seed_cubic_coefficients(n), q, c),
        "cubic3" => clipped_cubic(three_point_coefficients(n), q, c),
        "rational" => rational(),
        "cubic-rational" => {
            if c >= q {
                clipped_cubic(seed_cubic_coefficients(n), q, c)
            } else {
                rational()
            }
        }
        "power4" => power(4),
        "power8" => power(8),
        "power16" => power(16),
        "sg" => ((n / std::f64::consts::LN_2) * (c - 1.0)).exp2(),
        // UE4's own literal, not LOG2_E.
        #[allow(clippy::approx_constant)]
        "ue4-phong-approx" => (1.4427 * (n + 0.775) * (c - 1.0)).exp2(),
        // Tuned lobes: the printed family formula with the library's coefficient.
        "power4-tuned" => (1.0 + tuned::power_slope(4, n) * (c - 1.0))
            .max(0.0)
            .powi(4),
        "power8-tuned" => (1.0 + tuned::power_slope(8, n) * (c - 1.0))
            .max(0.0)
            .powi(8),
        "power16-tuned" => (1.0 + tuned::power_slope(16, n) * (c - 1.0))
            .max(0.0)
            .powi(16),
        "sg-tuned" => (tuned::exp2_rate(n) * (c - 1.0)).exp2(),
        "cubic-rational-tuned" => {
            let level = tuned::cubic_rational_level(n);
            let q = level.powf(1.0 / n);
            if c >= q {
                // p(c) = c (al + be (c - q) + ga (c - q)^2): p(0) = 0 by construction; p(q) = Q,
                // p'(q) = n Q / q and p(1) = 1 give al, be, ga directly.
                let al = level / q;
                let be = (n * level / q - al) / q;
                let d = 1.0 - q;
                let ga = (1.0 - al - be * d) / (d * d);
                let t = c - q;
                c * (al + be * t + ga * t * t)
            } else {
                c / (n * q / level - (n - 1.0) / level * c)
            }
        }
        _ => panic!("no reference for lobe {id}"),
    }
}

/// Absolute tolerance of the library's f64 lobe against `ref_lobe`, with its reason.
pub(crate) fn lobe_tolerance(id: &str, n: f64) -> f64 {
    match id {
        // The reference sums monomials whose coefficients reach ~3e5 (n = 1000): its own f64
        // rounding is ~ 1e-16 * a ~ 1e-10 per term, and the coefficients themselves carry ~1e-13
        // relative error from the closed forms' cancellation.
        "cubic" | "cubic3" | "cubic-rational" | "cubic-rational-tuned" => 1e-12 * n * n,
        "rational" => 1e-13 * n,
        _ => 1e-13,
    }
}

/// `Int(n) = integral_0^{pi/2} lobe(cos t) cos t sin t dt` by composite Simpson in theta.
pub(crate) fn simpson_int(id: &str, n: f64) -> f64 {
    let m = 200_000;
    let h = (PI / 2.0) / m as f64;
    let f = |t: f64| ref_lobe(id, n, t.cos()) * t.cos() * t.sin();
    let mut s = f(0.0) + f(PI / 2.0);
    for i in 1..m {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

pub(crate) fn lobe64(id: &str, n: f64) -> Box<dyn fastbrdf::Lobe<f64>> {
    match build::<f64>(id, &[("n", &n.to_string())]).unwrap() {
        Model::Lobe(l) => l,
        _ => panic!("{id} is not a lobe"),
    }
}

#[test]
fn lobes_match_their_printed_formulas() {
    let mut ns: Vec<f64> = N_VALUES.iter().copied().filter(|n| *n <= 1000.0).collect();
    ns.extend((1..=1000).step_by(37).map(f64::from));
    for id in fastbrdf::registry::ids_of(fastbrdf::Kind::Lobe) {
        for &n in &ns {
            let lobe = lobe64(id, n);
            for c in lobe_samples(n) {
                let (got, want) = (lobe.eval(c), ref_lobe(id, n, c));
                let tol = lobe_tolerance(id, n) * want.abs().max(1.0);
                assert!(
                    (got - want).abs() <= tol,
                    "{id} n={n} c={c}: library {got} vs formula {want} (tol {tol})"
                );
            }
        }
    }
}

#[test]
fn seed_cubic_is_exact_where_it_should_be() {
    // n = 1, 2, 3: c, c^2 and c^3 satisfy every condition of the Hermite cubic.
    for (n, k) in [(1.0, 1), (2.0, 2), (3.0, 3)] {
        let lobe = lobe64("cubic", n);
        for i in 0..=100 {
            let c = i as f64 / 100.0;
            assert!((lobe.eval(c) - c.powi(k)).abs() < 1e-12, "n={n} c={c}");
        }
    }
    // Seed 003's a and b at n = 1000 (the conditioning problem): ~3e5.
    let (a, _, _) = seed_cubic_coefficients(1000.0);
    assert!(a > 2e5 && a < 4e5, "a = {a}");
}
