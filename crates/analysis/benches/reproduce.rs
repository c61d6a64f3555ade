//! How long the whole seed-claim reproduction takes (every claim: ~10 sweeps over n = 1..1000
//! with refinement, 1000 quadratures, the fits), on all cores.
//! Run: `cargo bench -p fastbrdf-analysis --bench reproduce`.

fn main() {
    divan::main();
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn reproduce_all_claims() {
    let report = fastbrdf_analysis::reproduce::run(&[], &|| {}).expect("the report runs");
    divan::black_box(report);
}

/// One lobe sweep, the unit of the report: flog against pow, n = 1..1000, with refinement.
#[divan::bench(sample_count = 3, sample_size = 1)]
fn one_sweep_n_1_to_1000() {
    let spec = fastbrdf_analysis::errors::Spec {
        model: "flog".into(),
        reference: "pow".into(),
        param: "n".into(),
        zone: fastbrdf::Zone::All,
    };
    let ns: Vec<f64> = (1..=1000).map(f64::from).collect();
    divan::black_box(fastbrdf_analysis::errors::sweep(&spec, &ns, &|| {}).expect("sweep runs"));
}
