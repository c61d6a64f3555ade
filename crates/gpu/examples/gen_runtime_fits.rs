//! Generates the fitted normalisation integrals of `crates/fastbrdf/src/runtime.wgsl`
//! (see `fastbrdf_gpu::runtime_fits`): prints the WGSL block and each fit's maximum relative
//! error against `reference_integral` (`lobe_integral`, kink-aware for the clamped flog) on 400 log-spaced n; with `--write`, replaces the block in
//! `runtime.wgsl`.
//!
//! `cargo run -p fastbrdf-gpu --example gen_runtime_fits [-- --write]`

use fastbrdf_gpu::runtime_fits::{generate, reference_integral, replace_block, wgsl_block};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let fits = generate()?;
    let block = wgsl_block(&fits);
    for f in &fits {
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..=400 {
            let n = f.n_lo * (f.n_hi / f.n_lo).powf(f64::from(i) / 400.0);
            let n = (n as f32 as f64).clamp(f.n_lo, f.n_hi);
            let want = reference_integral(f.lobe, n)?;
            let e = (f.integral(n) - want).abs() / want;
            if e > worst.0 {
                worst = (e, n);
            }
        }
        eprintln!(
            "{}: degree {}, max relative error {:.3e} at n = {}",
            f.lobe,
            f.coefs.len() - 1,
            worst.0,
            worst.1
        );
    }
    if std::env::args().any(|a| a == "--write") {
        // The core crate's file (`fastbrdf::plan::RUNTIME`), beside this crate.
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../fastbrdf/src/runtime.wgsl");
        let src = std::fs::read_to_string(path)?;
        let new = replace_block(&src, &block).ok_or("runtime.wgsl has no generated block")?;
        std::fs::write(path, new)?;
        eprintln!("wrote {path}");
    } else {
        print!("{block}");
    }
    Ok(())
}
