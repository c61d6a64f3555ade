//! The batch kernels against f64 ([`kernel_worst`]): what `fastbrdf check` measures of the
//! code `eval` runs (the SIMD kernels of `crate::batch`, on each instruction set this CPU
//! has), where [`super::f32_worst`] measures the scalar f32 model. The inputs are
//! `f32_worst`'s grid, plus cosines at the ends of `[0, 1]` (zero, subnormal, tiny, grazing,
//! one) and, for validity alone, invalid ones (NaN, infinite, negative, above one,
//! back-facing and zero directions), which every kernel must answer with a finite,
//! non-negative value.

use super::mixed_error;
use super::precision::{Grid, GridKind};
use crate::batch::{Input, Isa, Kernel};
use crate::error::Result;
use crate::spec::ModelSpec;

/// Valid cosines at the ends of `[0, 1]`: zero, subnormal, the smallest normal, tiny,
/// grazing (issue 27's), and one and its neighbour.
const ENDS: [f32; 12] = [
    0.0,
    1e-45,
    1e-40,
    1.175_494_4e-38,
    1e-20,
    1e-7,
    1e-4,
    0.003_908_168,
    0.5,
    0.999,
    0.999_999_94,
    1.0,
];

/// Invalid inputs: the kernels' domain rules answer them (0 in every model so far).
const INVALID: [f32; 5] = [f32::NAN, f32::INFINITY, -0.5, 1.5, -0.0];

/// What [`kernel_worst`] found for one configuration.
#[derive(Clone, Debug, Default)]
pub struct KernelWorst {
    /// The largest `|kernel - f64| / max(1, |f64|)` over the valid inputs and every
    /// instruction set.
    pub err: f64,
    /// Where: the instruction set and the input.
    pub at: String,
    /// The instruction sets measured (`crate::batch::Isa::available`).
    pub isas: Vec<&'static str>,
    /// Kernel values compared (valid inputs, every instruction set) and checked for validity.
    pub evaluations: usize,
    /// The first non-finite or negative kernel value, where.
    pub invalid: Option<String>,
}

/// The batch kernel of `spec` against its f64 model on [`super::f32_worst`]'s grid and the
/// ends of the domain, on every instruction set of this CPU; `None` for a shadowing term
/// (no kernel: it is a part of BRDFs).
pub fn kernel_worst(spec: &ModelSpec) -> Result<Option<KernelWorst>> {
    let m64 = spec.model::<f64>()?;
    let Some(mut grid) = Grid::of(spec, &m64) else {
        return Ok(None);
    };
    let valid = grid.len();
    add_ends(&mut grid);
    let checked = grid.len();
    add_invalid(&mut grid);
    let kernel = Kernel::new(spec)?;
    // The f64 values, once for every instruction set.
    let want: Vec<f64> = (0..checked).map(|i| grid.eval(&m64, i)).collect();
    let mut found = KernelWorst::default();
    let mut out = vec![0.0f32; grid.len()];
    for &isa in Isa::available() {
        found.isas.push(isa.name());
        let c = &grid.cols;
        let input = match grid.kind {
            GridKind::Brdf => Input::Dirs([&c[0], &c[1], &c[2], &c[3], &c[4], &c[5]]),
            GridKind::Env => Input::Env([&c[0], &c[1]]),
            _ => Input::Cos(&c[0]),
        };
        kernel.eval_with(isa, input, &mut out)?;
        for (i, &v) in out.iter().enumerate() {
            found.evaluations += 1;
            if !(v.is_finite() && v >= 0.0) && found.invalid.is_none() {
                found.invalid = Some(format!("{} {}: {v}", isa.name(), grid.at(i)));
            }
            let Some(&w) = want.get(i) else {
                continue;
            };
            let err = mixed_error(v, w);
            if !(err <= found.err) {
                let end = if i >= valid { " (an end)" } else { "" };
                found.err = err;
                found.at = format!("{} {}{end}", isa.name(), grid.at(i));
            }
        }
    }
    Ok(Some(found))
}

/// A direction of cosine `c` with the azimuth `(ca, sa)`, its sine from f64.
fn dir(c: f32, (ca, sa): (f64, f64)) -> [f32; 3] {
    let s = (1.0 - c as f64 * c as f64).max(0.0).sqrt();
    [(s * ca) as f32, (s * sa) as f32, c]
}

fn push_pair(g: &mut Grid, wi: [f32; 3], wo: [f32; 3]) {
    for k in 0..3 {
        g.cols[k].push(wi[k]);
        g.cols[k + 3].push(wo[k]);
    }
}

/// The ends of the domain: [`ENDS`] as cosines; for a split-sum term with alphas 0.005,
/// 0.3 and 1; for a BRDF as `wi` and `wo` cosines (every pair of them, `wo` at two
/// azimuths) and each `wi` with its mirror direction.
fn add_ends(g: &mut Grid) {
    match g.kind {
        GridKind::Brdf => {
            for &ci in &ENDS {
                let wi = dir(ci, (1.0, 0.0));
                push_pair(g, wi, [-wi[0], -wi[1], wi[2]]);
                for &co in &ENDS {
                    push_pair(g, wi, dir(co, (-0.6, 0.8)));
                    push_pair(g, wi, dir(co, (0.28, -0.96)));
                }
            }
        }
        GridKind::Env => {
            for &c in &ENDS {
                for a in [0.005f32, 0.3, 1.0] {
                    g.cols[0].push(c);
                    g.cols[1].push(a);
                }
            }
        }
        _ => g.cols[0].extend_from_slice(&ENDS),
    }
}

/// Invalid inputs, checked for a finite non-negative answer only.
fn add_invalid(g: &mut Grid) {
    match g.kind {
        GridKind::Brdf => {
            let up = [0.0, 0.0, 1.0];
            let mut bad: Vec<[f32; 3]> = INVALID.iter().map(|&x| [x, 0.0, 1.0]).collect();
            bad.extend([
                [0.0; 3],
                [0.3, 0.2, -0.9],
                [1.0, 0.0, 0.0],
                [0.0, 0.0, 1e-9],
            ]);
            for b in bad {
                push_pair(g, b, up);
                push_pair(g, up, b);
            }
        }
        GridKind::Env => {
            for &x in &INVALID {
                g.cols[0].extend([x, 0.5]);
                g.cols[1].extend([0.3, x]);
            }
        }
        _ => g.cols[0].extend_from_slice(&INVALID),
    }
}
