//! Prints the measured worst error of every documented bound (the numbers in the registry
//! are these, rounded up). Run: `cargo run --release -p fastbrdf --example measure_bounds`;
//! with `-- wide`, only the bounds on the widened domain of issue 14 (n above 1000, alpha
//! below 0.05); with `-- ID`, only that model's.
use rayon::prelude::*;

fn main() {
    let filter = std::env::args().nth(1);
    let mut rows = vec![];
    for e in fastbrdf::registry::all() {
        for b in e.info.bounds {
            let (name, lo, hi) = b.param;
            let keep = match filter.as_deref() {
                None => true,
                Some("wide") => (name == "n" && hi > 1000.0) || (name != "n" && lo < 0.05),
                Some(id) => e.info.id == id,
            };
            if keep {
                rows.push((e.info.id, b));
            }
        }
    }
    let lines: Vec<String> = rows
        .par_iter()
        .map(|(id, b)| {
            let w = fastbrdf::accuracy::worst(id, b).unwrap();
            let s = fastbrdf::accuracy::worst_search(id, b, fastbrdf::accuracy::SearchSize::CI)
                .unwrap();
            format!(
                "{:<18} vs {:<12} {:?} {:?} {}=[{},{}]: measured {:.6e} at {}={} x={:.8}; search {:.6e} at {}={} (documented {})",
                id,
                b.reference,
                b.metric,
                b.zone,
                b.param.0,
                b.param.1,
                b.param.2,
                w.err,
                b.param.0,
                w.param,
                w.x,
                s.err,
                b.param.0,
                s.param,
                b.bound
            )
        })
        .collect();
    for l in lines {
        println!("{l}");
    }
}
