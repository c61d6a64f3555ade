//! Error of a model against a reference, per parameter value.
//!
//! For each parameter value `p` (n for lobes, alpha for microfacet terms), both models are
//! reduced to functions of one scalar `x` (`fastbrdf::accuracy::Curve`: the cosine for lobes,
//! distributions and shadowing; the angle for full BRDFs with `wi = wo`). On the dense sample
//! set of `fastbrdf::accuracy::samples` we compute, within the zone (decided by the reference
//! divided by its peak):
//! - max absolute error (divided by the reference's peak for non-lobes) and where;
//! - max relative error `|f - ref| / ref` and where;
//! - RMS absolute error with respect to solid angle, i.e. uniform in `cos`
//!   (`sqrt(integral e^2 dcos / integral dcos)` by the trapezoid rule over the samples in the zone).
//!
//! The maxima are refined by golden-section search around the eight largest grid errors
//! (`fastbrdf::accuracy::worst_at`): they are true maxima, not grid maxima.

use fastbrdf::accuracy::{self, Curve};
use fastbrdf::{ErrorBound, Metric, Model, Result, Zone};
use rayon::prelude::*;
use serde::Serialize;

/// The errors at one parameter value.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ErrorRow {
    /// The parameter value (n or alpha).
    pub param: f64,
    pub max_abs: f64,
    /// The input `x` (cosine, or angle in radians for BRDFs) of the max absolute error.
    pub max_abs_at: f64,
    pub max_rel: f64,
    pub max_rel_at: f64,
    pub rms: f64,
    /// Grid samples in the zone.
    pub samples: usize,
}

/// What to compare.
#[derive(Clone, Debug)]
pub struct Spec {
    pub model: String,
    pub reference: String,
    /// `n` or `alpha`.
    pub param: String,
    pub zone: Zone,
}

impl Spec {
    fn bound(&self, metric: Metric) -> ErrorBound {
        // ErrorBound wants 'static names (validate() has checked the name).
        let name = ["n", "alpha", "f0"]
            .into_iter()
            .find(|n| *n == self.param)
            .unwrap_or("n");
        let reference = fastbrdf::registry::find(&self.reference)
            .map(|e| e.info.id)
            .unwrap_or("pow");
        ErrorBound {
            reference,
            metric,
            zone: self.zone,
            param: (name, 0.0, 0.0),
            bound: 0.0,
        }
    }

    /// Checks that both ids exist, are of the same kind, and take the parameter.
    pub fn validate(&self) -> Result<()> {
        let m = fastbrdf::registry::find(&self.model)?;
        let r = fastbrdf::registry::find(&self.reference)?;
        if m.info.kind != r.info.kind {
            return Err(fastbrdf::Error::WrongKind {
                model: self.reference.clone(),
                expected: m.info.kind.name().into(),
                found: r.info.kind.name().into(),
            });
        }
        for e in [m, r] {
            if e.info.sweep_range(&self.param).is_none() {
                return Err(fastbrdf::Error::UnknownParam {
                    model: e.info.id.into(),
                    param: self.param.clone(),
                });
            }
        }
        Ok(())
    }
}

/// The errors of `spec` at parameter value `p`.
pub fn at(spec: &Spec, p: f64) -> Result<ErrorRow> {
    let abs = accuracy::worst_at(&spec.model, &spec.bound(Metric::MaxAbs), p)?;
    let rel = accuracy::worst_at(&spec.model, &spec.bound(Metric::MaxRel), p)?;
    let m = Curve::new(&spec.model, &spec.param, p)?;
    let r = Curve::new(&spec.reference, &spec.param, p)?;
    let mut xs = accuracy::samples(r.model(), p);
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let refs: Vec<f64> = xs.iter().map(|&x| r.at(x)).collect();
    let peak = refs
        .iter()
        .copied()
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let scale = if matches!(r.model(), Model::Lobe(_)) {
        1.0
    } else {
        peak
    };
    let to_cos = |x: f64| {
        if matches!(r.model(), Model::Brdf(_)) {
            x.cos()
        } else {
            x
        }
    };
    let (mut num, mut den, mut count) = (0.0, 0.0, 0);
    for i in 0..xs.len() {
        let inside = accuracy::in_zone(spec.zone, refs[i] / peak);
        if inside {
            count += 1;
        }
        if i + 1 < xs.len() && inside && accuracy::in_zone(spec.zone, refs[i + 1] / peak) {
            let e0 = (m.at(xs[i]) - refs[i]) / scale;
            let e1 = (m.at(xs[i + 1]) - refs[i + 1]) / scale;
            let w = (to_cos(xs[i + 1]) - to_cos(xs[i])).abs();
            num += 0.5 * (e0 * e0 + e1 * e1) * w;
            den += w;
        }
    }
    Ok(ErrorRow {
        param: p,
        max_abs: abs.err,
        max_abs_at: abs.x,
        max_rel: rel.err,
        max_rel_at: rel.x,
        rms: if den > 0.0 { (num / den).sqrt() } else { 0.0 },
        samples: count,
    })
}

/// The errors at every parameter value, in parallel.
pub fn sweep(spec: &Spec, values: &[f64], progress: &(dyn Fn() + Sync)) -> Result<Vec<ErrorRow>> {
    spec.validate()?;
    let rows: Vec<ErrorRow> = values
        .par_iter()
        .map(|&p| {
            let r = at(spec, p);
            progress();
            r
        })
        .collect::<Result<_>>()?;
    // A zone that holds no sample measured nothing: refuse it rather than report error 0.
    if let Some(r) = rows.iter().find(|r| r.samples == 0) {
        return Err(fastbrdf::Error::Domain {
            input: "--zone".into(),
            reason: format!(
                "no sample of the reference lies in this zone at {} = {}: nothing to measure (widen the zone)",
                spec.param, r.param
            ),
        });
    }
    Ok(rows)
}

/// The worst of each metric over rows: (max abs row, max rel row, max rms row).
pub fn worst(rows: &[ErrorRow]) -> Option<(ErrorRow, ErrorRow, ErrorRow)> {
    let pick = |f: fn(&ErrorRow) -> f64| rows.iter().copied().max_by(|a, b| f(a).total_cmp(&f(b)));
    Some((pick(|r| r.max_abs)?, pick(|r| r.max_rel)?, pick(|r| r.rms)?))
}
