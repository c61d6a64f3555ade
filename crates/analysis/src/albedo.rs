//! Directional albedo `a(wi) = integral f(wi, wo) cos theta_o dwo` against the incidence angle,
//! by deterministic nested adaptive Gauss-Kronrod (`fastbrdf::quad::albedo`, polar coordinates
//! around the mirror direction, split at the lobe's cut), with its error estimate; and the
//! white-furnace verdict (albedo <= 1) for models that claim to conserve energy.
//!
//! A non-reciprocal BRDF (`cook-torrance` with `ms = filament`, whose compensation uses the view
//! direction `wo` only) is integrated the other way, over `wi` at a fixed `wo` (`Target::view`):
//! the albedo its method defines. Energy-compensated models (`ms`) aim at 1 and may read above
//! it by their documented table error (`Target::furnace_tol`).
//!
//! Lobes are evaluated as BRDFs: `phong` (default: the lobe of `reflect(wi) . wo`, the geometry
//! of the seeds' normalisation) or `blinn-phong`, normalised (`norm = energy`) or not.

use fastbrdf::{Model, Result, registry};
use serde::Serialize;

/// One incidence angle.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct AlbedoRow {
    pub theta_deg: f64,
    pub albedo: f64,
    /// Estimated absolute error of the quadrature.
    pub error: f64,
}

/// A BRDF to integrate, described by registry id and parameters.
pub struct Target {
    pub id: String,
    pub params: Vec<(String, String)>,
    /// Whether the model claims energy conservation (albedo <= 1).
    pub claims_energy: bool,
    /// How far above 1 its albedo may read (`Plan::furnace_tol`).
    pub furnace_tol: f64,
    /// Integrate over `wi` at a fixed `wo` (the angle is the view's): non-reciprocal BRDFs.
    pub view: bool,
}

impl Target {
    /// The white furnace's tolerance: how far above 1 the albedo may read (at least 1e-6, the
    /// quadrature's own error).
    pub fn furnace_tolerance(&self) -> f64 {
        self.furnace_tol.max(1e-6)
    }

    /// The parameters as a JSON object ([`crate::params_json`]).
    pub fn params_json(&self) -> serde_json::Map<String, serde_json::Value> {
        crate::params_json(&self.params)
    }
}

/// Builds the BRDF target for any model id: full BRDFs as they are, lobes wrapped as `as_brdf`
/// (`phong` or `blinn-phong`) with `norm`. Distributions, shadowing and Fresnel terms are not
/// BRDFs: an error.
pub fn target(id: &str, params: &[(String, String)], as_brdf: &str, norm: &str) -> Result<Target> {
    let e = registry::find(id)?;
    match e.info.kind {
        fastbrdf::Kind::Brdf => {
            let given: Vec<(&str, &str)> = params
                .iter()
                .map(|(k, v)| (k.as_str(), v.as_str()))
                .collect();
            let plan = registry::plan(id, &given)?;
            Ok(Target {
                id: id.into(),
                params: params.to_vec(),
                // The model's own metadata (`BrdfForm::claims_energy`): normalised models.
                claims_energy: plan.claims_energy(),
                furnace_tol: plan.furnace_tol(),
                view: !plan.reciprocal(),
            })
        }
        fastbrdf::Kind::Lobe => {
            let mut p = vec![
                ("lobe".to_string(), id.to_string()),
                ("norm".to_string(), norm.to_string()),
            ];
            p.extend(params.iter().cloned());
            let given: Vec<(&str, &str)> =
                p.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
            let plan = registry::plan(as_brdf, &given)?;
            Ok(Target {
                claims_energy: plan.claims_energy(),
                furnace_tol: plan.furnace_tol(),
                view: !plan.reciprocal(),
                id: as_brdf.into(),
                params: p,
            })
        }
        k => Err(fastbrdf::Error::WrongKind {
            model: id.into(),
            expected: "brdf or lobe".into(),
            found: k.name().into(),
        }),
    }
}

/// The albedo at each incidence angle (degrees, in [0, 90)).
pub fn curve(t: &Target, angles_deg: &[f64], rel_tol: f64) -> Result<Vec<AlbedoRow>> {
    let given: Vec<(&str, &str)> = t
        .params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect();
    let Model::Brdf(b) = registry::build::<f64>(&t.id, &given)? else {
        unreachable!("target() only names BRDFs")
    };
    Ok(angles_deg
        .iter()
        .map(|&deg| {
            let th = deg.to_radians();
            let w = [th.sin(), 0.0, th.cos()];
            let mirror = [-w[0], -w[1], w[2]];
            let breaks = b.mirror_breaks();
            let (albedo, error) = if t.view {
                fastbrdf::quad::albedo(|wi| b.eval(wi, w), mirror, &breaks, rel_tol)
            } else {
                fastbrdf::quad::albedo(|wo| b.eval(w, wo), mirror, &breaks, rel_tol)
            };
            AlbedoRow {
                theta_deg: deg,
                albedo,
                error,
            }
        })
        .collect())
}

/// A quick estimate of [`curve`] for interactive use (the explorer draws it while the precise
/// curve computes): the same polar coordinates around the mirror direction and the same
/// outer breakpoints, but a fixed rule (Gauss-Legendre 7 points on [`QUICK_OUTER_PANELS`]
/// panels per outer interval, [`QUICK_INNER_PANELS`] per ring interval) instead of adaptive
/// refinement: about 30 times fewer evaluations, no error estimate (`error` is NaN). Its
/// accuracy is measured against [`curve`] in the explorer's tests, not guaranteed.
pub fn curve_quick(t: &Target, angles_deg: &[f64]) -> Result<Vec<AlbedoRow>> {
    let given: Vec<(&str, &str)> = t
        .params
        .iter()
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect();
    let Model::Brdf(b) = registry::build::<f64>(&t.id, &given)? else {
        unreachable!("target() only names BRDFs")
    };
    let breaks = b.mirror_breaks();
    Ok(angles_deg
        .iter()
        .map(|&deg| {
            let th = deg.to_radians();
            let w = [th.sin(), 0.0, th.cos()];
            let mirror = [-w[0], -w[1], w[2]];
            let albedo = if t.view {
                quick_albedo(|wi| b.eval(wi, w), mirror, &breaks)
            } else {
                quick_albedo(|wo| b.eval(w, wo), mirror, &breaks)
            };
            AlbedoRow {
                theta_deg: deg,
                albedo,
                error: f64::NAN,
            }
        })
        .collect())
}

/// Panels per outer (u) interval and per ring (phi) interval of [`curve_quick`].
pub const QUICK_OUTER_PANELS: usize = 2;
pub const QUICK_INNER_PANELS: usize = 8;

/// Gauss-Legendre 7 points on [-1, 1]: (node, weight), the non-negative nodes.
const GL7: [(f64, f64); 4] = [
    (0.0, 0.417_959_183_673_469_4),
    (0.405_845_151_377_397_2, 0.381_830_050_505_118_9),
    (0.741_531_185_599_394_4, 0.279_705_391_489_276_7),
    (0.949_107_912_342_758_5, 0.129_484_966_168_869_7),
];

/// `f` over `[a, b]` split at `breaks`, `panels` Gauss-Legendre 7 panels per piece.
fn fixed(f: impl Fn(f64) -> f64, a: f64, b: f64, breaks: &[f64], panels: usize) -> f64 {
    let mut pts = vec![a];
    let mut inner: Vec<f64> = breaks
        .iter()
        .copied()
        .filter(|x| *x > a && *x < b)
        .collect();
    inner.sort_by(f64::total_cmp);
    pts.extend(inner);
    pts.push(b);
    let mut sum = 0.0;
    for w in pts.windows(2) {
        for i in 0..panels {
            let lo = w[0] + (w[1] - w[0]) * i as f64 / panels as f64;
            let hi = w[0] + (w[1] - w[0]) * (i + 1) as f64 / panels as f64;
            let (c, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            let mut s = GL7[0].1 * f(c);
            for &(x, wt) in &GL7[1..] {
                s += wt * (f(c - h * x) + f(c + h * x));
            }
            sum += s * h;
        }
    }
    sum
}

/// `fastbrdf::quad::albedo`'s integral (polar coordinates around `peak`, the horizon cut of
/// each ring, u broken at 1 - 10^-k and `u_breaks`) with [`fixed`] rules.
fn quick_albedo(f: impl Fn([f64; 3]) -> f64, peak: [f64; 3], u_breaks: &[f64]) -> f64 {
    let p = peak;
    let t = if p[2].abs() < 0.9 {
        [p[1], -p[0], 0.0]
    } else {
        [0.0, p[2], -p[1]]
    };
    let tl = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
    let t = [t[0] / tl, t[1] / tl, t[2] / tl];
    let b = [
        p[1] * t[2] - p[2] * t[1],
        p[2] * t[0] - p[0] * t[2],
        p[0] * t[1] - p[1] * t[0],
    ];
    let ring = |u: f64| {
        let s = (1.0 - u * u).max(0.0).sqrt();
        let g = |phi: f64| {
            let (sp, cp) = phi.sin_cos();
            let w = [
                s * (cp * t[0] + sp * b[0]) + u * p[0],
                s * (cp * t[1] + sp * b[1]) + u * p[1],
                s * (cp * t[2] + sp * b[2]) + u * p[2],
            ];
            if w[2] > 0.0 { f(w) * w[2] } else { 0.0 }
        };
        let mut breaks = vec![];
        let (a, bb, c) = (s * t[2], s * b[2], u * p[2]);
        let r = (a * a + bb * bb).sqrt();
        if r > 0.0 && (c / r).abs() < 1.0 {
            let base = bb.atan2(a);
            let d = (-c / r).acos();
            for x in [base + d, base - d] {
                breaks.push(x.rem_euclid(2.0 * std::f64::consts::PI));
            }
        }
        fixed(
            g,
            0.0,
            2.0 * std::f64::consts::PI,
            &breaks,
            QUICK_INNER_PANELS,
        )
    };
    let mut breaks: Vec<f64> = (1..=7).map(|k| 1.0 - 10f64.powi(-k)).collect();
    breaks.extend_from_slice(u_breaks);
    // The wide piece [-1, 0.9] holds the diffuse part: a few more panels there.
    breaks.extend([-0.5, 0.0, 0.5]);
    fixed(ring, -1.0, 1.0, &breaks, QUICK_OUTER_PANELS)
}

/// The white-furnace verdict: `(holds, worst row)`; holds when every albedo is at most
/// `1 + max(tol, its error estimate)`.
pub fn furnace(rows: &[AlbedoRow], tol: f64) -> (bool, Option<AlbedoRow>) {
    let worst = rows
        .iter()
        .copied()
        .max_by(|a, b| a.albedo.total_cmp(&b.albedo));
    (
        rows.iter().all(|r| r.albedo <= 1.0 + tol.max(r.error)),
        worst,
    )
}
