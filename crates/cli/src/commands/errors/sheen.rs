//! `fastbrdf errors --model ID` for a sheen albedo row (`sheen-albedo-*`, kind env): its
//! DFG-ledger row against `sheen-albedo` at the same visibility over `mu` in [0.001, 1] and
//! `alpha` in [0.07, 1] (fastbrdf-analysis::sheen_ledger): the albedo's max absolute error and
//! where, its mean, and the white-furnace consequence for `gltf-pbr`'s base.

use crate::CliError;
use fastbrdf::microfacet::sheen::ALPHA_MIN;
use fastbrdf::microfacet::sheen_albedo::MU_MIN;
use fastbrdf_analysis::env_errors::TermError;
use fastbrdf_analysis::sheen_ledger::{REFERENCE, Reference, SheenErrors, spec, v_of};

pub struct Args<'a> {
    pub model: &'a str,
    pub reference: &'a str,
    pub params: &'a [(String, String)],
    pub json: bool,
    pub csv: bool,
}

pub fn run(a: &Args) -> Result<(), CliError> {
    if a.reference != REFERENCE {
        return Err(CliError::input(format!(
            "--reference {}: a sheen albedo row is measured against {REFERENCE} (its v: the row's own, or --param v=V for a row without one)",
            a.reference
        )));
    }
    let own_v = fastbrdf::registry::find(a.model)?
        .info
        .params
        .iter()
        .any(|p| p.name == "v");
    // `v` of a row without one (Khronos' fit) picks the reference's visibility.
    let mut v = None;
    let mut params = vec![];
    for (k, x) in a.params {
        if k == "v" && !own_v {
            if fastbrdf::microfacet::sheen::Vis::parse(x).is_none() {
                return Err(CliError::input(format!(
                    "--param v={x}: expected charlie or neubelt"
                )));
            }
            v = Some(x.clone());
        } else {
            params.push((k.clone(), x.clone()));
        }
    }
    // Validate before the reference's quadratures (a few seconds).
    let s = spec(a.model, &params)?;
    let v = v.unwrap_or_else(|| v_of(&s));
    let e = Reference::new(&v)?.measure(&s)?;
    let label = label(a.model, a.params);
    if a.json {
        let j = serde_json::json!({
            "model": a.model, "params": a.params.iter().cloned()
                .collect::<std::collections::BTreeMap<_, _>>(),
            "reference": REFERENCE, "v": e.v,
            "domain": {"cos_v": [MU_MIN, 1.0], "alpha": [ALPHA_MIN, 1.0]},
            "albedo": e.albedo, "furnace": e.furnace,
            "furnace_gain": e.furnace_gain, "furnace_loss": e.furnace_loss,
            "furnace_peak": e.furnace_peak, "furnace_peak_exact": e.furnace_peak_exact,
        });
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&j).expect("serialisable")
        );
    } else if a.csv {
        crate::outln!("model,v,quantity,max_abs,cos_v,alpha,mean_abs,mean_abs_r");
        for (q, t) in rows(&e) {
            crate::outln!(
                "{label},{},{q},{},{},{},{},{}",
                e.v,
                t.max_abs,
                t.cos_v,
                t.alpha,
                t.mean_abs,
                t.mean_abs_r
            );
        }
    } else {
        crate::outln!(
            "{label} vs {REFERENCE}:v={} over mu (cos_v) in [{MU_MIN}, 1], alpha in [{ALPHA_MIN}, 1]",
            e.v
        );
        crate::outln!(
            "  {:<8} {:>11} {:>9} {:>9} {:>11} {:>11}",
            "",
            "max abs",
            "at mu",
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
            "  (mean abs: uniform in mu and alpha; mean, r: uniform in mu and r = sqrt(alpha))"
        );
        crate::outln!(
            "  furnace (gltf-pbr's white Lambertian base under a white sheen, A' - A): at most {:.4e} too bright, {:.4e} too dark; largest albedo {:.4} (exact scaling: {:.4})",
            e.furnace_gain,
            e.furnace_loss,
            e.furnace_peak,
            e.furnace_peak_exact
        );
    }
    Ok(())
}

fn rows(e: &SheenErrors) -> [(&'static str, TermError); 2] {
    [("albedo", e.albedo), ("furnace", e.furnace)]
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
