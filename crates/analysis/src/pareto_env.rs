//! `fastbrdf pareto --env`: every split-sum model (`Kind::Env`), each configuration of its
//! choices (the table's sizes and storages), its DFG-ledger errors against `env-brdf`
//! ([`crate::env_errors`]) beside its cost, and the Pareto front on (cost, the larger of the
//! two terms' max absolute errors).
//!
//! Cost: nanoseconds per evaluation of the batch kernel of the `scale` term (4096 pairs of
//! `cos_v` and `alpha` spread over the domain, one core, measured now): an engine reads both
//! terms at once (one fetch, one polynomial pair), so the one term's time ranks the models as
//! their shaders would. `env-brdf` itself (the reference, error 0) is listed for its cost.

use crate::env_errors::{EnvErrors, Reference};
use crate::speed;
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::params::ParamKind;
use fastbrdf::{Given, Kind, ModelSpec, Result, registry};
use serde::Serialize;
use std::time::Duration;

/// The reference of every row.
pub const REFERENCE: &str = "env-brdf";

/// One configuration.
#[derive(Clone, Debug, Serialize)]
pub struct EnvRow {
    pub model: &'static str,
    /// Its choices besides `term`, `NAME=VALUE` (empty for a model without any).
    pub params: Vec<(String, String)>,
    /// Operation counts, `mul/add/div/sqrt/transcendental`.
    pub ops: String,
    pub ns_per_eval: f64,
    /// The larger of the two terms' max absolute errors: the error axis.
    pub max_abs: f64,
    pub errors: EnvErrors,
    pub pareto: bool,
}

impl EnvRow {
    /// `model` or `model:size=32,bits=16`.
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            self.model.to_string()
        } else {
            let p: Vec<String> = self
                .params
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect();
            format!("{}:{}", self.model, p.join(","))
        }
    }
}

/// A split-sum model: an env model other than the sheen albedo rows
/// ([`crate::sheen_ledger`], `fastbrdf pareto --sheen`).
fn split_sum(info: &fastbrdf::ModelInfo) -> bool {
    info.kind == Kind::Env && !crate::sheen_ledger::is_sheen(info.id)
}

/// Every configuration of every env model: `(id, choices besides term)`.
pub fn configs() -> Vec<(&'static str, Vec<(String, String)>)> {
    let mut out = vec![];
    for e in registry::all().iter().filter(|e| split_sum(&e.info)) {
        let mut sets: Vec<Vec<(String, String)>> = vec![vec![]];
        for p in e.info.params.iter().filter(|p| p.name != "term") {
            if let ParamKind::Choice { options, .. } = p.kind {
                sets = sets
                    .iter()
                    .flat_map(|s| {
                        options.names().iter().map(move |o| {
                            let mut s = s.clone();
                            s.push((p.name.to_string(), o.to_string()));
                            s
                        })
                    })
                    .collect();
            }
        }
        out.extend(sets.into_iter().map(|s| (e.info.id, s)));
    }
    out
}

fn given(params: &[(String, String)]) -> Vec<(&str, Given)> {
    params
        .iter()
        .map(|(k, v)| (k.as_str(), Given::Choice(v.clone())))
        .collect()
}

/// Nanoseconds per evaluation of the `scale` term's batch kernel of `id` with `params`.
pub fn ns_per_eval(id: &str, params: &[(String, String)]) -> Result<f64> {
    let mut g = given(params);
    g.push(("term", Given::Choice("scale".into())));
    let k = Kernel::new(&ModelSpec::new(id, &g)?)?;
    let n = 4096;
    let cos: Vec<f32> = (0..n).map(|i| (i as f32 + 0.5) / n as f32).collect();
    let alpha: Vec<f32> = (0..n)
        .map(|i| 0.005 + 0.995 * ((i * 37) % n) as f32 / n as f32)
        .collect();
    let mut out = vec![0.0f32; n];
    // The quadrature takes ~20 us per value: time fewer of them.
    let m = if id == REFERENCE { 64 } else { n };
    let t = speed::time(
        || {
            k.eval(Input::Env([&cos[..m], &alpha[..m]]), &mut out[..m])
                .expect("sizes match")
        },
        Duration::from_millis(60),
    );
    Ok(t / m as f64 * 1e9)
}

/// Every row, errors against [`REFERENCE`], the front marked, cheapest first. `progress` is
/// called once per configuration.
pub fn rows(progress: &(dyn Fn() + Sync)) -> Result<Vec<EnvRow>> {
    let r = Reference::new(REFERENCE)?;
    let mut rows = vec![];
    for (id, params) in configs() {
        let info = &registry::find(id)?.info;
        let errors = r.measure(id, &given(&params))?;
        let o = info.ops;
        rows.push(EnvRow {
            model: info.id,
            ops: format!(
                "{}/{}/{}/{}/{}",
                o.mul, o.add, o.div, o.sqrt, o.transcendental
            ),
            ns_per_eval: ns_per_eval(id, &params)?,
            max_abs: errors.scale.max_abs.max(errors.bias.max_abs),
            errors,
            params,
            pareto: false,
        });
        progress();
    }
    mark_front(&mut rows);
    Ok(rows)
}

/// Marks the rows no other row beats on both cost and max error (at least as good on both,
/// better on one); sorts cheapest first.
pub fn mark_front(rows: &mut [EnvRow]) {
    for i in 0..rows.len() {
        let (ci, ei) = (rows[i].ns_per_eval, rows[i].max_abs);
        rows[i].pareto = !rows.iter().enumerate().any(|(j, r)| {
            j != i
                && r.ns_per_eval <= ci
                && r.max_abs <= ei
                && (r.ns_per_eval < ci || r.max_abs < ei)
        });
    }
    rows.sort_by(|a, b| a.ns_per_eval.total_cmp(&b.ns_per_eval));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every env model is listed, the table once per size and storage (12), and the reference
    /// is on the front (nothing has a smaller error).
    #[test]
    fn every_env_configuration_is_listed() {
        let c = configs();
        let tables = c.iter().filter(|(id, _)| *id == "env-brdf-table").count();
        assert_eq!(tables, 4 * 3);
        for e in registry::all().iter().filter(|e| split_sum(&e.info)) {
            assert!(c.iter().any(|(id, _)| *id == e.info.id), "{}", e.info.id);
        }
        let r = Reference::new(REFERENCE).unwrap();
        let mut rows: Vec<EnvRow> = [("env-brdf", vec![]), ("env-brdf-approx", vec![])]
            .into_iter()
            .enumerate()
            .map(|(k, (id, params))| {
                let errors = r.measure(id, &given(&params)).unwrap();
                EnvRow {
                    model: id,
                    params,
                    ops: String::new(),
                    ns_per_eval: [100.0, 1.0][k],
                    max_abs: errors.scale.max_abs.max(errors.bias.max_abs),
                    errors,
                    pareto: false,
                }
            })
            .collect();
        mark_front(&mut rows);
        assert_eq!(rows[0].model, "env-brdf-approx");
        assert!(rows.iter().all(|r| r.pareto));
        assert_eq!(rows[1].max_abs, 0.0);
        assert!(ns_per_eval("env-brdf-materialx", &[]).unwrap() > 0.0);
    }
}
