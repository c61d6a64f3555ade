//! The ends of the ranges where the GPU's f32 is further from f64 than the CPU's f32
//! (issue 27): Fresnel at eta = 0.01 near its critical angle, Beckmann Cook-Torrance and Ward
//! at alpha = 0.005 on grazing near-mirror pairs, Phong with a flog lobe at n = 200. The CPU
//! computes the pair set-up (half vector, cosines, `reflect(wi).wo`) in f64 and rounds once
//! (ARCHITECTURE.md, f32/f64 policy); WGSL has no f64, so the shader's pair set-up rounds
//! several times, and these corners amplify that rounding: a steep lobe, or a near-step
//! Fresnel term near its critical angle, turns a few ulp of its argument into a large
//! relative change.
//!
//! Measured on lavapipe (printed by this test) in the mixed metric
//! `|v - v64| / max(1, |v64|)`, v64 the f64 model on the same f32 inputs and parameters, for
//! the GPU (every coefficient form: storage, literals, runtime parameters) and the CPU's f32;
//! each GPU figure is asserted within the bound in `CORNERS` (the measured maximum, rounded
//! up), so that a change that makes a corner worse fails here, and ARCHITECTURE.md's table
//! quotes these figures.

mod common;

use fastbrdf_gpu::compute::{GpuInput, GpuKernel};

/// A corner: the model, its parameters and the bound on the GPU's mixed error there. The
/// bounds are lavapipe's maxima (LLVM 15), rounded up: Fresnel 1.20e-2 (CPU f32 3.8e-7) at
/// cos = 0.99995005, 5e-8 above the critical cosine 0.99994999875; Cook-Torrance (Beckmann)
/// 3.55e-3 and Ward 3.55e-3 (CPU 2.0e-6, 1.8e-6) at wi 89.9 degrees from the normal and wo
/// 1.4 degrees from the mirror (the f32 normalisations of wi and wo, each ~1e-7, survive the
/// cancellation in wi + wo, magnified 1/|wi + wo| = 36 times, and the exponent
/// tan^2 / alpha^2 ~ 6 multiplies it again); Phong 4.2e-4 and Blinn-Phong 3.0e-4 with flog at
/// n = 200 (CPU 6.3e-5, 7.1e-5). All coefficient forms measure the same: the error is the
/// pair set-up's, not the coefficients'.
struct Corner {
    label: &'static str,
    id: &'static str,
    params: &'static [(&'static str, &'static str)],
    bound: f64,
}

const CORNERS: [Corner; 5] = [
    Corner {
        label: "fresnel-dielectric eta = 0.01 near the critical angle",
        id: "fresnel-dielectric",
        params: &[("eta", "0.01")],
        bound: 2e-2,
    },
    Corner {
        label: "cook-torrance beckmann alpha = 0.005, grazing near-mirror",
        id: "cook-torrance",
        params: &[("d", "beckmann"), ("g", "smith"), ("alpha", "0.005")],
        bound: 5e-3,
    },
    Corner {
        label: "ward alpha = 0.005, grazing near-mirror",
        id: "ward",
        params: &[("alpha", "0.005")],
        bound: 5e-3,
    },
    Corner {
        label: "phong lobe = flog n = 200, near-mirror",
        id: "phong",
        params: &[("lobe", "flog"), ("n", "200")],
        bound: 6e-4,
    },
    Corner {
        label: "blinn-phong lobe = flog n = 200, near-mirror",
        id: "blinn-phong",
        params: &[("lobe", "flog"), ("n", "200")],
        bound: 5e-4,
    },
];

/// Cosines around the critical angle of eta < 1 (sin = eta): 4001 f32 steps either side, and
/// a log sweep out to 1e-2 away.
fn critical_cosines(eta: f64) -> Vec<f32> {
    let c = (1.0 - eta * eta).sqrt() as f32;
    let mut v = vec![];
    let mut x = c;
    for _ in 0..4000 {
        x = f32::from_bits(x.to_bits() - 1);
    }
    for _ in 0..8001 {
        v.push(x);
        x = f32::from_bits(x.to_bits() + 1).min(1.0);
    }
    for k in 0..400 {
        let d = 10f64.powf(-7.0 + 5.0 * k as f64 / 400.0);
        for s in [-1.0, 1.0] {
            let y = (c as f64 + s * d).clamp(0.0, 1.0) as f32;
            v.push(y);
        }
    }
    v
}

/// Pairs near the mirror direction: wi at polar angles up to 89.9 degrees (grazing), wo its
/// mirror turned by up to `spread` radians in polar angle and azimuth.
fn near_mirror(spread: f64) -> [Vec<f32>; 6] {
    let mut cols: [Vec<f32>; 6] = Default::default();
    let thetas = [10.0, 45.0, 70.0, 80.0, 85.0, 88.0, 89.0, 89.5, 89.8, 89.9];
    for &ti in &thetas {
        let ti = f64::to_radians(ti);
        for a in -20..=20 {
            for b in -20..=20 {
                let (dt, dp) = (spread * a as f64 / 20.0, spread * b as f64 / 20.0);
                let to = (ti + dt).min(89.95f64.to_radians());
                let po = std::f64::consts::PI + dp;
                let wi = [ti.sin(), 0.0, ti.cos()];
                let wo = [to.sin() * po.cos(), to.sin() * po.sin(), to.cos()];
                for (k, x) in wi.iter().chain(wo.iter()).enumerate() {
                    cols[k].push(*x as f32);
                }
            }
        }
    }
    cols
}

fn mixed(v: f64, want: f64) -> f64 {
    (v - want).abs() / want.abs().max(1.0)
}

#[test]
fn gpu_corners_at_the_ends_of_the_ranges_are_measured_and_bounded() {
    let Some(gpu) = common::gpu() else { return };
    let (d, q) = (&gpu.device, &gpu.queue);
    let mut failures = vec![];
    for c in &CORNERS {
        let cpu = fastbrdf::ModelSpec::parse(c.id, c.params)
            .and_then(|s| s.model::<f32>())
            .unwrap();
        let exact = fastbrdf::ModelSpec::parse(c.id, c.params)
            .and_then(|s| s.model::<f64>())
            .unwrap();
        let cos;
        let dirs;
        let (inputs, rows): (GpuInput, Vec<Vec<f32>>) = if c.id.starts_with("fresnel") {
            cos = critical_cosines(0.01);
            (GpuInput::Cos(&cos), cos.iter().map(|&x| vec![x]).collect())
        } else {
            let spread = if c.id.contains("phong") { 0.3 } else { 0.03 };
            dirs = near_mirror(spread);
            (
                GpuInput::Dirs([&dirs[0], &dirs[1], &dirs[2], &dirs[3], &dirs[4], &dirs[5]]),
                (0..dirs[0].len())
                    .map(|i| dirs.iter().map(|col| col[i]).collect())
                    .collect(),
            )
        };
        let want: Vec<f64> = rows
            .iter()
            .map(|r| {
                let r: Vec<Option<f64>> = r.iter().map(|&x| Some(x as f64)).collect();
                exact.eval_row(&r)
            })
            .collect();
        let cpu_err = rows
            .iter()
            .zip(&want)
            .map(|(r, &w)| {
                let r: Vec<Option<f32>> = r.iter().map(|&x| Some(x)).collect();
                mixed(cpu.eval_row(&r) as f64, w)
            })
            .fold(0.0, f64::max);
        for form in ["storage", "literals", "runtime"] {
            let instance = common::instance(c.id, c.params, form);
            let kernel = GpuKernel::new(d, instance).unwrap();
            let mut out = vec![0.0f32; rows.len()];
            kernel.eval(d, q, inputs, &mut out).unwrap();
            let (mut worst, mut at) = (0.0f64, 0);
            for (i, (&g, &w)) in out.iter().zip(&want).enumerate() {
                let e = mixed(g as f64, w);
                if e > worst || e.is_nan() {
                    (worst, at) = (e, i);
                }
            }
            eprintln!(
                "{} ({form}): GPU {worst:.3e}, CPU f32 {cpu_err:.3e} ({:.0}x) at {:?}: GPU {} CPU {} f64 {}",
                c.label,
                worst / cpu_err.max(1e-12),
                rows[at],
                out[at],
                {
                    let r: Vec<Option<f32>> = rows[at].iter().map(|&x| Some(x)).collect();
                    cpu.eval_row(&r)
                },
                want[at]
            );
            if worst.is_nan() || worst > c.bound {
                failures.push(format!("{} ({form}): {worst:.3e} > {}", c.label, c.bound));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
