//! `fastbrdf errors --measured`: a model's residuals against a MERL file at each swept value
//! (fastbrdf-analysis::measured_fit without a search).

use crate::CliError;
use crate::commands::common::numbers::csv_num;
use crate::commands::common::progress::bar;
use fastbrdf::{Given, ModelSpec};
use fastbrdf_analysis::measured_fit::{self, Data, Options, Problem};
use std::fmt::Write;
use std::path::Path;

/// What `errors --measured` measures: the model (`spec`, as it shades) at each swept value.
pub struct Args<'a> {
    /// The model as the user named it.
    pub model: &'a str,
    /// The BRDF the model shades as, with the values given.
    pub spec: &'a ModelSpec,
    /// The parameter swept and its values (`--n` or `--m`), or none: once, at `spec`.
    pub swept: Option<(&'static str, Vec<f64>)>,
    pub file: &'a Path,
    pub samples: usize,
    pub json: bool,
    pub csv: bool,
}

/// `errors --measured`: the model's residuals against measured data at each swept value.
pub fn run(a: &Args) -> Result<(), CliError> {
    let (model, file) = (a.model, a.file);
    let brdf = a.spec.id();
    let (param, values) = match &a.swept {
        Some((p, v)) => (*p, v.clone()),
        None => ("", vec![f64::NAN]),
    };
    let problems: Vec<Problem> = values
        .iter()
        .map(|&v| {
            let spec = if param.is_empty() {
                Ok(a.spec.clone())
            } else {
                a.spec.with(param, Given::Num(v)).map_err(|e| e.to_string())
            };
            spec.and_then(|s| Problem::new(&s, false))
                .map_err(|e| CliError::input(format!("--model {model}: {e}")))
        })
        .collect::<Result<_, _>>()?;
    let b = fastbrdf::measured::MeasuredBrdf::read(file)?;
    let data = Data::from_measured(&b, a.samples);
    if data.is_empty() {
        return Err(CliError::input(format!(
            "{}: no valid (measured) bin within {} degrees of the normal",
            file.display(),
            measured_fit::MAX_THETA_DEG
        )));
    }
    let pb = bar(values.len() as u64, "errors");
    let mut fits = Vec::with_capacity(values.len());
    for p in &problems {
        let f = measured_fit::fit(p, &data, &Options::default(), &|_, _| {})
            .map_err(|e| CliError::input(format!("{}: {e}", file.display())))?;
        fits.push(f);
        pb.inc(1);
    }
    pb.finish_and_clear();
    let label = if param.is_empty() { "value" } else { param };
    if a.json {
        let rows: Vec<serde_json::Value> = values
            .iter()
            .zip(&fits)
            .map(|(v, f)| {
                serde_json::json!({
                    label: v.is_finite().then_some(*v),
                    "ngan_l2": f.residuals.ngan_l2,
                    "low_log": f.residuals.low_log,
                    "max": f.residuals.max,
                    "rho_d": f.rho_d,
                    "rho_s": f.rho_s,
                })
            })
            .collect();
        let v = serde_json::json!({
            "model": model, "brdf": brdf, "measured": file.display().to_string(),
            "param": (!param.is_empty()).then_some(param), "samples": data.len(),
            "eligible": data.eligible, "rows": rows,
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    if a.csv {
        let mut s = format!(
            "{label},ngan_l2,low_log,max,rho_d_r,rho_d_g,rho_d_b,rho_s_r,rho_s_g,rho_s_b\n"
        );
        for (v, f) in values.iter().zip(&fits) {
            let r = &f.residuals;
            let _ = writeln!(
                s,
                "{},{},{},{},{},{}",
                csv_num(*v),
                csv_num(r.ngan_l2),
                csv_num(r.low_log),
                csv_num(r.max),
                f.rho_d.map(csv_num).join(","),
                f.rho_s.map(csv_num).join(",")
            );
        }
        crate::out!("{s}");
        return Ok(());
    }
    let mut s = format!(
        "{model} ({brdf}) against {} on {} of {} eligible bins, albedos solved for ngan-l2\n  {label:>10} {:>13} {:>13} {:>13}   rho_d (R, G, B) / rho_s (R, G, B)\n",
        file.display(),
        data.len(),
        data.eligible,
        "ngan-l2",
        "low-log",
        "max"
    );
    for (v, f) in values.iter().zip(&fits) {
        let r = &f.residuals;
        let rgb = |x: [f64; 3]| format!("{:.4} {:.4} {:.4}", x[0], x[1], x[2]);
        let _ = writeln!(
            s,
            "  {:>10} {:>13.6e} {:>13.6e} {:>13.6e}   {} / {}",
            if v.is_finite() {
                // Six decimals: a range's steps (0.30000000000000004) print as given.
                let t = format!("{v:.6}");
                t.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                "-".into()
            },
            r.ngan_l2,
            r.low_log,
            r.max,
            rgb(f.rho_d),
            rgb(f.rho_s)
        );
    }
    crate::out!("{s}");
    Ok(())
}
