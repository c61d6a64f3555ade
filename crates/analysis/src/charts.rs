//! The data of `fastbrdf plot` and of the seeds' figures: every chart's series computed from
//! the models, ready for [`crate::plot::render`]. Nothing here draws or writes.

use crate::plot::{Chart, Series};
use crate::{albedo, errors, normalize, range};
use fastbrdf::{Given, Lobe, Model, ModelSpec, Zone, registry};
use std::fmt;

/// Why a chart cannot be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum ChartError {
    /// A model id, parameter or value the registry refuses.
    Model(fastbrdf::Error),
    /// A model of the wrong kind: `'{id}' is a {kind}, not a lobe`.
    NotALobe { id: String, kind: &'static str },
    /// The polar chart needs a full BRDF.
    NotABrdf { id: String, kind: &'static str },
    /// The polar chart's incidence angle (degrees) is outside [0, 90).
    IncidenceAngle(f64),
    /// The closed form has more constants than the values of n fit it
    /// ([`normalize::Form::check_points`]'s message).
    TooFewPoints(String),
}

impl fmt::Display for ChartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChartError::Model(e) => e.fmt(f),
            ChartError::NotALobe { id, kind } => write!(f, "'{id}' is a {kind}, not a lobe"),
            ChartError::NotABrdf { id, kind } => {
                write!(f, "polar needs a BRDF; '{id}' is a {kind}")
            }
            ChartError::IncidenceAngle(t) => {
                write!(f, "incidence angle {t} is outside [0, 90) degrees")
            }
            ChartError::TooFewPoints(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for ChartError {}

impl From<fastbrdf::Error> for ChartError {
    fn from(e: fastbrdf::Error) -> Self {
        ChartError::Model(e)
    }
}

/// The lobe `id` at exponent `n`, in f64; an error when `id` is not a lobe or refuses `n`.
pub fn lobe(id: &str, n: f64) -> Result<Box<dyn Lobe<f64>>, ChartError> {
    let not_a_lobe = |kind: fastbrdf::Kind| ChartError::NotALobe {
        id: id.into(),
        kind: kind.name(),
    };
    let kind = registry::find(id)?.info.kind;
    if kind != fastbrdf::Kind::Lobe {
        return Err(not_a_lobe(kind));
    }
    match ModelSpec::new(id, &[("n", Given::Num(n))])?.model::<f64>()? {
        Model::Lobe(l) => Ok(l),
        m => Err(not_a_lobe(m.kind())),
    }
}

/// Checks that every lobe of `ids` builds at both ends of `ns`: before a sweep over them
/// ([`max_error`], [`coef`]), for the lobe's own message rather than the sweep's.
pub fn check_lobes<'a>(
    ids: impl IntoIterator<Item = &'a str>,
    ns: &[f64],
) -> Result<(), ChartError> {
    for id in ids {
        for n in [ns[0], ns[ns.len() - 1]] {
            lobe(id, n)?;
        }
    }
    Ok(())
}

/// Angles (degrees) over which a lobe of exponent n is visible: 601 values from 0 to where
/// c^n ~ 1e-4 (at most 90).
pub fn angles(n: f64) -> Vec<f64> {
    let top = (1.0 - 9.2 / n).max(0.0).acos().to_degrees().min(90.0);
    (0..=600).map(|i| top * f64::from(i) / 600.0).collect()
}

/// Lobe curves of several models against the angle from the peak, at one n.
pub fn lobes(models: &[String], n: f64) -> Result<Chart, ChartError> {
    let xs = angles(n);
    let mut series = vec![];
    for id in models {
        let l = lobe(id, n)?;
        series.push(Series::new(
            id.clone(),
            xs.iter()
                .map(|&d| (d, l.eval(d.to_radians().cos())))
                .collect(),
        ));
    }
    Ok(Chart {
        title: format!("Lobes at n = {n}"),
        x_label: "angle from the peak (degrees)".into(),
        y_label: "lobe value".into(),
        series,
        log_y: false,
        log_x: false,
        equal_aspect: false,
    })
}

/// The signed error `model - reference` against the angle from the peak, at one n.
pub fn signed_error(model: &str, reference: &str, n: f64) -> Result<Chart, ChartError> {
    let (m, r) = (lobe(model, n)?, lobe(reference, n)?);
    let xs = angles(n);
    Ok(Chart {
        title: format!("{model} - {reference} at n = {n}"),
        x_label: "angle from the peak (degrees)".into(),
        y_label: "signed error".into(),
        series: vec![Series::new(
            format!("{model} - {reference}"),
            xs.iter()
                .map(|&d| {
                    (
                        d,
                        m.eval(d.to_radians().cos()) - r.eval(d.to_radians().cos()),
                    )
                })
                .collect(),
        )],
        log_y: false,
        log_x: false,
        equal_aspect: false,
    })
}

/// Max error (relative when `rel`, else absolute) in `zone` against `n`, one series per lobe
/// of `models`, against `reference`, on a log y axis. `progress` is called once per
/// (model, n).
pub fn max_error(
    models: &[String],
    reference: &str,
    ns: &[f64],
    rel: bool,
    zone: Zone,
    title: &str,
    progress: &(dyn Fn() + Sync),
) -> Result<Chart, ChartError> {
    let mut series = vec![];
    for id in models {
        let spec = errors::Spec {
            model: id.clone(),
            reference: reference.into(),
            param: "n".into(),
            zone,
        };
        let rows = errors::sweep(&spec, ns, progress)?;
        series.push(Series::new(
            id.clone(),
            rows.iter()
                .map(|r| (r.param, if rel { r.max_rel } else { r.max_abs }))
                .collect(),
        ));
    }
    Ok(Chart {
        title: title.into(),
        x_label: "n".into(),
        y_label: if rel {
            "max relative error".into()
        } else {
            "max absolute error".into()
        },
        series,
        log_y: true,
        // Sweeps beyond n = 1000 (to the domain's 1e5) on a log axis; the seeds' figures stop
        // at 1000 and keep their linear axis.
        log_x: ns.first().is_some_and(|&a| a > 0.0)
            && ns.iter().copied().fold(0.0, f64::max) > 1000.0,
        equal_aspect: false,
    })
}

/// coef(n) of a lobe by quadrature with the closed form `form` fitted to it, and the energy
/// residual `|coef_fit(n) 2 pi Int(n) - 1|` of that fit (log y).
pub fn coef(model: &str, ns: &[f64], form: normalize::Form) -> Result<(Chart, Chart), ChartError> {
    form.check_points(ns.len())
        .map_err(ChartError::TooFewPoints)?;
    let rows = normalize::table(model, ns)?;
    let f = normalize::fit(form, &rows);
    let k: Vec<f64> = f.constants.iter().map(|(_, v)| *v).collect();
    let eval = |n: f64| {
        if k.len() == 2 {
            k[0] * (n + k[1])
        } else {
            k[0] * (n + k[1]) + k[2] / (k[3] + n)
        }
    };
    let consts: Vec<String> = f
        .constants
        .iter()
        .map(|(n, v)| format!("{n}={v:.4}"))
        .collect();
    let coef = Chart {
        title: format!("coef(n) of {model} and the fit {}", f.form),
        x_label: "n".into(),
        y_label: "coef(n) = 1 / (2 pi Int(n))".into(),
        series: vec![
            Series::new("integrated", rows.iter().map(|r| (r.n, r.coef)).collect()),
            Series::new(
                format!("fit {}", consts.join(" ")),
                rows.iter().map(|r| (r.n, eval(r.n))).collect(),
            ),
        ],
        log_y: false,
        log_x: false,
        equal_aspect: false,
    };
    let residual = Chart {
        title: format!("Energy residual |coef_fit(n) 2 pi Int(n) - 1| of {model}"),
        x_label: "n".into(),
        y_label: "|coef_fit 2 pi Int - 1|".into(),
        series: vec![Series::new(
            format!("fit {}", f.form),
            rows.iter()
                .map(|r| (r.n, (eval(r.n) / r.coef - 1.0).abs()))
                .collect(),
        )],
        log_y: true,
        log_x: false,
        equal_aspect: false,
    };
    Ok((coef, residual))
}

/// A BRDF in the plane of incidence as a polar lobe: `f(wi, wo) cos theta_o` along `wo` for
/// theta_o in [-90, 90] degrees (1801 points, the mirror side at x < 0), and the incident
/// direction (on the opposite side) at the lobe's peak length. `theta_i` in degrees, [0, 90).
/// A grey BRDF (a coloured spec is an error naming its R,G,B parameters).
pub fn polar(spec: &ModelSpec, theta_i: f64) -> Result<Chart, ChartError> {
    if spec.kind() != fastbrdf::Kind::Brdf {
        return Err(ChartError::NotABrdf {
            id: spec.id().into(),
            kind: spec.kind().name(),
        });
    }
    let Model::Brdf(b) = spec.model::<f64>()? else {
        unreachable!("a BRDF's model is a BRDF")
    };
    if !(0.0..90.0).contains(&theta_i) {
        return Err(ChartError::IncidenceAngle(theta_i));
    }
    let ti = theta_i.to_radians();
    // wi in +x; the mirror direction is -x (wo = (-sin ti, 0, cos ti)), drawn at x < 0.
    let wi = [ti.sin(), 0.0, ti.cos()];
    let pts: Vec<(f64, f64)> = (0..=1800)
        .map(|i| {
            let t = (-90.0 + 180.0 * f64::from(i) / 1800.0).to_radians();
            let wo = [t.sin(), 0.0, t.cos()];
            let v = b.eval(wi, wo) * t.cos();
            (v * t.sin(), v * t.cos())
        })
        .collect();
    let peak = pts
        .iter()
        .map(|(x, y)| x.hypot(*y))
        .fold(0.0, f64::max)
        .max(1e-12);
    Ok(Chart {
        title: format!(
            "{} {} in the plane of incidence, theta_i = {theta_i} deg",
            spec.id(),
            crate::check::fmt_params(spec)
        ),
        x_label: "f cos theta_o along wo (x)".into(),
        y_label: "(z)".into(),
        series: vec![
            Series::new("f(wi, wo) cos theta_o", pts),
            Series::new(
                "incident direction",
                vec![(0.0, 0.0), (peak * wi[0], peak * wi[2])],
            ),
        ],
        log_y: false,
        log_x: false,
        equal_aspect: true,
    })
}

/// Directional albedo against the incidence angle (0 to 88 degrees in steps of 2), with the
/// white-furnace line at 1. A lobe is evaluated as an energy-normalised Phong BRDF.
pub fn albedo(spec: &ModelSpec) -> Result<Chart, ChartError> {
    let t = albedo::target(spec, "phong", "energy")?;
    let angles = range::parse("0..88:2", 1.0).expect("valid range");
    let rows = albedo::curve(&t, &angles, 1e-6)?;
    Ok(Chart {
        title: format!(
            "Directional albedo of {} {}",
            t.id(),
            crate::check::fmt_params(&t.spec)
        ),
        x_label: "incidence angle (degrees)".into(),
        y_label: "albedo".into(),
        series: vec![
            Series::new(
                "albedo",
                rows.iter().map(|r| (r.theta_deg, r.albedo)).collect(),
            ),
            Series::new("1 (white furnace)", vec![(0.0, 1.0), (88.0, 1.0)]),
        ],
        log_y: false,
        log_x: false,
        equal_aspect: false,
    })
}

/// One max-error figure of the seeds: its lobes, first n (the sweep runs to 1000), relative or
/// absolute, zone and title; all against `pow`.
struct SeedSweep {
    models: &'static [&'static str],
    first_n: &'static str,
    rel: bool,
    zone: Zone,
    title: &'static str,
}

/// The seeds' max-error figures, in the order [`seed_figures`] returns them.
const SEED_SWEEPS: [SeedSweep; 3] = [
    SeedSweep {
        models: &["flog", "schlick"],
        first_n: "1",
        rel: true,
        zone: Zone::Epicentre,
        title: "Seed 001 Fig. 3: max relative error in the epicentre",
    },
    SeedSweep {
        models: &["flog", "schlick"],
        first_n: "1",
        rel: false,
        zone: Zone::All,
        title: "Seed 001 Fig. 4: max absolute error",
    },
    SeedSweep {
        models: &["cubic", "cubic3", "schlick"],
        first_n: "4",
        rel: false,
        zone: Zone::Epicentre,
        title: "Seed 003 Fig. 1: max absolute error in the epicentre",
    },
];

impl SeedSweep {
    fn ns(&self) -> Vec<f64> {
        range::parse(&format!("{}..1000", self.first_n), 1.0).expect("valid range")
    }

    fn chart(&self, progress: &(dyn Fn() + Sync)) -> Result<Chart, ChartError> {
        let models: Vec<String> = self.models.iter().map(|m| m.to_string()).collect();
        max_error(
            &models,
            "pow",
            &self.ns(),
            self.rel,
            self.zone,
            self.title,
            progress,
        )
    }
}

/// How many times [`seed_figures`] calls its `progress`: once per (lobe, n) of its sweeps.
pub fn seed_figure_steps() -> usize {
    SEED_SWEEPS
        .iter()
        .map(|s| s.models.len() * s.ns().len())
        .sum()
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

/// The charts of the seeds' figures, with their file stems. `progress` is called
/// [`seed_figure_steps`] times.
pub fn seed_figures(
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<(&'static str, Chart)>, ChartError> {
    let mut out = vec![(
        "seed001-fig2-lobes-n20",
        lobes(&strings(&["pow", "flog", "schlick"]), 20.0)?,
    )];
    out.push((
        "seed001-fig3-max-rel-epicentre",
        SEED_SWEEPS[0].chart(progress)?,
    ));
    out.push(("seed001-fig4-max-abs", SEED_SWEEPS[1].chart(progress)?));
    let ns = range::parse("1..1000", 1.0).expect("valid range");
    let (_, residual) = coef("flog", &ns, normalize::Form::SeedPublished)?;
    out.push(("seed001-fig9-energy-residual", residual));
    out.push((
        "seed003-fig1-cubic-epicentre",
        SEED_SWEEPS[2].chart(progress)?,
    ));
    out.push((
        "seed003-fig3-lobes-n20",
        lobes(
            &strings(&["pow", "schlick", "rational", "cubic-rational"]),
            20.0,
        )?,
    ));
    let (forms, rel) = beckmann_forms(0.3)?;
    out.push(("seed000-fig1-3-beckmann-forms", forms));
    out.push(("seed000-fig2-4-relative-error", rel));
    Ok(out)
}

/// Seed 000 Fig. 1-4: Beckmann (Cook-Torrance form) and its one-function forms at slope `m`
/// against theta_h in [0, 50] degrees (501 points), and each form's relative error against
/// `beckmann-ct` (log y).
pub fn beckmann_forms(m: f64) -> Result<(Chart, Chart), ChartError> {
    let distribution =
        |id: &str| match ModelSpec::new(id, &[("alpha", Given::Num(m))])?.model::<f64>()? {
            Model::Distribution(d) => Ok(d),
            other => Err(ChartError::Model(fastbrdf::Error::WrongKind {
                model: id.into(),
                expected: fastbrdf::Kind::Distribution.name().into(),
                found: other.kind().name().into(),
            })),
        };
    let exact = distribution("beckmann-ct")?;
    let mut series = vec![];
    let mut rel = vec![];
    for id in [
        "beckmann-ct",
        "beckmann-pow",
        "beckmann-power4",
        "beckmann-power8",
        "beckmann-power16",
    ] {
        let d = distribution(id)?;
        let pts: Vec<(f64, f64)> = (0..=500)
            .map(|i| 50.0 * f64::from(i) / 500.0)
            .map(|deg| (deg, d.eval(deg.to_radians().cos())))
            .collect();
        if id != "beckmann-ct" {
            rel.push(Series::new(
                id,
                pts.iter()
                    .map(|&(deg, v)| (deg, (v / exact.eval(deg.to_radians().cos()) - 1.0).abs()))
                    .collect(),
            ));
        }
        series.push(Series::new(id, pts));
    }
    let chart = |title: String, y: &str, series: Vec<Series>, log_y| Chart {
        title,
        x_label: "theta_h (degrees)".into(),
        y_label: y.into(),
        series,
        log_y,
        log_x: false,
        equal_aspect: false,
    };
    Ok((
        chart(
            format!("Seed 000 Fig. 1 and 3: D and its one-function forms, m = {m}"),
            "D",
            series,
            false,
        ),
        chart(
            format!("Seed 000 Fig. 2 and 4: relative error against beckmann-ct, m = {m}"),
            "|D / D_exact - 1|",
            rel,
            true,
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(id: &str, v: &[(&str, &str)]) -> ModelSpec {
        ModelSpec::parse(id, v).unwrap()
    }

    /// Issue 11: the incident direction was drawn on the mirror side, on top of the lobe. It
    /// must lie on the opposite side of the normal (x = 0) from the specular peak.
    #[test]
    fn polar_incident_direction_is_opposite_the_specular_peak() {
        for (model, params, theta_i) in [
            ("cook-torrance", vec![("alpha", "0.2")], 45.0),
            ("ward", vec![("alpha", "0.3")], 30.0),
            ("cook-torrance", vec![("alpha", "0.5")], 70.0),
        ] {
            let c = polar(&spec(model, &params), theta_i).unwrap();
            let lobe = &c.series[0].points;
            assert_eq!(lobe.len(), 1801);
            let peak = lobe
                .iter()
                .copied()
                .max_by(|a, b| a.0.hypot(a.1).total_cmp(&b.0.hypot(b.1)))
                .unwrap();
            let incident = c
                .series
                .iter()
                .find(|s| s.name.contains("incident"))
                .unwrap();
            let tip = incident.points[1];
            assert!(
                peak.0 < 0.0,
                "{model}: the peak {peak:?} is on the mirror side"
            );
            assert!(
                tip.0 > 0.0 && tip.0 * peak.0 < 0.0,
                "{model}: incident {tip:?} vs peak {peak:?}"
            );
            // The drawn direction is wi itself: its angle from the normal is theta_i, and its
            // length the lobe's peak length.
            let angle = tip.0.atan2(tip.1).to_degrees();
            assert!((angle - theta_i).abs() < 1e-9, "{angle}");
            let len = tip.0.hypot(tip.1);
            assert!((len - peak.0.hypot(peak.1)).abs() < 1e-12 * len);
        }
    }

    #[test]
    fn polar_refuses_lobes_and_grazing_incidence() {
        assert_eq!(
            polar(&spec("flog", &[]), 30.0).unwrap_err().to_string(),
            "polar needs a BRDF; 'flog' is a lobe"
        );
        for t in [90.0, -1.0, f64::NAN] {
            assert!(matches!(
                polar(&spec("ward", &[]), t),
                Err(ChartError::IncidenceAngle(_))
            ));
        }
    }

    #[test]
    fn angles_span_the_visible_lobe() {
        // n = 20: up to acos(1 - 9.2 / 20), where cos^20 is about 1e-4 of the peak.
        let a = angles(20.0);
        assert_eq!(a.len(), 601);
        assert_eq!(a[0], 0.0);
        let top = (1.0f64 - 9.2 / 20.0).acos().to_degrees();
        assert!((a[600] - top).abs() < 1e-12);
        assert!(a.windows(2).all(|w| w[1] > w[0]));
        assert!(20.0 * a[600].to_radians().cos().ln() < -8.0);
        // Broad lobes stop at the horizon.
        assert_eq!(*angles(2.0).last().unwrap(), 90.0);
    }

    #[test]
    fn lobes_are_one_at_the_peak_and_fall_off() {
        let c = lobes(&["pow".into(), "flog".into(), "schlick".into()], 20.0).unwrap();
        assert_eq!(c.series.len(), 3);
        assert_eq!(c.title, "Lobes at n = 20");
        for s in &c.series {
            assert_eq!(s.points.len(), 601);
            assert!((s.points[0].1 - 1.0).abs() < 1e-12, "{}", s.name);
            assert!(s.points[600].1 < 0.1, "{}", s.name);
            assert!(s.points.windows(2).all(|w| w[1].1 <= w[0].1), "{}", s.name);
        }
        // pow is cos^n exactly.
        for &(d, v) in &c.series[0].points {
            assert!((v - d.to_radians().cos().powi(20)).abs() < 1e-12);
        }
        assert_eq!(
            lobes(&["beckmann".into()], 20.0).unwrap_err().to_string(),
            "'beckmann' is a distribution, not a lobe"
        );
    }

    #[test]
    fn signed_error_is_model_minus_reference() {
        let c = signed_error("pow", "pow", 50.0).unwrap();
        assert!(c.series[0].points.iter().all(|p| p.1 == 0.0));
        let c = signed_error("schlick", "pow", 50.0).unwrap();
        let (m, r) = (lobe("schlick", 50.0).unwrap(), lobe("pow", 50.0).unwrap());
        for &(d, e) in c.series[0].points.iter().step_by(37) {
            let x = d.to_radians().cos();
            assert_eq!(e, m.eval(x) - r.eval(x));
        }
        assert!(c.series[0].points.iter().any(|p| p.1 != 0.0));
    }

    #[test]
    fn max_error_follows_the_sweep_and_counts_progress() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let ns = [8.0, 50.0, 200.0];
        let calls = AtomicUsize::new(0);
        let models = ["flog".to_string(), "schlick".to_string()];
        let c = max_error(&models, "pow", &ns, false, Zone::All, "t", &|| {
            calls.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(calls.load(Ordering::Relaxed), 6);
        assert!(c.log_y);
        assert_eq!(c.y_label, "max absolute error");
        for (s, id) in c.series.iter().zip(&models) {
            let spec = errors::Spec {
                model: id.clone(),
                reference: "pow".into(),
                param: "n".into(),
                zone: Zone::All,
            };
            let xs: Vec<f64> = s.points.iter().map(|p| p.0).collect();
            assert_eq!(xs, ns);
            for &(n, e) in &s.points {
                assert_eq!(e, errors::at(&spec, n).unwrap().max_abs);
                assert!(e > 0.0 && e < 1.0);
            }
        }
        assert!(check_lobes(["flog", "pow"], &ns).is_ok());
        assert!(check_lobes(["beckmann"], &ns).is_err());
    }

    #[test]
    fn coef_fit_follows_the_integral() {
        let ns: Vec<f64> = (1..=40).map(f64::from).collect();
        let (c, r) = coef("pow", &ns, normalize::Form::Linear).unwrap();
        // coef(n) of cos^n is (n + 2) / (2 pi): the linear fit a (n + b) finds it.
        let integrated = &c.series[0].points;
        for &(n, v) in integrated {
            let exact = (n + 2.0) / std::f64::consts::TAU;
            assert!((v - exact).abs() < 1e-9 * exact, "n = {n}: {v}");
        }
        assert!(r.log_y);
        assert!(r.series[0].points.iter().all(|p| p.1 < 1e-6), "{r:?}");
        let few = coef("flog", &ns[..3], normalize::Form::Seed).unwrap_err();
        assert!(matches!(few, ChartError::TooFewPoints(_)));
    }

    #[test]
    fn albedo_stays_under_the_furnace_line() {
        let c = albedo(&spec("ward", &[("alpha", "0.5")])).unwrap();
        let pts = &c.series[0].points;
        assert_eq!(pts.len(), 45);
        assert_eq!((pts[0].0, pts[44].0), (0.0, 88.0));
        assert!(
            pts.iter().all(|p| p.1 > 0.0 && p.1 <= 1.0 + 1e-6),
            "{pts:?}"
        );
        assert_eq!(c.series[1].points, vec![(0.0, 1.0), (88.0, 1.0)]);
    }

    #[test]
    fn beckmann_forms_approach_the_exact_distribution() {
        let (forms, rel) = beckmann_forms(0.3).unwrap();
        assert_eq!(forms.series.len(), 5);
        assert_eq!(rel.series.len(), 4);
        // Cook-Torrance's Beckmann peaks at 1 / (4 m^2), and every form matches it there.
        let peak = 1.0 / (4.0 * 0.09);
        for s in &forms.series {
            assert_eq!(s.points.len(), 501);
            assert!((s.points[0].1 - peak).abs() < 1e-9 * peak, "{}", s.name);
        }
        // Each relative-error curve is |D_form / D_exact - 1| of the curves drawn above, and
        // every form stays within 10% of the exact D up to 20 degrees from the peak.
        for (r, f) in rel.series.iter().zip(&forms.series[1..]) {
            assert_eq!(r.name, f.name);
            for ((&(x, e), &(_, v)), &(_, d)) in
                r.points.iter().zip(&f.points).zip(&forms.series[0].points)
            {
                assert_eq!(e, (v / d - 1.0).abs());
                assert!(x > 20.0 || e < 0.1, "{} at {x}: {e}", r.name);
            }
        }
    }

    #[test]
    fn seed_figures_count_their_progress() {
        // The sweep sizes: two lobes over n = 1..1000 twice, three over n = 4..1000.
        assert_eq!(seed_figure_steps(), 2 * 1000 + 2 * 1000 + 3 * 997);
    }
}
