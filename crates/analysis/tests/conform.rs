//! `conform` (issue 31): every built-in BRDF passes; each deliberately broken BSDF (a
//! `UserBrdf` wrapper around a built-in) fails exactly the check it breaks.

use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, SampleBatch, UserBrdf};
use fastbrdf::{Kind, ModelSpec, registry};
use fastbrdf_analysis::conform::{self, CHECKS, Config, Status};

fn builtin(id: &str, p: &[(&str, &str)]) -> Builtin {
    Builtin::new(&ModelSpec::parse(id, p).unwrap(), Strategy::Auto).unwrap()
}

fn quiet(_: &str) {}

/// Every registry BRDF at its defaults and cook-torrance with each distribution, each by its
/// default strategy, and a few harder cases.
fn builtins() -> Vec<Builtin> {
    let mut out: Vec<Builtin> = registry::ids_of(Kind::Brdf)
        .into_iter()
        .map(|id| builtin(id, &[]))
        .collect();
    for d in registry::ids_of(Kind::Distribution) {
        out.push(builtin("cook-torrance", &[("d", d)]));
    }
    // Narrow and wide lobes, anisotropy, an energy compensation, three channels.
    let ct = "cook-torrance";
    out.push(builtin(ct, &[("d", "ggx"), ("alpha", "0.005")]));
    out.push(builtin(ct, &[("d", "beckmann"), ("alpha", "0.01")]));
    out.push(builtin(ct, &[("d", "ggx"), ("alpha", "1")]));
    out.push(builtin(
        ct,
        &[
            ("d", "ggx"),
            ("g", "smith-ggx-correlated"),
            ("ms", "kulla-conty"),
        ],
    ));
    out.push(builtin(
        ct,
        &[("d", "ggx"), ("f0", "0.9,0.6,0.2"), ("f", "schlick")],
    ));
    out.push(builtin("ward", &[("alpha_x", "0.1"), ("alpha_y", "0.4")]));
    out.push(builtin("phong", &[("n", "1000")]));
    out
}

#[test]
fn every_builtin_brdf_conforms() {
    let cfg = Config::ci();
    let mut failures = vec![];
    for b in builtins() {
        let t = std::time::Instant::now();
        let r = conform::run(&b, None, &cfg, &quiet).unwrap();
        eprintln!(
            "{} [{}]: {} in {:.1} s",
            r.model,
            b.strategy().name(),
            if r.passed { "pass" } else { "FAIL" },
            t.elapsed().as_secs_f64()
        );
        assert_eq!(
            r.checks.iter().map(|c| c.check).collect::<Vec<_>>(),
            CHECKS.to_vec()
        );
        for c in &r.checks {
            let skipped = c.check == "reference";
            assert_eq!(c.status == Status::Skip, skipped, "{}: {c:?}", r.model);
            if c.status == Status::Fail {
                failures.push(format!("{} {}: {}", r.model, c.check, c.summary));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// How a [`Broken`] model breaks its base (lambert, albedo 1, cosine-sampled).
#[derive(Clone, Copy, Debug)]
enum Break {
    /// pdf and reported pdf both 1.05 times the true one, the weight consistent with them.
    PdfLarge,
    /// The weight is f / pdf, without the cosine.
    WeightNoCos,
    /// f depends on wi only: (1 + z_i) / (2 pi) above the horizon.
    WiOnly,
    /// f = 1.2 / pi: albedo 1.2.
    Gain,
    /// NaN when either direction is exactly on the horizon.
    NanGrazing,
    /// f = (1 - 2 (wi . wo)^8) / pi: negative near wi = wo.
    Negative,
    /// Samples only theta_i < 60 degrees (renormalised): pdf 0 where f is not.
    Partial,
}

struct Broken {
    base: Builtin,
    how: Break,
}

impl Broken {
    fn new(how: Break) -> Self {
        Self {
            base: builtin("lambert", &[("albedo", "1")]),
            how,
        }
    }

    fn f(&self, wi: [f64; 3], wo: [f64; 3], base: f64) -> f64 {
        match self.how {
            Break::Gain => 1.2 * base,
            // base > 0 only above the horizon: z_i in (0, 1] there (inf read as 1).
            Break::WiOnly if base > 0.0 => base * (1.0 + wi[2].min(1.0)) / 2.0,
            Break::NanGrazing if wi[2] == 0.0 || wo[2] == 0.0 => f64::NAN,
            Break::Negative => {
                let d = wi[0] * wo[0] + wi[1] * wo[1] + wi[2] * wo[2];
                if base > 0.0 {
                    base * (1.0 - 2.0 * d.powi(8))
                } else {
                    0.0
                }
            }
            _ => base,
        }
    }
}

/// sin^2 of 60 degrees: `Partial` samples sin^2 theta in [0, 0.75).
const PARTIAL: f64 = 0.75;

impl UserBrdf for Broken {
    fn name(&self) -> String {
        format!("broken {:?}", self.how)
    }
    fn channels(&self) -> usize {
        1
    }
    fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        self.base.eval(wi, wo, out)?;
        for k in 0..out.len() {
            out[k] = self.f(wi[k], wo[k], out[k]);
        }
        Ok(())
    }
    fn samples(&self) -> bool {
        true
    }
    fn sample(&self, wo: &[[f64; 3]], u: &[[f64; 2]]) -> Result<SampleBatch, String> {
        let u2: Vec<[f64; 2]> = match self.how {
            Break::Partial => u.iter().map(|x| [x[0] * PARTIAL, x[1]]).collect(),
            _ => u.to_vec(),
        };
        let mut s = self.base.sample(wo, &u2)?;
        let mut f = vec![0.0; wo.len()];
        self.eval(&s.wi, wo, &mut f)?;
        for (k, fk) in f.iter().enumerate() {
            if !s.valid[k] {
                continue;
            }
            s.pdf[k] *= match self.how {
                Break::PdfLarge => 1.05,
                Break::Partial => 1.0 / PARTIAL,
                _ => 1.0,
            };
            let cos = match self.how {
                Break::WeightNoCos => 1.0,
                _ => s.wi[k][2].max(0.0),
            };
            s.weight[k] = fk * cos / s.pdf[k];
        }
        Ok(s)
    }
    fn pdf(&self, wo: &[[f64; 3]], wi: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        self.base.pdf(wo, wi, out)?;
        for k in 0..out.len() {
            out[k] *= match self.how {
                Break::PdfLarge => 1.05,
                Break::Partial => {
                    let z =
                        wi[k][2] / (wi[k][0].powi(2) + wi[k][1].powi(2) + wi[k][2].powi(2)).sqrt();
                    if 1.0 - z * z < PARTIAL {
                        1.0 / PARTIAL
                    } else {
                        0.0
                    }
                }
                _ => 1.0,
            };
        }
        Ok(())
    }
}

#[test]
fn each_broken_bsdf_fails_exactly_the_check_it_breaks() {
    let cfg = Config::ci();
    let cases = [
        (Break::PdfLarge, vec!["pdf-integral"]),
        (Break::WeightNoCos, vec!["weight"]),
        (Break::WiOnly, vec!["reciprocity"]),
        (Break::Gain, vec!["energy"]),
        (Break::NanGrazing, vec!["finite"]),
        (Break::Negative, vec!["non-negative"]),
        (Break::Partial, vec!["pdf-coverage"]),
    ];
    let mut wrong = vec![];
    for (how, want) in cases {
        let t = std::time::Instant::now();
        let r = conform::run(&Broken::new(how), None, &cfg, &quiet).unwrap();
        eprintln!(
            "{how:?}: {:?} in {:.1} s",
            r.failed(),
            t.elapsed().as_secs_f64()
        );
        if r.failed() != want {
            wrong.push(format!(
                "{how:?}: failed {:?}, expected {want:?}: {:#?}",
                r.failed(),
                r.checks
            ));
        }
        assert!(!r.passed);
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// A built-in that is non-reciprocal by design (ms = filament compensates with `wo` only)
/// fails `reciprocity`, also at an alpha where its asymmetry is a few percent.
#[test]
fn a_non_reciprocal_builtin_fails_reciprocity() {
    let cfg = Config {
        sample_angles_deg: vec![45.0],
        ..Config::ci()
    };
    for alpha in ["0.01", "0.3"] {
        let m = builtin(
            "cook-torrance",
            &[
                ("d", "ggx"),
                ("g", "smith-ggx-correlated"),
                ("ms", "filament"),
                ("alpha", alpha),
            ],
        );
        let r = conform::run(&m, None, &cfg, &quiet).unwrap();
        let c = r.checks.iter().find(|c| c.check == "reciprocity").unwrap();
        assert_eq!(c.status, Status::Fail, "{alpha}: {c:?}");
        assert!(c.value > 5e-3 && c.at.is_some(), "{alpha}: {c:?}");
    }
}

#[test]
fn a_reference_is_compared_and_the_report_serialises() {
    let cfg = Config {
        sample_angles_deg: vec![45.0],
        ..Config::ci()
    };
    let m = builtin("cook-torrance", &[("d", "ggx"), ("alpha", "0.3")]);
    let same = conform::run(&m, Some(&m), &cfg, &quiet).unwrap();
    let c = same.checks.iter().find(|c| c.check == "reference").unwrap();
    assert_eq!(c.status, Status::Pass, "{c:?}");
    assert_eq!(c.value, 0.0);
    let other = builtin("cook-torrance", &[("d", "ggx"), ("alpha", "0.32")]);
    let diff = conform::run(&m, Some(&other), &cfg, &quiet).unwrap();
    let c = diff.checks.iter().find(|c| c.check == "reference").unwrap();
    assert_eq!(c.status, Status::Fail, "{c:?}");
    assert!(c.value > 1e-3 && c.summary.contains("RMS"), "{c:?}");
    assert_eq!(diff.failed(), vec!["reference"]);

    // JSON: the record's fields; a non-finite number is null.
    let v = serde_json::to_value(&diff).unwrap();
    assert_eq!(v["mode"], "ci");
    assert_eq!(v["passed"], false);
    let checks = v["checks"].as_array().unwrap();
    assert_eq!(checks.len(), CHECKS.len());
    let r = &checks[5];
    assert_eq!(r["check"], "reference");
    assert_eq!(r["status"], "fail");
    assert_eq!(r["at"]["wi"].as_array().unwrap().len(), 3);
    assert!(r["value"].as_f64().unwrap() > 1e-3);
    let skip = conform::run(&m, None, &cfg, &quiet).unwrap();
    let v = serde_json::to_value(&skip).unwrap();
    assert_eq!(v["checks"][5]["status"], "skip");
    assert!(v["checks"][5]["value"].is_null());
    assert_eq!(v["checks"][4]["check"], "energy");
    assert!(v["checks"][4]["at"]["theta_o_deg"].is_number());
}

/// A model whose evaluator fails: `run` returns its message.
struct Failing;

impl UserBrdf for Failing {
    fn name(&self) -> String {
        "failing".into()
    }
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, _: &[[f64; 3]], _: &[[f64; 3]], _: &mut [f64]) -> Result<(), String> {
        Err("shader exploded".into())
    }
}

#[test]
fn an_evaluator_error_is_the_result_and_progress_names_the_checks() {
    let e = conform::run(&Failing, None, &Config::ci(), &quiet).unwrap_err();
    assert!(
        e.contains("shader exploded") && e.contains("failing"),
        "{e}"
    );
    let seen = std::sync::Mutex::new(vec![]);
    let m = builtin("lambert", &[]);
    let r = conform::run(&m, None, &Config::ci(), &|s: &str| {
        seen.lock().unwrap().push(s.to_string())
    })
    .unwrap();
    assert!(r.passed, "{:?}", r.failed());
    let seen = seen.into_inner().unwrap();
    for c in CHECKS.iter().filter(|c| **c != "reference") {
        assert!(seen.iter().any(|s| s == c), "{c}: {seen:?}");
    }
}

/// The batched albedo resolves narrow lobes: GGX and Beckmann at alpha = 0.01 (and a wide
/// one) at normal to grazing incidence, against the adaptive nested Gauss-Kronrod of
/// `fastbrdf albedo` (`analysis::albedo::curve`, to 1e-7): within 1e-5, ten times inside `energy_rel`.
#[test]
fn the_albedo_resolves_narrow_lobes() {
    let cfg = Config::ci();
    for (d, a) in [("ggx", "0.01"), ("beckmann", "0.01"), ("ggx", "0.5")] {
        let spec = ModelSpec::parse("cook-torrance", &[("d", d), ("alpha", a)]).unwrap();
        let m = Builtin::new(&spec, Strategy::Auto).unwrap();
        let t = fastbrdf_analysis::albedo::target(&spec, "phong", "energy").unwrap();
        let angles = [0.0, 45.0, 80.0, 89.0];
        let want = fastbrdf_analysis::albedo::curve(&t, &angles, 1e-7).unwrap();
        for (deg, w) in angles.iter().zip(want) {
            let (got, settled) = conform::albedo(&m, *deg, &cfg).unwrap();
            assert!(settled, "{d} {a} at {deg}");
            let e = (got[0] - w.albedo).abs();
            assert!(
                e <= 1e-5 * w.albedo,
                "{d} {a} at {deg}: {} vs {}",
                got[0],
                w.albedo
            );
        }
    }
}
