//! Analysis correctness: quadrature against closed forms, sweeps against known maxima, the
//! refinement beating the grid, fits recovering known constants, and albedo verdicts.

use fastbrdf::accuracy::{self, golden_max};
use fastbrdf::{ErrorBound, Metric, Zone};
use fastbrdf_analysis::errors::{self, Spec};
use fastbrdf_analysis::{albedo, normalize, reproduce};

#[test]
fn quadrature_matches_pow_closed_form() {
    for n in [1.0, 1.5, 2.0, 7.0, 20.0, 100.0, 333.0, 1000.0, 10000.0] {
        let (int, err) = normalize::integral("pow", n).unwrap();
        let exact = 1.0 / (n + 2.0);
        assert!(
            ((int - exact) / exact).abs() < 1e-10,
            "n={n}: {int} vs {exact}"
        );
        assert!(err < 1e-10 * exact, "n={n}: error estimate {err}");
    }
}

#[test]
fn beckmann_normalisation_to_1e8() {
    for i in 1..=20 {
        let a = 0.05 * f64::from(i);
        let fastbrdf::Model::Distribution(d) =
            fastbrdf::ModelSpec::new("beckmann", &[("alpha", fastbrdf::Given::Num(a))])
                .and_then(|s| s.model::<f64>())
                .unwrap()
        else {
            panic!()
        };
        let breaks: Vec<f64> = [0.5, 1.0, 2.0, 4.0]
            .iter()
            .map(|k| 1.0 / (1.0 + (k * a) * (k * a)).sqrt())
            .collect();
        let (v, _) = fastbrdf::quad::integrate(|c| d.eval(c) * c, 0.0, 1.0, &breaks, 1e-12);
        assert!(
            (2.0 * std::f64::consts::PI * v - 1.0).abs() < 1e-8,
            "alpha={a}"
        );
    }
}

#[test]
fn sweeps_find_known_maxima() {
    // schlick is exactly c at n = 1, like pow.
    let s = Spec {
        model: "schlick".into(),
        reference: "pow".into(),
        param: "n".into(),
        zone: Zone::All,
    };
    let r = errors::at(&s, 1.0).unwrap();
    assert!(r.max_abs < 1e-15 && r.rms < 1e-15, "{r:?}");
    // power16 is exactly c^16 at n = 16.
    let s = Spec {
        model: "power16".into(),
        reference: "pow".into(),
        param: "n".into(),
        zone: Zone::All,
    };
    assert!(errors::at(&s, 16.0).unwrap().max_abs < 1e-14);
    // flog's max abs error is exactly 1/8, at c = 2^(-3/n), for every n.
    let s = Spec {
        model: "flog".into(),
        reference: "pow".into(),
        param: "n".into(),
        zone: Zone::All,
    };
    for n in [1.0, 10.0, 77.0, 1000.0] {
        let r = errors::at(&s, n).unwrap();
        assert!((r.max_abs - 0.125).abs() < 1e-9, "n={n}: {r:?}");
        assert!(
            (r.max_abs_at - (-3.0 / n).exp2()).abs() < 1e-9,
            "n={n}: {r:?}"
        );
    }
    // Zones: the rational lobe has value 0.5 and the slope of pow at q; its band error is
    // small and grows away from q.
    let s = Spec {
        model: "rational".into(),
        reference: "pow".into(),
        param: "n".into(),
        zone: Zone::Band { lo: 0.42, hi: 0.5 },
    };
    let near = errors::at(&s, 20.0).unwrap();
    let s2 = Spec {
        zone: Zone::Band { lo: 0.27, hi: 0.37 },
        ..s
    };
    let far = errors::at(&s2, 20.0).unwrap();
    assert!(near.max_rel < far.max_rel && near.max_rel > 0.0);
}

#[test]
fn refinement_finds_a_maximum_the_grid_misses() {
    // flog against pow has its maximum at a corner (flog's zero), between grid nodes.
    let b = ErrorBound {
        reference: "pow",
        metric: Metric::MaxAbs,
        zone: Zone::All,
        param: ("n", 0.0, 0.0),
        bound: 0.0,
    };
    let mut misses = 0;
    for n in 100..=140 {
        let grid = accuracy::worst_at_grid("flog", &b, f64::from(n)).unwrap();
        let refined = accuracy::worst_at("flog", &b, f64::from(n)).unwrap();
        assert!(refined.err >= grid.err);
        assert!((refined.err - 0.125).abs() < 1e-9);
        if refined.err - grid.err > 1e-5 {
            misses += 1;
        }
    }
    assert!(
        misses > 20,
        "the grid alone should miss the corner for most n ({misses} of 41)"
    );
    // A narrow peak between two grid points: golden-section search finds its top.
    let f = |x: f64| (-((x - 0.3137) / 1e-3).powi(2)).exp();
    let grid_max = (0..=10).map(|i| f(i as f64 / 10.0)).fold(0.0, f64::max);
    let (x, v) = golden_max(&f, 0.3, 0.4, 100);
    assert!(grid_max < 1e-10 && (v - 1.0).abs() < 1e-12 && (x - 0.3137).abs() < 1e-7);
}

#[test]
fn fits_recover_known_constants_and_report_the_seed_residual() {
    // Synthetic coef(n) = 0.2 (n + 1.3) + 0.07 / (0.6 + n): the seed form must recover it.
    let rows: Vec<normalize::NormRow> = (1..=500)
        .map(|n| {
            let n = f64::from(n);
            let coef = 0.2 * (n + 1.3) + 0.07 / (0.6 + n);
            normalize::NormRow {
                n,
                int: 1.0 / (2.0 * std::f64::consts::PI * coef),
                coef,
                int_err: 0.0,
            }
        })
        .collect();
    let f = normalize::fit(normalize::Form::Seed, &rows);
    let k: Vec<f64> = f.constants.iter().map(|c| c.1).collect();
    assert!(
        (k[0] - 0.2).abs() < 1e-6
            && (k[1] - 1.3).abs() < 1e-4
            && (k[2] - 0.07).abs() < 1e-3
            && (k[3] - 0.6).abs() < 1e-2,
        "{k:?}"
    );
    assert!(f.max_rel < 1e-7);
    // flog: the seed's published constants leave an energy residual of 1.29e-3, all of it
    // from rounding a = 0.197254 to 0.197; our refit does far better.
    let rows = normalize::table("flog", &(1..=1000).map(f64::from).collect::<Vec<_>>()).unwrap();
    let published = normalize::fit(normalize::Form::SeedPublished, &rows);
    assert!(
        (published.energy_residual_max - 1.287e-3).abs() < 1e-5,
        "{}",
        published.energy_residual_max
    );
    let refit = normalize::fit(normalize::Form::Seed, &rows);
    assert!(
        refit.max_rel < published.max_rel / 5.0,
        "refit {} vs published {}",
        refit.max_rel,
        published.max_rel
    );
}

#[test]
fn albedo_verdicts() {
    let spec = |id: &str, given: &[(&str, &str)]| fastbrdf::ModelSpec::parse(id, given).unwrap();
    let ct = albedo::target(
        &spec("cook-torrance", &[("alpha", "0.3")]),
        "phong",
        "energy",
    )
    .unwrap();
    assert!(ct.claims_energy);
    let rows = albedo::curve(&ct, &[0.0, 45.0, 80.0], 1e-7).unwrap();
    assert!(albedo::furnace(&rows, 1e-6).0);
    let ward = albedo::target(&spec("ward", &[("alpha", "1")]), "phong", "energy").unwrap();
    let rows = albedo::curve(&ward, &[0.0, 89.9], 1e-7).unwrap();
    let (holds, worst) = albedo::furnace(&rows, 1e-6);
    assert!(!holds && worst.unwrap().theta_deg == 89.9);
    let lobe = albedo::target(&spec("cubic3", &[("n", "7")]), "phong", "energy").unwrap();
    assert_eq!(lobe.spec.to_string(), "phong lobe=cubic3 norm=energy n=7");
    let rows = albedo::curve(&lobe, &[0.0], 1e-9).unwrap();
    assert!((rows[0].albedo - 1.0).abs() < 1e-7, "{rows:?}");
    assert!(albedo::target(&spec("beckmann", &[]), "phong", "energy").is_err());
    // A coloured spec is integrated one channel at a time.
    let rgb = spec("cook-torrance", &[("f0", "0.2,0.4,0.6")]);
    assert!(albedo::target(&rgb, "phong", "energy").is_err());
    assert!(albedo::target(&rgb.channel_specs()[1], "phong", "energy").is_ok());
}

#[test]
fn exp_power16_rows_agree_with_an_independent_dense_scan() {
    for m in [0.2, 0.4, 0.6] {
        let (e, _) = reproduce::exp_vs_power16(m);
        let t_max = (m * m * 2f64.ln()).sqrt().atan();
        let s = 2.0 / (m * m) / 16.0;
        let dense = (0..=200_000)
            .map(|i| t_max * f64::from(i) / 200_000.0)
            .map(|t| {
                let ex = (-(t.tan() / m).powi(2)).exp();
                ((1.0 + s * (t.cos() - 1.0)).max(0.0).powi(16) - ex).abs() / ex
            })
            .fold(0.0, f64::max);
        assert!(
            e >= dense - 1e-9 && e - dense < 1e-6,
            "m={m}: {e} vs {dense}"
        );
    }
}
