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
        // Walter et al. 2007, eq. 33, as printed (through tan^2 = (1 - c^2) / c^2).
        "ggx" => {
            let tan2 = (1.0 - c * c) / (c * c);
            alpha * alpha / (PI * c.powi(4) * (alpha * alpha + tan2).powi(2))
        }
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

/// Beckmann's Smith Lambda as printed (Walter et al. 2007, eq. 25-27), with erf.
fn beckmann_lambda(alpha: f64, c: f64) -> f64 {
    if c >= 1.0 {
        return 0.0;
    }
    let a = c / (alpha * (1.0 - c * c).sqrt());
    (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * PI.sqrt())
}

/// GGX's Smith Lambda as printed (Walter et al. 2007, eq. 34; Heitz 2014, eq. 72), naively:
/// `(-1 + sqrt(1 + alpha^2 tan^2)) / 2`.
fn ggx_lambda(alpha: f64, c: f64) -> f64 {
    let tan2 = (1.0 - c * c) / (c * c);
    (-1.0 + (1.0 + alpha * alpha * tan2).sqrt()) / 2.0
}

/// Every new shadowing id's printed formula, two-sided (`l = Some`) or one-sided; `vh` is
/// `v.h` (Kelemen only).
fn ref_shadowing(id: &str, alpha: f64, remap: &str, v: f64, l: Option<f64>, vh: f64) -> f64 {
    let g1_ggx = |c: f64| 1.0 / (1.0 + ggx_lambda(alpha, c));
    let k = if remap == "ue4" {
        (alpha.sqrt() + 1.0).powi(2) / 8.0
    } else {
        alpha / 2.0
    };
    let schlick = |c: f64| c / (c * (1.0 - k) + k);
    // Filament's V_SmithGGXCorrelated_Fast and Unreal's Vis_SmithJointApprox, as printed,
    // times 4 NL NV; one-sided at NL = 1.
    let nl = l.unwrap_or(1.0);
    let a = alpha;
    let mix = |x: f64, y: f64, t: f64| x * (1.0 - t) + y * t;
    match id {
        "smith-ggx" => g1_ggx(v) * l.map_or(1.0, g1_ggx),
        "smith-ggx-correlated" => {
            1.0 / (1.0 + ggx_lambda(alpha, v) + l.map_or(0.0, |l| ggx_lambda(alpha, l)))
        }
        "smith-beckmann-correlated" => {
            1.0 / (1.0 + beckmann_lambda(alpha, v) + l.map_or(0.0, |l| beckmann_lambda(alpha, l)))
        }
        "smith-ggx-correlated-fast" => 4.0 * nl * v * (0.5 / mix(2.0 * nl * v, nl + v, a)),
        "smith-ggx-correlated-fast-tuned" => {
            // Hammon's form at k = alpha (0.529334 + 0.505461 alpha - 0.035766 alpha^2).
            let k = a * (0.529334 + 0.505461 * a - 0.035766 * a * a);
            4.0 * nl * v * (0.5 / mix(2.0 * nl * v, nl + v, k))
        }
        "smith-ggx-joint-approx" => {
            let vis = 0.5 / (nl * (v * (1.0 - a) + a) + v * (nl * (1.0 - a) + a));
            4.0 * nl * v * vis
        }
        "schlick-ggx" => schlick(v) * l.map_or(1.0, schlick),
        "kelemen" => (nl * v / (vh * vh)).min(1.0),
        "neumann" => nl * v / nl.max(v),
        _ => panic!("no reference for shadowing term {id}"),
    }
}

/// The shadowing ids `ref_shadowing` covers, with their `remap` choices.
const NEW_SHADOWING: &[(&str, &str)] = &[
    ("smith-ggx", ""),
    ("smith-ggx-correlated", ""),
    ("smith-beckmann-correlated", ""),
    ("smith-ggx-correlated-fast", ""),
    ("smith-ggx-correlated-fast-tuned", ""),
    ("smith-ggx-joint-approx", ""),
    ("schlick-ggx", "alpha-half"),
    ("schlick-ggx", "ue4"),
    ("kelemen", ""),
    ("neumann", ""),
];

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

/// issue 14: the GGX Smith terms, their approximations, the correlated Beckmann term and the
/// parameterless Kelemen and Neumann terms against their printed formulas, on random direction
/// pairs (two-sided, with the pair's own half vector) and one-sided.
#[test]
fn issue14_shadowing_terms_match_their_printed_formulas() {
    let mut rng = Rng(14);
    let pairs: Vec<_> = (0..400)
        .map(|_| (rng.hemisphere(), rng.hemisphere()))
        .collect();
    for &(id, remap) in NEW_SHADOWING {
        let info = registry::find(id).unwrap().info;
        let alphas: &[f64] = if info.params.is_empty() {
            &[0.3]
        } else {
            ALPHA_VALUES
        };
        for &alpha in alphas {
            let a = alpha.to_string();
            let mut given: Vec<(&str, &str)> = vec![];
            if !info.params.is_empty() {
                given.push(("alpha", &a));
            }
            if !remap.is_empty() {
                given.push(("remap", remap));
            }
            let Model::Shadowing(g) = registry::build::<f64>(id, &given).unwrap() else {
                panic!()
            };
            for &(wi, wo) in &pairs {
                let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
                let (nv, nl, nh, vh) = (wo[2], wi[2], h[2], dotv(wo, h));
                for l in [Some(nl), None] {
                    let got = g.g(&fastbrdf::model::ShadowInput {
                        cos_v: nv,
                        cos_l: l,
                        cos_h: nh,
                        cos_vh: vh,
                    });
                    let want = ref_shadowing(id, alpha, remap, nv, l, vh);
                    // The naive -1 + sqrt(1 + x) loses ~1e-16 / x relative in Lambda: absolute
                    // errors stay near 1e-16 since G is in [0, 1].
                    assert!(
                        (got - want).abs() <= 1e-12,
                        "{id} {remap} alpha={alpha} v={nv} l={l:?} vh={vh}: {got} vs {want}"
                    );
                }
            }
        }
    }
}

/// `smith-ggx-correlated` is `1 / (1 + Lambda(v) + Lambda(l))` at tabulated points: values
/// computed outside this project with mpmath at 30 digits from Lambda's printed form (rounded
/// to the nearest f64).
#[test]
fn smith_ggx_correlated_at_tabulated_points() {
    const TABLE: &[(f64, f64, f64, f64)] = &[
        (0.01, 0.5, 0.5, 0.9998500337415647),
        (0.01, 0.01, 0.9, 0.828435232486224),
        (0.1, 0.2, 0.7, 0.9439557058538371),
        (0.3, 0.5, 0.5, 0.8873565094161138),
        (0.3, 0.05, 1.0, 0.28267112623968893),
        (0.5, 0.9, 0.3, 0.6879610724085811),
        (0.7072, 0.25, 0.75, 0.48847565168719737),
        (1.0, 0.5, 0.5, 0.5),
        (1.0, 0.1, 0.1, 0.1),
        (1.0, 1.0, 1.0, 1.0),
    ];
    for &(alpha, v, l, want) in TABLE {
        for (prec, tol) in [("f64", 1e-15), ("f32", 3e-7)] {
            let s = fastbrdf::model::ShadowInput {
                cos_v: v,
                cos_l: Some(l),
                cos_h: 1.0,
                cos_vh: 1.0,
            };
            let given = [("alpha", alpha.to_string())];
            let given = [("alpha", given[0].1.as_str())];
            let got = if prec == "f64" {
                let Model::Shadowing(g) =
                    registry::build::<f64>("smith-ggx-correlated", &given).unwrap()
                else {
                    panic!()
                };
                g.g(&s)
            } else {
                let Model::Shadowing(g) =
                    registry::build::<f32>("smith-ggx-correlated", &given).unwrap()
                else {
                    panic!()
                };
                g.g(&fastbrdf::model::ShadowInput {
                    cos_v: v as f32,
                    cos_l: Some(l as f32),
                    cos_h: 1.0,
                    cos_vh: 1.0,
                }) as f64
            };
            assert!(
                (got - want).abs() <= tol * want,
                "{prec} alpha={alpha} v={v} l={l}: {got} vs {want}"
            );
            // And the formula of this file agrees with the table.
            let mine = 1.0 / (1.0 + ggx_lambda(alpha, v) + ggx_lambda(alpha, l));
            assert!((mine - want).abs() <= 1e-14, "{mine} vs {want}");
        }
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

/// Schlick with `f90` (Filament's `F_Schlick(f0, f90, VoH)`) and Karis's spherical-Gaussian
/// form `f0 + (f90 - f0) 2^((-5.55473 c - 6.98316) c)` (UE4 course notes, 2013), written
/// here from the published formulas; the tuned form's constants are its documented ones.
#[test]
fn schlick_f90_and_spherical_gaussian_schlick_match_their_published_formulas() {
    let build = |id: &str, f0: f64, f90: f64| {
        let given = [("f0", f0.to_string()), ("f90", f90.to_string())];
        let given: Vec<(&str, &str)> = given.iter().map(|(k, v)| (*k, v.as_str())).collect();
        match registry::build::<f64>(id, &given).unwrap() {
            Model::Fresnel(f) => f,
            _ => panic!("{id}"),
        }
    };
    for (f0, f90) in [(0.04, 1.0), (0.0, 1.0), (0.5, 0.8), (1.0, 0.0), (0.9, 0.9)] {
        let schlick = build("fresnel-schlick", f0, f90);
        let sg = build("fresnel-schlick-sg", f0, f90);
        let tuned = build("fresnel-schlick-sg-tuned", f0, f90);
        for i in 0..=200 {
            let c = i as f64 / 200.0;
            let want = f0 + (f90 - f0) * (1.0 - c).powi(5);
            assert!(
                (schlick.f(c) - want).abs() < 1e-15,
                "schlick {f0} {f90} {c}"
            );
            let want = f0 + (f90 - f0) * 2f64.powf((-5.55473 * c - 6.98316) * c);
            assert!((sg.f(c) - want).abs() < 1e-14, "sg {f0} {f90} {c}");
            let want = f0 + (f90 - f0) * 2f64.powf((-5.551343 * c - 6.996120) * c);
            assert!((tuned.f(c) - want).abs() < 1e-14, "sg-tuned {f0} {f90} {c}");
        }
        // Out of [0, 1] the cosine is clamped, NaN acts as 0.
        assert_eq!(sg.f(f64::NAN), sg.f(0.0));
        assert_eq!(sg.f(2.0), sg.f(1.0));
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

/// issue 14: `cook-torrance` with `d = ggx` and each new shadowing term (with `alpha`, or
/// none) against `F D G / (4 cos_i cos_o)` from this file's formulas.
#[test]
fn cook_torrance_with_ggx_is_fdg_over_4_cos_cos() {
    let pairs = direction_pairs(200, 14);
    for &alpha in ALPHA_VALUES {
        for &(g, remap) in NEW_SHADOWING {
            if remap == "ue4" {
                continue; // cook-torrance cannot choose a part's choice: alpha-half only
            }
            for f in ["none", "schlick", "conductor"] {
                let a = alpha.to_string();
                let ct = brdf64(
                    "cook-torrance",
                    &[
                        ("alpha", &a),
                        ("d", "ggx"),
                        ("g", g),
                        ("f", f),
                        ("eta", "0.2"),
                        ("k", "3.9"),
                    ],
                );
                for (wi, wo) in &pairs {
                    let (wi, wo) = (unit(*wi), unit(*wo));
                    let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
                    let d = ref_distribution("ggx", alpha, h[2]);
                    let gv = ref_shadowing(g, alpha, remap, wo[2], Some(wi[2]), dotv(wo, h));
                    let fv = match f {
                        "none" => 1.0,
                        "schlick" => 0.04 + 0.96 * (1.0 - dotv(wi, h)).powi(5),
                        _ => fresnel_complex(dotv(wi, h), Complex64::new(0.2, 3.9)),
                    };
                    let want = fv * d * gv / (4.0 * wi[2] * wo[2]);
                    let got = ct.eval(wi, wo);
                    assert!(
                        (got - want).abs() <= 1e-9 * want.abs() + 1e-300,
                        "alpha={alpha} g={g} f={f}: {got} vs {want}"
                    );
                }
            }
        }
    }
}

/// Anisotropic slope pairs for the anisotropic Cook-Torrance tests: extremes both ways.
const ANISO_SLOPES: &[(f64, f64)] = &[
    (0.005, 1.0),
    (1.0, 0.005),
    (0.02, 0.5),
    (0.3, 0.1),
    (0.7072, 0.05),
    (0.2, 0.2),
];

/// The projected slope `alpha_w` of direction `w` on an anisotropic surface (Heitz 2014,
/// eq. 80), from the azimuth: `sqrt(cos^2 phi alpha_x^2 + sin^2 phi alpha_y^2)`; and
/// `tan^2 theta`.
fn projected_alpha(w: [f64; 3], ax: f64, ay: f64) -> (f64, f64) {
    let r2 = w[0] * w[0] + w[1] * w[1];
    if r2 == 0.0 {
        return (ax, 0.0);
    }
    let phi = w[1].atan2(w[0]);
    let aw = (phi.cos().powi(2) * ax * ax + phi.sin().powi(2) * ay * ay).sqrt();
    (aw, r2 / (w[2] * w[2]))
}

/// Anisotropic D of GGX (Heitz 2014, eq. 85) and Beckmann (eq. 84) as printed, in `h`'s
/// slopes; `beckmann-ct` is `beckmann` times pi / 4.
fn ref_aniso_d(d: &str, h: [f64; 3], ax: f64, ay: f64) -> f64 {
    let q = h[0] * h[0] / (ax * ax) + h[1] * h[1] / (ay * ay);
    match d {
        "ggx" => 1.0 / (PI * ax * ay * (q + h[2] * h[2]).powi(2)),
        "beckmann" => (-q / (h[2] * h[2])).exp() / (PI * ax * ay * h[2].powi(4)),
        "beckmann-ct" => PI / 4.0 * ref_aniso_d("beckmann", h, ax, ay),
        _ => panic!("no anisotropic reference for {d}"),
    }
}

/// Anisotropic Smith G of `v`, `l` (Heitz 2014, sec. 5): the exact terms are the isotropic
/// Lambdas at the projected slope (`projected_alpha`, through the azimuth); the
/// approximations are their isotropic formulas at `alpha = sqrt(ax ay)` on the cosine that
/// gives the same `alpha^2 tan^2` (the anisotropic extension the model documents).
fn ref_aniso_g(g: &str, v: [f64; 3], l: [f64; 3], ax: f64, ay: f64) -> f64 {
    let lambda_ggx = |w: [f64; 3]| {
        let (aw, t2) = projected_alpha(w, ax, ay);
        (-1.0 + (1.0 + aw * aw * t2).sqrt()) / 2.0
    };
    let a_of = |w: [f64; 3]| {
        let (aw, t2) = projected_alpha(w, ax, ay);
        1.0 / (aw * t2.sqrt())
    };
    let lambda_beckmann = |w: [f64; 3]| {
        let a = a_of(w);
        if a.is_infinite() {
            return 0.0;
        }
        (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * PI.sqrt())
    };
    let rational = |w: [f64; 3]| {
        let a = a_of(w);
        if a >= 1.6 {
            1.0
        } else {
            (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
        }
    };
    let alpha = (ax * ay).sqrt();
    let cos_eff = |w: [f64; 3]| {
        let (aw, t2) = projected_alpha(w, ax, ay);
        1.0 / (1.0 + aw * aw * t2 / (alpha * alpha)).sqrt()
    };
    match g {
        "smith" => 1.0 / ((1.0 + lambda_beckmann(v)) * (1.0 + lambda_beckmann(l))),
        "smith-beckmann-correlated" => 1.0 / (1.0 + lambda_beckmann(v) + lambda_beckmann(l)),
        "smith-ggx" => 1.0 / ((1.0 + lambda_ggx(v)) * (1.0 + lambda_ggx(l))),
        "smith-ggx-correlated" => 1.0 / (1.0 + lambda_ggx(v) + lambda_ggx(l)),
        "smith-rational" => rational(v) * rational(l),
        _ => ref_shadowing(g, alpha, "alpha-half", cos_eff(v), Some(cos_eff(l)), 0.0),
    }
}

/// issue 14: anisotropic `cook-torrance` (`alpha_x`, `alpha_y`) with every allowed D and G
/// against `F D G / (4 cos_i cos_o)` from the textbook anisotropic D and Smith Lambda
/// (projected slope from the azimuth, not the model's stretch), slopes to their extremes.
#[test]
fn anisotropic_cook_torrance_matches_its_textbook_form() {
    let pairs = direction_pairs(200, 15);
    let ds = fastbrdf::brdf::cook_torrance::ANISO_D;
    let gs = fastbrdf::brdf::cook_torrance::ANISO_G;
    let mut nonzero = 0;
    for &(ax, ay) in ANISO_SLOPES {
        for &d in ds {
            for &g in gs {
                let (sx, sy) = (ax.to_string(), ay.to_string());
                let ct = brdf64(
                    "cook-torrance",
                    &[
                        ("alpha_x", &sx),
                        ("alpha_y", &sy),
                        ("d", d),
                        ("g", g),
                        ("f", "schlick"),
                    ],
                );
                // Mirror-ish pairs too, where narrow lobes are not 0.
                let mut all = pairs.clone();
                for (wi, _) in &pairs {
                    let wi = unit(*wi);
                    all.push((wi, [-wi[0] * 0.999, -wi[1], wi[2]]));
                }
                for (wi, wo) in &all {
                    let (wi, wo) = (unit(*wi), unit(*wo));
                    if wi[2] < 1e-3 || wo[2] < 1e-3 {
                        continue;
                    }
                    let h = unit([wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]]);
                    let fv = 0.04 + 0.96 * (1.0 - dotv(wi, h)).powi(5);
                    let want = fv * ref_aniso_d(d, h, ax, ay) * ref_aniso_g(g, wo, wi, ax, ay)
                        / (4.0 * wi[2] * wo[2]);
                    let got = ct.eval(wi, wo);
                    if want > 1e-200 {
                        nonzero += 1;
                    }
                    // Beckmann's exponent reaches ~700: its rounding is 1e-16 of that.
                    assert!(
                        (got - want).abs() <= 1e-10 * want.abs() + 1e-300,
                        "ax={ax} ay={ay} d={d} g={g} wi={wi:?} wo={wo:?}: {got} vs {want}"
                    );
                }
            }
        }
    }
    assert!(nonzero > 10_000, "too few non-zero values: {nonzero}");
}

/// issue 14: `alpha_x = alpha_y = a` is the isotropic model at `alpha = a` for every allowed
/// D and G, to rounding (f64 and f32; the stretched arguments are recomputed, not copied).
#[test]
fn anisotropic_cook_torrance_at_equal_slopes_is_isotropic() {
    let pairs = direction_pairs(300, 16);
    for &a in ALPHA_VALUES {
        for &d in fastbrdf::brdf::cook_torrance::ANISO_D {
            for &g in fastbrdf::brdf::cook_torrance::ANISO_G {
                let s = a.to_string();
                let base = [("d", d), ("g", g), ("f", "schlick")];
                let iso: Vec<(&str, &str)> = base
                    .iter()
                    .copied()
                    .chain([("alpha", s.as_str())])
                    .collect();
                let aniso: Vec<(&str, &str)> = base
                    .iter()
                    .copied()
                    .chain([
                        ("alpha_x", s.as_str()),
                        ("alpha_y", s.as_str()),
                        ("alpha", "0.9"),
                    ])
                    .collect();
                let (i64m, a64m) = (
                    brdf64("cook-torrance", &iso),
                    brdf64("cook-torrance", &aniso),
                );
                let b32 =
                    |given: &[(&str, &str)]| match registry::build::<f32>("cook-torrance", given)
                        .unwrap()
                    {
                        Model::Brdf(b) => b,
                        _ => panic!(),
                    };
                let (i32m, a32m) = (b32(&iso), b32(&aniso));
                for (wi, wo) in &pairs {
                    let (x, y) = (i64m.eval(*wi, *wo), a64m.eval(*wi, *wo));
                    assert!(
                        (x - y).abs() <= 1e-11 * x.abs() + 1e-300,
                        "f64 a={a} d={d} g={g}: iso {x} aniso {y}"
                    );
                    let (wi, wo) = (wi.map(|c| c as f32), wo.map(|c| c as f32));
                    let (x, y) = (i32m.eval(wi, wo), a32m.eval(wi, wo));
                    assert!(
                        (x - y).abs() <= 1e-4 * x.abs() + 1e-30,
                        "f32 a={a} d={d} g={g}: iso {x} aniso {y}"
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

/// The split-sum terms of GGX with height-correlated Smith, from their definition: the
/// integral over light directions of `w(v.h) D G2 / (4 cos_v cos_l) cos_l` with
/// `w = 1 - (1 - v.h)^5` (scale) or `(1 - v.h)^5` (bias), every factor written here from the
/// published formulas (Walter et al. 2007's GGX D; Heitz 2014's correlated G2), integrated by
/// the adaptive Gauss-Kronrod of `quad::albedo` around the mirror direction (another
/// variable and another rule than `env-brdf`'s product Gauss-Legendre in the half vector).
fn ref_env(cos_v: f64, alpha: f64, bias: bool) -> f64 {
    let a2 = alpha * alpha;
    let v = [(1.0 - cos_v * cos_v).sqrt(), 0.0, cos_v];
    let lambda = |c: f64| ((1.0 + a2 * (1.0 - c * c) / (c * c)).sqrt() - 1.0) / 2.0;
    let f = |l: [f64; 3]| {
        let h = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
        let n = dotv(h, h).sqrt();
        let h = [h[0] / n, h[1] / n, h[2] / n];
        let (ch, vh, cl) = (h[2], dotv(v, h), l[2]);
        if cl <= 0.0 || ch <= 0.0 {
            return 0.0;
        }
        let t2 = (1.0 - ch * ch) / (ch * ch);
        let d = a2 / (PI * ch.powi(4) * (a2 + t2).powi(2));
        let g2 = 1.0 / (1.0 + lambda(cos_v) + lambda(cl));
        let f5 = (1.0 - vh).powi(5);
        let w = if bias { f5 } else { 1.0 - f5 };
        w * d * g2 / (4.0 * cos_v * cl)
    };
    let mirror = [-v[0], 0.0, v[2]];
    fastbrdf::quad::albedo(f, mirror, &[], 1e-9).0
}

/// Karis's `EnvBRDFApprox` as printed (UE4 mobile, 2014), with the bias clamped at 0.
fn ref_env_approx(cos_v: f64, alpha: f64, c: &[f64; 11], bias: bool) -> f64 {
    let r = alpha.sqrt();
    let p = [0, 1, 2, 3].map(|i| r * c[i] + c[i + 4]);
    let a004 = (p[0] * p[0]).min((c[8] * cos_v).exp2()) * p[0] + p[1];
    let v = if bias {
        c[10] * a004 + p[3]
    } else {
        c[9] * a004 + p[2]
    };
    v.max(0.0)
}

fn env64(id: &str, bias: bool) -> Box<dyn fastbrdf::model::Env<f64>> {
    let term = if bias { "bias" } else { "scale" };
    match registry::build::<f64>(id, &[("term", term)]).unwrap() {
        Model::Env(e) => e,
        _ => panic!("{id} is not a split-sum term"),
    }
}

/// `env-brdf`'s fixed rule against adaptive quadrature of the definition, within its
/// documented quadrature error, on views from grazing (0.001) to normal and the whole alpha
/// range; and the white-furnace anchors (scale + bias = the directional albedo with F = 1)
/// that a three.js issue published for GGX with height-correlated Smith: 0.86, 0.66, 0.45,
/// 0.31 at perceptual roughness r (alpha = r^2) and cos_v (0.5, 0.5), (0.75, 0.5), (1, 0.5),
/// (1, 1).
#[test]
fn env_brdf_matches_adaptive_quadrature_of_its_definition_and_the_furnace_anchors() {
    let (scale, bias) = (env64("env-brdf", false), env64("env-brdf", true));
    let mut worst: f64 = 0.0;
    for cos_v in [0.001, 0.01, 0.1, 0.3, 0.5, 0.8, 0.999, 1.0] {
        for alpha in [0.005, 0.01, 0.05, 0.2, 0.5, 1.0] {
            for (m, b) in [(&scale, false), (&bias, true)] {
                let (got, want) = (m.e(cos_v, alpha), ref_env(cos_v.min(1.0 - 1e-12), alpha, b));
                worst = worst.max((got - want).abs());
                assert!(
                    (got - want).abs() <= fastbrdf::microfacet::env_brdf::QUADRATURE_ERROR,
                    "env-brdf bias={b} cos_v={cos_v} alpha={alpha}: {got} vs {want}"
                );
            }
        }
    }
    println!("env-brdf vs adaptive quadrature: max abs {worst:.2e}");
    for (r, cos_v, want) in [
        (0.5, 0.5, 0.86),
        (0.75, 0.5, 0.66),
        (1.0, 0.5, 0.45),
        (1.0, 1.0, 0.31),
    ] {
        let a: f64 = r * r;
        let got = scale.e(cos_v, a) + bias.e(cos_v, a);
        assert!(
            (got - want).abs() < 0.01,
            "r={r} cos_v={cos_v}: {got} vs {want}"
        );
    }
}

#[test]
fn env_brdf_approximations_match_karis_formula() {
    use fastbrdf::microfacet::env_brdf::{KARIS, TUNED};
    for (id, c) in [("env-brdf-approx", KARIS), ("env-brdf-approx-tuned", TUNED)] {
        for b in [false, true] {
            let m = env64(id, b);
            for i in 0..=20 {
                for j in 0..=20 {
                    let (v, a) = (i as f64 / 20.0, 0.005 + 0.995 * j as f64 / 20.0);
                    let want = ref_env_approx(v, a, &c, b);
                    assert!((m.e(v, a) - want).abs() < 1e-14, "{id} {b} {v} {a}");
                }
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
    // ref_shadowing (NEW_SHADOWING):
    "smith-beckmann-correlated",
    "smith-ggx",
    "smith-ggx-correlated",
    "smith-ggx-correlated-fast",
    "smith-ggx-correlated-fast-tuned",
    "smith-ggx-joint-approx",
    "schlick-ggx",
    "kelemen",
    "neumann",
    "fresnel-none",
    "fresnel-schlick",
    "fresnel-schlick-sg",
    "fresnel-schlick-sg-tuned",
    "env-brdf",
    "env-brdf-approx",
    "env-brdf-approx-tuned",
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
