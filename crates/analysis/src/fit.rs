//! Fitted approximations: for each n (or alpha), the coefficient of a family that minimises an
//! error metric against the exact model over the whole lobe. Every family here has one free
//! coefficient, so the fit is a robust 1-D minimisation: a log-spaced scan of 61 points around
//! the untuned coefficient, then golden-section search in the best bracket; the objective is
//! the true maximum (dense grid plus golden-section refinement, `lobe_error`).
//!
//! Families (free coefficient in brackets):
//! - `power4`, `power8`, `power16`: `max(0, 1 + s (c - 1))^g` [s; untuned n/g];
//! - `exp2`: `exp2(a (c - 1))` [a; untuned n / ln 2 (`sg`), UE4 uses 1.4427 (n + 0.775)];
//! - `cubic-rational`: seed 003's cubic above the junction `c^n = Q` and its rational below,
//!   both matched to `c^n` in value and slope at the junction [Q; untuned 0.5];
//! - `beckmann-power16`: `max(0, 1 + s (cos - 1))^16 / (4 m^2)` against `beckmann-ct` [s; untuned
//!   (2/m^2 - 4)/16], error relative to the distribution's peak.

use fastbrdf::accuracy::{golden_max, lobe_samples};
use rayon::prelude::*;
use serde::Serialize;

/// What is minimised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Metric {
    /// Max |f - c^n| over c in [0, 1].
    MaxAbs,
    /// Max |f - c^n| / c^n where c^n >= 0.5.
    MaxRelEpicentre,
    /// RMS of f - c^n over solid angle (uniform in c).
    Rms,
}

impl Metric {
    /// The metric's name, as [`parse`](Self::parse) reads it.
    pub fn name(self) -> &'static str {
        match self {
            Self::MaxAbs => "max-abs",
            Self::MaxRelEpicentre => "max-rel-epicentre",
            Self::Rms => "rms",
        }
    }

    /// Parses `max-abs`, `max-rel-epicentre`, `rms`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "max-abs" => Some(Self::MaxAbs),
            "max-rel-epicentre" => Some(Self::MaxRelEpicentre),
            "rms" => Some(Self::Rms),
            _ => None,
        }
    }
}

/// A one-coefficient family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    Power4,
    Power8,
    Power16,
    Exp2,
    CubicRational,
    BeckmannPower16,
}

impl Family {
    /// Parses a family name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "power4" => Some(Self::Power4),
            "power8" => Some(Self::Power8),
            "power16" => Some(Self::Power16),
            "exp2" => Some(Self::Exp2),
            "cubic-rational" => Some(Self::CubicRational),
            "beckmann-power16" => Some(Self::BeckmannPower16),
            _ => None,
        }
    }

    /// The family's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Power4 => "power4",
            Self::Power8 => "power8",
            Self::Power16 => "power16",
            Self::Exp2 => "exp2",
            Self::CubicRational => "cubic-rational",
            Self::BeckmannPower16 => "beckmann-power16",
        }
    }

    /// Whether the parameter is alpha (else n).
    pub fn is_microfacet(self) -> bool {
        self == Self::BeckmannPower16
    }

    fn g(self) -> f64 {
        match self {
            Self::Power4 => 4.0,
            Self::Power8 => 8.0,
            _ => 16.0,
        }
    }

    /// The untuned coefficient at parameter `p` (n, or alpha).
    pub fn untuned(self, p: f64) -> f64 {
        match self {
            Self::Power4 | Self::Power8 | Self::Power16 => p / self.g(),
            Self::Exp2 => p / std::f64::consts::LN_2,
            Self::CubicRational => 0.5,
            Self::BeckmannPower16 => fastbrdf::microfacet::beckmann_pow::exponent(p) / 16.0,
        }
    }

    /// The family member with coefficient `k` at parameter `p`, as a function of the cosine
    /// (lobe value, or D divided by the exact D's value at the peak for Beckmann).
    pub fn eval(self, k: f64, p: f64, c: f64) -> f64 {
        let c = c.clamp(0.0, 1.0);
        match self {
            Self::Power4 | Self::Power8 | Self::Power16 => {
                (1.0 + k * (c - 1.0)).max(0.0).powi(self.g() as i32)
            }
            Self::Exp2 => (k * (c - 1.0)).exp2(),
            Self::CubicRational => fastbrdf::lobes::tuned::cubic_rational_at(p, k, c),
            Self::BeckmannPower16 => {
                if c <= 0.0 {
                    return 0.0;
                }
                let s2 = (1.0 - c) * (1.0 + c);
                (1.0 - k * s2 / (1.0 + c)).max(0.0).powi(16)
            }
        }
    }

    /// The reference at parameter `p` (c^n, or exp(-tan^2/m^2)/cos^4 for Beckmann: both forms
    /// share the 1/(4 m^2) factor).
    pub fn reference(self, p: f64, c: f64) -> f64 {
        if self == Self::BeckmannPower16 {
            if c <= 0.0 {
                return 0.0;
            }
            let tan2 = (1.0 - c) * (1.0 + c) / (c * c);
            (-tan2 / (p * p)).exp() / (c * c * c * c)
        } else {
            c.clamp(0.0, 1.0).powf(p)
        }
    }

    /// Where the coefficient may lie, for the scan: (lo, hi).
    fn bracket(self, p: f64) -> (f64, f64) {
        let k0 = self.untuned(p);
        match self {
            Self::CubicRational => (0.02, 0.9),
            Self::BeckmannPower16 if k0 <= 0.0 => (-1.0, 0.5),
            _ => (0.5 * k0, 2.0 * k0),
        }
    }
}

fn samples(family: Family, p: f64) -> Vec<f64> {
    if family == Family::BeckmannPower16 {
        let mut xs: Vec<f64> = (0..=3000)
            .map(|i| 1.0 / (1.0 + p * p * (i as f64 * 0.01)).sqrt())
            .collect();
        xs.extend((1..=200).map(|i| i as f64 / 200.0));
        xs
    } else {
        lobe_samples(p)
    }
}

/// The error of `f` against `reference` under `metric`, true maxima (refined around the eight
/// largest grid errors). For Beckmann the absolute error is divided by the reference's peak.
pub fn lobe_error(
    f: &dyn Fn(f64) -> f64,
    reference: &dyn Fn(f64) -> f64,
    xs: &[f64],
    metric: Metric,
    scale: f64,
) -> f64 {
    let mut xs = xs.to_vec();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let err = |c: f64| {
        let r = reference(c);
        match metric {
            Metric::MaxAbs | Metric::Rms => (f(c) - r).abs() / scale,
            Metric::MaxRelEpicentre => {
                if r / scale >= 0.5 {
                    (f(c) - r).abs() / r
                } else {
                    0.0
                }
            }
        }
    };
    let e: Vec<f64> = xs.iter().map(|&c| err(c)).collect();
    if metric == Metric::Rms {
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..xs.len() - 1 {
            let w = xs[i + 1] - xs[i];
            num += 0.5 * (e[i] * e[i] + e[i + 1] * e[i + 1]) * w;
            den += w;
        }
        return (num / den).sqrt();
    }
    let mut order: Vec<usize> = (0..xs.len()).collect();
    order.sort_by(|&a, &b| e[b].total_cmp(&e[a]));
    let mut best = e[order[0]];
    for &i in order.iter().take(8) {
        let (lo, hi) = (xs[i.saturating_sub(1)], xs[(i + 1).min(xs.len() - 1)]);
        best = best.max(golden_max(&err, lo, hi, 50).1);
    }
    best
}

/// One fitted parameter value.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct FitRow {
    /// n (or alpha).
    pub param: f64,
    /// The optimal coefficient.
    pub coefficient: f64,
    pub error: f64,
    pub untuned_coefficient: f64,
    pub untuned_error: f64,
}

/// The error of coefficient `k` at parameter `p` (for Beckmann, absolute errors are divided by
/// the reference's peak over the samples).
pub fn error_of(family: Family, metric: Metric, p: f64, k: f64) -> f64 {
    let xs = samples(family, p);
    let scale = if family == Family::BeckmannPower16 {
        xs.iter()
            .map(|&c| family.reference(p, c))
            .fold(0.0, f64::max)
    } else {
        1.0
    };
    lobe_error(
        &|c| family.eval(k, p, c),
        &|c| family.reference(p, c),
        &xs,
        metric,
        scale,
    )
}

/// `Int = integral_0^1 f(c) c dc` of the family member (lobe families), for normalisation.
pub fn member_integral(family: Family, p: f64, k: f64) -> f64 {
    let mut breaks = vec![];
    if let Family::Power4 | Family::Power8 | Family::Power16 = family {
        breaks.push((1.0 - 1.0 / k).max(0.0));
    }
    if family == Family::CubicRational {
        breaks.push(k.powf(1.0 / p));
    }
    breaks.extend([1.0 - 1.0 / p, 1.0 - 4.0 / p, 1.0 - 16.0 / p]);
    fastbrdf::quad::integrate(|c| family.eval(k, p, c) * c, 0.0, 1.0, &breaks, 1e-10).0
}

/// The error of the energy-normalised member against the normalised reference,
/// `|coef_f f - coef_pow c^n| / coef_pow` with `coef = 1 / (2 pi Int)` (`coef_pow = (n + 2) / (2 pi)`):
/// the shapes compared at equal energy, in units of the normalised reference's peak.
pub fn error_of_normalized(family: Family, metric: Metric, p: f64, k: f64) -> f64 {
    let ratio = (1.0 / (p + 2.0)) / member_integral(family, p, k);
    let xs = samples(family, p);
    lobe_error(
        &|c| ratio * family.eval(k, p, c),
        &|c| family.reference(p, c),
        &xs,
        metric,
        1.0,
    )
}

/// The optimal coefficient at parameter `p`.
pub fn fit_one(family: Family, metric: Metric, p: f64) -> FitRow {
    fit_one_with(family, metric, p, false)
}

/// The optimal coefficient at parameter `p`; `normalized` compares the energy-normalised
/// member with the energy-normalised reference (lobe families only).
pub fn fit_one_with(family: Family, metric: Metric, p: f64, normalized: bool) -> FitRow {
    let (lo, hi) = family.bracket(p);
    let k0 = family.untuned(p);
    let obj = |k: f64| {
        if normalized {
            error_of_normalized(family, metric, p, k)
        } else {
            error_of(family, metric, p, k)
        }
    };
    // Scan (linear for brackets that include zero or negative values, else log-spaced).
    let mut pts: Vec<f64> = (0..=60)
        .map(|i| {
            let t = i as f64 / 60.0;
            if lo > 0.0 {
                lo * (hi / lo).powf(t)
            } else {
                lo + (hi - lo) * t
            }
        })
        .chain([k0])
        .collect();
    // The untuned coefficient may coincide with a scan point: a duplicate would become its own
    // neighbour and collapse the golden-section bracket.
    pts.sort_by(f64::total_cmp);
    pts.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs().max(1e-300));
    let vals: Vec<f64> = pts.iter().map(|&k| obj(k)).collect();
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    idx.sort_by(|&a, &b| pts[a].total_cmp(&pts[b]));
    let ibest = idx
        .iter()
        .copied()
        .min_by(|&a, &b| vals[a].total_cmp(&vals[b]))
        .unwrap_or(0);
    let pos = idx.iter().position(|&i| i == ibest).unwrap_or(0);
    let (a, b) = (
        pts[idx[pos.saturating_sub(1)]],
        pts[idx[(pos + 1).min(idx.len() - 1)]],
    );
    let (k, neg) = golden_max(&|k| -obj(k), a, b, 60);
    let (k, e) = if -neg <= vals[ibest] {
        (k, -neg)
    } else {
        (pts[ibest], vals[ibest])
    };
    FitRow {
        param: p,
        coefficient: k,
        error: e,
        untuned_coefficient: k0,
        untuned_error: obj(k0),
    }
}

/// The optimal coefficients over parameter values, in parallel.
pub fn fit(
    family: Family,
    metric: Metric,
    params: &[f64],
    progress: &(dyn Fn() + Sync),
) -> Vec<FitRow> {
    fit_with(family, metric, params, false, progress)
}

/// As `fit`, optionally for the energy-normalised forms.
pub fn fit_with(
    family: Family,
    metric: Metric,
    params: &[f64],
    normalized: bool,
    progress: &(dyn Fn() + Sync),
) -> Vec<FitRow> {
    params
        .par_iter()
        .map(|&p| {
            let r = fit_one_with(family, metric, p, normalized);
            progress();
            r
        })
        .collect()
}

/// The largest tuned / untuned error over the rows with p >= 8 (where the untuned error is
/// above 1e-9); 0 when there is none.
pub fn worst_tuned_gain(rows: &[FitRow]) -> f64 {
    rows.iter()
        .filter(|r| r.param >= 8.0 && r.untuned_error > 1e-9)
        .map(|r| r.error / r.untuned_error)
        .fold(0.0, f64::max)
}

/// A closed form for the coefficient: `k(p) = k0(p) R(1/p)` (or `R(1/p)` itself for the
/// cubic-rational level), `R` a polynomial of degree 4 fitted by least squares to the per-p
/// optima; with its own error: the largest relative deviation from the optima, and the
/// largest resulting error / untuned error over the rows with p >= 8.
#[derive(Clone, Debug, Serialize)]
pub struct ClosedForm {
    pub r: [f64; 5],
    pub max_coefficient_deviation: f64,
    pub worst_gain: f64,
    pub worst_gain_at: f64,
}

/// Whether the closed form is of the ratio k / k0 (else of k itself).
fn ratio_form(family: Family) -> bool {
    family != Family::CubicRational
}

/// Evaluates a closed form.
pub fn closed_form_coefficient(family: Family, r: &[f64; 5], p: f64) -> f64 {
    let x = 1.0 / p;
    let v = r[0] + x * (r[1] + x * (r[2] + x * (r[3] + x * r[4])));
    if ratio_form(family) {
        v * family.untuned(p)
    } else {
        v
    }
}

/// Fits the closed form to per-parameter optima (lobe families).
pub fn closed_form(family: Family, metric: Metric, rows: &[FitRow]) -> ClosedForm {
    let xs: Vec<Vec<f64>> = rows
        .iter()
        .map(|r| (0..5).map(|j| (1.0 / r.param).powi(j)).collect())
        .collect();
    let ys: Vec<f64> = rows
        .iter()
        .map(|r| {
            if ratio_form(family) {
                r.coefficient / r.untuned_coefficient
            } else {
                r.coefficient
            }
        })
        .collect();
    let beta = crate::normalize::lstsq(&xs, &ys, &vec![1.0; ys.len()]);
    let r: [f64; 5] = std::array::from_fn(|j| beta[j]);
    let (mut dev, mut gain, mut at) = (0.0f64, 0.0f64, 0.0);
    for row in rows {
        let k = closed_form_coefficient(family, &r, row.param);
        dev = dev.max((k / row.coefficient - 1.0).abs());
        if row.param >= 8.0 && row.untuned_error > 1e-9 {
            let g = error_of(family, metric, row.param, k) / row.untuned_error;
            if g > gain {
                (gain, at) = (g, row.param);
            }
        }
    }
    ClosedForm {
        r,
        max_coefficient_deviation: dev,
        worst_gain: gain,
        worst_gain_at: at,
    }
}

/// The closed form of a fit's rows, when there is one: lobe families with at least 5 rows.
pub fn closed_form_of(family: Family, metric: Metric, rows: &[FitRow]) -> Option<ClosedForm> {
    (!family.is_microfacet() && rows.len() >= 5).then(|| closed_form(family, metric, rows))
}

/// `fastbrdf fit --json`'s object: `{"family", "metric", "normalized", "param": "n"|"alpha",
/// "rows": [{n or alpha, coefficient, error, untuned_coefficient, untuned_error}],
/// "closed_form"}` (the CLI and the Python package print this one value).
pub fn json(
    family: Family,
    metric: Metric,
    normalized: bool,
    rows: &[FitRow],
    closed: Option<&ClosedForm>,
) -> serde_json::Value {
    let name = if family.is_microfacet() { "alpha" } else { "n" };
    let rows: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            let mut v = serde_json::to_value(r).expect("serialisable");
            if let Some(o) = v.as_object_mut() {
                // One vocabulary: the parameter's own name (n or alpha), as in CSV.
                if let Some(p) = o.remove("param") {
                    o.insert(name.into(), p);
                }
            }
            v
        })
        .collect();
    serde_json::json!({"family": family.name(), "metric": metric.name(), "normalized": normalized,
        "param": name, "rows": rows, "closed_form": closed})
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(param: f64, error: f64, untuned_error: f64) -> FitRow {
        FitRow {
            param,
            coefficient: 1.0,
            error,
            untuned_coefficient: 1.0,
            untuned_error,
        }
    }

    #[test]
    fn worst_tuned_gain_is_the_largest_ratio_from_n_8() {
        let rows = [
            // Below n = 8: ignored, however bad.
            row(4.0, 0.9, 0.1),
            row(8.0, 0.02, 0.1),
            row(16.0, 0.03, 0.1),
            // An untuned form that is exact: ignored.
            row(32.0, 0.5, 0.0),
        ];
        assert!((worst_tuned_gain(&rows) - 0.3).abs() < 1e-15);
        assert_eq!(worst_tuned_gain(&rows[..1]), 0.0);
        assert_eq!(worst_tuned_gain(&[]), 0.0);
    }

    /// The minimax fit never loses to the untuned coefficient it starts from.
    #[test]
    fn tuned_gain_of_a_real_fit_is_at_most_one() {
        let rows = fit_with(
            Family::Power16,
            Metric::MaxAbs,
            &[8.0, 50.0, 200.0],
            false,
            &|| {},
        );
        let g = worst_tuned_gain(&rows);
        assert!(g > 0.0 && g <= 1.0, "{g}");
    }
}
