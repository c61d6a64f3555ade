//! `fastbrdf albedo`: directional albedo against incidence, with a white-furnace verdict
//! (fastbrdf-analysis::albedo).

use super::common::progress::bar;
use crate::CliError;
use crate::model_args::{self, MaterialArg, ParamArgs, Use};
use fastbrdf::{Given, Kind, ModelSpec};
use fastbrdf_analysis::{albedo, range};

mod user;

#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  fastbrdf albedo --model cook-torrance --param alpha=0.3\n  \
fastbrdf albedo --model flog-normalized --param n=50 --norm none\n  fastbrdf albedo --model ward --param alpha=1 --angles 0,60,85,89,89.9\n  \
fastbrdf albedo --model cook-torrance --material gold-paint --param f=schlick"
)]
pub struct Args {
    /// A BRDF id, or a lobe id (evaluated as --as phong|blinn-phong), or a user's model
    /// `file:PATH` (a .brdf, .wgsl or .glsl file, evaluated on the GPU).
    #[arg(long)]
    model: String,
    #[command(flatten)]
    params: ParamArgs,
    #[command(flatten)]
    material: MaterialArg,
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

/// The `--angles` text as degrees in [0, 90).
fn angles(text: &str) -> Result<Vec<f64>, CliError> {
    let angles = range::parse(text, 5.0).map_err(|e| CliError::input(format!("--angles: {e}")))?;
    if let Some(bad) = angles.iter().find(|t| !(**t >= 0.0 && **t < 90.0)) {
        return Err(CliError::input(format!(
            "--angles: {bad} is outside [0, 90) degrees"
        )));
    }
    Ok(angles)
}

/// `fastbrdf albedo --ms-compare`.
fn ms_compare(a: &Args, spec: &ModelSpec, angles: &[f64]) -> Result<(), CliError> {
    if a.model != "cook-torrance" {
        return Err(CliError::input(format!(
            "--ms-compare: only for cook-torrance (its parameter ms), not {}",
            fastbrdf_io::shorten(&a.model, 64)
        )));
    }
    // Any ms given is replaced; d = ggx and g = smith-ggx-correlated unless given.
    let given: Vec<(&str, Given)> = spec
        .given()
        .iter()
        .filter(|(k, _)| *k != "ms")
        .map(|(k, v)| (*k, v.clone()))
        .collect();
    let base = ModelSpec::new(spec.id(), &given)?.with_defaults(&[
        ("d", Given::Choice("ggx".into())),
        ("g", Given::Choice("smith-ggx-correlated".into())),
    ])?;
    let names = fastbrdf::microfacet::ms::NAMES;
    let pb = bar(names.len() as u64, "albedo");
    let mut curves = vec![];
    for ms in names {
        let p = base.with("ms", Given::Choice(ms.to_string()))?;
        let mut t = albedo::target(&p, &a.as_brdf, &a.norm)?;
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
    let p: Vec<String> = base
        .given()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
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

pub fn run(a: &Args) -> Result<(), CliError> {
    if model_args::is_user(&a.model) {
        let angles = angles(&a.angles)?;
        if a.material.material.is_some() || a.ms_compare {
            return Err(CliError::input(format!(
                "{}: a user's model takes neither --material nor --ms-compare",
                fastbrdf_io::shorten(&a.model, 64)
            )));
        }
        let brdf = model_args::user(&a.model, &a.params.pairs()?)?.expect("a user's id");
        return user::run(&*brdf, &angles, a.json);
    }
    // The kind first (`albedo::target`'s message), so that a distribution is refused as one
    // whatever its values (--ms-compare names its one model itself).
    let info = fastbrdf::registry::find(&a.model)?.info;
    let kind = info.kind;
    if !a.ms_compare && !matches!(kind, Kind::Brdf | Kind::Lobe) {
        return Err(fastbrdf::Error::WrongKind {
            model: info.id.into(),
            expected: "brdf or lobe".into(),
            found: kind.name().into(),
        }
        .into());
    }
    let spec = model_args::spec(
        &a.model,
        &a.params.pairs()?,
        a.material.get()?,
        None,
        Use::AsIs,
    )?;
    let angles = angles(&a.angles)?;
    if a.ms_compare {
        return ms_compare(a, &spec, &angles);
    }
    let t = albedo::target(&spec, &a.as_brdf, &a.norm)?;
    let pb = bar(1, "albedo");
    let rows = albedo::curve(&t, &angles, 1e-7)?;
    pb.finish_and_clear();
    let (holds, worst) = albedo::furnace(&rows, t.furnace_tolerance());
    if a.json {
        let params = t.params_json();
        let v = serde_json::json!({"model": a.model, "brdf": t.id(), "params": params, "claims_energy": t.claims_energy,
            "conserves": holds, "rows": rows});
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    let p: Vec<String> = t
        .spec
        .given()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    crate::outln!(
        "directional albedo of {} {} (nested adaptive Gauss-Kronrod, rel. tol. 1e-7){}",
        t.id(),
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
