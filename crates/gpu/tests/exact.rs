//! Exact points: where a model's value is its peak (a lobe at c = 1, a distribution at
//! cos_h = 1, a BRDF with wi = wo = the normal), the GPU must return that peak to the last
//! bit or two, in every coefficient form (storage, literals, symbolic). Near such a point
//! a shader compiler that folds literal coefficients and reassociates (Mesa's NIR does:
//! `(a + #b) * #c -> a #c + #(b c)`, then sums of literals) can turn an arrangement whose
//! terms cancel into a difference of two rounded constants of size n: seed 003's `rational`
//! at n = 5000 was off by 3.4e-4 relative at c = 1 on real GPU compilers (issue 11).
//!
//! The peak is the f64 model's value rounded to f32; the GPU may differ by `ULPS` f32 ulp
//! (the f32 rounding of a coefficient computed in f64, and one WGSL division of 2.5 ulp;
//! Cook-Torrance: `ULPS_COOK_TORRANCE`). Fresnel and shadowing terms have no peak of this
//! kind and are left to tests/parity.rs.

mod common;

use fastbrdf::model::Kind;
use fastbrdf::registry;
use fastbrdf_gpu::GpuKernel;
use fastbrdf_gpu::compute::GpuInput;

/// Allowed distance from the peak, in f32 ulp of the peak.
const ULPS: f64 = 4.0;
/// Cook-Torrance at the normal is F D G k / (cos_i cos_o) with the exact Fresnel terms: a chain
/// of some 20 f32 operations, WGSL's division and sqrt at 2.5 ulp each (lavapipe: 9 ulp).
/// Nothing there cancels, so no folding can make it worse than the chain's rounding.
const ULPS_COOK_TORRANCE: f64 = 16.0;

/// The largest relative error bound of runtime.wgsl's `fb_rt_lobe_integral_*` (schlick,
/// schlick-modified and rational: 2.5e-6; measured by tests/runtime.rs on lavapipe).
const RUNTIME_NORM_REL: f64 = 2.5e-6;

fn ulp(x: f32) -> f64 {
    let x = x.abs();
    if x == 0.0 {
        return f32::from_bits(1) as f64;
    }
    (f32::from_bits(x.to_bits() + 1) - x) as f64
}

/// The peak checks of `configs` of model `info` on `gpu`: how many were made, and the failures.
fn peak_checks(
    gpu: &fastbrdf_gpu::Gpu,
    info: &fastbrdf::ModelInfo,
    configs: &[Vec<(String, String)>],
) -> (usize, Vec<String>) {
    let (d, q) = (&gpu.device, &gpu.queue);
    let mut failures = vec![];
    let mut checked = 0;
    let (cos, dirs): (Vec<f32>, [Vec<f32>; 6]);
    let (inputs, row64): (GpuInput, Vec<Option<f64>>) = match info.kind {
        Kind::Lobe | Kind::Distribution => {
            cos = vec![1.0];
            (GpuInput::Cos(&cos), vec![Some(1.0)])
        }
        Kind::Brdf => {
            dirs = [
                vec![0.0],
                vec![0.0],
                vec![1.0],
                vec![0.0],
                vec![0.0],
                vec![1.0],
            ];
            (
                GpuInput::Dirs([&dirs[0], &dirs[1], &dirs[2], &dirs[3], &dirs[4], &dirs[5]]),
                [0.0, 0.0, 1.0, 0.0, 0.0, 1.0].map(Some).to_vec(),
            )
        }
        Kind::Fresnel | Kind::Shadowing | Kind::Env => return (0, vec![]),
    };
    for config in configs {
        let given: Vec<(&str, &str)> = config
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .collect();
        let exact = fastbrdf::ModelSpec::parse(info.id, &given)
            .and_then(|s| s.model::<f64>())
            .unwrap();
        let peak = exact.eval_row(&row64) as f32;
        for &form in common::forms(info, config) {
            let instance = common::instance(info.id, &given, form);
            let rt_norm = instance.wrapper.contains("fb_rt_lobe_integral_");
            let kernel = GpuKernel::new(d, instance).unwrap();
            let mut out = [0.0f32];
            kernel.eval(d, q, inputs, &mut out).unwrap();
            let off = (out[0] as f64 - peak as f64).abs() / ulp(peak);
            checked += 1;
            let ulps = if info.id == "cook-torrance" {
                ULPS_COOK_TORRANCE
            } else {
                ULPS
            };
            // A runtime normalisation coef(n) = 1 / (2 pi Int(n)) is computed in f32 in
            // the shader: the peak moves by its relative error (tests/runtime.rs).
            let ulps = if rt_norm {
                ulps + RUNTIME_NORM_REL * f64::from(peak.abs()) / ulp(peak)
            } else {
                ulps
            };
            if off.is_nan() || off > ulps {
                failures.push(format!(
                    "{} ({form}) {config:?}: gpu {:e}, peak {:e} ({off:.0} ulp)",
                    info.id, out[0], peak
                ));
            }
        }
    }
    (checked, failures)
}

#[test]
fn every_lobe_distribution_and_brdf_is_exactly_its_peak_at_its_peak() {
    let Some(gpu) = common::gpu() else { return };
    let (checked, failures) = common::check_every_model(gpu, peak_checks);
    assert!(checked > 300, "only {checked} checks");
    assert!(
        failures.is_empty(),
        "{} of {checked} off their peak:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Allowed error near the peak, relative to the peak, for lobes (lavapipe: at most 9.2e-6, in
/// flog-normalized-clamped at n = 2000, where the clamp at 1 meets a slope of ~n / ln 2).
const NEAR_PEAK: f64 = 2e-5;
/// The same for the cubic family with literal coefficients (lavapipe: at most 3.7e-5, cubic at
/// n = 10000): a compiler folds `(y + x2) d3` into `y d3 + #(x2 d3)` and the sum with d2, whose
/// terms reach 1e8, cancels. Coefficients in a buffer (the compute and render paths) or passed
/// as uniforms keep the arrangement.
const NEAR_PEAK_LITERAL_CUBICS: f64 = 6e-5;

/// Near the peak (c in [1 - 10/n, 1]), every lobe within `NEAR_PEAK` of the f64 model, relative
/// to the peak, in every coefficient form. This is where a lerp rewrite of `1 + s (c - 1)` into
/// `(1 - s) + s c` (Mesa, in every form) cost the power lobes and the cubics about n ulp of the
/// peak (4.8e-4 at n = 10000 on lavapipe), and WGSL's pow about 2n ulp (6.4e-4).
#[test]
fn every_lobe_is_accurate_near_its_peak() {
    let Some(gpu) = common::gpu() else { return };
    let (d, q) = (&gpu.device, &gpu.queue);
    let mut failures = vec![];
    let report = std::env::var_os("FASTBRDF_PARITY_REPORT").is_some();
    for e in registry::all().iter().filter(|e| e.info.kind == Kind::Lobe) {
        let info = &e.info;
        for config in common::gpu_configs(info) {
            let given: Vec<(&str, &str)> = config
                .iter()
                .map(|(k, v)| (k.as_str(), v.as_str()))
                .collect();
            let n: f64 = given
                .iter()
                .find(|(k, _)| *k == "n")
                .map(|(_, v)| v.parse().unwrap())
                .unwrap();
            let cos: Vec<f32> = (0..=512)
                .map(|i| (1.0 - i as f64 * 10.0 / (512.0 * n)).max(0.0) as f32)
                .collect();
            let exact = fastbrdf::ModelSpec::parse(info.id, &given)
                .and_then(|s| s.model::<f64>())
                .unwrap();
            let want: Vec<f64> = cos
                .iter()
                .map(|&c| exact.eval_row(&[Some(c as f64)]))
                .collect();
            let peak = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for form in ["storage", "literals", "symbolic"] {
                let instance = common::instance(info.id, &given, form);
                let kernel = GpuKernel::new(d, instance).unwrap();
                let mut out = vec![0.0f32; cos.len()];
                kernel.eval(d, q, GpuInput::Cos(&cos), &mut out).unwrap();
                let (err, at) = out
                    .iter()
                    .zip(&want)
                    .enumerate()
                    .map(|(i, (g, w))| ((*g as f64 - w).abs() / peak, i))
                    .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
                let line = format!(
                    "{} ({form}) {config:?}: {err:.2e} of the peak at c = {}",
                    info.id, cos[at]
                );
                if report {
                    eprintln!("{line}");
                }
                let tol = if form == "literals" && info.id.starts_with("cubic") {
                    NEAR_PEAK_LITERAL_CUBICS
                } else {
                    NEAR_PEAK
                };
                if err.is_nan() || err > tol {
                    failures.push(line);
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} lobes off near their peak:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
