//! `fastbrdf errors --over materials`: every approximation against its reference at each MERL
//! material's own fitted parameter (fastbrdf_analysis::materials::over), and how many of the 86
//! materials each approximation is safe for at a threshold.

use crate::CliError;
use crate::commands::common::numbers::{csv_num, swept};
use crate::commands::common::progress::bar;
use fastbrdf::Zone;
use fastbrdf_analysis::errors::{self, ErrorRow};
use fastbrdf_analysis::materials::{self, OverRow, Pair};
use std::fmt::Write;

/// What `errors` passes on.
pub struct Args<'a> {
    pub model: Option<&'a str>,
    pub reference: Option<&'a str>,
    pub zone: Zone,
    pub zone_text: &'a str,
    pub threshold: f64,
    /// max-abs, max-rel or rms.
    pub metric: &'a str,
    pub json: bool,
    pub csv: bool,
}

/// The pairs to measure: one (--model, with --reference or its documented one), or every
/// model with a documented bound.
fn pairs(a: &Args) -> Result<Vec<Pair>, CliError> {
    let Some(model) = a.model else {
        if a.reference.is_some() {
            return Err(CliError::input(
                "--reference needs --model (without --model every approximation is measured against its documented reference)",
            ));
        }
        return Ok(materials::approximations());
    };
    let e = fastbrdf::registry::find(model)?;
    let reference = match a.reference {
        Some(r) => fastbrdf::registry::find(r)?.info.id,
        None => e.info.bounds.first().map(|b| b.reference).ok_or_else(|| {
            CliError::input(format!(
                "model '{model}' has no documented reference: give --reference"
            ))
        })?,
    };
    let param = swept(e).ok_or_else(|| {
        CliError::input(format!(
            "--over materials: model '{model}' takes neither n nor alpha"
        ))
    })?;
    let spec = errors::Spec {
        model: e.info.id.into(),
        reference: reference.into(),
        param: param.into(),
        zone: a.zone,
    };
    spec.validate()?;
    let param = if param == "n" { "n" } else { "alpha" };
    Ok(vec![Pair {
        model: e.info.id,
        reference,
        param,
    }])
}

fn metric_of(metric: &str, r: &ErrorRow) -> f64 {
    match metric {
        "max-rel" => r.max_rel,
        "rms" => r.rms,
        _ => r.max_abs,
    }
}

/// Per pair: safe, unsafe, outside counts and the worst measured error with its material.
struct Summary<'a> {
    pair: &'a Pair,
    column: &'static str,
    safe: usize,
    unsafe_: usize,
    outside: usize,
    worst: Option<(f64, &'static str)>,
}

fn summarise<'a>(
    pairs: &'a [Pair],
    rows: &[OverRow],
    metric: &str,
    threshold: f64,
) -> Vec<Summary<'a>> {
    pairs
        .iter()
        .map(|p| {
            let mine: Vec<&OverRow> = rows.iter().filter(|r| r.pair == *p).collect();
            let mut s = Summary {
                pair: p,
                column: mine.first().map_or("", |r| r.source.column()),
                safe: 0,
                unsafe_: 0,
                outside: 0,
                worst: None,
            };
            for r in mine {
                match &r.errors {
                    None => s.outside += 1,
                    Some(e) => {
                        let v = metric_of(metric, e);
                        if v <= threshold {
                            s.safe += 1;
                        } else {
                            s.unsafe_ += 1;
                        }
                        if s.worst.is_none_or(|(w, _)| v > w || v.is_nan()) {
                            s.worst = Some((v, r.material));
                        }
                    }
                }
            }
            s
        })
        .collect()
}

pub fn run(a: &Args) -> Result<(), CliError> {
    if !(a.threshold.is_finite() && a.threshold >= 0.0) {
        return Err(CliError::input(format!(
            "--threshold {}: must be a finite number >= 0",
            a.threshold
        )));
    }
    let pairs = pairs(a)?;
    let total = materials::all().len();
    let pb = bar((total * pairs.len()) as u64, "materials");
    let rows = materials::over(&pairs, a.zone, &|| pb.inc(1))?;
    pb.finish_and_clear();
    // A zone that holds no sample measured nothing: refuse it, as `errors` does.
    if let Some(r) = rows
        .iter()
        .find(|r| r.errors.is_some_and(|e| e.samples == 0))
    {
        return Err(CliError::input(format!(
            "--zone {}: no sample of {} lies in this zone at {} = {} (material {}): nothing to measure (widen the zone)",
            a.zone_text, r.pair.reference, r.pair.param, r.value, r.material
        )));
    }
    let summary = summarise(&pairs, &rows, a.metric, a.threshold);
    let safe_of = |r: &OverRow| r.errors.map(|e| metric_of(a.metric, &e) <= a.threshold);
    if a.json {
        let v = serde_json::json!({
            "over": "materials",
            "source": materials::SOURCE,
            "zone": a.zone_text,
            "metric": a.metric,
            "threshold": a.threshold,
            "materials": total,
            "summary": summary.iter().map(|s| serde_json::json!({
                "model": s.pair.model, "reference": s.pair.reference, "param": s.pair.param,
                "column": s.column, "safe": s.safe, "unsafe": s.unsafe_,
                "outside_domain": s.outside,
                "worst": s.worst.map(|w| w.0), "worst_material": s.worst.map(|w| w.1),
            })).collect::<Vec<_>>(),
            "rows": rows.iter().map(|r| {
                let e = r.errors;
                serde_json::json!({
                    "material": r.material, "model": r.pair.model, "reference": r.pair.reference,
                    "param": r.pair.param, "column": r.source.column(), "value": r.value,
                    "inside_domain": e.is_some(),
                    "max_abs": e.map(|e| e.max_abs), "max_abs_at": e.map(|e| e.max_abs_at),
                    "max_rel": e.map(|e| e.max_rel), "max_rel_at": e.map(|e| e.max_rel_at),
                    "rms": e.map(|e| e.rms), "samples": e.map(|e| e.samples),
                    "safe": safe_of(r),
                })
            }).collect::<Vec<_>>(),
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    let mut s = String::new();
    if a.csv {
        s.push_str("material,model,reference,param,column,value,inside_domain,max_abs,max_abs_at,max_rel,max_rel_at,rms,samples,safe\n");
        for r in &rows {
            let e = r.errors;
            let f =
                |g: fn(&ErrorRow) -> f64| e.as_ref().map_or_else(String::new, |e| csv_num(g(e)));
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                r.material,
                r.pair.model,
                r.pair.reference,
                r.pair.param,
                r.source.column(),
                csv_num(r.value),
                e.is_some(),
                f(|e| e.max_abs),
                f(|e| e.max_abs_at),
                f(|e| e.max_rel),
                f(|e| e.max_rel_at),
                f(|e| e.rms),
                e.map_or_else(String::new, |e| e.samples.to_string()),
                safe_of(r).map_or_else(String::new, |b| b.to_string()),
            );
        }
        crate::out!("{s}");
        return Ok(());
    }
    let _ = writeln!(
        s,
        "errors at each of the {total} MERL materials' own fitted parameter (Ngan, Matusik and Durand, EGSR 2005), zone {}",
        a.zone_text
    );
    let _ = writeln!(
        s,
        "safe: {} <= {} ({}); outside: the material's figure is outside the model's or the reference's documented domain",
        a.metric,
        a.threshold,
        match a.metric {
            "max-rel" => "max |f - ref| / ref",
            "rms" => "RMS error over solid angle, divided by the reference's peak for non-lobes",
            _ => "max absolute error, divided by the reference's peak for non-lobes",
        }
    );
    // Columns as wide as their longest entry (ids run to 31 characters).
    let wm = summary
        .iter()
        .map(|x| x.pair.model.len())
        .max()
        .unwrap_or(0)
        .max(5);
    let wr = summary
        .iter()
        .map(|x| x.pair.reference.len())
        .max()
        .unwrap_or(0)
        .max(9);
    let figure = |x: &Summary| format!("{} ({})", x.pair.param, x.column);
    let wf = summary
        .iter()
        .map(|x| figure(x).len())
        .max()
        .unwrap_or(0)
        .max(14);
    let _ = writeln!(
        s,
        "\n  {:<wm$} {:<wr$} {:<wf$} {:>5} {:>7} {:>8}  worst {} (material)",
        "model", "reference", "param (figure)", "safe", "unsafe", "outside", a.metric
    );
    for x in &summary {
        let worst = x
            .worst
            .map_or_else(|| "-".into(), |(v, m)| format!("{v:.3e} ({m})"));
        let _ = writeln!(
            s,
            "  {:<wm$} {:<wr$} {:<wf$} {:>5} {:>7} {:>8}  {worst}",
            x.pair.model,
            x.pair.reference,
            figure(x),
            x.safe,
            x.unsafe_,
            x.outside
        );
    }
    if pairs.len() == 1 {
        let p = &pairs[0];
        let _ = writeln!(
            s,
            "\n  {:<26} {:>10} {:>13} {:>13} {:>13}  verdict",
            "material", p.param, "max abs", "max rel", "rms"
        );
        for r in &rows {
            match r.errors {
                None => {
                    let _ = writeln!(
                        s,
                        "  {:<26} {:>10} {:>13} {:>13} {:>13}  outside the domain",
                        r.material, r.value, "-", "-", "-"
                    );
                }
                Some(e) => {
                    let _ = writeln!(
                        s,
                        "  {:<26} {:>10} {:>13.6e} {:>13.6e} {:>13.6e}  {}",
                        r.material,
                        r.value,
                        e.max_abs,
                        e.max_rel,
                        e.rms,
                        if safe_of(r) == Some(true) {
                            "safe"
                        } else {
                            "UNSAFE"
                        }
                    );
                }
            }
        }
    } else {
        let _ = writeln!(
            s,
            "\n  (per-material rows: --csv or --json, or one model with --model)"
        );
    }
    crate::out!("{s}");
    Ok(())
}
