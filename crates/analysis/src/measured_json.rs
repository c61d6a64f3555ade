//! The JSON documents of `fastbrdf measured info --json` and `fastbrdf fit-measured --json`,
//! built in one place so that the CLI and the Python package (`fastbrdf.Measured.info`,
//! `fastbrdf.fit_measured`) give the same names and the same numbers.

use crate::measured_fit::Fit;
use fastbrdf::ModelSpec;
use fastbrdf::measured::{self, CHANNELS, MeasuredBrdf};
use serde_json::{Value, json};

/// `measured info --json`: the file (as the caller names it), the dimensions, the samples per
/// channel, the channels' scales and each channel's min, max and mean over its valid samples
/// (null when it has none) with the valid and missing counts.
pub fn info(file: &str, b: &MeasuredBrdf) -> Value {
    let num = |x: f64| x.is_finite().then_some(x);
    let channels: Vec<Value> = b
        .stats()
        .iter()
        .zip(CHANNELS)
        .map(|(s, name)| {
            json!({
                "channel": name,
                "min": num(s.min),
                "max": num(s.max),
                "mean": num(s.mean),
                "valid": s.valid,
                "missing": s.missing,
            })
        })
        .collect();
    json!({
        "file": file,
        "dims": [measured::RES_THETA_H, measured::RES_THETA_D, measured::RES_PHI_D],
        "samples_per_channel": measured::SAMPLES,
        "scale": measured::SCALE,
        "channels": channels,
    })
}

/// What [`fit`] reports on besides the fit itself.
pub struct FitReport<'a> {
    /// The data file, as the caller names it.
    pub data: &'a str,
    /// The model id, as the caller gave it.
    pub model: &'a str,
    /// The spec of the given (fixed) values.
    pub fixed: &'a ModelSpec,
    /// Eligible bins of the file (`Data::eligible`).
    pub eligible: usize,
    /// The fit's wall time.
    pub seconds: f64,
    /// The comparison picture written, if any (null when none).
    pub picture: Option<&'a str>,
}

/// `fit-measured --json` (its help gives the shape).
pub fn fit(r: &FitReport<'_>, f: &Fit) -> Value {
    let params: serde_json::Map<String, Value> = f
        .problem
        .free
        .iter()
        .zip(&f.values)
        .map(|(p, v)| (p.name.to_string(), json!(v)))
        .collect();
    let held: serde_json::Map<String, Value> = f
        .problem
        .held
        .iter()
        .map(|(k, v)| (k.to_string(), json!(v)))
        .collect();
    let res = &f.residuals;
    json!({
        "data": r.data,
        "model": r.model,
        "metric": f.metric.name(),
        "samples": f.samples,
        "eligible": r.eligible,
        "fixed": crate::params_json(r.fixed),
        "params": params,
        "rho_d": f.rho_d,
        "rho_s": f.rho_s,
        "residuals": {"ngan-l2": res.ngan_l2, "low-log": res.low_log, "max": res.max},
        "evaluations": f.evaluations,
        "runs": f.runs,
        "fit_seconds": r.seconds,
        "picture": r.picture,
        "held": held,
        "undetermined": f.undetermined,
    })
}
