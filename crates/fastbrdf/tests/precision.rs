//! f32 against f64 for every model over its whole documented domain, on the same (f32)
//! inputs: the mixed error `|v32 - v64| / max(1, |v64|)` must stay within the model's
//! documented `f32_bound` (`fastbrdf::accuracy::f32_worst`). Run with `--nocapture` to print
//! the measured bound per model; `fastbrdf check` prints the same table.

mod common;

use common::{as_refs, configs};
use fastbrdf::{accuracy, registry};

#[test]
fn f32_tracks_f64_within_the_documented_bound() {
    let mut failures = vec![];
    for e in registry::all() {
        let mut model_worst = (0.0, String::new());
        for cfg in configs(&e.info, e.info.kind == fastbrdf::Kind::Brdf) {
            let (err, at) = accuracy::f32_worst(e.info.id, &as_refs(&cfg)).unwrap();
            assert!(
                err.is_finite(),
                "{}: non-finite f32/f64 difference at {cfg:?} {at}",
                e.info.id
            );
            if err > model_worst.0 {
                model_worst = (err, format!("{cfg:?} {at}"));
            }
        }
        println!(
            "f32-vs-f64 {:<24} measured {:.3e} (documented {:.0e}) at {}",
            e.info.id, model_worst.0, e.info.f32_bound, model_worst.1
        );
        if model_worst.0 > e.info.f32_bound {
            failures.push(format!(
                "{}: {:.3e} > {:.0e} at {}",
                e.info.id, model_worst.0, e.info.f32_bound, model_worst.1
            ));
        }
        // A documented bound more than 100x the measured error says nothing useful.
        assert!(
            model_worst.0 == 0.0 || model_worst.0 > e.info.f32_bound / 100.0,
            "{}: bound {:.0e} is loose (measured {:.3e})",
            e.info.id,
            e.info.f32_bound,
            model_worst.0
        );
    }
    assert!(
        failures.is_empty(),
        "f32 bound exceeded:\n{}",
        failures.join("\n")
    );
}
