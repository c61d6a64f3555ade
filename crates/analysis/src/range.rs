//! Parameter lists: `LO..HI` (step 1 for `n`, 0.01 otherwise), `LO..HI:STEP`, `LO..HI:logK`
//! (K log-spaced values per decade, both ends included: `1..100000:log50` sweeps the whole
//! exponent domain in 251 values), or `A,B,C`.
//!
//! Every list is checked before anything is computed or printed: numbers must be finite, a
//! range must not be reversed, its step must be positive, finite and large enough to move the
//! value (`LO + STEP != LO` in f64, and every value distinct from the previous one), and a list
//! has between 1 and [`MAX_VALUES`] values. The count is computed in checked arithmetic.

/// The most values a range or list may have.
pub const MAX_VALUES: usize = 1_000_000;

/// A parameter value as text (for labels and messages): the shortest round-trip
/// text, in exponent form when that is long (1e308 rather than 309 digits).
pub fn num(x: f64) -> String {
    let s = x.to_string();
    if s.len() > 20 { format!("{x:e}") } else { s }
}

/// Parses a range or list; `default_step` applies to `LO..HI`. Errors say what is wrong.
pub fn parse(text: &str, default_step: f64) -> Result<Vec<f64>, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("empty: expected LO..HI[:STEP] or a list A,B,C".into());
    }
    let num = |s: &str| -> Result<f64, String> {
        let x: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("'{}' is not a number in '{text}'", s.trim()))?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(format!("'{}' is not finite in '{text}'", s.trim()))
        }
    };
    if let Some((lo, rest)) = t.split_once("..") {
        if let Some((hi, per)) = rest.split_once(':')
            && let Some(k) = per.trim().strip_prefix("log")
        {
            return log_range(text, num(lo)?, num(hi)?, k);
        }
        let (hi, step) = match rest.split_once(':') {
            Some((hi, step)) => (num(hi)?, num(step)?),
            None => (num(rest)?, default_step),
        };
        let lo = num(lo)?;
        if !(step > 0.0 && step.is_finite()) {
            return Err(format!("the step of '{text}' must be positive and finite"));
        }
        if hi < lo {
            return Err(format!(
                "'{text}' is empty: its upper end is below its lower end"
            ));
        }
        if lo + step == lo {
            return Err(format!(
                "the step {step:e} of '{text}' is too small to change {lo:e} in f64"
            ));
        }
        // The count in f64 first (finite: both ends are finite, the step positive); refuse it
        // before converting, so nothing saturates or wraps.
        let span = (hi - lo) / step;
        if !span.is_finite() || span + 1.0 > MAX_VALUES as f64 {
            return Err(format!(
                "'{text}' has more than {MAX_VALUES} values; at most {MAX_VALUES} are allowed"
            ));
        }
        let count = ((span + 1e-9).floor() as usize)
            .checked_add(1)
            .filter(|c| (1..=MAX_VALUES).contains(c))
            .ok_or_else(|| format!("'{text}' has no usable number of values"))?;
        let mut v: Vec<f64> = Vec::with_capacity(count);
        for i in 0..count {
            let x = lo + i as f64 * step;
            if let Some(&prev) = v.last()
                && !(x > prev)
            {
                return Err(format!(
                    "the step {step:e} of '{text}' is too small to change {prev:e} in f64"
                ));
            }
            v.push(x);
        }
        if let Some(last) = v.last_mut()
            && (*last - hi).abs() < 1e-9 * step
        {
            *last = hi;
        }
        return Ok(v);
    }
    let v: Vec<f64> = t.split(',').map(num).collect::<Result<_, _>>()?;
    if v.is_empty() {
        return Err("empty list".into());
    }
    if v.len() > MAX_VALUES {
        return Err(format!(
            "'{}' has {} values; at most {MAX_VALUES} are allowed",
            fastbrdf_io::shorten(text, 40),
            v.len()
        ));
    }
    Ok(v)
}

/// `LO..HI:logK`: `K` (an integer in 1..=1000) values per decade from `LO` to `HI`
/// (`0 < LO <= HI`), geometric, both ends exact.
fn log_range(text: &str, lo: f64, hi: f64, k: &str) -> Result<Vec<f64>, String> {
    let per: u32 = k
        .trim()
        .parse()
        .ok()
        .filter(|k| (1..=1000).contains(k))
        .ok_or_else(|| format!("'{text}': logK needs K, values per decade, in 1..=1000"))?;
    if !(lo > 0.0) {
        return Err(format!("'{text}': a log-spaced range needs LO > 0"));
    }
    if hi < lo {
        return Err(format!(
            "'{text}' is empty: its upper end is below its lower end"
        ));
    }
    let decades = (hi / lo).log10();
    let count = (decades * per as f64 - 1e-9).ceil().max(0.0);
    if !(count + 1.0 <= MAX_VALUES as f64) {
        return Err(format!(
            "'{text}' has more than {MAX_VALUES} values; at most {MAX_VALUES} are allowed"
        ));
    }
    let count = count as usize;
    if count == 0 {
        return Ok(vec![lo]);
    }
    let mut v: Vec<f64> = (0..count)
        .map(|i| lo * (hi / lo).powf(i as f64 / count as f64))
        .collect();
    v.push(hi);
    if v.windows(2).any(|w| !(w[1] > w[0])) {
        return Err(format!(
            "'{text}': its values are too close to tell apart in f64"
        ));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::parse;

    #[test]
    fn log_spaced_ranges() {
        let v = parse("1..100000:log50", 1.0).unwrap();
        assert_eq!(v.len(), 251);
        assert_eq!((v[0], v[250]), (1.0, 100000.0));
        assert!((v[50] - 10.0).abs() < 1e-12 && (v[200] - 10000.0).abs() < 1e-9);
        assert!(v.windows(2).all(|w| w[1] > w[0]));
        assert_eq!(parse("0.005..1:log10", 0.01).unwrap().len(), 25);
        assert_eq!(parse("3..3:log10", 1.0).unwrap(), vec![3.0]);
        for bad in [
            "0..10:log10",
            "-1..10:log10",
            "10..1:log10",
            "1..10:log0",
            "1..10:logx",
            "1..10:log1001",
        ] {
            assert!(parse(bad, 1.0).is_err(), "{bad}");
        }
    }

    #[test]
    fn ranges_and_lists() {
        assert_eq!(parse("1..5", 1.0).unwrap(), vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(parse("1..2:0.5", 1.0).unwrap(), vec![1.0, 1.5, 2.0]);
        assert_eq!(parse("0.05..0.1", 0.01).unwrap().len(), 6);
        assert_eq!(parse("1, 20,300", 1.0).unwrap(), vec![1.0, 20.0, 300.0]);
        assert_eq!(parse("3..3", 1.0).unwrap(), vec![3.0]);
        assert!(parse("5..1", 1.0).unwrap_err().contains("empty"));
        assert!(parse("1..5:0", 1.0).unwrap_err().contains("positive"));
        assert!(parse("1..5:-1", 1.0).unwrap_err().contains("positive"));
        assert!(parse("1..x", 1.0).unwrap_err().contains("not a number"));
        assert!(parse("1,nan", 1.0).is_err());
        assert!(parse("1..inf", 1.0).is_err());
        assert!(parse("", 1.0).is_err());
        assert!(parse("1..1e9", 1.0).unwrap_err().contains("at most"));
    }

    /// Issue 11: these counts saturated (usize::MAX + 1 wrapped to 0, an empty list) or the
    /// step did not move the value; each must be an error, never an empty or endless list.
    #[test]
    fn degenerate_ranges_are_refused() {
        for text in [
            "1..2:1e-300",
            "1e308..1.7e308",
            "0..10:1e-300",
            "-1.7e308..1.7e308",
            "1e17..1e17:1",
            "1e16..2e16:1",
            "0..1:5e-324",
        ] {
            let r = parse(text, 1.0);
            assert!(r.is_err(), "{text}: {r:?}");
        }
        // A step that moves the value is fine even if tiny relative to 1.
        assert_eq!(parse("0..1e-300:1e-300", 1.0).unwrap().len(), 2);
    }
}
