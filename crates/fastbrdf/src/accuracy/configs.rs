//! The model specs covering a model's documented domain ([`domain_configs`]): the
//! configurations `tests/precision.rs`, `tests/properties.rs`, `fastbrdf check` and the GPU
//! crate's tests iterate.

use crate::spec::{Given, ModelSpec};

/// Model specs covering a model's documented domain: every combination of its choice
/// parameters, crossed with "rows" that walk each numeric parameter through representative
/// values including the range's edges (cycling, so that every value of every parameter
/// appears). Optional parameters (`alpha_x`, `alpha_y` of Ward and Cook-Torrance) are given
/// on odd rows only, where their `requires` hold ([`crate::params::ParamSpec::allowed`]), both
/// at the same value (the anisotropic code paths at equal slopes; truly anisotropic slopes
/// have their own tests: `tests/reference/`, `tests/precision.rs`, `tests/batch/`, the
/// GPU crate's `tests/parity.rs`).
/// `light` keeps about four numeric rows (for the BRDFs, whose choice products are large).
///
/// Panics if a configuration is refused (a model whose parameter specs contradict
/// themselves, or an `info` that is not in the registry): every registry model's
/// configurations are valid, and the registry-wide tests iterate them all.
pub fn domain_configs(info: &crate::ModelInfo, light: bool) -> Vec<ModelSpec> {
    domain_given(info, light)
        .iter()
        .map(|given| {
            ModelSpec::new(info.id, given).unwrap_or_else(|e| {
                panic!("domain configuration {} {given:?} is refused: {e}", info.id)
            })
        })
        .collect()
}

/// The given values of [`domain_configs`], in its order.
pub(crate) fn domain_given(
    info: &crate::ModelInfo,
    light: bool,
) -> Vec<Vec<(&'static str, Given)>> {
    use crate::params::ParamKind;
    fn values(name: &str, min: f64, max: f64) -> Vec<f64> {
        match name {
            "n" => vec![
                1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 16.0, 20.0, 33.0, 50.0, 100.0, 128.0,
                200.0, 333.0, 500.0, 777.0, 1000.0, 2000.0, 5000.0, 10000.0, 30000.0, 100000.0,
            ],
            // 0.7072 sits just above 1/sqrt(2), where seed 000's exponent 2/alpha^2 - 4 changes sign.
            "alpha" | "alpha_x" | "alpha_y" => {
                vec![
                    0.005, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7072, 0.85, 1.0,
                ]
            }
            "f0" => vec![0.0, 0.04, 0.5, 1.0],
            "eta" => vec![0.01, 0.5, 1.0, 1.33, 1.5, 3.0, 10.0],
            "k" => vec![0.0, 0.5, 3.0, 20.0],
            _ => vec![min, 0.5 * (min + max), max],
        }
    }
    let choice_sets = choice_sets(info);
    let mut numeric: Vec<(&crate::params::ParamSpec, Vec<f64>, bool)> = vec![];
    for p in info.params {
        if let ParamKind::Number {
            min, max, default, ..
        } = p.kind
        {
            numeric.push((p, values(p.name, min, max), default.is_none()))
        }
    }
    let rows = numeric.iter().map(|(_, v, _)| v.len()).max().unwrap_or(1);
    let rows: Vec<usize> = if light {
        (0..rows).step_by(rows.div_ceil(4).max(1)).collect()
    } else {
        (0..rows).collect()
    };
    let mut out = vec![];
    for set in &choice_sets {
        for &r in &rows {
            let mut s = set.clone();
            for (spec, vals, optional) in &numeric {
                let name = spec.name;
                let choice = |n: &str| choice_of(set, n);
                if *optional && (r % 2 == 0 || !spec.allowed(choice)) {
                    continue;
                }
                s.push((name, Given::Num(vals[(r * 7 + name.len()) % vals.len()])));
            }
            out.push(s);
        }
    }
    out
}

/// Every combination of a model's choice parameters (one empty set when it has none).
pub(super) fn choice_sets(info: &crate::ModelInfo) -> Vec<Vec<(&'static str, Given)>> {
    let mut sets: Vec<Vec<(&'static str, Given)>> = vec![vec![]];
    for p in info.params {
        if let crate::params::ParamKind::Choice { options, default } = p.kind {
            sets = sets
                .iter()
                .flat_map(|set| {
                    options
                        .names()
                        .iter()
                        // Gated options only where their requirements hold (`Options::Gated`).
                        .filter(|o| options.allows(o, default, |n| choice_of(set, n)))
                        .map(move |o| {
                            let mut s = set.clone();
                            s.push((p.name, Given::Choice(o.to_string())));
                            s
                        })
                })
                .collect();
        }
    }
    sets
}

/// Values worth starting from for a numeric parameter: its edges, its default, the values
/// of [`domain_configs`] and, for `eta`, 1 (where the Fresnel terms vanish).
pub(super) fn special_values(name: &str, min: f64, max: f64) -> Vec<f64> {
    let mut v = match name {
        "n" => vec![1.0, 2.0, 10.0, 100.0, 1000.0, 5000.0, 30000.0],
        "alpha" | "alpha_x" | "alpha_y" => vec![0.01, 0.05, 0.1, 0.5, 0.7072],
        "eta" => vec![1.0, 0.5, 1.5, 0.99, 1.01],
        "k" => vec![0.5, 3.0],
        _ => vec![0.5 * (min + max)],
    };
    v.extend([min, max]);
    v.retain(|x| *x >= min && *x <= max);
    v
}

/// The value of `name` in a set of given values, as text (what `Options::allows` and
/// `ParamSpec::allowed` read).
fn choice_of(set: &[(&'static str, Given)], name: &str) -> Option<String> {
    set.iter()
        .find(|(k, _)| *k == name)
        .map(|(_, v)| v.to_string())
}
