//! Sampling (issue 15): for every BRDF id (every lobe through `phong` and `blinn-phong`, every
//! distribution through `cook-torrance`), narrow and wide parameters, incidences 0, 45 and 80
//! degrees and every strategy the model offers:
//! - chi-square goodness of fit of `sample` against `pdf` (f64, and the f32 sampler at 45
//!   degrees), Bonferroni-corrected 0.01, fixed seeds (`chi2::Config::ci`: 10 x 20 bins,
//!   1e5 samples; `FASTBRDF_FULL=1`: Mitsuba's 101 x 202 bins and 1e6 samples);
//! - the pdf integrates (adaptive quadrature) to 1 minus the missing mass the sampler shows;
//! - sample/pdf consistency (the returned pdf is `pdf(wo, wi)`, the weight `f cos / pdf`);
//! - the Monte Carlo albedo (mean weight) within 3 standard errors of `quad::albedo`.

use fastbrdf::chi2::{self, Config};
use fastbrdf::sample::{Rng, Strategy};
mod common;

use common::build;
use fastbrdf::{Brdf, Kind, Model, quad, registry};
use rayon::prelude::*;

#[derive(Clone, Debug)]
struct Case {
    id: &'static str,
    params: Vec<(String, String)>,
}

impl Case {
    fn new(id: &'static str, p: &[(&str, &str)]) -> Self {
        Self {
            id,
            params: p
                .iter()
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .collect(),
        }
    }
    fn refs(&self) -> Vec<(&str, &str)> {
        self.params
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect()
    }
    fn build<T: fastbrdf::Real>(&self) -> Box<dyn Brdf<T>> {
        match build::<T>(self.id, &self.refs()).unwrap() {
            Model::Brdf(b) => b,
            _ => panic!("{} is not a BRDF", self.id),
        }
    }
    fn name(&self) -> String {
        let p: Vec<String> = self
            .params
            .iter()
            .map(|(a, b)| format!("{a}={b}"))
            .collect();
        format!("{} {}", self.id, p.join(" "))
    }
}

fn full() -> bool {
    std::env::var("FASTBRDF_FULL").is_ok_and(|v| v == "1")
}

/// Every lobe at n = 20 through both lobe BRDFs, narrow (n = 1000) and wide (n = 1)
/// closed-form and twin lobes; every distribution at alpha = 0.3 through Cook-Torrance,
/// narrow (0.05), wide (1), anisotropic, energy-compensated and with Fresnel; Ward's three
/// forms narrow, wide and anisotropic; Lambert.
fn cases() -> Vec<Case> {
    let mut out = vec![Case::new("lambert", &[("albedo", "0.7")])];
    for brdf in ["phong", "blinn-phong"] {
        for lobe in registry::ids_of(Kind::Lobe) {
            out.push(Case::new(brdf, &[("lobe", lobe), ("n", "20")]));
        }
        for (lobe, n) in [
            ("pow", "1000"),
            ("pow", "1"),
            ("power16", "1000"),
            ("power4", "1"),
            ("sg", "1000"),
            ("schlick", "1000"),
        ] {
            out.push(Case::new(brdf, &[("lobe", lobe), ("n", n)]));
        }
    }
    out.push(Case::new(
        "blinn-phong",
        &[("lobe", "pow"), ("n", "50"), ("norm", "none")],
    ));
    for d in registry::ids_of(Kind::Distribution) {
        out.push(Case::new("cook-torrance", &[("d", d), ("alpha", "0.3")]));
    }
    for d in ["ggx", "beckmann", "beckmann-pow", "beckmann-power16"] {
        for a in ["0.05", "1"] {
            out.push(Case::new("cook-torrance", &[("d", d), ("alpha", a)]));
        }
    }
    out.push(Case::new(
        "cook-torrance",
        &[
            ("d", "ggx"),
            ("g", "smith-ggx"),
            ("alpha_x", "0.1"),
            ("alpha_y", "0.4"),
        ],
    ));
    out.push(Case::new(
        "cook-torrance",
        &[("d", "beckmann"), ("alpha_x", "0.4"), ("alpha_y", "0.1")],
    ));
    out.push(Case::new(
        "cook-torrance",
        &[
            ("d", "ggx"),
            ("g", "smith-ggx-correlated"),
            ("ms", "kulla-conty"),
            ("alpha", "0.5"),
        ],
    ));
    out.push(Case::new(
        "cook-torrance",
        &[("d", "ggx"), ("f", "schlick"), ("alpha", "0.2")],
    ));
    for a in ["0.3", "0.05", "1"] {
        out.push(Case::new("ward", &[("alpha", a)]));
        out.push(Case::new("ward-pow", &[("alpha", a)]));
    }
    out.push(Case::new("ward", &[("alpha_x", "0.1"), ("alpha_y", "0.4")]));
    // gltf-pbr: a mixture of the base's and the coat's visible normals and the cosine lobe.
    out.push(Case::new("gltf-pbr", &[("roughness", "0.5")]));
    out.push(Case::new(
        "gltf-pbr",
        &[
            ("metallic", "0.2"),
            ("roughness", "0.3"),
            ("clearcoat", "0.7"),
            ("clearcoat_roughness", "0.1"),
            ("sheen_color", "0.5"),
            ("sheen_roughness", "0.4"),
            ("anisotropy", "0.6"),
            ("anisotropy_rotation", "0.7"),
        ],
    ));
    out.push(Case::new("ward-power16", &[("alpha", "0.3")]));
    out.push(Case::new("ward-power16", &[("alpha", "0.05")]));
    out
}

const ANGLES: [f64; 3] = [0.0, 45.0, 80.0];

/// `wo` at `theta` degrees, azimuth 0.5 rad (off the anisotropic axes).
fn wo_at(theta: f64) -> [f64; 3] {
    let t = theta.to_radians();
    [t.sin() * 0.5f64.cos(), t.sin() * 0.5f64.sin(), t.cos()]
}

/// The (case, strategy) runs: every strategy of every case, `cosine` only on the first case
/// of each id (the same sampler for every model).
fn runs() -> Vec<(Case, Strategy)> {
    let mut seen = std::collections::HashSet::new();
    let mut out = vec![];
    for c in cases() {
        let b = c.build::<f64>();
        let first = seen.insert(c.id);
        for &s in b.strategies() {
            if s != Strategy::Cosine || first {
                out.push((c.clone(), s));
            }
        }
    }
    out
}

#[test]
fn every_brdf_lobe_and_distribution_is_sampled() {
    let cs = cases();
    for id in registry::ids_of(Kind::Brdf) {
        assert!(cs.iter().any(|c| c.id == id), "no sampling case for {id}");
        // Every BRDF samples by a strategy of its own besides `cosine`, and refuses the rest.
        let b = Case::new(id, &[]).build::<f64>();
        let all = b.strategies();
        assert!(all.len() >= 2 || id == "lambert", "{id}: {all:?}");
        for s in Strategy::ALL {
            assert_eq!(
                b.resolve(s).is_ok(),
                s == Strategy::Auto || all.contains(&s),
                "{id} {s}"
            );
        }
    }
    let has = |brdf: &str, key: &str, v: &str| {
        cs.iter()
            .any(|c| c.id == brdf && c.params.iter().any(|(a, b)| a == key && b == v))
    };
    for lobe in registry::ids_of(Kind::Lobe) {
        assert!(
            has("phong", "lobe", lobe) && has("blinn-phong", "lobe", lobe),
            "{lobe}"
        );
    }
    for d in registry::ids_of(Kind::Distribution) {
        assert!(has("cook-torrance", "d", d), "{d}");
    }
}

#[test]
fn chi_square_goodness_of_fit() {
    let cfg = if full() { Config::full() } else { Config::ci() };
    let runs = runs();
    // f64 at every angle, f32 at 45 degrees.
    let mut jobs = vec![];
    for (i, (c, s)) in runs.iter().enumerate() {
        for theta in ANGLES {
            jobs.push((c, *s, theta, false, i as u64));
        }
        jobs.push((c, *s, 45.0, true, i as u64));
    }
    let tests = jobs.len();
    let failures: Vec<String> = jobs
        .par_iter()
        .filter_map(|&(c, s, theta, f32, seed)| {
            let b64 = c.build::<f64>();
            let b32 = c.build::<f32>();
            let wo = wo_at(theta);
            let cfg = Config {
                seed: cfg.seed ^ (seed << 8) ^ theta as u64,
                ..cfg
            };
            let out = chi2::run_brdf(
                b64.as_ref(),
                f32.then_some(b32.as_ref()),
                wo,
                s,
                &cfg,
                tests,
            );
            (!out.passed).then(|| {
                format!(
                    "{} [{s}] theta={theta} f32={f32}: p={:.3e} chi2={:.1} dof={} integral={:.6} missing {}/{:.1}",
                    c.name(),
                    out.p_value,
                    out.chi2,
                    out.dof,
                    out.pdf_integral,
                    out.missing_observed,
                    out.missing_expected
                )
            })
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {tests} chi-square tests failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The pdf integrates (nested adaptive quadrature around the mirror direction) to the
/// fraction of draws that give a sample: 1 where nothing is lost.
#[test]
fn pdf_integrates_to_one_minus_the_missing_mass() {
    let n = 100_000;
    let failures: Vec<String> = runs()
        .par_iter()
        .flat_map_iter(|(c, s)| ANGLES.iter().map(move |&t| (c, *s, t)))
        .filter_map(|(c, s, theta)| {
            let b = c.build::<f64>();
            let wo = wo_at(theta);
            let (integral, err) = quad::albedo(
                |wi| {
                    if wi[2] > 0.0 {
                        b.pdf(wo, wi, s) / wi[2]
                    } else {
                        0.0
                    }
                },
                [-wo[0], -wo[1], wo[2]],
                &[],
                1e-7,
            );
            let mut rng = Rng::new(99 + theta as u64);
            let hits = (0..n)
                .filter(|_| b.sample(wo, rng.pair(), s).is_some())
                .count() as f64;
            let p = hits / n as f64;
            // At least one draw's worth of variance, so p = 1 still allows the rare miss.
            let se = ((p * (1.0 - p)).max(1.0 / n as f64) / n as f64).sqrt();
            let ok = (integral - p).abs() <= 4.0 * se + 1e-5 + err && integral <= 1.0 + 1e-5;
            (!ok).then(|| {
                format!(
                    "{} [{s}] theta={theta}: integral {integral} +- {err}, sampled fraction {p} +- {se}",
                    c.name()
                )
            })
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn sample_and_pdf_agree_in_both_precisions() {
    for (c, s) in runs() {
        let b64 = c.build::<f64>();
        let b32 = c.build::<f32>();
        for theta in ANGLES {
            let wo = wo_at(theta);
            let wo32 = wo.map(|x| x as f32);
            let mut rng = Rng::new(5);
            for _ in 0..300 {
                let u = rng.pair();
                if let Some(x) = b64.sample(wo, u, s) {
                    let p = b64.pdf(wo, x.wi, s);
                    assert!(
                        (x.pdf - p).abs() <= 1e-9 * p,
                        "{} [{s}] {theta}: {} vs {p}",
                        c.name(),
                        x.pdf
                    );
                    let len = x.wi.iter().map(|v| v * v).sum::<f64>().sqrt();
                    assert!((len - 1.0).abs() < 1e-12 && x.wi[2] > 0.0);
                    let f = b64.eval(x.wi, wo) * x.wi[2];
                    assert!(
                        (x.weight * x.pdf - f).abs() <= 1e-9 * f.max(1e-300),
                        "{} [{s}]: weight",
                        c.name()
                    );
                }
                // f32: the same formula in single precision; its pdf is the f64 one at the
                // f32 direction to f32 accuracy (narrow lobes amplify a rounded cosine by n).
                if let Some(x) = b32.sample(wo32, [u[0] as f32, u[1] as f32], s) {
                    let p = b64.pdf(wo32.map(f64::from), x.wi.map(f64::from), s);
                    assert!(
                        (f64::from(x.pdf) - p).abs() <= 2e-3 * p,
                        "{} [{s}] {theta} f32: {} vs {p}",
                        c.name(),
                        x.pdf
                    );
                    // pdf() normalises the (unit) wi again: an f32 rounding, times the lobe's
                    // slope (n <= 1000 here; steepest near a power-g cut).
                    let p32 = b32.pdf(wo32, x.wi, s);
                    assert!(
                        (x.pdf - p32).abs() <= 2e-3 * p32,
                        "{} [{s}] {theta} f32: {} vs pdf {p32}",
                        c.name(),
                        x.pdf
                    );
                    assert!(x.weight.is_finite() && x.weight >= 0.0);
                }
            }
        }
    }
}

/// The mean weight is the directional albedo seen from `wo`: within 3 standard errors (plus
/// the quadrature's own error) of `quad::albedo`.
#[test]
fn monte_carlo_albedo_matches_quadrature() {
    let n = 100_000;
    let failures: Vec<String> = runs()
        .par_iter()
        .flat_map_iter(|(c, s)| [0.0, 45.0].into_iter().map(move |t| (c, *s, t)))
        .filter_map(|(c, s, theta)| {
            let b = c.build::<f64>();
            let wo = wo_at(theta);
            let (a, err) = quad::albedo(
                |wi| b.eval(wi, wo),
                [-wo[0], -wo[1], wo[2]],
                &b.mirror_breaks(),
                1e-7,
            );
            let mut rng = Rng::new(1234 + theta as u64);
            let (mut sum, mut sum2) = (0.0, 0.0);
            for _ in 0..n {
                let w = b.sample(wo, rng.pair(), s).map_or(0.0, |x| x.weight);
                sum += w;
                sum2 += w * w;
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
            let ok = (mean - a).abs() <= 3.0 * se + err + 1e-9;
            (!ok).then(|| {
                format!(
                    "{} [{s}] theta={theta}: MC {mean} +- {se}, quadrature {a} +- {err}",
                    c.name()
                )
            })
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn invalid_strategies_are_refused_by_name() {
    let b = Case::new("lambert", &[]).build::<f64>();
    let e = b.resolve(Strategy::Vndf).unwrap_err();
    assert!(e.contains("vndf") && e.contains("cosine"), "{e}");
    assert!(
        b.sample([0.0, 0.0, 1.0], [0.5, 0.5], Strategy::Vndf)
            .is_none()
    );
    assert_eq!(b.pdf([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], Strategy::Vndf), 0.0);
    let ct = Case::new("cook-torrance", &[("d", "beckmann-power8")]).build::<f64>();
    assert!(ct.resolve(Strategy::Vndf).is_err() && ct.resolve(Strategy::Twin).is_ok());
    // Out of the domain: no sample.
    let g = Case::new("cook-torrance", &[("d", "ggx")]).build::<f64>();
    assert!(
        g.sample([0.0, 0.0, -1.0], [0.5, 0.5], Strategy::Auto)
            .is_none()
    );
    assert!(
        g.sample([0.0, 0.0, 0.0], [0.5, 0.5], Strategy::Auto)
            .is_none()
    );
}
