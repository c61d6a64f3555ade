//! `fastbrdf errors`: max absolute, max relative and RMS error of a model against a reference
//! over a range of its parameter (fastbrdf-analysis::errors); against every MERL material's
//! own parameter (`--over materials`, [`over_materials`]); or against measured data
//! (`--measured`, [`measured`]).

mod env;
mod measured;
mod over_materials;
mod sheen;
mod user;

use super::common::numbers::{csv_num, swept};
use super::common::progress::bar;
use crate::CliError;
use crate::model_args::{MaterialArg, ParamArgs, Use, with_material};
use fastbrdf::{Given, ModelSpec, Zone};
use fastbrdf_analysis::{errors, range};
use std::fmt::Write;

const ERRORS_MATERIAL_HELP: &str = "A MERL material (see `fastbrdf materials`): measure at its \
fitted parameter (n from blinn_phong_n; alpha from ward_alpha for ward-*, cook_torrance_m \
otherwise) when --n or --m is not given";

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
fastbrdf errors --model cook-torrance --param d=ggx --measured brass.binary --m 0.005..1:log10 --json\n  \
fastbrdf errors --model env-brdf-table --param size=128 --param bits=16   (a split-sum model: the DFG ledger row)\n  \
fastbrdf errors --model sheen-albedo-table --param v=neubelt --param bits=8   (a sheen albedo row)\n\n\
A split-sum model (kind env) without --m: both terms and the white furnace (scale + bias)\n\
against --reference (default env-brdf) over cos_v in (0, 1] and alpha in [0.005, 1]: max\n\
absolute error and where (cos_v, alpha), mean absolute error (uniform in cos_v and alpha), and\n\
the furnace's largest gain and loss; --param sets its parameters (size, bits).\n\n\
A sheen albedo row (sheen-albedo-*) without --m: its albedo E against sheen-albedo at the same\n\
visibility v over mu in [0.001, 1] and alpha in [0.07, 1] (max absolute error and where, mean),\n\
and the furnace of gltf-pbr's white Lambertian base under a white sheen with that E in the\n\
scaling (A' - A: max, mean, largest gain and loss; the largest albedo); --param v=V picks the\n\
reference's visibility of a row without v (sheen-albedo-khronos).\n\n\
--over materials measures each approximation against its reference at every MERL material's\n\
own fitted parameter (Ngan, Matusik and Durand, EGSR 2005; see `fastbrdf materials`): lobes at\n\
the Blinn-Phong n, Beckmann approximations and smith-rational at the Beckmann m, Ward's at\n\
Ward's alpha. An approximation is safe for a material when its --metric (default max-abs: the\n\
max absolute error, divided by the reference's peak for non-lobes) is at most --threshold\n\
(default 0.01). Materials outside the model's or the reference's documented domain are counted\n\
as outside, not measured.",
    mut_arg("material", |a| a.help(ERRORS_MATERIAL_HELP).conflicts_with("over")),
    mut_arg("params", |a| a
        .help("With --measured or a user's model (file:PATH): a model parameter NAME=VALUE (d=ggx, f=schlick, ...); repeat"))
)]
pub struct Args {
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
    #[command(flatten)]
    material: MaterialArg,
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
    #[command(flatten)]
    params: ParamArgs,
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

pub fn run(a: &Args) -> Result<(), CliError> {
    let user = [&a.model, &a.reference]
        .iter()
        .any(|id| id.as_deref().is_some_and(crate::model_args::is_user));
    // A split-sum model without a sweep: its DFG-ledger row over the whole domain.
    let env = a.model.as_deref().is_some_and(|m| {
        fastbrdf::registry::find(m).is_ok_and(|e| e.info.kind == fastbrdf::Kind::Env)
    }) && a.n.is_none()
        && a.m.is_none()
        && a.over.is_none()
        && a.measured.is_none()
        && a.material.material.is_none();
    if env
        && a.model
            .as_deref()
            .is_some_and(fastbrdf_analysis::sheen_ledger::is_sheen)
    {
        return sheen::run(&sheen::Args {
            model: a.model.as_deref().unwrap_or_default(),
            reference: a
                .reference
                .as_deref()
                .unwrap_or(fastbrdf_analysis::sheen_ledger::REFERENCE),
            params: &a.params.pairs()?,
            json: a.json,
            csv: a.csv,
        });
    }
    if env {
        return env::run(&env::Args {
            model: a.model.as_deref().unwrap_or_default(),
            reference: a.reference.as_deref().unwrap_or("env-brdf"),
            params: &a.params.pairs()?,
            json: a.json,
            csv: a.csv,
        });
    }
    if !a.params.params.is_empty() && a.measured.is_none() && !user {
        return Err(CliError::input(
            "--param: only with --measured, a user's model (file:PATH) or a split-sum model (env-brdf-table:size, bits) without --m",
        ));
    }
    if a.over.is_some() {
        return over_materials::run(&over_materials::Args {
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
        let Some(model) = &a.model else {
            return Err(CliError::input("--measured: give --model ID"));
        };
        // The model as it shades, its values parsed once here.
        let e = fastbrdf::registry::find(model)?;
        if e.info.kind.shading() == fastbrdf::kind::Shading::Not {
            return Err(CliError::input(format!(
                "--measured: {model} is a {} model; measured data is compared with BRDFs (and with lobes and distributions shaded as BRDFs)",
                format!("{:?}", e.info.kind).to_lowercase()
            )));
        }
        let spec = a.params.spec(model, Use::Shaded)?;
        let swept = match (&a.n, &a.m) {
            (Some(n), None) => Some((
                "n",
                range::parse(n, 1.0).map_err(|e| CliError::input(format!("--n: {e}")))?,
            )),
            (None, Some(m)) => Some((
                "alpha",
                range::parse(m, 0.01).map_err(|e| CliError::input(format!("--m: {e}")))?,
            )),
            _ => None,
        };
        return measured::run(&measured::Args {
            model,
            spec: &spec,
            swept,
            file,
            samples: a.samples,
            json: a.json,
            csv: a.csv,
        });
    }
    let (Some(model), Some(reference)) = (&a.model, &a.reference) else {
        return Err(CliError::input(
            "give --model and --reference (or --over materials)",
        ));
    };
    if crate::model_args::is_user(model) || crate::model_args::is_user(reference) {
        if a.n.is_some() || a.m.is_some() || a.material.material.is_some() {
            return Err(CliError::input(
                "--n, --m and --material sweep registry parameters: with a user's model (file:PATH) give its values with --param",
            ));
        }
        return user::run(model, reference, &a.params.pairs()?, a.json, a.csv);
    }
    let material = a.material.get()?;
    let from_material;
    let (param, text, step) = match (&a.n, &a.m, material) {
        (Some(n), None, _) => ("n", n, 1.0),
        (None, Some(m), _) => ("alpha", m, 0.01),
        (None, None, Some(mat)) => {
            let e = fastbrdf::registry::find(model)?;
            let p = swept(e).ok_or_else(|| {
                CliError::input(format!(
                    "--material {}: model '{model}' takes neither n nor alpha",
                    mat.name
                ))
            })?;
            let given = with_material(mat, &ModelSpec::new(model, &[])?)?;
            from_material = given
                .get(p)
                .expect("the material supplies n and alpha")
                .to_string();
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
    if let (Some(mat), None, None) = (material, &a.n, &a.m) {
        // The reference must hold the material's figure too (a clear message, not the registry's).
        with_material(mat, &ModelSpec::new(reference, &[])?)?;
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
        for v in [values[0], values[values.len() - 1]] {
            ModelSpec::new(e, &[(param, Given::Num(v))])?;
        }
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
        let of = material.map_or_else(String::new, |m| {
            format!(" (material {}'s fit, Ngan et al. 2005)", m.name)
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
