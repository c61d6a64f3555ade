//! `fastbrdf errors --model ID` for a split-sum model (`Kind::Env`): its DFG-ledger row against
//! `--reference` (default `env-brdf`) over the whole domain (fastbrdf-analysis::env_errors):
//! per term and for the white furnace (scale + bias), the max absolute error and where, and the
//! mean absolute error.

use crate::CliError;
use fastbrdf_analysis::env_errors::{EnvErrors, Reference, TermError, given_of};

pub struct Args<'a> {
    pub model: &'a str,
    pub reference: &'a str,
    pub params: &'a [(String, String)],
    pub json: bool,
    pub csv: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    for id in [a.model, a.reference] {
        let e = fastbrdf::registry::find(id)?;
        if e.info.kind != fastbrdf::Kind::Env {
            return Err(CliError::input(format!(
                "--reference {id}: a split-sum model needs a split-sum reference (env-brdf)"
            )));
        }
    }
    if let Some((k, _)) = a.params.iter().find(|(k, _)| k == "term") {
        return Err(CliError::input(format!(
            "--param {k}: both terms are measured; give the other parameters only"
        )));
    }
    let given = given_of(a.model, a.params)?;
    // Validate before the reference's quadrature (a second or so).
    fastbrdf::ModelSpec::new(a.model, &given)?;
    let r = Reference::new(a.reference)?;
    let e = r.measure(a.model, &given)?;
    let label = label(a.model, a.params);
    if a.json {
        let v = serde_json::json!({
            "model": a.model, "params": a.params.iter().map(|(k, v)| (k.clone(), v.clone()))
                .collect::<std::collections::BTreeMap<_, _>>(),
            "reference": a.reference, "domain": {"cos_v": [0.0, 1.0], "alpha": [fastbrdf::params::ALPHA.range().0, 1.0]},
            "scale": e.scale, "bias": e.bias, "furnace": e.furnace,
            "furnace_gain": e.furnace_gain, "furnace_loss": e.furnace_loss,
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
    } else if a.csv {
        crate::outln!("model,quantity,max_abs,cos_v,alpha,mean_abs,mean_abs_r");
        for (q, t) in rows(&e) {
            crate::outln!(
                "{label},{q},{},{},{},{},{}",
                t.max_abs,
                t.cos_v,
                t.alpha,
                t.mean_abs,
                t.mean_abs_r
            );
        }
    } else {
        crate::outln!(
            "{label} vs {} over cos_v in (0, 1], alpha in [{}, 1]",
            a.reference,
            fastbrdf::params::ALPHA.range().0
        );
        crate::outln!(
            "  {:<8} {:>11} {:>9} {:>9} {:>11} {:>11}",
            "",
            "max abs",
            "at cos_v",
            "alpha",
            "mean abs",
            "mean, r"
        );
        for (q, t) in rows(&e) {
            crate::outln!(
                "  {:<8} {:>11.4e} {:>9.5} {:>9.5} {:>11.4e} {:>11.4e}",
                q,
                t.max_abs,
                t.cos_v,
                t.alpha,
                t.mean_abs,
                t.mean_abs_r
            );
        }
        crate::outln!(
            "  (mean abs: uniform in cos_v and alpha; mean, r: uniform in cos_v and r = sqrt(alpha))"
        );
        crate::outln!(
            "  furnace (F = 1, albedo scale + bias): at most {:.4e} too bright, {:.4e} too dark",
            e.furnace_gain,
            e.furnace_loss
        );
    }
    Ok(())
}

fn rows(e: &EnvErrors) -> [(&'static str, TermError); 3] {
    [("scale", e.scale), ("bias", e.bias), ("furnace", e.furnace)]
}

/// `ID` or `ID:NAME=VALUE,...`.
fn label(id: &str, params: &[(String, String)]) -> String {
    if params.is_empty() {
        id.to_string()
    } else {
        let p: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{id}:{}", p.join(","))
    }
}
