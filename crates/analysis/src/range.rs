//! Parameter lists: `LO..HI` (step 1 for `n`, 0.01 otherwise), `LO..HI:STEP`, or `A,B,C`.

/// Parses a range or list; `default_step` applies to `LO..HI`. Errors say what is wrong.
pub fn parse(text: &str, default_step: f64) -> Result<Vec<f64>, String> {
    let t = text.trim();
    let num = |s: &str| -> Result<f64, String> {
        let x: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not a number in '{text}'"))?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(format!("'{s}' is not finite in '{text}'"))
        }
    };
    if let Some((lo, rest)) = t.split_once("..") {
        let (hi, step) = match rest.split_once(':') {
            Some((hi, step)) => (num(hi)?, num(step)?),
            None => (num(rest)?, default_step),
        };
        let lo = num(lo)?;
        if !(step > 0.0) {
            return Err(format!("the step of '{text}' must be positive"));
        }
        if hi < lo {
            return Err(format!(
                "'{text}' is empty: its upper end is below its lower end"
            ));
        }
        let count = ((hi - lo) / step + 1e-9).floor() as usize + 1;
        if count > 1_000_000 {
            return Err(format!(
                "'{text}' has {count} values; at most 1000000 are allowed"
            ));
        }
        let mut v: Vec<f64> = (0..count).map(|i| lo + i as f64 * step).collect();
        if let Some(last) = v.last_mut() {
            if (*last - hi).abs() < 1e-9 * step {
                *last = hi;
            }
        }
        return Ok(v);
    }
    let v: Vec<f64> = t.split(',').map(num).collect::<Result<_, _>>()?;
    if v.is_empty() {
        return Err("empty list".into());
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::parse;

    #[test]
    fn ranges_and_lists() {
        assert_eq!(parse("1..5", 1.0).unwrap(), vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(parse("1..2:0.5", 1.0).unwrap(), vec![1.0, 1.5, 2.0]);
        assert_eq!(parse("0.05..0.1", 0.01).unwrap().len(), 6);
        assert_eq!(parse("1, 20,300", 1.0).unwrap(), vec![1.0, 20.0, 300.0]);
        assert!(parse("5..1", 1.0).unwrap_err().contains("empty"));
        assert!(parse("1..5:0", 1.0).unwrap_err().contains("positive"));
        assert!(parse("1..x", 1.0).unwrap_err().contains("not a number"));
        assert!(parse("1,nan", 1.0).is_err());
        assert!(parse("1..1e9", 1.0).unwrap_err().contains("at most"));
    }
}
