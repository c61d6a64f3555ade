//! Shared test helpers: parameter configurations covering each model's documented domain,
//! input samples, and a deterministic random generator.
#![allow(dead_code)]

use fastbrdf::model::ModelInfo;

/// Exponents covering [1, 100000], edges included.
pub const N_VALUES: &[f64] = &[
    1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0, 16.0, 20.0, 33.0, 50.0, 100.0, 128.0, 200.0, 333.0,
    500.0, 777.0, 1000.0, 2000.0, 5000.0, 10000.0, 30000.0, 100000.0,
];
/// Slopes covering [0.005, 1], edges included; 0.7072 sits just above 1/sqrt(2), where the
/// exponent 2/alpha^2 - 4 of seed 000's forms changes sign.
pub const ALPHA_VALUES: &[f64] = &[
    0.005, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.6, 0.7072, 0.85, 1.0,
];

/// Parameter sets covering a model's domain (the library's generator, shared with
/// `fastbrdf check`).
pub fn configs(info: &ModelInfo, light: bool) -> Vec<Vec<(String, String)>> {
    fastbrdf::accuracy::domain_configs(info, light)
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
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        fastbrdf::accuracy::splitmix(&mut self.0)
    }
    /// A direction in the upper hemisphere, uniform in solid angle, with cos theta >= 1e-3.
    pub fn hemisphere(&mut self) -> [f64; 3] {
        let z = 1e-3 + (1.0 - 1e-3) * self.f64();
        let r = (1.0 - z * z).sqrt();
        let phi = 2.0 * std::f64::consts::PI * self.f64();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

/// Direction pairs for BRDF tests (the library's generator).
pub fn direction_pairs(count: usize, seed: u64) -> Vec<([f64; 3], [f64; 3])> {
    fastbrdf::accuracy::direction_pairs(count, seed)
}
