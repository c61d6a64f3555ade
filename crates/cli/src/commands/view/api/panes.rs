//! `/api/panes`: the panes of BRDF Explorer (Walt Disney Animation Studios' tool) for every
//! model the explorer shows: the 3D lobe for an incident direction, the angle plots in
//! Rusinkiewicz's coordinates (f against theta_h, against theta_d, and against theta_v, the
//! outgoing angle in one plane), and the theta_h x theta_d slice at any phi_d.
//!
//! Every model goes through one code path, the batch trait [`UserBrdf`]: a registry model as
//! [`Builtin`] of the spec it is shaded as (a lobe or distribution as its BRDF, as the plots
//! and pictures show it), a user's model (`--model file:PATH`) as its GPU evaluator (one
//! dispatch per request), the measured reference as its table. RGB values are shown as their
//! Rec. 709 luminance, as in the other plots. docs/book/src/explorer-panes.md documents the
//! query and the JSON.

use super::grids::{curve_theta, luminance};
use super::query::{Query, Reference, Response, one_model, parse_u32, theta_i};
use super::user::eval_batch;
use crate::CliError;
use crate::commands::view::state::State;
use crate::model_args::asked_pairs;
use fastbrdf::sample::Strategy;
use fastbrdf::user::{Builtin, UserBrdf, check_rows};
use serde_json::{Value, json};
use std::time::Instant;

/// The keys of `/api/panes` that are not model parameters (taken out of the query before the
/// models' values are read: a model parameter of the same name would not reach a model).
pub const PANE_KEYS: [&str; 9] = [
    "theta_i", "phi_i", "phi_h", "phi_d", "phi_v", "theta_h", "theta_d", "res", "slice",
];
/// Default and largest theta_o count of the lobe grid (`res`; phi_o has twice as many).
pub const LOBE_RES: u32 = 32;
pub const MAX_LOBE_RES: u32 = 64;
/// Default and largest side of the theta_h x theta_d slice (`slice`).
pub const SLICE_SIDE: u32 = 48;
pub const MAX_SLICE_SIDE: u32 = 128;
/// Why a term (shadowing, Fresnel, split-sum) has no panes.
const TERM_WHY: &str =
    "a shadowing, Fresnel or split-sum term is not a BRDF: its curves are in the Terms plots";
/// Points of the theta_v plot (theta_v from -89.9 to 89.9 degrees).
const THETA_V_POINTS: usize = 361;
/// Largest polar angle sampled, degrees (the horizon itself is left out, as in the lobe curves).
const MAX_THETA: f64 = 89.9;

type Pair = ([f64; 3], [f64; 3]);

/// The unit vector at polar angle `theta` and azimuth `phi` (radians) in the shading frame.
fn dir(theta: f64, phi: f64) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    [st * cp, st * sp, ct]
}

/// The pair of Rusinkiewicz's coordinates (radians): the difference vector `d` at (theta_d,
/// phi_d) in the half vector's frame, its mirror about the half vector, both turned by theta_h
/// about y and then by phi_h about the normal (z).
pub fn rusinkiewicz(th: f64, ph: f64, td: f64, pd: f64) -> Pair {
    let d = dir(td, pd);
    let (s, c) = th.sin_cos();
    let (sp, cp) = ph.sin_cos();
    let turn = |v: [f64; 3]| {
        let r = [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]];
        [cp * r[0] - sp * r[1], sp * r[0] + cp * r[1], r[2]]
    };
    (turn(d), turn([-d[0], -d[1], d[2]]))
}

/// The measured reference as a batch BRDF (its R, G, B).
struct MeasuredBatch<'a>(&'a crate::commands::view::state::Measured);

impl UserBrdf for MeasuredBatch<'_> {
    fn name(&self) -> String {
        self.0.name.clone()
    }
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        check_rows(wi.len(), wo.len(), out.len(), 3)?;
        for (k, (a, b)) in wi.iter().zip(wo).enumerate() {
            out[3 * k..3 * k + 3].copy_from_slice(&self.0.brdf.eval_rgb(*a, *b));
        }
        Ok(())
    }
}

/// An angle `key` in degrees within `[lo, hi]` (`hi` excluded when `open`), or `default`.
fn angle(
    q: &Query,
    key: &str,
    default: f64,
    lo: f64,
    hi: f64,
    open: bool,
) -> Result<f64, CliError> {
    let Some(t) = q.get(key) else {
        return Ok(default);
    };
    let v: f64 = t.trim().parse().map_err(|_| {
        CliError::input(format!(
            "{key} '{}': not a number",
            fastbrdf_io::shorten(t, 64)
        ))
    })?;
    let inside = v >= lo && (v < hi || (!open && v == hi));
    if !inside {
        let close = if open { ")" } else { "]" };
        return Err(CliError::input(format!(
            "{key} {v}: must be in [{lo}, {hi}{close} degrees"
        )));
    }
    Ok(v)
}

/// The request's angles (degrees) and grid sizes.
struct Setup {
    ti: f64,
    pi: f64,
    ph: f64,
    pd: f64,
    pv: f64,
    th: f64,
    td: f64,
    res: usize,
    side: usize,
}

impl Setup {
    fn parse(q: &Query) -> Result<Self, CliError> {
        // theta_i, else the page's `theta` (its incidence angle), with the same range.
        let ti = match q.get("theta_i") {
            Some(_) => angle(q, "theta_i", 30.0, 0.0, 90.0, true)?,
            None => theta_i(q)?,
        };
        let pi = angle(q, "phi_i", 0.0, -360.0, 360.0, false)?;
        let default_pv = (pi + 180.0).rem_euclid(360.0);
        Ok(Self {
            ti,
            pi,
            ph: angle(q, "phi_h", 0.0, -360.0, 360.0, false)?,
            pd: angle(q, "phi_d", 90.0, -360.0, 360.0, false)?,
            pv: angle(q, "phi_v", default_pv, -360.0, 360.0, false)?,
            th: angle(q, "theta_h", 0.0, 0.0, 90.0, false)?,
            td: angle(q, "theta_d", 30.0, 0.0, 90.0, false)?,
            res: parse_u32(q, "res", LOBE_RES, 4, MAX_LOBE_RES)? as usize,
            side: parse_u32(q, "slice", SLICE_SIDE, 8, MAX_SLICE_SIDE)? as usize,
        })
    }

    fn lobe_theta(&self) -> Vec<f64> {
        (0..self.res)
            .map(|k| MAX_THETA * k as f64 / (self.res - 1) as f64)
            .collect()
    }
    fn lobe_phi(&self) -> Vec<f64> {
        (0..2 * self.res)
            .map(|j| 360.0 * j as f64 / (2 * self.res) as f64)
            .collect()
    }
    fn theta_v(&self) -> Vec<f64> {
        (0..THETA_V_POINTS)
            .map(|k| -MAX_THETA + 2.0 * MAX_THETA * k as f64 / (THETA_V_POINTS - 1) as f64)
            .collect()
    }
    /// The slice's cell centres, degrees (theta_h across, theta_d down).
    fn slice_theta(&self) -> Vec<f64> {
        (0..self.side)
            .map(|k| (k as f64 + 0.5) / self.side as f64 * 90.0)
            .collect()
    }
    fn wi(&self) -> [f64; 3] {
        dir(self.ti.to_radians(), self.pi.to_radians())
    }

    /// Every pair of a model's panes, in the order of [`Panes`]: the lobe grid (rows theta_o,
    /// columns phi_o), the theta_h, theta_d and theta_v plots, the slice (rows theta_d,
    /// columns theta_h), and the lengths of those parts.
    fn pairs(&self) -> (Vec<Pair>, [usize; 5]) {
        let r = f64::to_radians;
        let wi = self.wi();
        let mut out = Vec::new();
        for t in self.lobe_theta() {
            for p in self.lobe_phi() {
                out.push((wi, dir(r(t), r(p))));
            }
        }
        let n0 = out.len();
        let curve = curve_theta();
        for &t in &curve {
            out.push(rusinkiewicz(r(t), r(self.ph), r(self.td), r(self.pd)));
        }
        for &t in &curve {
            out.push(rusinkiewicz(r(self.th), r(self.ph), r(t), r(self.pd)));
        }
        let pv = r(self.pv);
        for t in self.theta_v() {
            let (s, c) = r(t).sin_cos();
            out.push((wi, [s * pv.cos(), s * pv.sin(), c]));
        }
        let st = self.slice_theta();
        for &d in &st {
            for &h in &st {
                out.push(rusinkiewicz(r(h), r(self.ph), r(d), r(self.pd)));
            }
        }
        let v = THETA_V_POINTS;
        (
            out,
            [n0, curve.len(), curve.len(), v, self.side * self.side],
        )
    }
}

/// `b` at every pair above the horizon (both z > 0), in one batch: per pair the value (RGB: its
/// luminance), None below the horizon or where it is not finite.
fn shown(b: &dyn UserBrdf, pairs: &[Pair]) -> Result<Vec<Option<f64>>, CliError> {
    let above: Vec<usize> = (0..pairs.len())
        .filter(|&k| pairs[k].0[2] > 0.0 && pairs[k].1[2] > 0.0)
        .collect();
    let batch: Vec<Pair> = above.iter().map(|&k| pairs[k]).collect();
    let c = b.channels().max(1);
    let v = if batch.is_empty() {
        vec![]
    } else {
        eval_batch(b, &batch)?
    };
    let mut out = vec![None; pairs.len()];
    for (j, &k) in above.iter().enumerate() {
        let x = &v[j * c..(j + 1) * c];
        let g = if c == 3 {
            luminance([x[0], x[1], x[2]])
        } else {
            x[0]
        };
        out[k] = g.is_finite().then_some(g);
    }
    Ok(out)
}

/// One model's panes: `id`, its kind, the batch BRDF it is evaluated as, `extra` fields.
fn panes_of(
    id: &str,
    kind: &str,
    b: &dyn UserBrdf,
    s: &Setup,
    extra: Value,
) -> Result<Value, CliError> {
    let (pairs, lens) = s.pairs();
    let mut v = shown(b, &pairs)?;
    // The lobe as drawn: f cos theta_o.
    for (k, x) in v[..lens[0]].iter_mut().enumerate() {
        if let Some(f) = x {
            *f *= pairs[k].1[2];
        }
    }
    let mut parts = Vec::new();
    let mut at = 0;
    for n in lens {
        parts.push(&v[at..at + n]);
        at += n;
    }
    let lobe_max = parts[0].iter().flatten().copied().fold(0.0, f64::max);
    let mut m = json!({
        "id": id, "kind": kind, "evaluated": b.name(),
        "channel": if b.channels() == 3 { "luminance" } else { "value" },
        "lobe": parts[0], "lobe_max": lobe_max,
        "theta_h": parts[1], "theta_d": parts[2], "theta_v": parts[3], "slice": parts[4],
    });
    if let (Value::Object(o), Value::Object(e)) = (&mut m, extra) {
        o.extend(e);
    }
    Ok(m)
}

/// `GET /api/panes?models=A,B&ref=R&NAME=VALUE...&theta_i=DEG&phi_i=DEG&phi_h=DEG&phi_d=DEG
/// &phi_v=DEG&theta_h=DEG&theta_d=DEG&res=N&slice=N`: each model's lobe, angle plots and
/// slice (docs/book/src/explorer-panes.md).
pub fn panes(state: &State, q: &Query) -> Result<Response, CliError> {
    let t = Instant::now();
    let s = Setup::parse(q)?;
    // The panes' own keys are not model parameters.
    let mq = Query(
        q.0.iter()
            .filter(|(k, _)| !PANE_KEYS.contains(&k.as_str()))
            .cloned()
            .collect(),
    );
    // Shadowing, Fresnel and split-sum terms are not BRDFs: skipped, named (kinds.rs draws
    // their curves).
    let skipped: Vec<Value> = super::kinds::split(state, &mq)?
        .terms
        .iter()
        .map(|(id, _)| json!({"id": id, "why": TERM_WHY}))
        .collect();
    let c = super::kinds::shaded(state, &mq)?;
    for (id, spec) in &c.models {
        one_model(id, spec)?;
    }
    use rayon::prelude::*;
    let mut out: Vec<Value> = c
        .models
        .par_iter()
        .map(|(id, spec)| {
            let b = Builtin::new(spec, Strategy::Auto)?;
            let kind = fastbrdf::registry::find(id)?.info.kind.name();
            let params: Vec<Value> = asked_pairs(id, spec)
                .iter()
                .map(|(k, v)| json!([k, v]))
                .collect();
            panes_of(id, kind, &b, &s, json!({ "params": params }))
        })
        .collect::<Result<_, CliError>>()?;
    // The users' models: one batch (a GPU dispatch) each.
    let user = |u: &super::query::UserPick| {
        let params: Vec<Value> = u.values.iter().map(|(k, v)| json!([k, v])).collect();
        let extra = json!({"params": params, "file": u.model.path.display().to_string()});
        panes_of(&u.model.name, "user", u.brdf.as_ref(), &s, extra)
    };
    for u in &c.users {
        out.push(user(u)?);
    }
    if let Some(u) = &c.ref_user {
        out.insert(0, user(u)?);
    }
    if let Some(Reference::Measured(m)) = &c.reference {
        let b = MeasuredBatch(m);
        out.insert(
            0,
            panes_of(&m.name, "measured", &b, &s, json!({"params": []}))?,
        );
    }
    Ok(Response::json(&json!({
        "theta_i_deg": s.ti, "phi_i_deg": s.pi, "phi_h_deg": s.ph, "phi_d_deg": s.pd,
        "phi_v_deg": s.pv, "theta_h_deg": s.th, "theta_d_deg": s.td, "wi": s.wi(),
        "lobe_theta_deg": s.lobe_theta(), "lobe_phi_deg": s.lobe_phi(),
        "curve_theta_deg": curve_theta(), "theta_v_deg": s.theta_v(),
        "slice_size": s.side, "slice_theta_deg": s.slice_theta(),
        "reference": c.reference.as_ref().map(Reference::name),
        "reference_kind": c.reference.as_ref().map(Reference::kind),
        "models": out,
        "skipped": skipped,
        "ms": t.elapsed().as_secs_f64() * 1e3,
    })))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rusinkiewicz_pairs_have_their_half_and_difference_angles() {
        let r = f64::to_radians;
        for (th, ph, td, pd) in [(20.0, 0.0, 35.0, 90.0), (50.0, 130.0, 10.0, 250.0)] {
            let (wi, wo) = rusinkiewicz(r(th), r(ph), r(td), r(pd));
            let h: Vec<f64> = (0..3).map(|k| wi[k] + wo[k]).collect();
            let n = h.iter().map(|x| x * x).sum::<f64>().sqrt();
            let cos_h = h[2] / n;
            let cos_d = (0..3).map(|k| wi[k] * h[k] / n).sum::<f64>();
            assert!((cos_h.acos().to_degrees() - th).abs() < 1e-9, "{th}");
            assert!((cos_d.acos().to_degrees() - td).abs() < 1e-9, "{td}");
            let phi_h = h[1].atan2(h[0]).to_degrees().rem_euclid(360.0);
            assert!((phi_h - ph).abs() < 1e-9, "{phi_h} vs {ph}");
        }
    }
}
