//! Properties over the whole documented domain (proptest), reciprocity on random pairs, and
//! the out-of-domain rules: 0 by a documented rule or an error, never NaN or a panic.

mod common;

use common::{as_refs, build, configs, direction_pairs};
use fastbrdf::model::{ModelInfo, ShadowInput};
use fastbrdf::params::ParamKind;
use fastbrdf::{Given, Model, Real, registry};
use proptest::prelude::*;

/// A strategy for a valid parameter set of `info`: numbers anywhere in their range (edges
/// weighted), choices uniformly.
fn params_strategy(info: &'static ModelInfo) -> BoxedStrategy<Vec<(String, String)>> {
    let parts: Vec<BoxedStrategy<Option<(String, String)>>> = info
        .params
        .iter()
        .map(|p| {
            let name = p.name.to_string();
            match p.kind {
                ParamKind::Number { min, max, .. } => {
                    let value = prop_oneof![
                        Just(min),
                        Just(max),
                        min..=max,
                        (0.0f64..1.0).prop_map(move |t| min + (max - min) * t * t * t)
                    ];
                    value
                        .prop_map(move |v| Some((name.clone(), v.to_string())))
                        .boxed()
                }
                ParamKind::Choice { options, .. } => (0..options.names().len())
                    .prop_map(move |i| Some((name.clone(), options.names()[i].to_string())))
                    .boxed(),
            }
        })
        .collect();
    // Optional parameters (alpha_x, alpha_y) are given together or not at all, and only where
    // their `requires` hold (cook-torrance's need d, g and ms with an anisotropic form).
    let optional: Vec<&str> = info
        .params
        .iter()
        .filter(|p| matches!(p.kind, ParamKind::Number { default: None, .. }))
        .map(|p| p.name)
        .collect();
    (parts, any::<bool>())
        .prop_map(move |(v, keep_optional)| {
            let v: Vec<(String, String)> = v
                .into_iter()
                .flatten()
                .filter(|(k, _)| keep_optional || !optional.contains(&k.as_str()))
                .collect();
            // A gated choice (`Options::Gated`: cook-torrance's `ms`) falls back to its default
            // where its requirements do not hold (they are refused, tested in energy.rs).
            let v: Vec<(String, String)> =
                v.iter()
                    .filter(|(k, val)| {
                        info.params.iter().all(|p| match p.kind {
                            ParamKind::Choice { options, default } if p.name == k => options
                                .allows(val, default, |n| {
                                    v.iter().find(|(k2, _)| k2 == n).map(|(_, x)| x.clone())
                                }),
                            _ => true,
                        })
                    })
                    .cloned()
                    .collect();
            // So are gated optional numbers (`requires`: cook-torrance's alpha_x, alpha_y), on
            // the choices left (a choice not given is its default).
            let choice = |n: &str| {
                v.iter()
                    .find(|(k, _)| k == n)
                    .map(|(_, x)| x.clone())
                    .or_else(|| {
                        info.params
                            .iter()
                            .find(|p| p.name == n)
                            .map(|p| p.default_text())
                    })
            };
            v.iter()
                .filter(|(k, _)| info.params.iter().all(|p| p.name != k || p.allowed(choice)))
                .cloned()
                .collect()
        })
        .boxed()
}

fn any_model() -> impl Strategy<Value = (&'static ModelInfo, Vec<(String, String)>)> {
    (0..registry::all().len()).prop_flat_map(|i| {
        let info = &registry::all()[i].info;
        params_strategy(info).prop_map(move |p| (info, p))
    })
}

/// Evaluates a model on in-domain inputs derived from `u` (three numbers in [0, 1]).
fn eval_in_domain<T: Real>(m: &Model<T>, u: [f64; 6]) -> T {
    let c = |x: f64| T::c(x);
    match m {
        Model::Lobe(l) => l.eval(c(u[0])),
        Model::Distribution(d) => d.eval(c(u[0])),
        Model::Shadowing(s) => s.g(&ShadowInput {
            cos_v: c(u[0]),
            cos_l: Some(c(u[1])),
            cos_h: c(u[2]),
            cos_vh: c(u[3].max(1e-3)),
        }),
        Model::Fresnel(f) => f.f(c(u[0])),
        Model::Env(e) => {
            let (lo, hi) = fastbrdf::params::ALPHA.range();
            e.e(c(u[0]), c(lo + (hi - lo) * u[1]))
        }
        Model::Brdf(b) => {
            let dir = |a: f64, b: f64| {
                let z = 1e-3 + (1.0 - 1e-3) * a;
                let r = (1.0 - z * z).sqrt();
                let phi = 2.0 * std::f64::consts::PI * b;
                [c(r * phi.cos()), c(r * phi.sin()), c(z)]
            };
            b.eval(dir(u[0], u[1]), dir(u[2], u[3]))
        }
    }
}

/// issue 14: at the edges of the widened domain (n = 1e5, alpha = 0.005, and the other ends)
/// every model is finite and non-negative in f32 and f64, on inputs dense at the peak
/// (where `c^n` with n = 1e5 and Beckmann's `1/(pi alpha^2)` are largest) and at grazing. The
/// proptest above draws the edges too, but at random; this walks every configuration of
/// `accuracy::domain_configs` that holds an edge value.
#[test]
fn finite_and_non_negative_at_the_edges_of_the_domain() {
    let us = [
        0.0,
        1e-9,
        1e-6,
        1e-4,
        1e-3,
        0.01,
        0.1,
        0.3,
        0.5,
        0.7,
        0.9,
        0.99,
        0.999,
        0.9999,
        0.99999,
        0.999_999,
        0.999_999_9,
        1.0,
    ];
    let mut checked = 0;
    for e in registry::all() {
        let edges: Vec<(&str, f64, f64)> = e
            .info
            .params
            .iter()
            .filter_map(|p| match p.kind {
                ParamKind::Number { min, max, .. } => Some((p.name, min, max)),
                ParamKind::Choice { .. } => None,
            })
            .collect();
        for cfg in configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf) {
            let at_edge = edges.iter().any(|&(name, min, max)| {
                common::get(&cfg, name).is_some_and(|v| v == min || v == max)
            });
            if !at_edge {
                continue;
            }
            let m64 = cfg.model::<f64>().unwrap();
            let m32 = cfg.model::<f32>().unwrap();
            for (i, &a) in us.iter().enumerate() {
                for &b in &us[i % 3..] {
                    // Inputs near the peak: cosines and directions from a and b, and 1 - a.
                    for u in [
                        [a, b, 1.0 - a, b, a, b],
                        [1.0 - a, b, 1.0 - b, a, a, 1.0 - b],
                    ] {
                        let (v64, v32) = (eval_in_domain(&m64, u), eval_in_domain(&m32, u));
                        assert!(
                            v64.is_finite() && v64 >= 0.0 && v32.is_finite() && v32 >= 0.0,
                            "{} {cfg:?} {u:?}: f64 {v64}, f32 {v32}",
                            e.info.id
                        );
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 10_000, "{checked}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    /// Any model, any valid parameters, any input in the documented domain: finite and
    /// non-negative, in f32 and in f64.
    #[test]
    fn finite_and_non_negative_on_the_domain((info, params) in any_model(), u in proptest::array::uniform6(0.0f64..=1.0)) {
        let given = as_refs(&params);
        let m64 = build::<f64>(info.id, &given).unwrap();
        let m32 = build::<f32>(info.id, &given).unwrap();
        let v64 = eval_in_domain(&m64, u);
        let v32 = eval_in_domain(&m32, u);
        prop_assert!(v64.is_finite() && v64 >= 0.0, "{} {:?} {:?}: f64 {}", info.id, params, u, v64);
        prop_assert!(v32.is_finite() && v32 >= 0.0, "{} {:?} {:?}: f32 {}", info.id, params, u, v32);
    }

    /// Out-of-domain inputs (NaN, infinities, negative or > 1 cosines, zero vectors,
    /// directions below the horizon): finite and non-negative, never NaN, never a panic.
    #[test]
    fn out_of_domain_inputs_are_harmless((info, params) in any_model(),
        x in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(0.0), Just(-0.0), -10.0f64..0.0, 1.0f64..10.0, Just(1.0 + 1e-7)],
        v in proptest::array::uniform3(-1.0f64..1.0)) {
        let given = as_refs(&params);
        for m in [build::<f64>(info.id, &given).unwrap()] {
            let vals: Vec<f64> = match &m {
                Model::Lobe(l) => vec![l.eval(x)],
                Model::Distribution(d) => vec![d.eval(x)],
                Model::Shadowing(s) => vec![
                    s.g(&ShadowInput { cos_v: x, cos_l: None, cos_h: x, cos_vh: x }),
                    s.g(&ShadowInput { cos_v: 0.5, cos_l: Some(x), cos_h: 0.9, cos_vh: 0.7 }),
                ],
                Model::Fresnel(f) => vec![f.f(x)],
                Model::Env(e) => vec![e.e(x, 0.3), e.e(0.5, x), e.e(x, x)],
                Model::Brdf(b) => vec![
                    b.eval([x, v[1], v[2]], [v[0], v[1], 1.0]),
                    b.eval([0.0, 0.0, 0.0], [v[0], v[1], 1.0]),
                    b.eval([v[0], v[1], -v[2].abs()], [0.1, 0.2, 0.9]),
                    b.eval([0.1, 0.2, 0.9], [v[0], v[1], -v[2].abs() - 1e-9]),
                    b.eval([x, x, x], [x, x, x]),
                ],
            };
            for val in vals {
                prop_assert!(val.is_finite() && val >= 0.0, "{} {:?} x={} v={:?}: {}", info.id, params, x, v, val);
            }
        }
        let m32 = build::<f32>(info.id, &given).unwrap();
        if let Model::Brdf(b) = &m32 {
            let w = [x as f32, v[1] as f32, v[2] as f32];
            let val = b.eval(w, [0.0, 0.0, 1.0]);
            prop_assert!(val.is_finite() && val >= 0.0);
        }
    }

    /// Invalid parameter values are an error, never a panic or a model.
    #[test]
    fn invalid_parameters_are_errors((info, params) in any_model(), bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(-1.0), Just(0.0), Just(1e9), Just(-1e-300)]) {
        for p in info.params {
            if let ParamKind::Number { min, max, .. } = p.kind {
                if bad >= min && bad <= max { continue; }
                let mut given = params.clone();
                given.retain(|(k, _)| k != p.name);
                given.push((p.name.to_string(), bad.to_string()));
                let r = build::<f32>(info.id, &as_refs(&given));
                prop_assert!(r.is_err(), "{} {}={} was accepted", info.id, p.name, bad);
            }
        }
    }
}

#[test]
fn brdfs_are_reciprocal() {
    let pairs = direction_pairs(200, 21);
    for e in registry::all()
        .iter()
        .filter(|e| e.info.kind == fastbrdf::Kind::Brdf)
    {
        for cfg in configs(&e.info, true) {
            let Model::Brdf(b) = cfg.model::<f64>().unwrap() else {
                panic!()
            };
            if !b.reciprocal() {
                // The documented exceptions: Filament's energy compensation uses wo only, and
                // gltf-pbr's clearcoat weighs the coat by the Fresnel of N . V
                // (KHR_materials_clearcoat's fresnel_coat).
                let coated = e.info.id == "gltf-pbr"
                    && !matches!(cfg.get("clearcoat"), Some(Given::Num(x)) if *x == 0.0);
                assert!(
                    cfg.get("ms") == Some(&Given::Choice("filament".into())) || coated,
                    "{} {cfg:?} claims not to be reciprocal",
                    e.info.id
                );
                continue;
            }
            let Model::Brdf(b32) = cfg.model::<f32>().unwrap() else {
                panic!()
            };
            for (wi, wo) in &pairs {
                let (a, r) = (b.eval(*wi, *wo), b.eval(*wo, *wi));
                // Pair::new is symmetric in (wi, wo) to the last bit, so equality is exact.
                assert_eq!(
                    a.to_bits(),
                    r.to_bits(),
                    "{} {cfg:?}: f(wi, wo) = {a}, f(wo, wi) = {r}",
                    e.info.id
                );
                let (i32, o32) = (wi.map(|x| x as f32), wo.map(|x| x as f32));
                let (a, r) = (b32.eval(i32, o32), b32.eval(o32, i32));
                assert_eq!(
                    a.to_bits(),
                    r.to_bits(),
                    "{} {cfg:?} f32: {a} vs {r}",
                    e.info.id
                );
            }
        }
    }
}

#[test]
fn unknown_ids_and_params_are_errors() {
    assert!(matches!(
        build::<f32>("phong-fast", &[]),
        Err(fastbrdf::Error::UnknownModel(_))
    ));
    assert!(matches!(
        build::<f32>("pow", &[("m", "3")]),
        Err(fastbrdf::Error::UnknownParam { .. })
    ));
    assert!(matches!(
        build::<f32>("pow", &[("n", "abc")]),
        Err(fastbrdf::Error::InvalidParam { .. })
    ));
    assert!(matches!(
        build::<f32>("pow", &[("n", "2"), ("n", "3")]),
        Err(fastbrdf::Error::InvalidParam { .. })
    ));
    assert!(matches!(
        build::<f32>("cook-torrance", &[("d", "trowbridge-reitz")]),
        Err(fastbrdf::Error::InvalidParam { .. })
    ));
    assert!(matches!(
        build::<f32>("ward", &[("alpha_x", "0.2")]),
        Err(fastbrdf::Error::MissingParam { .. })
    ));
    let e = build::<f32>("beckmann", &[("alpha", "0")]).err().unwrap();
    assert_eq!(
        e.to_string(),
        "model 'beckmann': parameter alpha = 0 is invalid: expected a number in [0.005, 1]"
    );
}

#[test]
fn strict_evaluation_rejects_out_of_domain_rows() {
    let m = build::<f64>("pow", &[]).unwrap();
    assert!(m.try_eval_row(&[Some(0.5)]).is_ok());
    for bad in [f64::NAN, -0.1, 1.5, f64::INFINITY] {
        assert!(m.try_eval_row(&[Some(bad)]).is_err(), "{bad}");
    }
    let b = build::<f64>("ward", &[]).unwrap();
    let row = |v: [f64; 6]| v.map(Some);
    assert!(b.try_eval_row(&row([0.0, 0.0, 1.0, 0.3, 0.0, 0.9])).is_ok());
    assert!(
        b.try_eval_row(&row([0.0, 0.0, 0.0, 0.3, 0.0, 0.9]))
            .unwrap_err()
            .to_string()
            .contains("zero-length")
    );
    assert!(
        b.try_eval_row(&row([0.0, 0.2, -1.0, 0.3, 0.0, 0.9]))
            .unwrap_err()
            .to_string()
            .contains("below the horizon")
    );
}

/// issue 14: anisotropic `cook-torrance` with differing slopes (the configuration lists give
/// equal ones) is reciprocal to the last bit in both precisions (the stretched cosines enter
/// G symmetrically) and finite and non-negative.
#[test]
fn anisotropic_cook_torrance_is_reciprocal_and_finite() {
    let pairs = direction_pairs(200, 22);
    for &d in fastbrdf::brdf::cook_torrance::ANISO_D {
        for &g in fastbrdf::brdf::cook_torrance::ANISO_G {
            for (ax, ay) in [("0.005", "1"), ("1", "0.005"), ("0.02", "0.5")] {
                let given = [
                    ("d", d),
                    ("g", g),
                    ("f", "schlick"),
                    ("alpha_x", ax),
                    ("alpha_y", ay),
                ];
                let Model::Brdf(b) = build::<f64>("cook-torrance", &given).unwrap() else {
                    panic!()
                };
                let Model::Brdf(b32) = build::<f32>("cook-torrance", &given).unwrap() else {
                    panic!()
                };
                for (wi, wo) in &pairs {
                    let (a, r) = (b.eval(*wi, *wo), b.eval(*wo, *wi));
                    assert!(a.is_finite() && a >= 0.0, "{given:?}: {a}");
                    assert_eq!(a.to_bits(), r.to_bits(), "{given:?}: {a} vs {r}");
                    let (i32, o32) = (wi.map(|x| x as f32), wo.map(|x| x as f32));
                    let (a, r) = (b32.eval(i32, o32), b32.eval(o32, i32));
                    assert!(a.is_finite() && a >= 0.0, "{given:?}: {a}");
                    assert_eq!(a.to_bits(), r.to_bits(), "{given:?} f32: {a} vs {r}");
                }
            }
        }
    }
}
