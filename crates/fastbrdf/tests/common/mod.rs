//! Shared test helpers: parameter configurations covering each model's documented domain,
//! input samples, and a deterministic random generator.
#![allow(dead_code)]

use fastbrdf::model::ModelInfo;
use fastbrdf::params::ParamKind;

/// Exponents covering [1, 10000], edges included.
pub const N_VALUES: &[f64] = &[
    1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 16.0, 20.0, 33.0, 50.0, 100.0, 128.0, 200.0, 333.0,
    500.0, 777.0, 1000.0, 2000.0, 5000.0, 10000.0,
];
/// Slopes covering [0.01, 1], edges included; 0.7072 sits just above 1/sqrt(2), where the
/// exponent 2/alpha^2 - 4 of seed 000's forms changes sign.
pub const ALPHA_VALUES: &[f64] = &[0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7072, 0.85, 1.0];

fn values(name: &str, min: f64, max: f64) -> Vec<f64> {
    match name {
        "n" => N_VALUES.to_vec(),
        "alpha" | "alpha_x" | "alpha_y" => ALPHA_VALUES.to_vec(),
        "f0" => vec![0.0, 0.04, 0.5, 1.0],
        "eta" => vec![0.01, 0.5, 1.0, 1.33, 1.5, 3.0, 10.0],
        "k" => vec![0.0, 0.5, 3.0, 20.0],
        _ => vec![min, 0.5 * (min + max), max],
    }
}

/// Parameter sets for a model: every combination of its choice parameters, crossed with
/// "rows" that walk every numeric parameter through its values (cycling), so each value of
/// each parameter appears. `light` keeps only a few numeric rows (for slow tests).
pub fn configs(info: &ModelInfo, light: bool) -> Vec<Vec<(String, String)>> {
    let mut choice_sets: Vec<Vec<(String, String)>> = vec![vec![]];
    let mut numeric: Vec<(&str, Vec<f64>, bool)> = vec![];
    for p in info.params {
        match p.kind {
            ParamKind::Choice { options, .. } => {
                let mut next = vec![];
                for set in &choice_sets {
                    for o in options {
                        let mut s = set.clone();
                        s.push((p.name.to_string(), o.to_string()));
                        next.push(s);
                    }
                }
                choice_sets = next;
            }
            ParamKind::Number { min, max, default } => {
                numeric.push((p.name, values(p.name, min, max), default.is_none()))
            }
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
            for (name, vals, optional) in &numeric {
                // Optional parameters (Ward's alpha_x, alpha_y) are left out on even rows.
                if *optional && r % 2 == 0 {
                    continue;
                }
                s.push((
                    name.to_string(),
                    vals[(r * 7 + name.len()) % vals.len()].to_string(),
                ));
            }
            out.push(s);
        }
    }
    out
}

/// As `&[(&str, &str)]`.
pub fn as_refs(c: &[(String, String)]) -> Vec<(&str, &str)> {
    c.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect()
}

/// A parameter's numeric value in a configuration.
pub fn get(c: &[(String, String)], name: &str) -> Option<f64> {
    c.iter()
        .find(|(k, _)| k == name)
        .map(|(_, v)| v.parse().unwrap())
}

/// A small deterministic generator (SplitMix64).
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A direction in the upper hemisphere, uniform in solid angle, with cos theta >= 1e-3.
    pub fn hemisphere(&mut self) -> [f64; 3] {
        let z = 1e-3 + (1.0 - 1e-3) * self.f64();
        let r = (1.0 - z * z).sqrt();
        let phi = 2.0 * std::f64::consts::PI * self.f64();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

/// Direction pairs for BRDF tests: random pairs, near-specular pairs (wo close to the
/// mirror of wi, where narrow lobes live), normal incidence and near-grazing pairs.
pub fn direction_pairs(count: usize, seed: u64) -> Vec<([f64; 3], [f64; 3])> {
    let mut rng = Rng(seed);
    let mut out = vec![
        ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
        ([0.6, 0.0, 0.8], [-0.6, 0.0, 0.8]),
    ];
    for i in 0..count {
        let wi = rng.hemisphere();
        let wo = match i % 3 {
            0 => rng.hemisphere(),
            _ => {
                let s = if i % 3 == 1 { 0.02 } else { 0.2 };
                let m = [
                    -wi[0] + s * (rng.f64() - 0.5),
                    -wi[1] + s * (rng.f64() - 0.5),
                    wi[2],
                ];
                let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                [m[0] / l, m[1] / l, (m[2] / l).max(1e-3)]
            }
        };
        out.push((wi, wo));
    }
    out.push(([0.9999, 0.0, 0.0141], [-0.9999, 0.0, 0.0141]));
    out
}
