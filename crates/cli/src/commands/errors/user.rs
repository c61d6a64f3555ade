//! `fastbrdf errors --model A --reference B` when either is a user's model (`file:PATH`,
//! issue 31): one comparison on `fastbrdf conform`'s pair set (a grid of directions with
//! grazing and mirror pairs, and uniform random pairs), batched, instead of a sweep over n or
//! alpha (a user's file has its own parameters). Each user's model takes the `--param` values
//! its file declares; a registry model takes the rest.

use crate::CliError;
use crate::model_args::{self, Use};
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, UserBrdf};
use fastbrdf_analysis::conform::{self, Config};
use std::sync::Arc;

/// A user's model with the values its file declares, or a registry BRDF with the rest.
fn model(id: &str, all: &[(String, String)]) -> Result<Arc<dyn UserBrdf>, CliError> {
    if model_args::is_user(id) {
        let path = std::path::Path::new(&id[model_args::USER_PREFIX.len()..]);
        let names: Vec<String> = fastbrdf_gpu::user::UserShader::load(path)
            .map_err(|e| CliError::input(e.message))?
            .params()
            .iter()
            .map(|p| p.name.clone())
            .collect();
        let own: Vec<(String, String)> = all
            .iter()
            .filter(|(k, _)| names.contains(k))
            .cloned()
            .collect();
        return Ok(model_args::user(id, &own)?.expect("a user's id"));
    }
    let rest: Vec<(String, String)> = all
        .iter()
        .filter(|(k, _)| model_args::takes(id, k).unwrap_or(false))
        .cloned()
        .collect();
    let spec = model_args::spec(id, &rest, None, None, Use::AsIs)?;
    Ok(Arc::new(Builtin::new(&spec, Strategy::Auto)?))
}

/// Prints the comparison (text, `--json` or `--csv`).
pub fn run(
    model_id: &str,
    reference_id: &str,
    all: &[(String, String)],
    json: bool,
    csv: bool,
) -> Result<(), CliError> {
    let m = model(model_id, all)?;
    let r = model(reference_id, all)?;
    // A value that neither model takes is an error, as in a comparison.
    for (k, _) in all {
        let taken = [model_id, reference_id].iter().any(|id| {
            if model_args::is_user(id) {
                true
            } else {
                model_args::takes(id, k).unwrap_or(false)
            }
        });
        if !taken {
            return Err(CliError::input(format!(
                "--param {k}: neither {model_id} nor {reference_id} takes it"
            )));
        }
    }
    let cfg = Config::ci();
    let a = conform::agreement(&*m, &*r, &cfg).map_err(|e| CliError {
        code: crate::EXIT_CHECK_FAILED,
        message: e,
    })?;
    if json {
        let mut v = serde_json::to_value(&a).expect("serialisable");
        v["model"] = m.name().into();
        v["reference"] = r.name().into();
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&v).expect("serialisable")
        );
        return Ok(());
    }
    let f = |x: f64| {
        if x.is_finite() {
            x.to_string()
        } else {
            String::new()
        }
    };
    if csv {
        crate::outln!("model,reference,pairs,max_abs,max_abs_of_peak,reference_peak,max_rel,rms");
        crate::outln!(
            "\"{}\",\"{}\",{},{},{},{},{},{}",
            m.name().replace('"', "\"\""),
            r.name().replace('"', "\"\""),
            a.pairs,
            f(a.max_abs),
            f(a.max_abs_of_peak),
            f(a.reference_peak),
            f(a.max_rel),
            f(a.rms)
        );
        return Ok(());
    }
    let at = |w: &conform::At| {
        let d = |v: Option<[f64; 3]>| {
            v.map(|v| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]))
                .unwrap_or_default()
        };
        let ch = w
            .channel
            .map(|c| format!(" channel {c}"))
            .unwrap_or_default();
        format!("wi={} wo={}{ch}", d(w.wi), d(w.wo))
    };
    crate::outln!(
        "{} against {} on {} direction pairs (conform's set: a grid with grazing and mirror pairs, and uniform pairs)",
        m.name(),
        r.name(),
        a.pairs
    );
    crate::outln!(
        "  max abs  {:.4e} ({:.3e} of the reference's peak {:.6}) at {}",
        a.max_abs,
        a.max_abs_of_peak,
        a.reference_peak,
        at(&a.max_abs_at)
    );
    crate::outln!(
        "  max rel  {:.4e} (where the reference > {} of its peak) at {}",
        a.max_rel,
        a.rel_floor,
        at(&a.max_rel_at)
    );
    crate::outln!("  rms      {:.4e} over solid angle", a.rms);
    Ok(())
}
