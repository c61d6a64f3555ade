//! Distributions, shadowing-masking terms and Fresnel terms against their printed formulas
//! (complex arithmetic for Fresnel).

use super::*;

pub(crate) fn beckmann_naive(alpha: f64, c: f64, scale: f64) -> f64 {
    let tan2 = (1.0 - c * c) / (c * c);
    (-tan2 / (alpha * alpha)).exp() / (scale * alpha * alpha * c.powi(4))
}

pub(crate) fn ref_distribution(id: &str, alpha: f64, c: f64) -> f64 {
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

pub(crate) fn smith_g1_exact(alpha: f64, c: f64) -> f64 {
    if c >= 1.0 {
        return 1.0;
    }
    let a = c / (alpha * (1.0 - c * c).sqrt());
    let lambda = (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * PI.sqrt());
    1.0 / (1.0 + lambda)
}

/// Beckmann's Smith Lambda as printed (Walter et al. 2007, eq. 25-27), with erf.
pub(crate) fn beckmann_lambda(alpha: f64, c: f64) -> f64 {
    if c >= 1.0 {
        return 0.0;
    }
    let a = c / (alpha * (1.0 - c * c).sqrt());
    (libm::erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * PI.sqrt())
}

/// GGX's Smith Lambda as printed (Walter et al. 2007, eq. 34; Heitz 2014, eq. 72), naively:
/// `(-1 + sqrt(1 + alpha^2 tan^2)) / 2`.
pub(crate) fn ggx_lambda(alpha: f64, c: f64) -> f64 {
    let tan2 = (1.0 - c * c) / (c * c);
    (-1.0 + (1.0 + alpha * alpha * tan2).sqrt()) / 2.0
}

/// Every shadowing id's printed formula, two-sided (`l = Some`) or one-sided; `nh` is `n.h`
/// (the V-cavity only) and `vh` is `v.h` (the V-cavity and Kelemen). Panics on an id without
/// one, so a registered term without a reference fails (`shadowing_cases`).
pub(crate) fn ref_shadowing(
    id: &str,
    alpha: f64,
    remap: &str,
    v: f64,
    l: Option<f64>,
    nh: f64,
    vh: f64,
) -> f64 {
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
        "v-cavity" => {
            let g1 = |c: f64| 2.0 * nh * c / vh;
            1f64.min(g1(v)).min(l.map_or(f64::INFINITY, g1))
        }
        "smith" => smith_g1_exact(alpha, v) * l.map_or(1.0, |l| smith_g1_exact(alpha, l)),
        "smith-rational" => {
            smith_g1_rational(alpha, v) * l.map_or(1.0, |l| smith_g1_rational(alpha, l))
        }
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

/// Every registered shadowing id (`registry::ids_of`, not a list kept here), with each of
/// its `remap` choices (`""`: it has none): `ref_shadowing` panics on one it does not cover.
pub(crate) fn shadowing_cases() -> Vec<(&'static str, &'static str)> {
    let mut out = Vec::new();
    for id in registry::ids_of(fastbrdf::Kind::Shadowing) {
        let remap = registry::find(id)
            .unwrap()
            .info
            .params
            .iter()
            .find_map(|p| match p.kind {
                fastbrdf::params::ParamKind::Choice { options, .. } if p.name == "remap" => {
                    Some(options.names())
                }
                _ => None,
            });
        match remap {
            Some(names) => out.extend(names.iter().map(|r| (id, *r))),
            None => out.push((id, "")),
        }
    }
    out
}

pub(crate) fn smith_g1_rational(alpha: f64, c: f64) -> f64 {
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
pub(crate) fn fresnel_complex(cos_i: f64, eta: Complex64) -> f64 {
    let sin2_i = 1.0 - cos_i * cos_i;
    let cos_t = (Complex64::new(1.0, 0.0) - sin2_i / (eta * eta)).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs.norm_sqr() + rp.norm_sqr())
}

#[test]
fn distributions_match_their_printed_formulas() {
    for id in fastbrdf::registry::ids_of(fastbrdf::Kind::Distribution) {
        for &alpha in ALPHA_VALUES {
            let Model::Distribution(d) =
                build::<f64>(id, &[("alpha", &alpha.to_string())]).unwrap()
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
        let Model::Distribution(d) = build::<f64>("beckmann", &[("alpha", &a)]).unwrap() else {
            panic!()
        };
        let Model::Distribution(ct) = build::<f64>("beckmann-ct", &[("alpha", &a)]).unwrap() else {
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
        let Model::Shadowing(exact) = build::<f64>("smith", &[("alpha", &a)]).unwrap() else {
            panic!()
        };
        let Model::Shadowing(rat) = build::<f64>("smith-rational", &[("alpha", &a)]).unwrap()
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
    let Model::Shadowing(v) = build::<f64>("v-cavity", &[]).unwrap() else {
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

/// issue 14: every shadowing term (the GGX Smith terms, their approximations, the Beckmann
/// terms, the V-cavity, Kelemen and Neumann; issue 28: the registry's list) against its
/// printed formula, on random direction pairs (two-sided, with the pair's own half vector) and
/// one-sided.
#[test]
fn issue14_shadowing_terms_match_their_printed_formulas() {
    let mut rng = Rng(14);
    let pairs: Vec<_> = (0..400)
        .map(|_| (rng.hemisphere(), rng.hemisphere()))
        .collect();
    for (id, remap) in shadowing_cases() {
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
            let Model::Shadowing(g) = build::<f64>(id, &given).unwrap() else {
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
                    let want = ref_shadowing(id, alpha, remap, nv, l, nh, vh);
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
                let Model::Shadowing(g) = build::<f64>("smith-ggx-correlated", &given).unwrap()
                else {
                    panic!()
                };
                g.g(&s)
            } else {
                let Model::Shadowing(g) = build::<f32>("smith-ggx-correlated", &given).unwrap()
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
        let Model::Fresnel(f) = build::<f64>(
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
            build::<f64>("fresnel-dielectric", &[("eta", &eta.to_string())]).unwrap()
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
    let Model::Fresnel(s) = build::<f64>("fresnel-schlick", &[("f0", "0.04")]).unwrap() else {
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
        match build::<f64>(id, &given).unwrap() {
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
