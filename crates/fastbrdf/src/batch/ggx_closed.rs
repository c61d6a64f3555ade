//! Cook-Torrance with GGX in closed form (issue 30): the batch kernel of `d = ggx` with its own
//! Smith term, `g = smith-ggx` or `smith-ggx-correlated` (the same slope), `f = none` or
//! `schlick`, isotropic, without energy compensation: the Python package's and the renderer's
//! main case. (The rule of `batch::cook_torrance` sends these here.)
//!
//! With `h = wi + wo` of the unit directions (not normalised), `l = |h|^2`,
//! `q = alpha^2 h_z^2 + h_x^2 + h_y^2` and `s(w) = sqrt(w_z^2 + alpha^2 (w_x^2 + w_y^2))`:
//! `D = alpha^2 r^2 / pi` with `r = l / q` (`1 / (alpha^2 cos^2 + sin^2)` of the half vector,
//! in [1, 1 / alpha^2]), `G1(w) = 2 w_z / (w_z + s(w))` and `G2 = 2 wi_z wo_z / (wi_z s(wo) +
//! wo_z s(wi))`, so that
//!
//! - `smith-ggx`: `f = F 4 k alpha^2 r^2 / (pi (wi_z + s(wi)) (wo_z + s(wo)))`,
//! - `smith-ggx-correlated`: `f = F 2 k alpha^2 r^2 / (pi (wi_z s(wo) + wo_z s(wi)))`,
//!
//! `F` at `wi.h = sqrt(l) / 2`, `k` the denominator's constant. Two divisions and two square
//! roots (three with Schlick's term), where the product of the parts (`Pair`'s normalised half
//! vector, `D`, `G` and `F` apart, then `k / (cos_i cos_o)`) takes the half vector's f64
//! reciprocal root and, in f32, two roots and six divisions (`smith-ggx`: one in `D`, two per
//! `G1`, one for `k / (cos_i cos_o)`; five with `smith-ggx-correlated`). `D`'s cut at
//! `cos_h < COS_MIN` never applies: a valid pair has `h_z >= 2 COS_MIN` and `|h| <= 2`.
//!
//! Precision. The directions are normalised and added in f64 as `vec3::pair_setup` does
//! (the same validity and `COS_MIN` cut, so the same zeros as the scalar model; `h`'s x and
//! y free of cancellation for back-to-back pairs), then `h`, `wi`, `wo` are rounded once to
//! f32: every sum above adds non-negative terms. Within 2.5e-6 of the f64 model at the same
//! f32 inputs: the worst cases of its roundings add up to about 38 x 2^-24 (2.3e-6:
//! `l` and `q` 5 each, `r` 11, `r^2` 23, the denominator 11, the rest 4); measured, 7.5e-7
//! over 30 configurations (`alpha` 0.005 to 1, every denominator, unit and non-unit, grazing
//! and back-to-back pairs, the `COS_MIN` cut) and 9.2e-7 at the worst pair an adversarial
//! search found (`tests/ggx_closed.rs`; 9.1e-7 with ten times its steps). With
//! Schlick's term, add what it makes of a relative error of 2.4e-7 in `wi.h` (at most 5.4e-7
//! with `f0 = 0.04`; unbounded as `F` goes to 0, with `f0 = 0` and `wi.h` near 1, as for any
//! f32 `wi.h`). Not the parts' bits: the scalar models keep the product, and
//! `tests/kernels.rs` holds the two within 5e-6 of each other.
//!
//! Speed (`cargo run --release -p fastbrdf --example eval_speed`, AVX-512, one thread, GGX
//! alpha 0.3 `smith-ggx`, unit pairs): 2.39-2.41 ns an evaluation against 3.93-4.02 for the
//! product of the parts.

use super::{Imp, Map6, Op6};
use crate::forms::FresnelForm;
use crate::math::Math;
use crate::vec3::{COS_MIN, unit64};

/// The closed form (module header) with Fresnel term `F`; `CORRELATED`: `smith-ggx-correlated`,
/// else `smith-ggx`.
#[derive(Clone, Copy, Debug)]
pub(super) struct GgxClosed<F, const CORRELATED: bool> {
    /// `alpha^2`.
    a2: f32,
    /// `4 k alpha^2 / pi` (separable) or `2 k alpha^2 / pi` (correlated), rounded once.
    c: f32,
    f: F,
}

/// The kernel of the closed form at `alpha^2 = a2`, denominator constant `k`, Fresnel term
/// `f` (`NoFresnel` or `Schlick`: the callers' rule).
pub(super) fn kernel<F: FresnelForm, const CORRELATED: bool>(
    a2: f64,
    k: f64,
    f: F,
) -> Box<dyn Imp> {
    let m = if CORRELATED { 2.0 } else { 4.0 };
    Box::new(Map6 {
        simd: true,
        op: GgxClosed::<F, CORRELATED> {
            a2: a2 as f32,
            c: (m * k * a2 / std::f64::consts::PI) as f32,
            f,
        },
    })
}

impl<F: FresnelForm, const CORRELATED: bool> Op6 for GgxClosed<F, CORRELATED> {
    #[inline(always)]
    fn f<M: Math<f32>, const NEAR: bool>(&self, wi: [f32; 3], wo: [f32; 3]) -> f32 {
        // `vec3::pair_setup_as`'s normalisation, validity and cut, in f64.
        let (ui, vi) = unit64::<f32, NEAR>(wi);
        let (uo, vo) = unit64::<f32, NEAR>(wo);
        let valid = vi && vo && ui[2] >= COS_MIN && uo[2] >= COS_MIN;
        let h = [
            (ui[0] + uo[0]) as f32,
            (ui[1] + uo[1]) as f32,
            (ui[2] + uo[2]) as f32,
        ];
        let (i, o) = (ui.map(|x| x as f32), uo.map(|x| x as f32));
        let a2 = self.a2;
        let xy = M::madd(h[1], h[1], h[0] * h[0]);
        let l = M::madd(h[2], h[2], xy);
        let q = M::madd(a2 * h[2], h[2], xy);
        let r = l / q;
        let s = |w: [f32; 3]| M::madd(a2, M::madd(w[1], w[1], w[0] * w[0]), w[2] * w[2]).sqrt();
        let (si, so) = (s(i), s(o));
        let den = if CORRELATED {
            M::madd(i[2], so, o[2] * si)
        } else {
            (i[2] + si) * (o[2] + so)
        };
        // `NoFresnel` ignores its cosine: no square root is left in the loop.
        let fr = self.f.f::<f32, M>(0.5 * l.sqrt());
        // `F` last: the bracket is at least about 3e-7, so only a tiny `F` can flush to 0.
        let v = fr * (self.c * (r * r) / den);
        if valid { v } else { 0.0 }
    }
}
