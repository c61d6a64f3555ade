//! Numbers as the commands write them, and the parameter a sweep runs over.

pub use fastbrdf_analysis::range::num;

/// A number for CSV: the shortest round-trip text, or an empty field when it is not finite
/// (the same "no finite value" that JSON writes as null).
pub fn csv_num(x: f64) -> String {
    if x.is_finite() {
        x.to_string()
    } else {
        String::new()
    }
}

/// Whether `errors` can sweep `param` of model `e` (a numeric parameter, or a split-sum
/// term's `alpha` input).
pub fn takes(e: &fastbrdf::entry::Entry, param: &str) -> bool {
    e.info.sweep_range(param).is_some()
}

/// The parameter `fastbrdf errors` sweeps for model `e` (`n` for lobes, `alpha` otherwise),
/// if it takes one.
pub fn swept(e: &fastbrdf::entry::Entry) -> Option<&'static str> {
    ["n", "alpha"].into_iter().find(|p| takes(e, p))
}
