//! The speedups of a run: the seeds' claims, each approximation over its exact reference, the
//! GPU rows and thread scaling, each a ratio of two rows of the same run.

use super::{KernelRow, SpeedupRow};
use fastbrdf::{Kind, registry};

/// A naive scalar baseline's row from its time per 4096-element call.
pub(super) fn baseline(model: &str, secs: f64) -> KernelRow {
    KernelRow {
        model: model.into(),
        variant: "scalar".into(),
        batch: 4096,
        evals_per_s: 4096.0 / secs,
        isa: "scalar".into(),
        fma_fraction: None,
        limit: None,
        limit_fraction: None,
        instructions: None,
    }
}

fn find(k: &[KernelRow], model: &str, variant: &str, batch: usize) -> Option<f64> {
    k.iter()
        .find(|r| r.model == model && r.variant == variant && r.batch == batch)
        .map(|r| r.evals_per_s)
}

/// A GPU figure (one batch size per run).
fn find_gpu(k: &[KernelRow], model: &str) -> Option<f64> {
    k.iter()
        .find(|r| r.model == model && r.variant == "gpu")
        .map(|r| r.evals_per_s)
}

/// The speedups of one run: the seed-000 claims, each approximation over its exact reference
/// (SIMD over SIMD, and SIMD over the naive scalar loop), and thread scaling.
pub fn speedups(k: &[KernelRow], small: usize, large: usize) -> Vec<SpeedupRow> {
    let mut v = Vec::new();
    let mut push =
        |name: String, num: Option<f64>, den: Option<f64>, claimed: Option<f64>, how: String| {
            if let (Some(a), Some(b)) = (num, den) {
                v.push(SpeedupRow {
                    name,
                    measured: a / b,
                    claimed,
                    how,
                });
            }
        };
    let ct = |d: &str| format!("cook-torrance[seed-000,d={d}]");
    push(
        "ct.speedup".into(),
        find(k, &ct("beckmann-power16"), "scalar", small),
        find(k, &ct("beckmann-ct"), "scalar", small),
        Some(4.34),
        "scalar f32 Cook-Torrance as seed 000 (V-cavity G, Schlick F, (V.N)(L.N)): D16 over exp-based D, batch 4096".into(),
    );
    push(
        "ct.speedup.simd".into(),
        find(k, &ct("beckmann-power16"), "simd", small),
        find(k, &ct("beckmann-ct"), "simd", small),
        None,
        "the same, SIMD kernels on both sides".into(),
    );
    push(
        "ct.speedup.pow".into(),
        find(k, &ct("beckmann-pow"), "scalar", small),
        find(k, &ct("beckmann-ct"), "scalar", small),
        None,
        "scalar, the one-pow D (cos^(2/m^2-4)) over exp-based D".into(),
    );
    push(
        "ward.speedup".into(),
        find(k, "ward-power16", "scalar", small),
        find(k, "ward", "scalar", small),
        Some(2.0),
        "scalar f32 isotropic Ward: the g = 16 form of the exponential over exp (seed: more than 2)".into(),
    );
    push(
        "ward.speedup.simd".into(),
        find(k, "ward-power16", "simd", small),
        find(k, "ward", "simd", small),
        None,
        "the same, SIMD".into(),
    );
    push(
        "ward.speedup.pow".into(),
        find(k, "ward-pow", "scalar", small),
        find(k, "ward", "scalar", small),
        None,
        "scalar, cos^(2/m^2) over exp".into(),
    );
    for e in registry::all() {
        for b in e.info.bounds.iter().take(1) {
            let id = e.info.id;
            push(
                format!("{id}.over.{}.simd", b.reference),
                find(k, id, "simd", small),
                find(k, b.reference, "simd", small),
                None,
                format!("SIMD {id} over SIMD {}", b.reference),
            );
            if e.info.kind == Kind::Lobe {
                push(
                    format!("{id}.over.powf-loop"),
                    find(k, id, "simd", small),
                    find(k, "powf-loop", "scalar", small),
                    None,
                    format!("SIMD {id} over a scalar powf loop"),
                );
            }
        }
    }
    push(
        "pow.simd.over.powf-loop".into(),
        find(k, "pow", "simd", small),
        find(k, "powf-loop", "scalar", small),
        None,
        "SIMD exact pow over a scalar powf loop".into(),
    );
    push(
        "beckmann.simd.over.beckmann-expf-loop".into(),
        find(k, "beckmann", "simd", small),
        find(k, "beckmann-expf-loop", "scalar", small),
        None,
        "SIMD exact beckmann over the Beckmann formula in a scalar loop with expf".into(),
    );
    push(
        "beckmann.simd.over.expf-loop".into(),
        find(k, "beckmann", "simd", small),
        find(k, "expf-loop", "scalar", small),
        None,
        "SIMD exact beckmann (exp and 12 more operations) over a bare scalar expf loop".into(),
    );
    // GPU rows (`fastbrdf bench --gpu`): the same ratios on the GPU, and GPU over all CPU threads.
    push(
        "ct.speedup.gpu".into(),
        find_gpu(k, &ct("beckmann-power16")),
        find_gpu(k, &ct("beckmann-ct")),
        None,
        "seed 000's Cook-Torrance on the GPU: D16 over exp-based D".into(),
    );
    push(
        "ward.speedup.gpu".into(),
        find_gpu(k, "ward-power16"),
        find_gpu(k, "ward"),
        None,
        "isotropic Ward on the GPU: the g = 16 form over exp".into(),
    );
    for e in registry::all() {
        for b in e.info.bounds.iter().take(1) {
            let id = e.info.id;
            push(
                format!("{id}.over.{}.gpu", b.reference),
                find_gpu(k, id),
                find_gpu(k, b.reference),
                None,
                format!("GPU {id} over GPU {}", b.reference),
            );
        }
    }
    for m in ["pow", "power16", "beckmann", "cook-torrance", "ward"] {
        push(
            format!("{m}.gpu.over.cpu-threads"),
            find_gpu(k, m),
            find(k, m, "simd-threads", large),
            None,
            format!("{m}: GPU (data resident) over SIMD on all CPU threads, batch {large}"),
        );
    }
    for m in ["power16", "pow", "cook-torrance", "ward"] {
        push(
            format!("{m}.threads.scaling"),
            find(k, m, "simd-threads", large),
            find(k, m, "simd", large),
            None,
            format!("{m}: all threads over one thread, batch {large}"),
        );
    }
    v
}

#[cfg(test)]
mod tests {
    use super::super::Report;
    use super::*;

    #[test]
    fn measured_speedups_keep_the_run_order() {
        let kernels = vec![
            baseline("powf-loop", 4096.0 / 1e8),
            KernelRow {
                model: "pow".into(),
                variant: "simd".into(),
                batch: 4096,
                evals_per_s: 4e8,
                isa: "avx2".into(),
                fma_fraction: None,
                limit: None,
                limit_fraction: None,
                instructions: None,
            },
        ];
        let r = Report {
            cpu: "test".into(),
            isa: "avx2".into(),
            threads: 1,
            fma_per_s: 1e10,
            div_per_s: None,
            speedups: speedups(&kernels, 4096, 1 << 24),
            kernels,
            quick: true,
            gpu: None,
            peers: vec![],
            skipped: vec![],
        };
        let pairs = r.measured_speedups();
        assert_eq!(pairs.len(), r.speedups.len());
        let (name, v) = pairs
            .iter()
            .find(|(n, _)| n == "pow.simd.over.powf-loop")
            .expect("the pow speedup is computed");
        assert_eq!(name, "pow.simd.over.powf-loop");
        assert!((v - 4.0).abs() < 1e-12, "{v}");
    }
}
