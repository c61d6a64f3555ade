//! Full BRDFs against their printed formulas: Cook-Torrance (isotropic and anisotropic),
//! Ward, Lambert and the lobe BRDFs.

use super::*;

pub(crate) fn brdf64(id: &str, given: &[(&str, &str)]) -> Box<dyn fastbrdf::Brdf<f64>> {
    match build::<f64>(id, given).unwrap() {
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
        for (g, remap) in shadowing_cases() {
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
                    let gv = ref_shadowing(g, alpha, remap, wo[2], Some(wi[2]), h[2], dotv(wo, h));
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
pub(crate) const ANISO_SLOPES: &[(f64, f64)] = &[
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
pub(crate) fn projected_alpha(w: [f64; 3], ax: f64, ay: f64) -> (f64, f64) {
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
pub(crate) fn ref_aniso_d(d: &str, h: [f64; 3], ax: f64, ay: f64) -> f64 {
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
pub(crate) fn ref_aniso_g(g: &str, v: [f64; 3], l: [f64; 3], ax: f64, ay: f64) -> f64 {
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
        _ => ref_shadowing(
            g,
            alpha,
            "alpha-half",
            cos_eff(v),
            Some(cos_eff(l)),
            0.0,
            0.0,
        ),
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
                    |given: &[(&str, &str)]| match build::<f32>("cook-torrance", given).unwrap() {
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
