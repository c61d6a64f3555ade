//! `fastbrdf albedo --model file:PATH`: a user's model's directional albedo against incidence
//! with the white-furnace verdict (issue 31), by `fastbrdf conform`'s batched quadrature
//! (`fastbrdf_analysis::conform::albedo`: polar coordinates around the peak, panels doubled
//! until the value settles), per channel: the registry's nested Gauss-Kronrod calls the model
//! once per point, which a GPU evaluator cannot afford.

use super::super::common::progress::bar;
use crate::CliError;
use fastbrdf::user::UserBrdf;
use fastbrdf_analysis::conform::{self, Config};

/// Prints the curve (text or `--json`) of `brdf` at `angles` (degrees).
pub fn run(brdf: &dyn UserBrdf, angles: &[f64], json: bool) -> Result<(), CliError> {
    let cfg = Config::ci();
    let pb = bar(angles.len() as u64, "albedo");
    let mut rows = Vec::new();
    for &t in angles {
        let (a, settled) = conform::albedo(brdf, t, &cfg).map_err(|e| CliError {
            code: crate::EXIT_CHECK_FAILED,
            message: format!("--model {}: {e}", brdf.name()),
        })?;
        let max = a.iter().copied().fold(f64::NAN, f64::max);
        rows.push((t, a, max, settled));
        pb.inc(1);
    }
    pb.finish_and_clear();
    let tol = cfg.energy_tol;
    // The worst angle: the largest albedo of any channel (NaN counts as the worst).
    let worst = rows
        .iter()
        .max_by(|x, y| x.2.total_cmp(&y.2).then(y.0.total_cmp(&x.0)))
        .expect("at least one angle");
    let holds = rows.iter().all(|r| r.2 <= 1.0 + tol);
    if json {
        let rows: Vec<serde_json::Value> = rows
            .iter()
            .map(|(t, a, max, settled)| {
                serde_json::json!({"theta_deg": t, "albedo": max, "channels": a,
                    "settled": settled})
            })
            .collect();
        let v = serde_json::json!({"model": brdf.name(), "brdf": "user",
            "channels": brdf.channels(), "tolerance": tol, "conserves": holds, "rows": rows});
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    crate::outln!(
        "directional albedo of {} (seen from wo at each angle, integrated over wi; conform's batched quadrature, rel. tol. {:e}{})",
        brdf.name(),
        cfg.energy_rel,
        if brdf.channels() == 3 {
            "; R, G, B"
        } else {
            ""
        }
    );
    crate::outln!("  {:>8} {:>30} {:>8}", "theta", "albedo", "settled");
    for (t, a, _, settled) in &rows {
        let v: Vec<String> = a.iter().map(|x| format!("{x:.6}")).collect();
        crate::outln!(
            "  {:>8} {:>30} {:>8}",
            t,
            v.join(" "),
            if *settled { "yes" } else { "no" }
        );
    }
    let verdict = if holds {
        format!(
            "white furnace: passes (max albedo {:.6} at {} deg <= 1 + {tol})",
            worst.2, worst.0
        )
    } else {
        format!(
            "white furnace: FAILS (albedo {:.6} at {} deg > 1 + {tol})",
            worst.2, worst.0
        )
    };
    crate::outln!("{verdict}");
    Ok(())
}
