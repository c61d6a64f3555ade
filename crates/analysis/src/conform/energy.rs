//! `energy`: the directional albedo `a(wo) = integral f(wi, wo) cos theta_i dwi`, batched.
//!
//! The coordinates are `fastbrdf::quad::albedo`'s: polar around the peak direction `p` (the
//! outer variable `u = cos angle(wi, p)` in [-1, 1], split at `1 - 10^-k` for k = 1..7, where
//! a narrow lobe lives; the inner one the azimuth around `p`, split where the horizon cuts the
//! ring, and at the rings tangent to the horizon), so an alpha = 0.01 peak is a band of a few
//! `u` pieces. Instead of nested adaptive
//! Gauss-Kronrod, which asks for one direction at a time, a fixed Gauss-Legendre 7 rule with
//! `2 * 2^r` panels per `u` piece and `6 * 2^r` per ring piece, every piece not yet settled
//! evaluated in one batch per round `r`; a piece settles when two rounds agree to its share
//! (`1 / pieces`) of `Config::energy_rel` times the albedo, in every channel.
//! The peak is whichever of the mirror direction of `wo`, `wo` itself (a retro-reflector)
//! and the normal the model is largest at.

use super::{At, Batched, Check, Config, num, wo_at};
use fastbrdf::quad::Polar;
use std::f64::consts::TAU;

/// One angle's albedo per channel, and whether the rounds converged.
pub struct Albedo {
    pub value: Vec<f64>,
    pub converged: bool,
}

pub fn check(m: &Batched, cfg: &Config) -> Result<Check, String> {
    let c = m.channels;
    let mut worst = (f64::NEG_INFINITY, 0.0, 0);
    let mut per_channel = vec![f64::NEG_INFINITY; c];
    let mut unsettled = vec![];
    for &deg in &cfg.energy_angles_deg {
        let a = albedo(m, wo_at(deg), cfg)?;
        if !a.converged {
            unsettled.push(deg);
        }
        for (j, &v) in a.value.iter().enumerate() {
            if worse(v, worst.0) {
                worst = (v, deg, j);
            }
            if worse(v, per_channel[j]) {
                per_channel[j] = v;
            }
        }
    }
    let limit = 1.0 + cfg.energy_tol;
    let pass = worst.0 <= limit;
    let mut s = format!(
        "max albedo {} at theta_o = {} deg (limit 1 + {})",
        num(worst.0),
        num(worst.1),
        num(cfg.energy_tol)
    );
    if c > 1 {
        let p: Vec<String> = per_channel.iter().map(|&v| num(v)).collect();
        s += &format!(" channel {}; per channel max [{}]", worst.2, p.join(", "));
    }
    if !unsettled.is_empty() {
        let d: Vec<String> = unsettled.iter().map(|&v| num(v)).collect();
        s += &format!(
            "; the quadrature did not settle to {} at {} deg",
            num(cfg.energy_rel),
            d.join(", ")
        );
    }
    Ok(Check::new("energy", pass, worst.0, limit, s).at(Some(At {
        theta_o_deg: Some(worst.1),
        channel: (c > 1).then_some(worst.2),
        ..At::default()
    })))
}

/// Whether `v` is worse than `w`: larger, or the first NaN (which fails).
fn worse(v: f64, w: f64) -> bool {
    !w.is_nan() && (v.is_nan() || v > w)
}

/// The albedo at `wo`, per channel.
pub fn albedo(m: &Batched, wo: [f64; 3], cfg: &Config) -> Result<Albedo, String> {
    let c = m.channels;
    let mirror = [-wo[0], -wo[1], wo[2]];
    let candidates = [mirror, wo, [0.0, 0.0, 1.0]];
    let f = m.eval_at(&candidates, wo)?;
    let mut peak = mirror;
    let mut best = f64::NEG_INFINITY;
    for (k, w) in candidates.iter().enumerate() {
        let v = f[k * c..(k + 1) * c]
            .iter()
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        if v > best {
            best = v;
            peak = *w;
        }
    }
    let polar = Polar::new(peak);
    let outer = outer_breaks(peak);
    // The outer pieces, each refined on its own: (lo, hi, round, value, settled).
    let mut ends = vec![-1.0, 1.0];
    ends.extend(outer.iter().copied().filter(|x| *x > -1.0 && *x < 1.0));
    ends.sort_by(f64::total_cmp);
    ends.dedup();
    let n = ends.len() - 1;
    let mut value: Vec<Option<Vec<f64>>> = vec![None; n];
    let mut settled = vec![false; n];
    for r in 0..cfg.energy_rounds.max(2) {
        let (po, pi) = (2 << r, 6 << r);
        let todo: Vec<usize> = (0..n).filter(|&p| !settled[p]).collect();
        if todo.is_empty() {
            break;
        }
        let mut dirs = Vec::new();
        let mut weights = Vec::new();
        let mut piece = Vec::new();
        for (t, &p) in todo.iter().enumerate() {
            for (u, wu) in rule(ends[p], ends[p + 1], &[], po) {
                for (phi, wp) in rule(0.0, TAU, &polar.horizon(u), pi) {
                    let w = polar.direction(u, phi);
                    if w[2] > 0.0 {
                        dirs.push(w);
                        weights.push(wu * wp * w[2]);
                        piece.push(t);
                    }
                }
            }
        }
        let f = m.eval_at(&dirs, wo)?;
        let mut a = vec![vec![0.0; c]; todo.len()];
        for (k, wt) in weights.iter().enumerate() {
            for j in 0..c {
                a[piece[k]][j] += wt * f[k * c + j];
            }
        }
        // A piece settles when its change is within its share of the tolerance on the total.
        let total: Vec<f64> = (0..c)
            .map(|j| {
                let known: f64 = (0..n)
                    .filter(|p| !todo.contains(p))
                    .map(|p| value[p].as_ref().map_or(0.0, |v| v[j]))
                    .sum();
                known + a.iter().map(|v| v[j]).sum::<f64>()
            })
            .collect();
        for (t, &p) in todo.iter().enumerate() {
            if let Some(prev) = &value[p] {
                settled[p] = (0..c).all(|j| {
                    (a[t][j] - prev[j]).abs() <= (cfg.energy_rel * total[j].abs() + 1e-9) / n as f64
                });
            }
            value[p] = Some(std::mem::take(&mut a[t]));
        }
    }
    let value = (0..c)
        .map(|j| value.iter().map(|v| v.as_ref().map_or(0.0, |v| v[j])).sum())
        .collect();
    Ok(Albedo {
        value,
        converged: settled.iter().all(|s| *s),
    })
}

/// The outer variable's breakpoints around `peak`: `1 - 10^-k` (k = 1..7, where narrow
/// lobes live) and the rings tangent to the horizon (the ring integral kinks there).
fn outer_breaks(peak: [f64; 3]) -> Vec<f64> {
    let mut outer: Vec<f64> = (1..=7).map(|k| 1.0 - 10f64.powi(-k)).collect();
    let touch = (1.0 - peak[2] * peak[2]).max(0.0).sqrt();
    outer.extend([touch, -touch]);
    outer
}

/// Gauss-Legendre 7 on [-1, 1]: the non-negative nodes and their weights.
const GL7: [(f64, f64); 4] = [
    (0.0, 0.417_959_183_673_469_4),
    (0.405_845_151_377_397_2, 0.381_830_050_505_118_9),
    (0.741_531_185_599_394_4, 0.279_705_391_489_276_7),
    (0.949_107_912_342_758_5, 0.129_484_966_168_869_7),
];

/// Nodes and weights of `[lo, hi]` split at `breaks` (those inside), each piece in `panels`
/// Gauss-Legendre 7 panels.
fn rule(lo: f64, hi: f64, breaks: &[f64], panels: usize) -> Vec<(f64, f64)> {
    let mut pts = vec![lo];
    let mut inner: Vec<f64> = breaks
        .iter()
        .copied()
        .filter(|x| *x > lo && *x < hi)
        .collect();
    inner.sort_by(f64::total_cmp);
    pts.extend(inner);
    pts.push(hi);
    let mut out = Vec::with_capacity((pts.len() - 1) * panels * 7);
    for w in pts.windows(2) {
        for i in 0..panels {
            let a = w[0] + (w[1] - w[0]) * i as f64 / panels as f64;
            let b = w[0] + (w[1] - w[0]) * (i + 1) as f64 / panels as f64;
            let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
            out.push((c, GL7[0].1 * h));
            for &(x, wt) in &GL7[1..] {
                out.push((c - h * x, wt * h));
                out.push((c + h * x, wt * h));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_integrates_polynomials_and_the_hemisphere() {
        let r = rule(-1.0, 1.0, &[0.3, 0.9], 2);
        let v: f64 = r.iter().map(|(x, w)| w * x.powi(6)).sum();
        assert!((v - 2.0 / 7.0).abs() < 1e-14, "{v}");
        // Integral of cos over the hemisphere around a grazing peak: pi.
        // Integral of cos over the hemisphere around a grazing peak: pi, the error falling
        // as the panels double (a square-root kink at the tangent rings limits the order).
        let peak = [0.999f64.sqrt(), 0.0, 0.001f64.sqrt()];
        let polar = Polar::new(peak);
        let mut errors = vec![];
        for panels in [2, 8, 32] {
            let mut s = 0.0;
            for (u, wu) in rule(-1.0, 1.0, &outer_breaks(peak), panels) {
                for (phi, wp) in rule(0.0, TAU, &polar.horizon(u), 3 * panels) {
                    let w = polar.direction(u, phi);
                    if w[2] > 0.0 {
                        s += wu * wp * w[2];
                    }
                }
            }
            errors.push((s - std::f64::consts::PI).abs());
        }
        assert!(
            errors[2] < 1e-6 && errors[2] < errors[1] && errors[1] < errors[0],
            "{errors:?}"
        );
    }
}
