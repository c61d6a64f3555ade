//! `fastbrdf check`: every documented bound of the registry re-measured on this machine.
//! Two families of checks:
//! - error against the reference model: a dense grid plus golden-section refinement over the
//!   bound's parameter range (`fastbrdf::accuracy::worst`) and an adversarial search over the
//!   parameter as a continuum and the input together (`accuracy::worst_search`); the larger
//!   maximum counts;
//! - f32 against f64 on the same inputs over the whole documented domain, mixed metric
//!   `|v32 - v64| / max(1, |v64|)`: a grid of parameter sets (`accuracy::f32_worst` over
//!   `accuracy::domain_configs`) and an adversarial search (`accuracy::f32_search`, seeded, so
//!   reproducible). The search also fails a model that returns a non-finite or negative
//!   value in either precision.

use fastbrdf::entry::Entry;
use fastbrdf::{ErrorBound, Metric, Zone, accuracy};
use rayon::prelude::*;
use serde::Serialize;

/// One documented error bound against its reference, re-measured.
#[derive(Clone, Debug, Serialize)]
pub struct BoundRow {
    pub model: &'static str,
    pub reference: &'static str,
    pub metric: Metric,
    pub zone: Zone,
    pub param: (&'static str, f64, f64),
    pub documented: f64,
    pub measured: f64,
    pub at_param: f64,
    pub at_x: f64,
    pub samples: usize,
    pub ok: bool,
}

/// One model's f32 against f64 bound, re-measured.
#[derive(Clone, Debug, Serialize)]
pub struct F32Row {
    pub model: &'static str,
    pub documented: f64,
    /// The larger of the grid's and the search's maximum (`null` in JSON if infinite).
    pub measured: f64,
    pub configurations: usize,
    /// Evaluations (each in both precisions) of the adversarial search.
    pub evaluations: usize,
    pub at: String,
    /// Every value found finite and non-negative in both precisions.
    pub finite: bool,
    /// Where a non-finite or negative value was found ("" when none).
    pub invalid: String,
    pub ok: bool,
}

/// Every row of a check.
#[derive(Clone, Debug)]
pub struct CheckReport {
    pub bounds: Vec<BoundRow>,
    pub f32: Vec<F32Row>,
}

impl CheckReport {
    /// Whether every bound holds.
    pub fn ok(&self) -> bool {
        self.bounds.iter().all(|r| r.ok) && self.f32.iter().all(|r| r.ok)
    }

    /// How many bounds hold, of how many.
    pub fn holding(&self) -> (usize, usize) {
        let held =
            self.bounds.iter().filter(|r| r.ok).count() + self.f32.iter().filter(|r| r.ok).count();
        (held, self.bounds.len() + self.f32.len())
    }
}

/// The bound `b` of model `e`, re-measured: the worse of the grid and the search.
pub fn bound(e: &'static Entry, b: &'static ErrorBound, size: accuracy::SearchSize) -> BoundRow {
    let grid = accuracy::worst(e.info.id, b).expect("registry bounds name valid models");
    let found =
        accuracy::worst_search(e.info.id, b, size).expect("registry bounds name valid models");
    let w = accuracy::Worst {
        samples: grid.samples + found.samples,
        ..if found.err > grid.err { found } else { grid }
    };
    BoundRow {
        model: e.info.id,
        reference: b.reference,
        metric: b.metric,
        zone: b.zone,
        param: b.param,
        documented: b.bound,
        measured: w.err,
        at_param: w.param,
        at_x: w.x,
        samples: w.samples,
        ok: w.err <= b.bound,
    }
}

/// Parameters as `k=v k=v` (how `check` names a configuration).
pub fn fmt_params(params: &[(String, String)]) -> String {
    let kv: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    kv.join(" ")
}

/// Model `e`'s f32 bound, re-measured: the worst of the grid of parameter sets and the search.
pub fn f32_bound(e: &'static Entry, size: accuracy::SearchSize) -> F32Row {
    let configs = accuracy::domain_configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf);
    let mut worst = (0.0, String::new());
    for c in &configs {
        let given: Vec<(&str, &str)> = c.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        let (err, at) =
            accuracy::f32_worst(e.info.id, &given).expect("domain configurations are valid");
        if err.is_nan() || err > worst.0 || worst.1.is_empty() {
            worst = (err, format!("{} {at}", fmt_params(c)));
        }
    }
    let found = accuracy::f32_search(&e.info, size);
    if found.err > worst.0 {
        worst = (
            found.err,
            format!("{} {}", fmt_params(&found.params), found.at),
        );
    }
    F32Row {
        model: e.info.id,
        documented: e.info.f32_bound,
        measured: worst.0,
        configurations: configs.len(),
        evaluations: found.evaluations,
        at: worst.1,
        finite: found.invalid.is_none(),
        invalid: found.invalid.clone().unwrap_or_default(),
        ok: worst.0 <= e.info.f32_bound && found.invalid.is_none(),
    }
}

/// How many steps [`run`] reports to `progress` for `entries`: one per error bound and one
/// per model.
pub fn steps(entries: &[&'static Entry]) -> usize {
    entries.iter().map(|e| e.info.bounds.len() + 1).sum()
}

/// Re-measures every bound of `entries`, in parallel; `progress` is called [`steps`] times.
pub fn run(
    entries: &[&'static Entry],
    size: accuracy::SearchSize,
    progress: &(dyn Fn() + Sync),
) -> CheckReport {
    let bound_jobs: Vec<_> = entries
        .iter()
        .flat_map(|e| e.info.bounds.iter().map(move |b| (*e, b)))
        .collect();
    let bounds = bound_jobs
        .par_iter()
        .map(|(e, b)| {
            let r = bound(e, b, size);
            progress();
            r
        })
        .collect();
    let f32 = entries
        .par_iter()
        .map(|e| {
            let r = f32_bound(e, size);
            progress();
            r
        })
        .collect();
    CheckReport { bounds, f32 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf::registry;
    use std::sync::atomic::{AtomicUsize, Ordering};

    const SMALL: accuracy::SearchSize = accuracy::SearchSize {
        restarts: 2,
        steps: 40,
        seed: 7,
    };

    #[test]
    fn a_check_measures_every_bound_of_its_models() {
        let entries = vec![
            registry::find("schlick").unwrap(),
            registry::find("flog").unwrap(),
        ];
        let calls = AtomicUsize::new(0);
        let r = run(&entries, SMALL, &|| {
            calls.fetch_add(1, Ordering::Relaxed);
        });
        let n_bounds: usize = entries.iter().map(|e| e.info.bounds.len()).sum();
        assert!(n_bounds >= 2);
        assert_eq!(r.bounds.len(), n_bounds);
        assert_eq!(r.f32.len(), 2);
        assert_eq!(calls.load(Ordering::Relaxed), steps(&entries));
        assert_eq!(steps(&entries), n_bounds + 2);
        for b in &r.bounds {
            // An approximation differs from its reference somewhere, within its bound.
            assert!(b.measured > 0.0 && b.measured <= b.documented, "{b:?}");
            assert!(b.ok && b.samples > 0);
            assert!(b.at_param >= b.param.1 && b.at_param <= b.param.2, "{b:?}");
        }
        for f in &r.f32 {
            assert!(f.finite && f.ok && f.invalid.is_empty(), "{f:?}");
            assert!(f.measured >= 0.0 && f.measured <= f.documented, "{f:?}");
            assert!(f.configurations > 0 && f.evaluations > 0);
        }
        assert!(r.ok());
        assert_eq!(r.holding(), (n_bounds + 2, n_bounds + 2));
    }

    #[test]
    fn one_exceeded_bound_fails_the_check() {
        let e = registry::find("schlick").unwrap();
        let mut r = CheckReport {
            bounds: vec![bound(e, &e.info.bounds[0], SMALL)],
            f32: vec![f32_bound(e, SMALL)],
        };
        assert!(r.ok());
        r.f32[0].ok = false;
        assert!(!r.ok());
        assert_eq!(r.holding(), (1, 2));
    }

    #[test]
    fn configurations_are_named_by_their_parameters() {
        let p = [
            ("n".to_string(), "20".to_string()),
            ("f".into(), "schlick".into()),
        ];
        assert_eq!(fmt_params(&p), "n=20 f=schlick");
        assert_eq!(fmt_params(&[]), "");
    }
}
