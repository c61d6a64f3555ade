//! Fits to synthetic MERL data tabulated from known models (no real MERL file is reachable
//! from the test machines): the fit must recover the parameters it was made from, and a wrong
//! model must leave a larger residual.

use fastbrdf::measured::{MeasuredBrdf, from_half_diff, merl_bytes};
use fastbrdf::{Model, ModelSpec};
use fastbrdf_analysis::materials;
use fastbrdf_analysis::measured_fit::{Data, Metric, Options, Problem, fit};
use std::f64::consts::PI;
use std::path::Path;

/// A MERL table of `kd / pi + ks * model(params)` at the bin centres.
fn synthetic(id: &str, params: &[(&str, &str)], kd: [f64; 3], ks: [f64; 3]) -> MeasuredBrdf {
    let Model::Brdf(b) = ModelSpec::parse(id, params)
        .unwrap()
        .model::<f64>()
        .unwrap()
    else {
        panic!("a BRDF")
    };
    let bytes = merl_bytes(|th, td, pd| {
        let (wi, wo) = from_half_diff(th, td, pd);
        if wi[2] <= 0.0 || wo[2] <= 0.0 {
            return [-1.0; 3];
        }
        let s = b.eval(wi, wo);
        [0, 1, 2].map(|c| kd[c] / PI + ks[c] * s)
    });
    MeasuredBrdf::from_reader(&bytes[..], Path::new("synthetic.binary")).unwrap()
}

fn spec(id: &str, given: &[(&str, &str)]) -> ModelSpec {
    ModelSpec::parse(id, given).unwrap()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

/// Ward at the Ngan et al. 2005 fit of blue-rubber (alpha 0.289, its kd and ks): ngan-l2 and
/// low-log both recover alpha and the six albedos within 1 %, with a residual near 0; the
/// Blinn-Phong fit of the same data leaves a residual at least 10 times larger.
#[test]
fn ward_fit_recovers_the_ward_it_was_made_from() {
    let m = materials::find("blue-rubber").unwrap();
    let alpha = m.ward_alpha;
    let (kd, ks) = (m.ward.kd, m.ward.ks);
    let b = synthetic("ward", &[("alpha", &alpha.to_string())], kd, ks);
    let data = Data::from_measured(&b, 1500);
    assert_eq!(data.len(), 1500);
    assert!(data.eligible > 100_000, "{}", data.eligible);
    let problem = Problem::new(&spec("ward", &[]), true).unwrap();
    assert_eq!(
        problem.free.iter().map(|f| f.name).collect::<Vec<_>>(),
        ["alpha"]
    );
    let opts = Options {
        restarts: 3,
        ..Options::default()
    };
    let l2 = fit(&problem, &data, &opts, &|_, _| {}).unwrap();
    assert!(
        close(l2.values[0], alpha, 0.01),
        "alpha {} vs {alpha}",
        l2.values[0]
    );
    for c in 0..3 {
        assert!(
            close(l2.rho_d[c], kd[c], 0.01),
            "kd {:?} vs {kd:?}",
            l2.rho_d
        );
        assert!(
            close(l2.rho_s[c], ks[c], 0.01),
            "ks {:?} vs {ks:?}",
            l2.rho_s
        );
    }
    assert!(l2.residuals.ngan_l2 < 1e-4, "{:?}", l2.residuals);
    let log = fit(
        &problem,
        &data,
        &Options {
            metric: Metric::LowLog,
            ..opts
        },
        &|_, _| {},
    )
    .unwrap();
    assert!(close(log.values[0], alpha, 0.01), "{}", log.values[0]);
    assert!(log.residuals.low_log <= l2.residuals.low_log * 1.0001);
    // A wrong model cannot match: its best residual is much larger.
    let wrong = Problem::new(&spec("blinn-phong", &[]), true).unwrap();
    let w = fit(&wrong, &data, &opts, &|_, _| {}).unwrap();
    assert!(
        w.residuals.ngan_l2 > 10.0 * l2.residuals.ngan_l2.max(1e-6),
        "{:?} vs {:?}",
        w.residuals,
        l2.residuals
    );
    // Deterministic: the same fit twice gives the same numbers.
    let again = fit(&problem, &data, &opts, &|_, _| {}).unwrap();
    assert_eq!(again.values, l2.values);
}

/// Cook-Torrance with f = schlick fixed and f90 fixed: alpha and f0 are fitted (f0 traded
/// against rho_s only through the Fresnel curve's shape), recovered within 2 %.
#[test]
fn cook_torrance_fit_with_fixed_choices() {
    let m = materials::find("black-oxidized-steel").unwrap();
    let (alpha, f0) = (m.cook_torrance_m, 0.3);
    let params = [("f", "schlick"), ("f90", "1")];
    let mut given: Vec<(&str, String)> = params.iter().map(|(a, b)| (*a, b.to_string())).collect();
    given.push(("alpha", alpha.to_string()));
    given.push(("f0", f0.to_string()));
    let g: Vec<(&str, &str)> = given.iter().map(|(a, b)| (*a, b.as_str())).collect();
    let b = synthetic("cook-torrance", &g, [0.05, 0.04, 0.03], [1.0, 0.8, 0.6]);
    let data = Data::from_measured(&b, 1500);
    let problem = Problem::new(&spec("cook-torrance", &params), true).unwrap();
    let names: Vec<&str> = problem.free.iter().map(|f| f.name).collect();
    assert_eq!(names, ["alpha", "f0"]);
    let r = fit(&problem, &data, &Options::default(), &|_, _| {}).unwrap();
    assert!(close(r.values[0], alpha, 0.02), "{:?} vs {alpha}", r.values);
    assert!(close(r.values[1], f0, 0.02), "{:?} vs {f0}", r.values);
    assert!(r.residuals.ngan_l2 < 1e-4, "{:?}", r.residuals);
}

#[test]
fn only_brdfs_are_fitted() {
    let e = Problem::new(&spec("flog", &[]), true).unwrap_err();
    assert!(e.contains("BRDF"), "{e}");
    // An invalid value is refused where the text is parsed, once, naming it.
    let e = ModelSpec::parse("ward", &[("alpha", "7")]).unwrap_err();
    assert!(e.to_string().contains("alpha"), "{e}");
}
