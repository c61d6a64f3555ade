//! `fastbrdf plot KIND`: charts as PNG and SVG (1200x800), and the seeds' figures for
//! `fastbrdf reproduce --out DIR`.

use super::analysis::bar;
use super::eval::parse_params;
use crate::CliError;
use fastbrdf::{Model, Zone, registry};
use fastbrdf_analysis::plot::{Chart, Series, save};
use fastbrdf_analysis::{albedo, errors, normalize, range};
use std::path::{Path, PathBuf};

pub use fastbrdf_analysis::plot::write_atomic as write_atomic_io;

/// Writes a file atomically, mapping the error for the CLI.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), CliError> {
    Ok(write_atomic_io(path, bytes)?)
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf plot lobes --models pow,flog,schlick --n 20\n  \
fastbrdf plot error --model cubic --reference pow --n 200\n  \
fastbrdf plot max-error --models flog,schlick --reference pow --n 1..1000 --metric rel --zone epicentre\n  \
fastbrdf plot coef --model flog --n 1..1000 --fit seed\n  \
fastbrdf plot polar --model cook-torrance --param alpha=0.3 --theta-i 45\n  \
fastbrdf plot albedo --model ward --param alpha=0.5"
)]
pub struct Args {
    #[command(subcommand)]
    kind: Kind,
    /// Output path without extension (writes .png and .svg); default fastbrdf-out/plot-KIND.
    #[arg(long, global = true)]
    out: Option<PathBuf>,
}

#[derive(clap::Subcommand)]
enum Kind {
    /// Lobe curves of several models against the angle, at one n (the seeds' figures).
    Lobes {
        #[arg(long, value_delimiter = ',', default_value = "pow,flog,schlick")]
        models: Vec<String>,
        #[arg(long, default_value_t = 20.0)]
        n: f64,
    },
    /// Signed error (model - reference) against the angle, at one n.
    Error {
        #[arg(long)]
        model: String,
        #[arg(long, default_value = "pow")]
        reference: String,
        #[arg(long, default_value_t = 20.0)]
        n: f64,
    },
    /// Max error against n for several lobes (log scale).
    MaxError {
        #[arg(long, value_delimiter = ',', default_value = "flog,schlick")]
        models: Vec<String>,
        #[arg(long, default_value = "pow")]
        reference: String,
        #[arg(long, default_value = "1..1000")]
        n: String,
        #[arg(long, default_value = "abs", value_parser = ["abs", "rel"])]
        metric: String,
        #[arg(long, default_value = "all", value_parser = ["all", "epicentre"])]
        zone: String,
    },
    /// coef(n) = 1 / (2 pi Int(n)) of a lobe, with a fitted closed form.
    Coef {
        #[arg(long, default_value = "flog")]
        model: String,
        #[arg(long, default_value = "1..1000")]
        n: String,
        #[arg(long, default_value = "seed", value_parser = ["seed", "linear", "seed-published"])]
        fit: String,
    },
    /// A full BRDF in the plane of incidence, as a polar lobe (f cos theta_o along wo).
    Polar {
        #[arg(long)]
        model: String,
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Incidence angle in degrees.
        #[arg(long, default_value_t = 30.0)]
        theta_i: f64,
    },
    /// Directional albedo against the incidence angle.
    Albedo {
        #[arg(long)]
        model: String,
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
    match registry::build::<f64>(id, &[("n", &n.to_string())])? {
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
                vec![(0.0, 0.0), (-peak * ti.sin(), peak * ti.cos())],
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

fn saved(c: &Chart, base: &Path) -> Result<(), CliError> {
    let [png, svg] = save(c, base).map_err(|e| CliError {
        code: 1,
        message: e,
    })?;
    eprintln!("wrote {} and {}", png.display(), svg.display());
    Ok(())
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
    match &a.kind {
        Kind::Lobes { models, n } => saved(&lobes_chart(models, *n)?, &base),
        Kind::Error {
            model,
            reference,
            n,
        } => {
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
            saved(&c, &base)
        }
        Kind::MaxError {
            models,
            reference,
            n,
            metric,
            zone,
        } => {
            let ns = range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
            let zone = if zone == "epicentre" {
                Zone::Epicentre
            } else {
                Zone::All
            };
            let title = format!("Max {metric} error against {reference} ({zone:?})");
            saved(
                &max_error_chart(models, reference, &ns, metric == "rel", zone, &title)?,
                &base,
            )
        }
        Kind::Coef { model, n, fit } => {
            let ns = range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
            let form = normalize::Form::parse(fit).expect("clap checked the value");
            let (c, r) = coef_chart(model, &ns, form)?;
            saved(&c, &base)?;
            let mut rb = base.clone().into_os_string();
            rb.push("-residual");
            saved(&r, Path::new(&rb))
        }
        Kind::Polar {
            model,
            params,
            theta_i,
        } => saved(
            &polar_chart(model, &parse_params(params)?, *theta_i)?,
            &base,
        ),
        Kind::Albedo { model, params } => {
            saved(&albedo_chart(model, &parse_params(params)?)?, &base)
        }
    }
}

/// The plots corresponding to the seeds' figures, written into `dir`.
pub fn write_seed_figures(dir: &Path) -> Result<(), CliError> {
    let ns = range::parse("1..1000", 1.0).expect("valid range");
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    saved(
        &lobes_chart(&s(&["pow", "flog", "schlick"]), 20.0)?,
        &dir.join("seed001-fig2-lobes-n20"),
    )?;
    saved(
        &max_error_chart(
            &s(&["flog", "schlick"]),
            "pow",
            &ns,
            true,
            Zone::Epicentre,
            "Seed 001 Fig. 3: max relative error in the epicentre",
        )?,
        &dir.join("seed001-fig3-max-rel-epicentre"),
    )?;
    saved(
        &max_error_chart(
            &s(&["flog", "schlick"]),
            "pow",
            &ns,
            false,
            Zone::All,
            "Seed 001 Fig. 4: max absolute error",
        )?,
        &dir.join("seed001-fig4-max-abs"),
    )?;
    let (_, residual) = coef_chart("flog", &ns, normalize::Form::SeedPublished)?;
    saved(&residual, &dir.join("seed001-fig9-energy-residual"))?;
    let n4 = range::parse("4..1000", 1.0).expect("valid range");
    saved(
        &max_error_chart(
            &s(&["cubic", "cubic3", "schlick"]),
            "pow",
            &n4,
            false,
            Zone::Epicentre,
            "Seed 003 Fig. 1: max absolute error in the epicentre",
        )?,
        &dir.join("seed003-fig1-cubic-epicentre"),
    )?;
    saved(
        &lobes_chart(&s(&["pow", "schlick", "rational", "cubic-rational"]), 20.0)?,
        &dir.join("seed003-fig3-lobes-n20"),
    )?;
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
    saved(
        &chart(
            "Seed 000 Fig. 1 and 3: D and its one-function forms, m = 0.3",
            "D",
            series,
            false,
        ),
        &dir.join("seed000-fig1-3-beckmann-forms"),
    )?;
    saved(
        &chart(
            "Seed 000 Fig. 2 and 4: relative error against beckmann-ct, m = 0.3",
            "|D / D_exact - 1|",
            rel,
            true,
        ),
        &dir.join("seed000-fig2-4-relative-error"),
    )?;
    Ok(())
}
