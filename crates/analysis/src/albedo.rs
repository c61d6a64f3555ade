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

use fastbrdf::{Given, Model, ModelSpec, Result};
use serde::Serialize;

/// One incidence angle.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct AlbedoRow {
    pub theta_deg: f64,
    pub albedo: f64,
    /// Estimated absolute error of the quadrature.
    pub error: f64,
}

/// A BRDF to integrate: its spec (a lobe wrapped as the BRDF [`target`] names) and what its
/// plan says of its energy.
pub struct Target {
    /// The BRDF integrated.
    pub spec: ModelSpec,
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

    /// The BRDF's registry id.
    pub fn id(&self) -> &'static str {
        self.spec.id()
    }

    /// The given values as a JSON object ([`crate::params_json`]).
    pub fn params_json(&self) -> serde_json::Map<String, serde_json::Value> {
        crate::params_json(&self.spec)
    }
}

/// The BRDF target of any (grey) model: full BRDFs as they are, lobes wrapped as `as_brdf`
/// (`phong` or `blinn-phong`) with `lobe` and `norm` (the lobe's given values passed on).
/// Distributions, shadowing and Fresnel terms are not BRDFs: an error; so is a coloured spec
/// (integrate each of [`ModelSpec::channel_specs`]).
pub fn target(spec: &ModelSpec, as_brdf: &str, norm: &str) -> Result<Target> {
    let brdf = match spec.kind() {
        fastbrdf::Kind::Brdf => spec.clone(),
        fastbrdf::Kind::Lobe => {
            let mut given = vec![
                ("lobe", Given::Choice(spec.id().into())),
                ("norm", Given::Choice(norm.into())),
            ];
            given.extend(spec.given().iter().cloned());
            ModelSpec::new(as_brdf, &given)?
        }
        k => {
            return Err(fastbrdf::Error::WrongKind {
                model: spec.id().into(),
                expected: "brdf or lobe".into(),
                found: k.name().into(),
            });
        }
    };
    let plan = brdf.plan()?;
    Ok(Target {
        // The model's own metadata (`BrdfForm::claims_energy`): normalised models.
        claims_energy: plan.claims_energy(),
        furnace_tol: plan.furnace_tol(),
        view: !plan.reciprocal(),
        spec: brdf,
    })
}

/// The albedo at each incidence angle (degrees, in [0, 90)).
pub fn curve(t: &Target, angles_deg: &[f64], rel_tol: f64) -> Result<Vec<AlbedoRow>> {
    rows(t, angles_deg, |f, mirror, breaks| {
        fastbrdf::quad::albedo(f, mirror, breaks, rel_tol)
    })
}

/// A quick estimate of [`curve`] for interactive use (the explorer draws it while the precise
/// curve computes): the same polar coordinates around the mirror direction and the same
/// outer breakpoints (and three more in the wide diffuse piece), but a fixed rule
/// (`fastbrdf::quad::albedo_fixed`: Gauss-Legendre 7 points on [`QUICK_OUTER_PANELS`] panels
/// per outer interval, [`QUICK_INNER_PANELS`] per ring interval) instead of adaptive
/// refinement: about 30 times fewer evaluations, no error estimate (`error` is NaN). Its
/// accuracy is measured against [`curve`] in the explorer's tests, not guaranteed.
pub fn curve_quick(t: &Target, angles_deg: &[f64]) -> Result<Vec<AlbedoRow>> {
    rows(t, angles_deg, |f, mirror, breaks| {
        let mut breaks = breaks.to_vec();
        breaks.extend([-0.5, 0.0, 0.5]);
        let v = fastbrdf::quad::albedo_fixed(
            f,
            mirror,
            &breaks,
            QUICK_OUTER_PANELS,
            QUICK_INNER_PANELS,
        );
        (v, f64::NAN)
    })
}

/// Panels per outer (u) interval and per ring (phi) interval of [`curve_quick`].
pub const QUICK_OUTER_PANELS: usize = 2;
pub const QUICK_INNER_PANELS: usize = 8;

/// One row per angle: `albedo(slice, mirror direction, the BRDF's mirror breaks)` gives
/// `(albedo, error)`, the slice over `wo` (over `wi` for a view-dependent target).
fn rows(
    t: &Target,
    angles_deg: &[f64],
    albedo: impl Fn(&dyn Fn([f64; 3]) -> f64, [f64; 3], &[f64]) -> (f64, f64),
) -> Result<Vec<AlbedoRow>> {
    let Model::Brdf(b) = t.spec.model::<f64>()? else {
        unreachable!("target() only names BRDFs")
    };
    let breaks = b.mirror_breaks();
    Ok(angles_deg
        .iter()
        .map(|&deg| {
            let th = deg.to_radians();
            let w = [th.sin(), 0.0, th.cos()];
            let mirror = [-w[0], -w[1], w[2]];
            let (albedo, error) = if t.view {
                albedo(&|wi| b.eval(wi, w), mirror, &breaks)
            } else {
                albedo(&|wo| b.eval(w, wo), mirror, &breaks)
            };
            AlbedoRow {
                theta_deg: deg,
                albedo,
                error,
            }
        })
        .collect())
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
