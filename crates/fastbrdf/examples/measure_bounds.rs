//! Prints the measured worst error of every documented bound (the numbers in the registry
//! are these, rounded up). Run: `cargo run --release -p fastbrdf --example measure_bounds`.
fn main() {
    for e in fastbrdf::registry::all() {
        for b in e.info.bounds {
            let w = fastbrdf::accuracy::worst(e.info.id, b).unwrap();
            println!(
                "{:<18} vs {:<12} {:?} {:?} {}=[{},{}]: measured {:.6e} at {}={} x={:.8} (documented {})",
                e.info.id,
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
                b.bound
            );
        }
    }
}
