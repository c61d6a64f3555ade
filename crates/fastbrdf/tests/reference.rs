//! Every model against an independent f64 evaluation of its printed formula (written here
//! from ../shared/MODELS.md and the seeds, naively: monomial cubics with the seed's closed-form
//! coefficients, complex arithmetic for Fresnel, Simpson's rule for normalisation), on grids
//! covering the whole domain (n in [1, 1000] and beyond, alpha in [0.005, 1]) with the edges.

mod common;

use common::{ALPHA_VALUES, N_VALUES, Rng, direction_pairs};
use fastbrdf::accuracy::lobe_samples;
use fastbrdf::lobes::tuned;
use fastbrdf::{Model, registry};
use num_complex::Complex64;
use std::f64::consts::PI;

// ---------- Independent formulas ----------

/// Seed 003's closed forms for the Hermite cubic (Q = 0.5), with q = 0.5^(1/n).
fn seed_cubic_coefficients(n: f64) -> (f64, f64, f64) {
    let q = 0.5f64.powf(1.0 / n);
    let den = 2.0 * (q - 1.0).powi(2) * q * q;
    let a = ((q - 1.0) * (2.0 * q + n) + 1.0) / den;
    let b = -(q * q * (4.0 * q - 3.0) + n * (q * q - 1.0) + 1.0) / den;
    (a, b, 1.0 - a - b)
}

/// The three-point cubic by Gaussian elimination on the monomial system.
fn three_point_coefficients(n: f64) -> (f64, f64, f64) {
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
fn clipped_cubic((a, b, c1): (f64, f64, f64), upper: f64, c: f64) -> f64 {
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

fn ref_lobe(id: &str, n: f64, c: f64) -> f64 {
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
fn lobe_tolerance(id: &str, n: f64) -> f64 {
    match id {
        // The reference sums monomials whose coefficients reach ~3e5 (n = 1000): its own f64
        // rounding is ~ 1e-16 * a ~ 1e-10 per term, and the coefficients themselves carry ~1e-13
        // relative error from the closed forms' cancellation.
        "cubic" | "cubic3" | "cubic-rational" | "cubic-rational-tuned" => 1e-12 * n * n,
        "rational" => 1e-13 * n,
        _ => 1e-13,
    }
}

fn beckmann_naive(alpha: f64, c: f64, scale: f64) -> f64 {
    let tan2 = (1.0 - c * c) / (c * c);
    (-tan2 / (alpha * alpha)).exp() / (scale * alpha * alpha * c.powi(4))
}

fn ref_distribution(id: &str, alpha: f64, c: f64) -> f64 {
    let e = 2.0 / (alpha * alpha) - 4.0;
    let power = |g: i32| (1.0 + e / g as f64 * (c - 1.0)).max(0.0).powi(g) / (4.0 * alpha * alpha);
    match id {
        "beckmann" => beckmann_naive(alpha, c, PI),
        "beckmann-ct" => beckmann_naive(alpha, c, 4.0),
        "beckmann-pow" => c.powf(e) / (4.0 * alpha * alpha),
        "beckmann-power4" => power(4),
        "beckmann-power8" => power(8),
        "beckmann-power16" => power(16),
        _ => panic!("no reference for distribution {id}"),
    }
}

fn smith_g1_exact(alpha: f64, c: f64) -> f64 {
    if c >= 1.0 {
        return 1.0;
    }
    let a = c / (alpha * (1.0 - c * c).sqrt());
    let lambda = (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * PI.sqrt());
    1.0 / (1.0 + lambda)
}

fn smith_g1_rational(alpha: f64, c: f64) -> f64 {
    if c >= 1.0 {
        return 1.0;
    }
    let a = c / (alpha * (1.0 - c * c).sqrt());
    if a >= 1.6 {
        1.0
    } else {
        (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
    }
}

/// Unpolarised Fresnel reflectance for a complex relative index, by complex arithmetic.
fn fresnel_complex(cos_i: f64, eta: Complex64) -> f64 {
    let sin2_i = 1.0 - cos_i * cos_i;
    let cos_t = (Complex64::new(1.0, 0.0) - sin2_i / (eta * eta)).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs.norm_sqr() + rp.norm_sqr())
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

fn dotv(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `Int(n) = integral_0^{pi/2} lobe(cos t) cos t sin t dt` by composite Simpson in theta.
fn simpson_int(id: &str, n: f64) -> f64 {
    let m = 200_000;
    let h = (PI / 2.0) / m as f64;
    let f = |t: f64| ref_lobe(id, n, t.cos()) * t.cos() * t.sin();
    let mut s = f(0.0) + f(PI / 2.0);
    for i in 1..m {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

// ---------- Tests ----------

fn lobe64(id: &str, n: f64) -> Box<dyn fastbrdf::Lobe<f64>> {
    match registry::build::<f64>(id, &[("n", &n.to_string())]).unwrap() {
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

#[test]
fn distributions_match_their_printed_formulas() {
    for id in fastbrdf::registry::ids_of(fastbrdf::Kind::Distribution) {
        for &alpha in ALPHA_VALUES {
            let Model::Distribution(d) =
                registry::build::<f64>(id, &[("alpha", &alpha.to_string())]).unwrap()
            else {
                panic!()
            };
            for i in 0..=2000 {
                let c = 1e-3 + (1.0 - 1e-3) * (i as f64 / 2000.0).sqrt();
                let (got, want) = (d.eval(c), ref_distribution(id, alpha, c));
                // The naive reference computes tan^2 through 1 - c^2: ~1e-16 / (1 - c^2) relative
                // error in tan^2, times tan^2 / alpha^2 in the exponent.
                let tol = 1e-12 * want.abs().max(1e-300) * (1.0 + 1.0 / (alpha * alpha));
                assert!(
                    (got - want).abs() <= tol.max(1e-300),
                    "{id} alpha={alpha} c={c}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn beckmann_ct_is_pi_over_four_times_beckmann() {
    for &alpha in ALPHA_VALUES {
        let a = alpha.to_string();
        let Model::Distribution(d) = registry::build::<f64>("beckmann", &[("alpha", &a)]).unwrap()
        else {
            panic!()
        };
        let Model::Distribution(ct) =
            registry::build::<f64>("beckmann-ct", &[("alpha", &a)]).unwrap()
        else {
            panic!()
        };
        for i in 1..=100 {
            let c = i as f64 / 100.0;
            assert!((ct.eval(c) - d.eval(c) * PI / 4.0).abs() <= 1e-14 * d.eval(c).max(1e-300));
        }
    }
}

#[test]
fn shadowing_matches_its_printed_formulas() {
    for &alpha in ALPHA_VALUES {
        let a = alpha.to_string();
        let Model::Shadowing(exact) = registry::build::<f64>("smith", &[("alpha", &a)]).unwrap()
        else {
            panic!()
        };
        let Model::Shadowing(rat) =
            registry::build::<f64>("smith-rational", &[("alpha", &a)]).unwrap()
        else {
            panic!()
        };
        for i in 1..=1000 {
            let c = i as f64 / 1000.0;
            let s = fastbrdf::model::ShadowInput {
                cos_v: c,
                cos_l: None,
                cos_h: 1.0,
                cos_vh: 1.0,
            };
            let (g, w) = (exact.g(&s), smith_g1_exact(alpha, c));
            assert!(
                (g - w).abs() <= 1e-12,
                "smith alpha={alpha} c={c}: {g} vs {w}"
            );
            let (g, w) = (rat.g(&s), smith_g1_rational(alpha, c));
            assert!(
                (g - w).abs() <= 1e-14,
                "smith-rational alpha={alpha} c={c}: {g} vs {w}"
            );
            // Two-sided: separable product.
            let s2 = fastbrdf::model::ShadowInput {
                cos_l: Some(0.5),
                ..s
            };
            assert!(
                (exact.g(&s2) - smith_g1_exact(alpha, c) * smith_g1_exact(alpha, 0.5)).abs()
                    < 1e-12
            );
        }
    }
    let Model::Shadowing(v) = registry::build::<f64>("v-cavity", &[]).unwrap() else {
        panic!()
    };
    let mut rng = Rng(7);
    for _ in 0..2000 {
        let (wi, wo) = (rng.hemisphere(), rng.hemisphere());
        let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
        let (nv, nl, nh, vh) = (wo[2], wi[2], h[2], dotv(wo, h));
        let want = 1f64.min(2.0 * nh * nv / vh).min(2.0 * nh * nl / vh);
        let got = v.g(&fastbrdf::model::ShadowInput {
            cos_v: nv,
            cos_l: Some(nl),
            cos_h: nh,
            cos_vh: vh,
        });
        assert!((got - want).abs() < 1e-14);
    }
}

#[test]
fn fresnel_matches_complex_fresnel_equations() {
    for (eta, k) in [
        (0.2, 3.9),
        (0.47, 2.4),
        (1.5, 0.0),
        (1.33, 0.0),
        (3.0, 0.5),
        (0.01, 20.0),
        (10.0, 0.0),
    ] {
        let Model::Fresnel(f) = registry::build::<f64>(
            "fresnel-conductor",
            &[("eta", &eta.to_string()), ("k", &k.to_string())],
        )
        .unwrap() else {
            panic!()
        };
        for i in 0..=1000 {
            let c = i as f64 / 1000.0;
            let (got, want) = (f.f(c), fresnel_complex(c, Complex64::new(eta, k)));
            assert!(
                (got - want).abs() < 1e-12,
                "conductor eta={eta} k={k} cos={c}: {got} vs {want}"
            );
        }
    }
    for eta in [0.5, 0.9, 1.0, 1.33, 1.5, 2.4, 10.0] {
        let Model::Fresnel(f) =
            registry::build::<f64>("fresnel-dielectric", &[("eta", &eta.to_string())]).unwrap()
        else {
            panic!()
        };
        for i in 0..=1000 {
            let c = i as f64 / 1000.0;
            let sin2_t = (1.0 - c * c) / (eta * eta);
            // At eta = 1 there is no interface: 0 at every cosine, grazing included (the
            // limit c -> 0 of F(eta = 1) = 0, not the total-reflection 1 of eta < 1).
            let want = if eta == 1.0 {
                0.0
            } else if sin2_t >= 1.0 {
                1.0
            } else {
                fresnel_complex(c, Complex64::new(eta, 0.0))
            };
            assert!(
                (f.f(c) - want).abs() < 1e-12,
                "dielectric eta={eta} cos={c}"
            );
        }
    }
    let Model::Fresnel(s) = registry::build::<f64>("fresnel-schlick", &[("f0", "0.04")]).unwrap()
    else {
        panic!()
    };
    for i in 0..=100 {
        let c = i as f64 / 100.0;
        assert!((s.f(c) - (0.04 + 0.96 * (1.0 - c).powi(5))).abs() < 1e-15);
    }
}

fn brdf64(id: &str, given: &[(&str, &str)]) -> Box<dyn fastbrdf::Brdf<f64>> {
    match registry::build::<f64>(id, given).unwrap() {
        Model::Brdf(b) => b,
        _ => panic!("{id} is not a BRDF"),
    }
}

#[test]
fn cook_torrance_is_fdg_over_4_cos_cos() {
    let pairs = direction_pairs(300, 11);
    for &alpha in ALPHA_VALUES {
        for (g, denom) in [
            ("smith", "4"),
            ("smith-rational", "seed-000"),
            ("v-cavity", "seed-001"),
        ] {
            for f in ["none", "schlick", "conductor"] {
                let a = alpha.to_string();
                let ct = brdf64(
                    "cook-torrance",
                    &[
                        ("alpha", &a),
                        ("g", g),
                        ("f", f),
                        ("denominator", denom),
                        ("eta", "0.2"),
                        ("k", "3.9"),
                    ],
                );
                for (wi, wo) in &pairs {
                    let (wi, wo) = (unit(*wi), unit(*wo));
                    let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
                    let d = beckmann_naive(alpha, h[2], PI);
                    let gv = match g {
                        "smith" => smith_g1_exact(alpha, wi[2]) * smith_g1_exact(alpha, wo[2]),
                        "smith-rational" => {
                            smith_g1_rational(alpha, wi[2]) * smith_g1_rational(alpha, wo[2])
                        }
                        _ => 1f64
                            .min(2.0 * h[2] * wo[2] / dotv(wo, h))
                            .min(2.0 * h[2] * wi[2] / dotv(wi, h)),
                    };
                    let fv = match f {
                        "none" => 1.0,
                        "schlick" => 0.04 + 0.96 * (1.0 - dotv(wi, h)).powi(5),
                        _ => fresnel_complex(dotv(wi, h), Complex64::new(0.2, 3.9)),
                    };
                    let k = match denom {
                        "4" => 4.0,
                        "seed-000" => 1.0,
                        _ => PI,
                    };
                    let want = fv * d * gv / (k * wi[2] * wo[2]);
                    let got = ct.eval(wi, wo);
                    assert!(
                        (got - want).abs() <= 1e-9 * want.abs() + 1e-300,
                        "alpha={alpha} g={g} f={f} {denom}: {got} vs {want}"
                    );
                }
            }
        }
    }
}

#[test]
fn ward_matches_its_printed_formulas() {
    let pairs = direction_pairs(300, 12);
    for &alpha in ALPHA_VALUES {
        let a = alpha.to_string();
        let exact = brdf64("ward", &[("alpha", &a)]);
        let pow = brdf64("ward-pow", &[("alpha", &a)]);
        let p16 = brdf64("ward-power16", &[("alpha", &a)]);
        let aniso = brdf64(
            "ward",
            &[
                ("alpha_x", &a),
                ("alpha_y", &(alpha * 0.5).max(0.01).to_string()),
            ],
        );
        let ay = (alpha * 0.5).max(0.01);
        for (wi, wo) in &pairs {
            let (wi, wo) = (unit(*wi), unit(*wo));
            let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
            let norm = 1.0 / (4.0 * PI * alpha * alpha * (wi[2] * wo[2]).sqrt());
            let tan2 = (1.0 - h[2] * h[2]) / (h[2] * h[2]);
            let checks = [
                (exact.eval(wi, wo), norm * (-tan2 / (alpha * alpha)).exp()),
                (pow.eval(wi, wo), norm * h[2].powf(2.0 / (alpha * alpha))),
                (
                    p16.eval(wi, wo),
                    norm * (1.0 + 2.0 / (alpha * alpha) / 16.0 * (h[2] - 1.0))
                        .max(0.0)
                        .powi(16),
                ),
                (
                    aniso.eval(wi, wo),
                    (-(h[0] * h[0] / (alpha * alpha) + h[1] * h[1] / (ay * ay)) / (h[2] * h[2]))
                        .exp()
                        / (4.0 * PI * alpha * ay * (wi[2] * wo[2]).sqrt()),
                ),
            ];
            for (i, (got, want)) in checks.iter().enumerate() {
                // 1 - h_z^2 in the naive reference loses ~1e-16 / sin^2 relatively.
                let tol = 1e-9 * want.abs() * (1.0 + 1.0 / (alpha * alpha));
                assert!(
                    (got - want).abs() <= tol + 1e-300,
                    "ward form {i} alpha={alpha}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn lambert_and_lobe_brdfs_match_their_formulas() {
    let lambert = brdf64("lambert", &[("albedo", "0.5")]);
    assert!((lambert.eval([0.3, 0.1, 0.9], [-0.2, 0.4, 0.5]) - 0.5 / PI).abs() < 1e-15);
    assert_eq!(lambert.eval([0.3, 0.1, -0.9], [-0.2, 0.4, 0.5]), 0.0);
    let pairs = direction_pairs(100, 13);
    for id in [
        "pow",
        "flog",
        "cubic-rational",
        "power16",
        "schlick",
        "gauss",
    ] {
        for n in [1.0, 20.0, 300.0] {
            let ns = n.to_string();
            let int = simpson_int(id, n);
            let phong = brdf64("phong", &[("lobe", id), ("n", &ns)]);
            let blinn = brdf64("blinn-phong", &[("lobe", id), ("n", &ns)]);
            let raw = brdf64("blinn-phong", &[("lobe", id), ("n", &ns), ("norm", "none")]);
            for (wi, wo) in &pairs {
                let (wi, wo) = (unit(*wi), unit(*wo));
                let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
                let r = [-wi[0], -wi[1], wi[2]];
                let coef = 1.0 / (2.0 * PI * int);
                let want_phong = coef * ref_lobe(id, n, dotv(r, wo).max(0.0));
                let want_blinn = coef * ref_lobe(id, n, h[2]) / (4.0 * dotv(wi, h));
                // Simpson with 2e5 panels on a lobe with a kink: ~1e-7 relative in Int(n).
                for (got, want) in [
                    (phong.eval(wi, wo), want_phong),
                    (blinn.eval(wi, wo), want_blinn),
                ] {
                    assert!(
                        (got - want).abs() <= 1e-6 * want.abs() + 1e-12,
                        "{id} n={n}: {got} vs {want}"
                    );
                }
                assert!((raw.eval(wi, wo) - ref_lobe(id, n, h[2])).abs() < 1e-12 * n);
            }
        }
    }
}

/// Shadowing terms, Fresnel terms and BRDFs with an independent reference formula in this
/// file (lobes and distributions have theirs in `ref_lobe` / `ref_distribution`, which panic
/// on an unknown id).
const REFERENCED: &[&str] = &[
    "v-cavity",
    "smith",
    "smith-rational",
    "fresnel-none",
    "fresnel-schlick",
    "fresnel-dielectric",
    "fresnel-conductor",
    "cook-torrance",
    "ward",
    "ward-pow",
    "ward-power16",
    "lambert",
    "phong",
    "blinn-phong",
];

/// A model added to the registry without an independent f64 reference here fails this test
/// (rather than being skipped silently by the tests above).
#[test]
fn every_registered_model_has_an_independent_reference() {
    for e in registry::all() {
        match e.info.kind {
            fastbrdf::Kind::Lobe => {
                let _ = ref_lobe(e.info.id, 20.0, 0.9);
            }
            fastbrdf::Kind::Distribution => {
                let _ = ref_distribution(e.info.id, 0.3, 0.9);
            }
            _ => assert!(
                REFERENCED.contains(&e.info.id),
                "{}: no independent reference formula in tests/reference.rs",
                e.info.id
            ),
        }
    }
}
