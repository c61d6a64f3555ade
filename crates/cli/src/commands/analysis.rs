//! `fastbrdf errors`, `normalize`, `albedo`: the analysis commands (see fastbrdf-analysis).

use super::eval::parse_params;
use crate::CliError;
use fastbrdf::Zone;
use fastbrdf_analysis::{albedo, errors, normalize, range};
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt::Write;

/// A progress bar on stderr (drawn only on a terminal).
pub fn bar(len: u64, msg: &'static str) -> ProgressBar {
    let b = ProgressBar::new(len);
    b.set_style(
        ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} {elapsed}")
            .expect("valid template"),
    );
    b.set_message(msg);
    b
}

pub use fastbrdf_analysis::range::num;

/// A number for CSV: the shortest round-trip text, or an empty field when it is not finite
/// (the same "no finite value" that JSON writes as null).
pub fn csv_num(x: f64) -> String {
    if x.is_finite() {
        x.to_string()
    } else {
        String::new()
    }
}

fn parse_zone(z: &str) -> Result<Zone, CliError> {
    match z {
        "all" => Ok(Zone::All),
        "epicentre" | "epicenter" => Ok(Zone::Epicentre),
        _ => {
            let band = z.strip_prefix("band:").ok_or_else(|| {
                CliError::input(format!(
                    "--zone '{z}': expected all, epicentre or band:LO,HI"
                ))
            })?;
            let (lo, hi) = band
                .split_once(',')
                .ok_or_else(|| CliError::input(format!("--zone '{z}': expected band:LO,HI")))?;
            let (lo, hi): (f64, f64) = (
                lo.trim().parse().map_err(|_| {
                    CliError::input(format!("--zone '{z}': '{lo}' is not a number"))
                })?,
                hi.trim().parse().map_err(|_| {
                    CliError::input(format!("--zone '{z}': '{hi}' is not a number"))
                })?,
            );
            if !(lo >= 0.0 && hi > lo && hi <= 1.0) {
                return Err(CliError::input(format!(
                    "--zone '{z}': need 0 <= LO < HI <= 1 (fractions of the reference's peak)"
                )));
            }
            Ok(Zone::Band { lo, hi })
        }
    }
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf errors --model flog --reference pow --n 1..1000 --zone epicentre\n  \
fastbrdf errors --model rational --reference pow --n 2..1000 --zone band:0.42,0.5 --csv\n  \
fastbrdf errors --model beckmann-power16 --reference beckmann-ct --m 0.2,0.4,0.6 --json\n  \
fastbrdf errors --model flog --reference pow --material gold-paint   (n = the fit's Blinn-Phong n)\n  \
fastbrdf errors --over materials                         (every approximation, 86 materials)\n  \
fastbrdf errors --over materials --model ward-pow --threshold 0.05 --json\n  \
fastbrdf errors --model ward --measured blue-rubber.binary --m 0.1..0.5:0.05   (residuals against the data)\n  \
fastbrdf errors --model cook-torrance --param d=ggx --measured brass.binary --m 0.005..1:log10 --json\n\n\
--over materials measures each approximation against its reference at every MERL material's\n\
own fitted parameter (Ngan, Matusik and Durand, EGSR 2005; see `fastbrdf materials`): lobes at\n\
the Blinn-Phong n, Beckmann approximations and smith-rational at the Beckmann m, Ward's at\n\
Ward's alpha. An approximation is safe for a material when its --metric (default max-abs: the\n\
max absolute error, divided by the reference's peak for non-lobes) is at most --threshold\n\
(default 0.01). Materials outside the model's or the reference's documented domain are counted\n\
as outside, not measured."
)]
pub struct ErrorsArgs {
    /// The approximation (with --over materials: optional, default every model with a
    /// documented bound).
    #[arg(long)]
    model: Option<String>,
    /// The reference model (same kind; with --over materials: default the reference of the
    /// model's documented bounds).
    #[arg(long)]
    reference: Option<String>,
    /// Exponents for lobes: LO..HI[:STEP] (step 1), LO..HI:logK (K log-spaced values per
    /// decade; the whole domain: 1..100000:log50) or a list A,B,C.
    #[arg(long, conflicts_with = "m")]
    n: Option<String>,
    /// Slopes (alpha) for microfacet terms and Ward: LO..HI[:STEP] (step 0.01), LO..HI:logK
    /// (the whole domain: 0.005..1:log20) or a list.
    #[arg(long)]
    m: Option<String>,
    /// A MERL material (see `fastbrdf materials`): measure at its fitted parameter (n from
    /// blinn_phong_n; alpha from ward_alpha for ward-*, cook_torrance_m otherwise) when --n or
    /// --m is not given.
    #[arg(long, value_name = "NAME", conflicts_with = "over")]
    material: Option<String>,
    /// Measure at every material's own parameter instead of a range: `materials` (the 86 MERL
    /// materials' fits, Ngan et al. 2005).
    #[arg(long, value_parser = ["materials"], conflicts_with_all = ["n", "m"])]
    over: Option<String>,
    /// With --over materials: the largest error (in --metric) for which an approximation counts
    /// as safe for a material.
    #[arg(long, default_value_t = 0.01, requires = "over")]
    threshold: f64,
    /// With --over materials: the measure compared with --threshold: max-abs, max-rel or rms.
    #[arg(long, default_value = "max-abs", value_parser = ["max-abs", "max-rel", "rms"], requires = "over")]
    metric: String,
    /// Where to measure: all, epicentre (reference >= 0.5 of its peak) or band:LO,HI.
    #[arg(long, default_value = "all")]
    zone: String,
    /// A measured material (MERL .binary) as the reference instead of a model: at each --n or
    /// --m value (or once, at the model's parameters) the model with per-channel albedos
    /// (rho_d/pi + rho_s f, the albedos solved exactly for ngan-l2) against the file over its
    /// valid bins within 80 degrees of the normal: the three residuals of `fit-measured`.
    /// BRDFs, and lobes and distributions as they shade (blinn-phong with the lobe,
    /// cook-torrance with the distribution); --zone does not apply.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["reference", "over", "material"])]
    measured: Option<std::path::PathBuf>,
    /// With --measured: a model parameter NAME=VALUE (d=ggx, f=schlick, ...); repeat.
    #[arg(long = "param", value_name = "NAME=VALUE", requires = "measured")]
    params: Vec<String>,
    /// With --measured: bins sampled from the file (fixed seed, as fit-measured); 0 = all.
    #[arg(long, default_value_t = fastbrdf_analysis::measured_fit::DEFAULT_SAMPLES)]
    samples: usize,
    /// Print JSON: {"model", "reference", "param": "n"|"alpha", "zone", "worst": {...}, "rows":
    /// [{n or alpha, max_abs, max_abs_at, max_rel, max_rel_at, rms, samples}]}; no finite
    /// value (an infinite relative error) is null. With --over materials: {"over":
    /// "materials", "source", "zone", "metric", "threshold", "materials": 86, "summary":
    /// [{model, reference, param, column, safe, unsafe, outside_domain, worst, worst_material}],
    /// "rows": [{material, model, reference, param, column, value, inside_domain, max_abs,
    /// max_abs_at, max_rel, max_rel_at, rms, samples, safe}]} (errors and safe null outside
    /// the domain; worst is the largest --metric value measured, with its material).
    #[arg(long, conflicts_with = "csv")]
    json: bool,
    /// Print CSV, one row per parameter value: n or alpha, max_abs, max_abs_at, max_rel,
    /// max_rel_at, rms, samples; no finite value (an infinite relative error) is an empty field.
    /// With --over materials, one row per material and model: material, model, reference,
    /// param, column, value, inside_domain, max_abs, max_abs_at, max_rel, max_rel_at, rms,
    /// samples, safe (empty outside the domain).
    #[arg(long)]
    csv: bool,
}

pub fn errors(a: &ErrorsArgs) -> Result<(), CliError> {
    if a.over.is_some() {
        return super::over_materials::run(&super::over_materials::Args {
            model: a.model.as_deref(),
            reference: a.reference.as_deref(),
            zone: parse_zone(&a.zone)?,
            zone_text: &a.zone,
            threshold: a.threshold,
            metric: &a.metric,
            json: a.json,
            csv: a.csv,
        });
    }
    if let Some(file) = &a.measured {
        return measured_errors(a, file);
    }
    let (Some(model), Some(reference)) = (&a.model, &a.reference) else {
        return Err(CliError::input(
            "give --model and --reference (or --over materials)",
        ));
    };
    let from_material;
    let (param, text, step) = match (&a.n, &a.m, &a.material) {
        (Some(n), None, _) => ("n", n, 1.0),
        (None, Some(m), _) => ("alpha", m, 0.01),
        (None, None, Some(name)) => {
            let e = fastbrdf::registry::find(model)?;
            let p = ["n", "alpha"]
                .into_iter()
                .find(|p| takes(e, p))
                .ok_or_else(|| {
                    CliError::input(format!(
                        "--material {name}: model '{model}' takes neither n nor alpha"
                    ))
                })?;
            let given = super::materials::with_material(Some(name), model, &[])?;
            from_material = given
                .into_iter()
                .find(|(k, _)| k == p)
                .map(|(_, v)| v)
                .expect("the material supplies n and alpha");
            (p, &from_material, 1.0)
        }
        _ => {
            return Err(CliError::input(
                "give --n RANGE (lobes) or --m RANGE (microfacet terms, Ward), or --material NAME",
            ));
        }
    };
    let values = range::parse(text, step)
        .map_err(|e| CliError::input(format!("--{}: {e}", if param == "n" { "n" } else { "m" })))?;
    let spec = errors::Spec {
        model: model.clone(),
        reference: reference.clone(),
        param: param.into(),
        zone: parse_zone(&a.zone)?,
    };
    spec.validate()?;
    // Reject out-of-range parameter values before the sweep, with the registry's message.
    if let (Some(name), None, None) = (&a.material, &a.n, &a.m) {
        // The reference must hold the material's figure too (a clear message, not the registry's).
        super::materials::with_material(Some(name), reference, &[])?;
    }
    for e in [model, reference] {
        if fastbrdf::registry::find(e)?.info.kind == fastbrdf::Kind::Env {
            // alpha is an input of split-sum terms: its domain is params::ALPHA's.
            let (lo, hi) = fastbrdf::params::ALPHA.range();
            if let Some(v) = values.iter().find(|v| !(**v >= lo && **v <= hi)) {
                return Err(CliError::input(format!(
                    "--m: {v} is outside the domain [{lo}, {hi}] of {e}'s alpha input"
                )));
            }
            continue;
        }
        fastbrdf::registry::build::<f64>(e, &[(param, &num(values[0]))])?;
        fastbrdf::registry::build::<f64>(e, &[(param, &num(values[values.len() - 1]))])?;
    }
    let pb = bar(values.len() as u64, "errors");
    let rows = errors::sweep(&spec, &values, &|| pb.inc(1))?;
    pb.finish_and_clear();
    let (wa, wr, wq) = errors::worst(&rows).expect("at least one value");
    if a.json {
        let v = serde_json::json!({
            "model": model, "reference": reference, "param": param, "zone": a.zone,
            "worst": {"max_abs": wa.max_abs, "max_abs_param": wa.param, "max_abs_at": wa.max_abs_at,
                      "max_rel": wr.max_rel, "max_rel_param": wr.param, "max_rel_at": wr.max_rel_at,
                      "rms": wq.rms, "rms_param": wq.param},
            "rows": rows.iter().map(|r| serde_json::json!({
                param: r.param, "max_abs": r.max_abs, "max_abs_at": r.max_abs_at,
                "max_rel": r.max_rel, "max_rel_at": r.max_rel_at, "rms": r.rms, "samples": r.samples,
            })).collect::<Vec<_>>(),
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    } else if a.csv {
        let mut s = format!("{param},max_abs,max_abs_at,max_rel,max_rel_at,rms,samples\n");
        for r in &rows {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{}",
                csv_num(r.param),
                csv_num(r.max_abs),
                csv_num(r.max_abs_at),
                csv_num(r.max_rel),
                csv_num(r.max_rel_at),
                csv_num(r.rms),
                r.samples
            );
        }
        crate::out!("{s}");
    } else {
        let x = if matches!(
            fastbrdf::registry::find(model)?.info.kind,
            fastbrdf::Kind::Brdf
        ) {
            "theta"
        } else {
            "cos"
        };
        let of = a.material.as_ref().map_or_else(String::new, |m| {
            format!(" (material {m}'s fit, Ngan et al. 2005)")
        });
        crate::outln!(
            "{} vs {} over {param} in {}{of} ({} values), zone {}",
            model,
            reference,
            text,
            values.len(),
            a.zone
        );
        crate::outln!(
            "  max abs error {:.6e} at {param} = {}, {x} = {:.8}",
            wa.max_abs,
            wa.param,
            wa.max_abs_at
        );
        crate::outln!(
            "  max rel error {:.6e} at {param} = {}, {x} = {:.8}",
            wr.max_rel,
            wr.param,
            wr.max_rel_at
        );
        crate::outln!("  max RMS error {:.6e} at {param} = {}", wq.rms, wq.param);
        if rows.len() <= 30 {
            crate::outln!(
                "\n  {param:>8} {:>13} {:>13} {:>13}",
                "max abs",
                "max rel",
                "rms"
            );
            for r in &rows {
                crate::outln!(
                    "  {:>8} {:>13.6e} {:>13.6e} {:>13.6e}",
                    r.param,
                    r.max_abs,
                    r.max_rel,
                    r.rms
                );
            }
        } else {
            crate::outln!("  (per-{param} rows: --csv or --json)");
        }
    }
    Ok(())
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf normalize --model flog --n 1..7\n  \
fastbrdf normalize --model flog --n 1..1000 --fit seed\n  fastbrdf normalize --model cubic-rational --n 1..1000 --fit linear --json"
)]
pub struct NormalizeArgs {
    /// A lobe id.
    #[arg(long)]
    model: String,
    /// Exponents: LO..HI[:STEP] (step 1) or a list.
    #[arg(long)]
    n: String,
    /// Fit a closed form to coef(n): seed (a (n + b) + c / (d + n)), linear (a (n + b)), or
    /// seed-published (seed 001's printed constants, not fitted).
    #[arg(long, value_parser = ["seed", "linear", "seed-published"])]
    fit: Option<String>,
    /// Print JSON: {"model", "rows": [{n, int, coef, int_err}], "fit": {...}}.
    #[arg(long)]
    json: bool,
}

pub fn normalize(a: &NormalizeArgs) -> Result<(), CliError> {
    let e = fastbrdf::registry::find(&a.model)?;
    if e.info.kind != fastbrdf::Kind::Lobe {
        return Err(CliError::input(format!(
            "normalize needs a lobe; '{}' is a {}",
            a.model,
            e.info.kind.name()
        )));
    }
    let ns = range::parse(&a.n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?;
    for n in [ns[0], ns[ns.len() - 1]] {
        fastbrdf::registry::build::<f64>(&a.model, &[("n", &num(n))])?;
    }
    if let Some(form) = a.fit.as_deref().and_then(normalize::Form::parse) {
        form.check_points(ns.len()).map_err(CliError::input)?;
    }
    let rows = normalize::table(&a.model, &ns)?;
    let fit = a
        .fit
        .as_deref()
        .and_then(normalize::Form::parse)
        .map(|f| normalize::fit(f, &rows));
    if a.json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(
                &serde_json::json!({"model": a.model, "rows": rows, "fit": fit})
            )
            .expect("serialisable")
        );
        return Ok(());
    }
    crate::outln!(
        "Int(n) = integral_0^1 {}(c) c dc and coef(n) = 1 / (2 pi Int(n)) (adaptive Gauss-Kronrod, rel. tol. 1e-12)",
        a.model
    );
    let shown: Vec<_> = if rows.len() <= 40 {
        rows.iter().collect()
    } else {
        rows.iter()
            .step_by(rows.len().div_ceil(20))
            .chain(rows.last())
            .collect()
    };
    crate::outln!(
        "  {:>8} {:>20} {:>14} {:>10}",
        "n",
        "Int(n)",
        "coef(n)",
        "err(Int)"
    );
    for r in shown {
        crate::outln!(
            "  {:>8} {:>20.14e} {:>14.8} {:>10.1e}",
            r.n,
            r.int,
            r.coef,
            r.int_err
        );
    }
    if let Some(f) = fit {
        crate::outln!("\nfit {} over {} values of n:", f.form, rows.len());
        for (k, v) in &f.constants {
            crate::outln!("  {k} = {v:.8}");
        }
        crate::outln!("  RMS of coef_fit - coef        {:.6e}", f.rms);
        crate::outln!(
            "  max |coef_fit / coef - 1|     {:.6e} (n = {})",
            f.max_rel,
            f.max_rel_at
        );
        crate::outln!(
            "  energy residual max |coef_fit 2 pi Int - 1| = {:.6e}",
            f.energy_residual_max
        );
    }
    Ok(())
}

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf albedo --model cook-torrance --param alpha=0.3\n  \
fastbrdf albedo --model flog-normalized --param n=50 --norm none\n  fastbrdf albedo --model ward --param alpha=1 --angles 0,60,85,89,89.9\n  \
fastbrdf albedo --model cook-torrance --material gold-paint --param f=schlick"
)]
pub struct AlbedoArgs {
    /// A BRDF id, or a lobe id (evaluated as --as phong|blinn-phong).
    #[arg(long)]
    model: String,
    /// A parameter, NAME=VALUE; repeat for several.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// A MERL material (see `fastbrdf materials`) whose published fit supplies the model's n,
    /// alpha and f0 (Ngan et al. 2005); --param values win.
    #[arg(long, value_name = "NAME")]
    material: Option<String>,
    /// Incidence angles in degrees: LO..HI[:STEP] (step 5) or a list.
    #[arg(long, default_value = "0..85:5")]
    angles: String,
    /// For lobes: the BRDF geometry.
    #[arg(long = "as", default_value = "phong", value_parser = ["phong", "blinn-phong"])]
    as_brdf: String,
    /// For lobes: energy (coef(n) = 1 / (2 pi Int(n))) or none (the lobe as it is).
    #[arg(long, default_value = "energy", value_parser = ["energy", "none"])]
    norm: String,
    /// Print JSON: {"model", "brdf", "params": {NAME: number, or the choice's name}, "claims_energy", "conserves", "rows": [{theta_deg, albedo, error}]}; with --ms-compare: {"model", "params", "ms": {NAME: {"rows", "max_dev"}}}.
    #[arg(long)]
    json: bool,
    /// cook-torrance only: the white furnace before and after energy compensation, the albedo
    /// with ms = none, kulla-conty and filament side by side (d = ggx and
    /// g = smith-ggx-correlated unless given; any --param ms is replaced). Each angle is the
    /// view direction wo, integrated over wi (Filament's definition; the same as the incidence
    /// albedo for the reciprocal none and kulla-conty).
    #[arg(long)]
    ms_compare: bool,
}

/// `fastbrdf albedo --ms-compare`.
fn albedo_ms_compare(
    a: &AlbedoArgs,
    params: &[(String, String)],
    angles: &[f64],
) -> Result<(), CliError> {
    if a.model != "cook-torrance" {
        return Err(CliError::input(format!(
            "--ms-compare: only for cook-torrance (its parameter ms), not {}",
            fastbrdf_io::shorten(&a.model, 64)
        )));
    }
    let mut base: Vec<(String, String)> =
        params.iter().filter(|(k, _)| k != "ms").cloned().collect();
    for (k, v) in [("d", "ggx"), ("g", "smith-ggx-correlated")] {
        if !base.iter().any(|(n, _)| n == k) {
            base.push((k.into(), v.into()));
        }
    }
    let names = fastbrdf::microfacet::ms::NAMES;
    let pb = bar(names.len() as u64, "albedo");
    let mut curves = vec![];
    for ms in names {
        let mut p = base.clone();
        p.push(("ms".into(), ms.into()));
        let mut t = albedo::target(&a.model, &p, &a.as_brdf, &a.norm)?;
        t.view = true;
        curves.push(albedo::curve(&t, angles, 1e-7)?);
        pb.inc(1);
    }
    pb.finish_and_clear();
    let dev = |rows: &[albedo::AlbedoRow]| {
        rows.iter()
            .map(|r| (r.albedo - 1.0).abs())
            .fold(0.0f64, f64::max)
    };
    if a.json {
        let ms: serde_json::Map<String, serde_json::Value> = names
            .iter()
            .zip(&curves)
            .map(|(n, rows)| {
                (
                    n.to_string(),
                    serde_json::json!({"rows": rows, "max_dev": dev(rows)}),
                )
            })
            .collect();
        // Numbers as numbers, choices as their names.
        let p = fastbrdf_analysis::params_json(&base);
        let v = serde_json::json!({"model": a.model, "params": p, "ms": ms});
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    let p: Vec<String> = base.iter().map(|(k, v)| format!("{k}={v}")).collect();
    crate::outln!(
        "white furnace of cook-torrance {} before and after energy compensation (albedo seen from wo, over wi; nested adaptive Gauss-Kronrod, rel. tol. 1e-7)",
        p.join(" ")
    );
    crate::outln!(
        "  {:>8} {:>12} {:>12} {:>12}",
        "theta",
        "ms=none",
        "kulla-conty",
        "filament"
    );
    for (i, r) in curves[0].iter().enumerate() {
        crate::outln!(
            "  {:>8} {:>12.6} {:>12.6} {:>12.6}",
            r.theta_deg,
            r.albedo,
            curves[1][i].albedo,
            curves[2][i].albedo
        );
    }
    crate::outln!(
        "max |albedo - 1|: none {:.2e}, kulla-conty {:.2e}, filament {:.2e} (with f = none the compensated ones promise {} for alpha >= 0.005, cos >= 0.01)",
        dev(&curves[0]),
        dev(&curves[1]),
        dev(&curves[2]),
        fastbrdf::microfacet::ms::FURNACE_TOL
    );
    Ok(())
}

pub fn albedo(a: &AlbedoArgs) -> Result<(), CliError> {
    let params = super::materials::with_material(
        a.material.as_deref(),
        &a.model,
        &parse_params(&a.params)?,
    )?;
    let angles =
        range::parse(&a.angles, 5.0).map_err(|e| CliError::input(format!("--angles: {e}")))?;
    if let Some(bad) = angles.iter().find(|t| !(**t >= 0.0 && **t < 90.0)) {
        return Err(CliError::input(format!(
            "--angles: {bad} is outside [0, 90) degrees"
        )));
    }
    if a.ms_compare {
        return albedo_ms_compare(a, &params, &angles);
    }
    let t = albedo::target(&a.model, &params, &a.as_brdf, &a.norm)?;
    let pb = bar(1, "albedo");
    let rows = albedo::curve(&t, &angles, 1e-7)?;
    pb.finish_and_clear();
    let (holds, worst) = albedo::furnace(&rows, t.furnace_tolerance());
    if a.json {
        let params = t.params_json();
        let v = serde_json::json!({"model": a.model, "brdf": t.id, "params": params, "claims_energy": t.claims_energy,
            "conserves": holds, "rows": rows});
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    let p: Vec<String> = t.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    crate::outln!(
        "directional albedo of {} {} (nested adaptive Gauss-Kronrod, rel. tol. 1e-7){}",
        t.id,
        p.join(" "),
        if t.view {
            "; not reciprocal: seen from wo at each angle, integrated over wi"
        } else {
            ""
        }
    );
    crate::outln!("  {:>8} {:>12} {:>10}", "theta", "albedo", "error");
    for r in &rows {
        crate::outln!("  {:>8} {:>12.6} {:>10.1e}", r.theta_deg, r.albedo, r.error);
    }
    let w = worst.expect("at least one angle");
    let verdict = match (t.claims_energy, holds) {
        (true, true) if t.furnace_tol > 0.0 => format!(
            "white furnace: passes (max albedo {:.6} at {} deg <= 1 + {}, the compensation's table error)",
            w.albedo, w.theta_deg, t.furnace_tol
        ),
        (true, true) => format!(
            "white furnace: passes (max albedo {:.6} at {} deg <= 1)",
            w.albedo, w.theta_deg
        ),
        (true, false) => format!(
            "white furnace: FAILS (albedo {:.6} at {} deg > 1)",
            w.albedo, w.theta_deg
        ),
        (false, _) => format!(
            "no energy claim (unnormalised model); max albedo {:.6} at {} deg",
            w.albedo, w.theta_deg
        ),
    };
    crate::outln!("{verdict}");
    Ok(())
}

/// Whether `errors` can sweep `param` of model `e` (a numeric parameter, or a split-sum
/// term's `alpha` input).
pub fn takes(e: &fastbrdf::entry::Entry, param: &str) -> bool {
    e.info.sweep_range(param).is_some()
}

/// `errors --measured`: the model's residuals against measured data at each swept value (see
/// `ErrorsArgs::measured`).
fn measured_errors(a: &ErrorsArgs, file: &std::path::Path) -> Result<(), CliError> {
    use fastbrdf_analysis::measured_fit::{self, Data, Options, Problem};
    let Some(model) = &a.model else {
        return Err(CliError::input("--measured: give --model ID"));
    };
    let e = fastbrdf::registry::find(model)?;
    let given = parse_params(&a.params)?;
    let (brdf, given) = fastbrdf::registry::shading_brdf(model, &given).map_err(|_| {
        CliError::input(format!(
            "--measured: {model} is a {} model; measured data is compared with BRDFs (and with lobes and distributions shaded as BRDFs)",
            format!("{:?}", e.info.kind).to_lowercase()
        ))
    })?;
    let (param, values) = match (&a.n, &a.m) {
        (Some(n), None) => (
            "n",
            range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?,
        ),
        (None, Some(m)) => (
            "alpha",
            range::parse(m, 0.01).map_err(|e| CliError::input(format!("--m: {e}")))?,
        ),
        _ => ("", vec![f64::NAN]),
    };
    let problems: Vec<Problem> = values
        .iter()
        .map(|&v| {
            let mut p = given.clone();
            if !param.is_empty() {
                p.push((param.to_string(), num(v)));
            }
            Problem::new(brdf, &p, false)
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
