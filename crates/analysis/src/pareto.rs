//! `fastbrdf pareto`: every lobe's error against `cos^n` beside its SIMD cost, and the Pareto
//! front on (cost, max absolute error over n in [8, 1e5]).

use crate::plot::Point;
use crate::speed;
use fastbrdf::batch::{Input, Kernel};
use fastbrdf::{ErrorBound, Kind, Metric, ModelInfo, Zone, registry};
use rayon::prelude::*;
use serde::Serialize;
use std::time::Duration;

/// One lobe.
#[derive(Clone, Debug, Serialize)]
pub struct ParetoRow {
    pub model: &'static str,
    /// Operation counts, `mul/add/div/sqrt/transcendental`.
    pub ops: String,
    /// SIMD evaluations per second, one core, batch 4096 (NaN when unknown).
    pub simd_evals_per_s: f64,
    pub max_abs_1_1e5: f64,
    pub max_abs_8_1e5: f64,
    pub max_rel_epicentre_8_1e5: f64,
    /// On the Pareto front.
    pub pareto: bool,
}

impl ParetoRow {
    /// Nanoseconds per SIMD evaluation: the cost axis.
    pub fn ns_per_eval(&self) -> f64 {
        1e9 / self.simd_evals_per_s
    }
}

/// Every lobe compared with `pow` (not `pow` itself, nor the energy-normalised flog variants:
/// their scale differs from `pow` by design and the energy tests cover them).
pub fn lobes() -> Vec<&'static ModelInfo> {
    registry::all()
        .iter()
        .map(|e| &e.info)
        .filter(|i| i.kind == Kind::Lobe && i.id != "pow" && !i.id.starts_with("flog-normalized"))
        .collect()
}

/// SIMD evaluations per second of the lobe `id` at n = 200, batch 4096, one core, measured now.
pub fn throughput(id: &str) -> f64 {
    let x: Vec<f32> = (0..4096).map(|i| (i as f32 + 0.5) / 4096.0).collect();
    let mut out = vec![0.0f32; 4096];
    let spec = fastbrdf::ModelSpec::new(id, &[("n", fastbrdf::Given::Num(200.0))]);
    let k = Kernel::new(&spec.expect("lobes take n = 200")).expect("lobe kernels build");
    let t = speed::time(
        || k.eval(Input::Cos(&x), &mut out).expect("sizes match"),
        Duration::from_millis(60),
    );
    4096.0 / t
}

/// The SIMD batch-4096 throughput of `id` in a saved bench run (NaN when the run lacks it).
pub fn saved_throughput(run: &speed::Report, id: &str) -> f64 {
    run.kernels
        .iter()
        .find(|k| k.model == id && k.variant == "simd" && k.batch == 4096)
        .map(|k| k.evals_per_s)
        .unwrap_or(f64::NAN)
}

/// The row of one lobe, its throughput taken from `saved` when given, else measured (not yet
/// marked on the front).
pub fn row(info: &'static ModelInfo, saved: Option<&speed::Report>) -> ParetoRow {
    let mut r = error_row(info);
    r.simd_evals_per_s = speed_of(info.id, saved);
    r
}

/// The throughput of lobe `id`: from `saved` when given, else measured.
fn speed_of(id: &str, saved: Option<&speed::Report>) -> f64 {
    match saved {
        Some(r) => saved_throughput(r, id),
        None => throughput(id),
    }
}

/// The row of one lobe without its throughput (NaN).
fn error_row(info: &'static ModelInfo) -> ParetoRow {
    let worst = |lo: f64, metric, zone| {
        let b = ErrorBound {
            reference: "pow",
            metric,
            zone,
            param: ("n", lo, fastbrdf::params::N_MAX),
            bound: 0.0,
        };
        fastbrdf::accuracy::worst(info.id, &b)
            .map(|w| w.err)
            .unwrap_or(f64::NAN)
    };
    let o = info.ops;
    ParetoRow {
        model: info.id,
        ops: format!(
            "{}/{}/{}/{}/{}",
            o.mul, o.add, o.div, o.sqrt, o.transcendental
        ),
        simd_evals_per_s: f64::NAN,
        max_abs_1_1e5: worst(1.0, Metric::MaxAbs, Zone::All),
        max_abs_8_1e5: worst(8.0, Metric::MaxAbs, Zone::All),
        max_rel_epicentre_8_1e5: worst(8.0, Metric::MaxRel, Zone::Epicentre),
        pareto: false,
    }
}

/// Marks the rows on the Pareto front of (cost = 1 / throughput, max abs error over n in
/// [8, 1e5]): no other row is at least as good on both and better on one. Then sorts the
/// rows fastest first.
pub fn mark_front(rows: &mut [ParetoRow]) {
    for i in 0..rows.len() {
        let (ci, ei) = (1.0 / rows[i].simd_evals_per_s, rows[i].max_abs_8_1e5);
        rows[i].pareto = !rows.iter().enumerate().any(|(j, r)| {
            let (cj, ej) = (1.0 / r.simd_evals_per_s, r.max_abs_8_1e5);
            j != i && cj <= ci && ej <= ei && (cj < ci || ej < ei)
        });
    }
    rows.sort_by(|a, b| b.simd_evals_per_s.total_cmp(&a.simd_evals_per_s));
}

/// Every lobe's row, on the front or not, fastest first. `progress` is called once per lobe.
/// The errors are measured in parallel (they do not depend on the order), then the
/// throughputs one lobe at a time, alone on the machine.
pub fn rows(saved: Option<&speed::Report>, progress: &(dyn Fn() + Sync)) -> Vec<ParetoRow> {
    let mut rows: Vec<ParetoRow> = lobes()
        .into_par_iter()
        .map(|info| {
            let r = error_row(info);
            progress();
            r
        })
        .collect();
    for r in &mut rows {
        r.simd_evals_per_s = speed_of(r.model, saved);
    }
    mark_front(&mut rows);
    rows
}

/// The front as a line: (ns per evaluation, max abs error over n in [8, 1e5]), cheapest first.
pub fn front(rows: &[ParetoRow]) -> Vec<(f64, f64)> {
    let mut f: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.pareto)
        .map(|r| (r.ns_per_eval(), r.max_abs_8_1e5))
        .collect();
    f.sort_by(|a, b| a.0.total_cmp(&b.0));
    f
}

/// Every row as a labelled scatter point (ns per evaluation, max abs error over n in
/// [8, 1e5]), the front highlighted.
pub fn points(rows: &[ParetoRow]) -> Vec<Point> {
    rows.iter()
        .map(|r| Point {
            label: r.model.into(),
            x: r.ns_per_eval(),
            y: r.max_abs_8_1e5,
            highlight: r.pareto,
        })
        .collect()
}

/// `fastbrdf pareto --json`'s object: `{"models": [...]}` (the CLI and the Python package print
/// this one value).
pub fn json(rows: &[ParetoRow]) -> serde_json::Value {
    serde_json::json!({ "models": rows })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(model: &'static str, evals: f64, err: f64) -> ParetoRow {
        ParetoRow {
            model,
            ops: String::new(),
            simd_evals_per_s: evals,
            max_abs_1_1e5: err,
            max_abs_8_1e5: err,
            max_rel_epicentre_8_1e5: err,
            pareto: false,
        }
    }

    #[test]
    fn the_front_keeps_only_undominated_rows_fastest_first() {
        let mut rows = vec![
            row("slow-exact", 1e8, 0.001),
            row("fast-rough", 1e9, 0.1),
            row("dominated", 5e8, 0.2),
            row("middle", 5e8, 0.01),
            row("tie-slower", 5e8, 0.01),
        ];
        mark_front(&mut rows);
        let order: Vec<&str> = rows.iter().map(|r| r.model).collect();
        assert_eq!(order[0], "fast-rough");
        assert_eq!(order[4], "slow-exact");
        let on: Vec<&str> = rows.iter().filter(|r| r.pareto).map(|r| r.model).collect();
        // Equal rows do not dominate each other: both stay.
        assert_eq!(on, ["fast-rough", "middle", "tie-slower", "slow-exact"]);
        assert_eq!(
            front(&rows),
            vec![(1.0, 0.1), (2.0, 0.01), (2.0, 0.01), (10.0, 0.001)]
        );
        let p = points(&rows);
        assert_eq!(p.len(), 5);
        let d = p.iter().find(|p| p.label == "dominated").unwrap();
        assert!(!d.highlight && d.x == 2.0 && d.y == 0.2);
    }

    #[test]
    fn saved_runs_give_the_throughput_and_the_errors_are_measured() {
        let saved = speed::Report {
            cpu: "test".into(),
            isa: "sse2".into(),
            threads: 1,
            fma_per_s: 1e9,
            div_per_s: None,
            kernels: vec![speed::KernelRow {
                model: "schlick".into(),
                variant: "simd".into(),
                batch: 4096,
                evals_per_s: 2.5e9,
                isa: "sse2".into(),
                fma_fraction: None,
                limit: None,
                limit_fraction: None,
                instructions: None,
            }],
            speedups: vec![],
            quick: true,
            gpu: None,
            peers: vec![],
            skipped: vec![],
        };
        let ids: Vec<&str> = lobes().iter().map(|i| i.id).collect();
        assert!(ids.contains(&"schlick") && ids.contains(&"flog"));
        assert!(!ids.contains(&"pow") && !ids.iter().any(|i| i.starts_with("flog-normalized")));
        let info = lobes().into_iter().find(|i| i.id == "schlick").unwrap();
        let r = super::row(info, Some(&saved));
        assert_eq!(r.simd_evals_per_s, 2.5e9);
        assert_eq!(r.ns_per_eval(), 0.4);
        assert_eq!(
            r.ops,
            format!(
                "{}/{}/{}/{}/{}",
                info.ops.mul, info.ops.add, info.ops.div, info.ops.sqrt, info.ops.transcendental
            )
        );
        // n in [1, 1e5] contains [8, 1e5]: its maximum is at least as large.
        assert!(r.max_abs_8_1e5 > 0.0 && r.max_abs_8_1e5 < 1.0);
        assert!(r.max_abs_1_1e5 >= r.max_abs_8_1e5);
        assert!(r.max_rel_epicentre_8_1e5 > 0.0);
        // A lobe the run lacks has an unknown throughput.
        let flog = lobes().into_iter().find(|i| i.id == "flog").unwrap();
        assert!(super::row(flog, Some(&saved)).simd_evals_per_s.is_nan());
    }
}
