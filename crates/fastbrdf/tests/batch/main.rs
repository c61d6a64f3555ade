//! Batch kernels: the vector math's documented accuracy, every model's kernel against its
//! scalar model (including NaN, infinities, out-of-range and back-facing inputs, and lengths
//! that leave tails), and bit-identical results across instruction sets and threads.//!
//! One test binary in topic files: `vector_math` (the elementary functions) and `kernels`
//! (kernels against the scalar models); the inputs they share are here.

#[path = "../common/mod.rs"]
mod common;
mod kernels;
mod vector_math;

use common::{build, configs, direction_pairs, kernel};
use fastbrdf::accuracy::lobe_samples;
use fastbrdf::batch::{Input, Isa, Kernel, math};
use fastbrdf::{Given, Kind, Model, ModelSpec, registry};

/// Inputs for a kernel: domain samples plus the awkward values, with a length that leaves a
/// tail for every vector width.
pub(crate) fn cos_inputs(n: f64) -> Vec<f32> {
    let mut v: Vec<f32> = lobe_samples(n).into_iter().map(|c| c as f32).collect();
    v.extend([
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -0.5,
        -0.0,
        0.0,
        1.0,
        1.5,
        1e-7,
        1e-30,
        0.5,
    ]);
    v.truncate(v.len() / 16 * 16 + 13);
    v
}

pub(crate) fn dir_inputs() -> [Vec<f32>; 6] {
    let mut cols: [Vec<f32>; 6] = Default::default();
    let mut push = |wi: [f32; 3], wo: [f32; 3]| {
        for k in 0..3 {
            cols[k].push(wi[k]);
            cols[k + 3].push(wo[k]);
        }
    };
    for (wi, wo) in direction_pairs(400, 9) {
        push(wi.map(|x| x as f32), wo.map(|x| x as f32));
    }
    let up = [0.0, 0.0, 1.0];
    for bad in [
        [0.0, 0.0, 0.0],
        [f32::NAN, 0.0, 1.0],
        [0.3, 0.2, -0.9],
        [1.0, 0.0, 0.0],
        [f32::INFINITY, 0.0, 1.0],
        [0.0, 0.0, 1e-9],
    ] {
        push(bad, up);
        push(up, bad);
    }
    push([3.0, 1.0, 5.0], [-2.0, 0.5, 4.0]); // unnormalised
    // Tiny, huge and subnormal lengths (issue 11: normalised scale-safely, like f64).
    for (i, (wi, wo)) in direction_pairs(12, 21).into_iter().enumerate() {
        let (a, b) = [(1e-30, 1e30), (3e38, 1e-42), (1e-42, 1.0), (1e-20, 1e20)][i % 4];
        push(wi.map(|x| (x * a) as f32), wo.map(|x| (x * b) as f32));
    }
    for c in cols.iter_mut() {
        c.truncate(c.len() / 16 * 16 + 7);
    }
    cols
}

/// Split-sum inputs `(cos_v, alpha)`: a grid over the domain and the awkward values in both
/// columns (the quadrature reference is slow in the scalar loop: a small set).
pub(crate) fn env_inputs() -> [Vec<f32>; 2] {
    let odd = [f32::NAN, f32::INFINITY, -0.5, 0.0, 1.0, 1.5, 1e-30];
    let mut cols: [Vec<f32>; 2] = Default::default();
    for v in [0.0f32, 1e-3, 0.05, 0.3, 0.7, 0.99, 1.0]
        .into_iter()
        .chain(odd)
    {
        for a in [0.005f32, 0.02, 0.1, 0.4, 1.0].into_iter().chain(odd) {
            cols[0].push(v);
            cols[1].push(a);
        }
    }
    cols
}

pub(crate) fn scalar(m: &Model<f32>, input: &Input, i: usize) -> f32 {
    match *input {
        Input::Cos(x) => m.eval_row(&[Some(x[i])]),
        Input::Dirs(w) => m.eval_row(&w.map(|s| Some(s[i]))),
        Input::Env(x) => m.eval_row(&x.map(|s| Some(s[i]))),
    }
}

/// Inputs where the scalar models return 0 by a documented rule (not by underflow).
pub(crate) fn scalar_zero_by_rule(input: &Input, i: usize) -> bool {
    match *input {
        Input::Cos(x) => x[i].is_nan(),
        // The split-sum terms clamp their inputs: no zero by rule.
        Input::Env(_) => false,
        Input::Dirs(w) => {
            let (a, b) = ([w[0][i], w[1][i], w[2][i]], [w[3][i], w[4][i], w[5][i]]);
            // The scalar models' own cut (COS_MIN decided in f64 on the given components),
            // not an approximation of it: a valid pair just above the cut whose value is 0
            // by clipping (a cubic's max(0, p)) may be a few ulp above 0 with fused
            // multiply-adds, within the tolerance.
            let bad = |v: [f32; 3]| {
                v.iter().any(|x| !x.is_finite())
                    || !fastbrdf::vec3::above_cos_min(v)
                    || (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
            };
            bad(a) || bad(b)
        }
    }
}

pub(crate) fn opt<T: Copy>(v: &[T]) -> Vec<Option<T>> {
    v.iter().copied().map(Some).collect()
}
