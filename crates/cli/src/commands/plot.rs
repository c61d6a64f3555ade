//! `fastbrdf plot KIND`: charts as PNG and SVG (1200x800), and the seeds' figures for
//! `fastbrdf reproduce --out DIR`.

use super::analysis::bar;
use super::eval::parse_params;
use crate::CliError;
use fastbrdf::{Model, Zone, registry};
use fastbrdf_analysis::plot::{self as plots, Chart, Drawn, Series};
use fastbrdf_analysis::{albedo, errors, normalize, range};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf plot lobes --models pow,flog,schlick --n 20\n  \
fastbrdf plot error --model cubic --reference pow --n 200\n  \
fastbrdf plot max-error --models flog,schlick --reference pow --n 1..1000 --metric rel --zone epicentre\n  \
fastbrdf plot coef --model flog --n 1..1000 --fit seed\n  \
fastbrdf plot polar --model cook-torrance --param alpha=0.3 --theta-i 45\n  \
fastbrdf plot albedo --model ward --param alpha=0.5\n\n\
Output: OUT.png and OUT.svg (1200x800), written together or not at all (`coef` also writes\n\
OUT-residual.png and .svg). Every option is checked before anything is computed or written."
)]
pub struct Args {
    #[command(subcommand)]
    kind: Kind,
    /// Output path without extension (writes .png and .svg); default fastbrdf-out/plot-KIND.
    #[arg(long, global = true, value_name = "PATH")]
    out: Option<PathBuf>,
}

#[derive(clap::Subcommand)]
enum Kind {
    /// Lobe curves of several models against the angle, at one n (the seeds' figures).
    #[command(
        after_help = "Example:\n  fastbrdf plot lobes --models pow,flog,schlick --n 20 --out lobes"
    )]
    Lobes {
        /// Lobe ids, comma-separated (see `fastbrdf models --kind lobe`).
        #[arg(long, value_delimiter = ',', default_value = "pow,flog,schlick")]
        models: Vec<String>,
        /// The exponent n of every lobe (dimensionless, > 0).
        #[arg(long, default_value_t = 20.0)]
        n: f64,
    },
    /// Signed error (model - reference) against the angle, at one n.
    #[command(after_help = "Example:\n  fastbrdf plot error --model cubic --reference pow --n 200")]
    Error {
        /// The approximating lobe id.
        #[arg(long)]
        model: String,
        /// The reference lobe id (pow is cos^n).
        #[arg(long, default_value = "pow")]
        reference: String,
        /// The exponent n (dimensionless, > 0).
        #[arg(long, default_value_t = 20.0)]
        n: f64,
    },
    /// Max error against n for several lobes (log scale).
    #[command(
        after_help = "Example:\n  fastbrdf plot max-error --models flog,schlick --n 1..1000 --metric rel --zone epicentre"
    )]
    MaxError {
        /// Lobe ids, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "flog,schlick")]
        models: Vec<String>,
        /// The reference lobe id.
        #[arg(long, default_value = "pow")]
        reference: String,
        /// Exponents: LO..HI[:STEP] (step 1) or a list A,B,C; at most 1000000 values.
        #[arg(long, default_value = "1..1000")]
        n: String,
        /// abs: max |f - ref|; rel: max |f - ref| / ref.
        #[arg(long, default_value = "abs", value_parser = ["abs", "rel"])]
        metric: String,
        /// all: every cosine in [0, 1]; epicentre: where ref >= 0.5 of its peak.
        #[arg(long, default_value = "all", value_parser = ["all", "epicentre"])]
        zone: String,
    },
    /// coef(n) = 1 / (2 pi Int(n)) of a lobe, with a fitted closed form.
    #[command(
        after_help = "Example:\n  fastbrdf plot coef --model flog --n 1..1000 --fit seed --out coef"
    )]
    Coef {
        /// A lobe id.
        #[arg(long, default_value = "flog")]
        model: String,
        /// Exponents: LO..HI[:STEP] (step 1) or a list A,B,C; at most 1000000 values.
        #[arg(long, default_value = "1..1000")]
        n: String,
        /// The closed form: seed (a (n + b) + c / (d + n)), linear (a (n + b)) or
        /// seed-published (seed 001's printed constants).
        #[arg(long, default_value = "seed", value_parser = ["seed", "linear", "seed-published"])]
        fit: String,
    },
    /// A full BRDF in the plane of incidence, as a polar lobe (f cos theta_o along wo).
    #[command(
        after_help = "Example:\n  fastbrdf plot polar --model cook-torrance --param alpha=0.3 --theta-i 45\n\n\
The incident direction is drawn on the side opposite the mirror direction, at the lobe's peak length."
    )]
    Polar {
        /// A BRDF id (see `fastbrdf models --kind brdf`).
        #[arg(long)]
        model: String,
        /// A parameter of the model, NAME=VALUE; repeat for several.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Incidence angle from the normal, in degrees, in [0, 90).
        #[arg(long, default_value_t = 30.0)]
        theta_i: f64,
    },
    /// Directional albedo against the incidence angle.
    #[command(after_help = "Example:\n  fastbrdf plot albedo --model ward --param alpha=0.5")]
    Albedo {
        /// A BRDF id, or a lobe id (evaluated as an energy-normalised Phong BRDF).
        #[arg(long)]
        model: String,
        /// A parameter of the model, NAME=VALUE; repeat for several.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
    },
}

fn lobe(id: &str, n: f64) -> Result<Box<dyn fastbrdf::Lobe<f64>>, CliError> {
    let kind = registry::find(id)?.info.kind;
    if kind != fastbrdf::Kind::Lobe {
        return Err(CliError::input(format!(
            "'{id}' is a {}, not a lobe",
            kind.name()
        )));
    }
    match registry::build::<f64>(id, &[("n", &super::analysis::num(n))])? {
        Model::Lobe(l) => Ok(l),
        m => Err(CliError::input(format!(
            "'{id}' is a {}, not a lobe",
            m.kind().name()
        ))),
    }
}

/// Angles (degrees) over which a lobe of exponent n is visible: to where c^n ~ 1e-4.
fn angles(n: f64) -> Vec<f64> {
    let top = (1.0 - 9.2 / n).max(0.0).acos().to_degrees().min(90.0);
    (0..=600).map(|i| top * f64::from(i) / 600.0).collect()
}

fn lobes_chart(models: &[String], n: f64) -> Result<Chart, CliError> {
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
        equal_aspect: false,
    })
}

fn max_error_chart(
    models: &[String],
    reference: &str,
    ns: &[f64],
    rel: bool,
    zone: Zone,
    title: &str,
) -> Result<Chart, CliError> {
    let pb = bar((ns.len() * models.len()) as u64, "sweeping");
    let mut series = vec![];
    for id in models {
        let spec = errors::Spec {
            model: id.clone(),
            reference: reference.into(),
            param: "n".into(),
            zone,
        };
        let rows = errors::sweep(&spec, ns, &|| pb.inc(1))?;
        series.push(Series::new(
            id.clone(),
            rows.iter()
                .map(|r| (r.param, if rel { r.max_rel } else { r.max_abs }))
                .collect(),
        ));
    }
    pb.finish_and_clear();
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
        equal_aspect: false,
    })
}

fn coef_chart(model: &str, ns: &[f64], form: normalize::Form) -> Result<(Chart, Chart), CliError> {
    form.check_points(ns.len()).map_err(CliError::input)?;
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
        equal_aspect: false,
    };
    Ok((coef, residual))
}

fn polar_chart(model: &str, params: &[(String, String)], theta_i: f64) -> Result<Chart, CliError> {
    let given: Vec<(&str, &str)> = params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect();
    let b = match registry::build::<f64>(model, &given)? {
        Model::Brdf(b) => b,
        m => {
            return Err(CliError::input(format!(
                "polar needs a BRDF; '{model}' is a {}",
                m.kind().name()
            )));
        }
    };
    if !(0.0..90.0).contains(&theta_i) {
        return Err(CliError::input(format!(
            "--theta-i {theta_i} is outside [0, 90) degrees"
        )));
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
    let p: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    Ok(Chart {
        title: format!(
            "{model} {} in the plane of incidence, theta_i = {theta_i} deg",
            p.join(" ")
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
        equal_aspect: true,
    })
}

fn albedo_chart(model: &str, params: &[(String, String)]) -> Result<Chart, CliError> {
    let t = albedo::target(model, params, "phong", "energy")?;
    let angles = range::parse("0..88:2", 1.0).expect("valid range");
    let rows = albedo::curve(&t, &angles, 1e-6)?;
    let p: Vec<String> = t.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    Ok(Chart {
        title: format!("Directional albedo of {} {}", t.id, p.join(" ")),
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
        equal_aspect: false,
    })
}

/// A chart that could not be saved: an output failure (exit code 3).
pub fn save_error(e: plots::SaveError) -> CliError {
    match e {
        plots::SaveError::Io(e) => e.into(),
        plots::SaveError::Draw(_) => CliError::io(e.to_string()),
    }
}

/// Draws a chart in memory; a drawing failure means no output (exit code 3).
fn drawn(c: &Chart) -> Result<Drawn, CliError> {
    plots::render(c).map_err(|e| save_error(plots::SaveError::Draw(e)))
}

/// Writes every `(base, drawing)` as `base.png` and `base.svg`, all or nothing.
fn write_drawn(items: &[(PathBuf, Drawn)]) -> Result<(), CliError> {
    let refs: Vec<(&Path, &Drawn)> = items.iter().map(|(b, d)| (b.as_path(), d)).collect();
    for f in plots::write_all(&refs)? {
        eprintln!("wrote {}", f.display());
    }
    Ok(())
}

fn finite_n(n: f64) -> Result<f64, CliError> {
    if n.is_finite() && n > 0.0 {
        Ok(n)
    } else {
        Err(CliError::input(format!(
            "--n {n}: must be a positive finite number"
        )))
    }
}

pub fn run(a: &Args) -> Result<(), CliError> {
    let name = match &a.kind {
        Kind::Lobes { .. } => "lobes",
        Kind::Error { .. } => "error",
        Kind::MaxError { .. } => "max-error",
        Kind::Coef { .. } => "coef",
        Kind::Polar { .. } => "polar",
        Kind::Albedo { .. } => "albedo",
    };
    let base = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("fastbrdf-out/plot-{name}")));
    if base.file_name().is_none() {
        return Err(CliError::input(format!(
            "--out {}: expected a path without extension, e.g. out/plot",
            base.display()
        )));
    }
    // Every chart is computed and drawn in memory first; the files are written together.
    let charts: Vec<(PathBuf, Chart)> = match &a.kind {
        Kind::Lobes { models, n } => vec![(base, lobes_chart(models, finite_n(*n)?)?)],
        Kind::Error {
            model,
            reference,
            n,
        } => {
            let n = &finite_n(*n)?;
            let (m, r) = (lobe(model, *n)?, lobe(reference, *n)?);
            let xs = angles(*n);
            let c = Chart {
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
                equal_aspect: false,
            };
            vec![(base, c)]
        }
        Kind::MaxError {
            models,
            reference,
            n,
            metric,
            zone,
        } => {
            let ns = range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
            for id in models.iter().chain([reference]) {
                for n in [ns[0], ns[ns.len() - 1]] {
                    lobe(id, n)?;
                }
            }
            let zone = if zone == "epicentre" {
                Zone::Epicentre
            } else {
                Zone::All
            };
            let title = format!("Max {metric} error against {reference} ({zone:?})");
            vec![(
                base,
                max_error_chart(models, reference, &ns, metric == "rel", zone, &title)?,
            )]
        }
        Kind::Coef { model, n, fit } => {
            let ns = range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
            for n in [ns[0], ns[ns.len() - 1]] {
                lobe(model, n)?;
            }
            let form = normalize::Form::parse(fit).expect("clap checked the value");
            let (c, r) = coef_chart(model, &ns, form)?;
            let mut rb = base.clone().into_os_string();
            rb.push("-residual");
            vec![(base, c), (PathBuf::from(rb), r)]
        }
        Kind::Polar {
            model,
            params,
            theta_i,
        } => vec![(base, polar_chart(model, &parse_params(params)?, *theta_i)?)],
        Kind::Albedo { model, params } => {
            vec![(base, albedo_chart(model, &parse_params(params)?)?)]
        }
    };
    let items = charts
        .iter()
        .map(|(b, c)| Ok((b.clone(), drawn(c)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    write_drawn(&items)
}

/// Draws the plots of the seeds' figures and stages them (PNG and SVG) in `set`, in its
/// subfolder `folder` ("" for its top).
pub fn stage_seed_figures(set: &mut fastbrdf_io::OutputSet, folder: &str) -> Result<(), CliError> {
    for (stem, chart) in seed_figures()? {
        let name = Path::new(folder).join(stem);
        plots::stage(set, &drawn(&chart)?, &name.to_string_lossy())?;
    }
    Ok(())
}

/// The charts of the seeds' figures, with their file stems.
fn seed_figures() -> Result<Vec<(&'static str, Chart)>, CliError> {
    let mut out = vec![];
    let ns = range::parse("1..1000", 1.0).expect("valid range");
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    out.push((
        "seed001-fig2-lobes-n20",
        lobes_chart(&s(&["pow", "flog", "schlick"]), 20.0)?,
    ));
    out.push((
        "seed001-fig3-max-rel-epicentre",
        max_error_chart(
            &s(&["flog", "schlick"]),
            "pow",
            &ns,
            true,
            Zone::Epicentre,
            "Seed 001 Fig. 3: max relative error in the epicentre",
        )?,
    ));
    out.push((
        "seed001-fig4-max-abs",
        max_error_chart(
            &s(&["flog", "schlick"]),
            "pow",
            &ns,
            false,
            Zone::All,
            "Seed 001 Fig. 4: max absolute error",
        )?,
    ));
    let (_, residual) = coef_chart("flog", &ns, normalize::Form::SeedPublished)?;
    out.push(("seed001-fig9-energy-residual", residual));
    let n4 = range::parse("4..1000", 1.0).expect("valid range");
    out.push((
        "seed003-fig1-cubic-epicentre",
        max_error_chart(
            &s(&["cubic", "cubic3", "schlick"]),
            "pow",
            &n4,
            false,
            Zone::Epicentre,
            "Seed 003 Fig. 1: max absolute error in the epicentre",
        )?,
    ));
    out.push((
        "seed003-fig3-lobes-n20",
        lobes_chart(&s(&["pow", "schlick", "rational", "cubic-rational"]), 20.0)?,
    ));
    // Seed 000 Fig. 1-4: Beckmann (Cook-Torrance form) and its one-function forms, m = 0.3.
    let m = 0.3;
    let mut series = vec![];
    let mut rel = vec![];
    let exact = match registry::build::<f64>("beckmann-ct", &[("alpha", "0.3")])? {
        Model::Distribution(d) => d,
        _ => unreachable!(),
    };
    for id in [
        "beckmann-ct",
        "beckmann-pow",
        "beckmann-power4",
        "beckmann-power8",
        "beckmann-power16",
    ] {
        let Model::Distribution(d) = registry::build::<f64>(id, &[("alpha", &m.to_string())])?
        else {
            unreachable!()
        };
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
    let chart = |title: &str, y: &str, series: Vec<Series>, log_y| Chart {
        title: title.into(),
        x_label: "theta_h (degrees)".into(),
        y_label: y.into(),
        series,
        log_y,
        equal_aspect: false,
    };
    out.push((
        "seed000-fig1-3-beckmann-forms",
        chart(
            "Seed 000 Fig. 1 and 3: D and its one-function forms, m = 0.3",
            "D",
            series,
            false,
        ),
    ));
    out.push((
        "seed000-fig2-4-relative-error",
        chart(
            "Seed 000 Fig. 2 and 4: relative error against beckmann-ct, m = 0.3",
            "|D / D_exact - 1|",
            rel,
            true,
        ),
    ));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::polar_chart;

    /// Issue 11: the incident direction was drawn on the mirror side, on top of the lobe. It
    /// must lie on the opposite side of the normal (x = 0) from the specular peak.
    #[test]
    fn polar_incident_direction_is_opposite_the_specular_peak() {
        for (model, params, theta_i) in [
            ("cook-torrance", vec![("alpha", "0.2")], 45.0),
            ("ward", vec![("alpha", "0.3")], 30.0),
            ("cook-torrance", vec![("alpha", "0.5")], 70.0),
        ] {
            let p: Vec<(String, String)> = params
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            let c = polar_chart(model, &p, theta_i).unwrap();
            let lobe = &c.series[0].points;
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
            // The drawn direction is wi itself: its angle from the normal is theta_i.
            let angle = tip.0.atan2(tip.1).to_degrees();
            assert!((angle - theta_i).abs() < 1e-9, "{angle}");
        }
    }
}
