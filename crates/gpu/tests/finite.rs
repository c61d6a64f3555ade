//! No NaN or infinity from a GPU twin where the CPU's f32 model is finite: every model, every
//! parameter set of its documented domain (`domain_configs`, extremes included), on hostile
//! but finite inputs: zero, subnormal and tiny cosines, cosines at and just beyond 1, the cut
//! `COS_MIN`, and directions of extreme lengths (squares that underflow or overflow f32),
//! grazing, opposite and back-facing. (Non-finite inputs are outside the GPU contract: WGSL
//! lets implementations ignore NaN and infinity.) `FASTBRDF_FINITE_REPORT=1` lists the finite
//! rows where the two differ.

mod common;

use fastbrdf::model::Kind;
use fastbrdf::registry;
use fastbrdf_gpu::GpuKernel;
use fastbrdf_gpu::compute::GpuInput;
use fastbrdf_gpu::spec::Instance;

const COS: [f32; 16] = [
    -1.0,
    -1e-30,
    0.0,
    1e-40,
    1e-30,
    1e-12,
    9.536_743e-7,
    9.5367e-7,
    1e-6,
    1e-3,
    0.5,
    0.999_999_94,
    1.0,
    1.000_000_1,
    2.0,
    1e30,
];

fn dirs() -> Vec<[f32; 3]> {
    let mut v = vec![];
    for s in [1e-30f32, 1e-20, 1e-19, 1.0, 1e19, 1e20, 3e38] {
        for d in [
            [0.0, 0.0, 1.0],
            [0.6, 0.0, 0.8],
            [-0.6, 0.1, 0.8],
            [1.0, 0.0, 1e-6],
            [1.0, 0.0, 9.536_743e-7],
            [0.0, 1.0, 0.0],
            [0.3, 0.2, -0.5],
        ] {
            v.push(d.map(|x| x * s));
        }
    }
    v
}

/// The finiteness checks of `configs` of model `info` on `gpu`: how many values were checked,
/// and the failures (at most 40).
fn finite_checks(
    gpu: &fastbrdf_gpu::Gpu,
    info: &fastbrdf::ModelInfo,
    configs: &[Vec<(String, String)>],
) -> (usize, Vec<String>) {
    let (d, q) = (&gpu.device, &gpu.queue);
    let ds = dirs();
    let mut cols6: [Vec<f32>; 6] = Default::default();
    for a in &ds {
        for b in &ds {
            for (k, x) in a.iter().chain(b.iter()).enumerate() {
                cols6[k].push(*x);
            }
        }
    }
    // Split-sum terms: every pair of the special values as (cos_v, alpha).
    let mut cols2: [Vec<f32>; 2] = Default::default();
    for a in COS {
        for b in COS {
            cols2[0].push(a);
            cols2[1].push(b);
        }
    }
    let mut cols4: [Vec<f32>; 4] = Default::default();
    for a in COS {
        for b in COS {
            for c in [0.0, 1e-30, 0.5, 1.0] {
                for dd in [0.0, 1e-30, 0.5, 1.0] {
                    for (col, x) in cols4.iter_mut().zip([a, b, c, dd]) {
                        col.push(x);
                    }
                }
            }
        }
    }
    let mut failures = vec![];
    let mut checked = 0usize;
    // FASTBRDF_FINITE_REPORT=1 lists the finite rows where GPU and CPU differ (by more than
    // 1e-3, mixed): inputs the GPU twins do not treat as the CPU does.
    let report = std::env::var_os("FASTBRDF_FINITE_REPORT").is_some();
    let (inputs, rows): (GpuInput, Vec<Vec<Option<f32>>>) = match info.kind {
        Kind::Lobe | Kind::Distribution | Kind::Fresnel => (
            GpuInput::Cos(&COS),
            COS.iter().map(|c| vec![Some(*c)]).collect(),
        ),
        Kind::Shadowing => (
            GpuInput::Shadow([&cols4[0], &cols4[1], &cols4[2], &cols4[3]]),
            {
                let half_vector = fastbrdf::ModelSpec::parse(info.id, &[])
                    .and_then(|s| s.model::<f32>())
                    .unwrap()
                    .columns()
                    .0
                    .contains(&"cos_vh");
                (0..cols4[0].len())
                    .map(|i| {
                        let [v, l, h, vh] = [0, 1, 2, 3].map(|k| cols4[k][i]);
                        // The half-vector terms (v-cavity, kelemen) read cos_h, cos_vh.
                        if half_vector {
                            vec![Some(v), Some(h), Some(vh), Some(l)]
                        } else {
                            vec![Some(v), Some(l)]
                        }
                    })
                    .collect()
            },
        ),
        Kind::Brdf => (
            GpuInput::Dirs([
                &cols6[0], &cols6[1], &cols6[2], &cols6[3], &cols6[4], &cols6[5],
            ]),
            (0..cols6[0].len())
                .map(|i| cols6.iter().map(|c| Some(c[i])).collect())
                .collect(),
        ),
        Kind::Env => (
            GpuInput::Env([&cols2[0], &cols2[1]]),
            (0..cols2[0].len())
                .map(|i| vec![Some(cols2[0][i]), Some(cols2[1][i])])
                .collect(),
        ),
    };
    for config in configs {
        let given: Vec<(&str, &str)> = config
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .collect();
        let cpu = fastbrdf::ModelSpec::parse(info.id, &given)
            .and_then(|s| s.model::<f32>())
            .unwrap();
        let kernel = GpuKernel::new(
            d,
            Instance::with_storage(&common::spec(info.id, &given)).unwrap(),
        )
        .unwrap();
        let mut out = vec![0.0f32; rows.len()];
        kernel.eval(d, q, inputs, &mut out).unwrap();
        for (row, got) in rows.iter().zip(&out) {
            checked += 1;
            let want = cpu.eval_row(row);
            if report && (*got as f64 - want as f64).abs() > 1e-3 * (want.abs() as f64).max(1.0) {
                eprintln!("{} {config:?} at {row:?}: gpu {got}, cpu {want}", info.id);
            }
            if want.is_finite() && !got.is_finite() && failures.len() < 40 {
                failures.push(format!(
                    "{} {config:?} at {row:?}: gpu {got}, cpu {want}",
                    info.id
                ));
            }
        }
    }
    (checked, failures)
}

#[test]
fn no_gpu_twin_is_non_finite_where_the_cpu_is_finite() {
    let Some(gpu) = common::gpu() else { return };
    let (checked, mut failures) = common::check_every_model(gpu, finite_checks);
    failures.truncate(40);
    assert!(checked > 100_000, "only {checked}");
    assert!(
        failures.is_empty(),
        "non-finite GPU values where the CPU is finite:\n{}",
        failures.join("\n")
    );
}

/// Every BRDF twin is scale-invariant in its directions, bit for bit, down to lengths whose
/// squares underflow f32 and up to lengths whose squares overflow it: (1e-30, 0, 1e-30) is a
/// direction, not a zero vector (issue 11; the CPU normalises the same way, fastbrdf::vec3::unit).
/// Base directions have a largest component of exactly 1, so scaling by a power of two and the
/// twin's rescaling by the largest component give back the very same f32 numbers.
#[test]
fn brdf_twins_are_scale_invariant_in_their_directions() {
    let Some(gpu) = common::gpu() else { return };
    let (d, q) = (&gpu.device, &gpu.queue);
    let mut base: Vec<[f32; 3]> = vec![];
    for a in [-1.0f32, -0.5, -0.1, 0.0, 0.3, 0.9] {
        for b in [-0.7f32, 0.0, 0.2] {
            base.push([a, b, 1.0]);
        }
    }
    for z in [1e-3f32, 0.05, 0.5] {
        base.push([1.0, 0.25, z]);
        base.push([-1.0, 0.0, z]);
    }
    let scales: Vec<f32> = [-100, -90, -64, 0, 64, 70, 100, 120]
        .iter()
        .map(|&k| 2f32.powi(k))
        .collect();
    let mut cols: [Vec<f32>; 6] = Default::default();
    for &s in &scales {
        for a in &base {
            for b in &base {
                for (k, x) in a.iter().chain(b.iter()).enumerate() {
                    cols[k].push(x * s);
                }
            }
        }
    }
    let per_scale = base.len() * base.len();
    let unit = scales.iter().position(|&s| s == 1.0).unwrap();
    let mut failures = vec![];
    for e in registry::all().iter().filter(|e| e.info.kind == Kind::Brdf) {
        for config in common::gpu_configs(&e.info) {
            let given: Vec<(&str, &str)> = config
                .iter()
                .map(|(k, v)| (k.as_str(), v.as_str()))
                .collect();
            let kernel = GpuKernel::new(
                d,
                Instance::with_storage(&common::spec(e.info.id, &given)).unwrap(),
            )
            .unwrap();
            let mut out = vec![0.0f32; cols[0].len()];
            let input =
                GpuInput::Dirs([&cols[0], &cols[1], &cols[2], &cols[3], &cols[4], &cols[5]]);
            kernel.eval(d, q, input, &mut out).unwrap();
            let at_one = &out[unit * per_scale..(unit + 1) * per_scale];
            for (si, s) in scales.iter().enumerate() {
                let at_s = &out[si * per_scale..(si + 1) * per_scale];
                if let Some(i) = (0..per_scale).find(|&i| at_s[i].to_bits() != at_one[i].to_bits())
                    && failures.len() < 20
                {
                    failures.push(format!(
                        "{} {config:?}, directions scaled by {s:e}: {} instead of {} at row {i}",
                        e.info.id, at_s[i], at_one[i]
                    ));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "BRDF twins that depend on the directions' length:\n{}",
        failures.join("\n")
    );
}
