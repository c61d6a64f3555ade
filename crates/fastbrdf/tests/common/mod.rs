//! Shared test helpers: model specs from literal parameters (the tests' one text boundary),
//! the specs covering each model's documented domain, input samples, and a deterministic
//! random generator.
#![allow(dead_code)]

use fastbrdf::batch::Kernel;
use fastbrdf::model::ModelInfo;
use fastbrdf::plan::Plan;
use fastbrdf::{Given, Model, ModelSpec, Real};

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

/// The spec of model `id` with parameters given as text (`ModelSpec::parse`): errors are the
/// parser's.
pub fn spec(id: &str, given: &[(&str, &str)]) -> fastbrdf::Result<ModelSpec> {
    ModelSpec::parse(id, given)
}

/// Model `id` in precision `T` from parameters given as text (through [`spec`]).
pub fn build<T: Real>(id: &str, given: &[(&str, &str)]) -> fastbrdf::Result<Model<T>> {
    ModelSpec::parse(id, given)?.model()
}

/// The plan of model `id` from parameters given as text (through [`spec`]).
pub fn plan(id: &str, given: &[(&str, &str)]) -> fastbrdf::Result<Plan> {
    Ok(*ModelSpec::parse(id, given)?.plan()?)
}

/// The batch kernel of model `id` from parameters given as text (through [`spec`]).
pub fn kernel(id: &str, given: &[(&str, &str)]) -> fastbrdf::Result<Kernel> {
    Kernel::new(&ModelSpec::parse(id, given)?)
}

/// Model specs covering a model's domain (the library's generator, shared with
/// `fastbrdf check`).
pub fn configs(info: &ModelInfo, light: bool) -> Vec<ModelSpec> {
    fastbrdf::accuracy::domain_configs(info, light)
}

/// Text pairs (a test's generated parameters) as `&[(&str, &str)]`.
pub fn as_refs(c: &[(String, String)]) -> Vec<(&str, &str)> {
    c.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect()
}

/// A parameter's numeric value given in a spec.
pub fn get(c: &ModelSpec, name: &str) -> Option<f64> {
    match c.get(name) {
        Some(Given::Num(x)) => Some(*x),
        _ => None,
    }
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

/// The incident direction `theta_deg` from the normal, in the xz plane.
pub fn wi_at(theta_deg: f64) -> [f64; 3] {
    let t = theta_deg.to_radians();
    [t.sin(), 0.0, t.cos()]
}

/// The directional albedo at incidence `wi`: the quadrature `fastbrdf albedo` runs
/// (`quad::albedo` around the mirror direction, with the model's own breakpoints), converged to
/// 1e-6 relative or the test fails.
pub fn albedo(b: &dyn fastbrdf::Brdf<f64>, wi: [f64; 3]) -> f64 {
    let (v, e) = fastbrdf::quad::albedo(
        |wo| b.eval(wi, wo),
        [-wi[0], -wi[1], wi[2]],
        &b.mirror_breaks(),
        1e-8,
    );
    assert!(
        e <= 1e-6 * v.abs().max(1e-3),
        "albedo quadrature did not converge: {v} +- {e}"
    );
    v
}

/// Model `id` built in f64 from `given`, which must be a BRDF.
pub fn brdf(id: &str, given: &[(&str, &str)]) -> Box<dyn fastbrdf::Brdf<f64>> {
    match build::<f64>(id, given).unwrap() {
        fastbrdf::Model::Brdf(b) => b,
        _ => panic!("{id} is not a BRDF"),
    }
}

/// The batch sampler's output buffers of `n` elements, filled with a marker (-7) the sampler
/// must overwrite (`tests/batch_sample.rs`, `tests/batch_sample_unit.rs`).
pub struct Outs {
    pub wi: [Vec<f32>; 3],
    pub weight: Vec<f32>,
    pub pdf: Vec<f32>,
}

impl Outs {
    pub fn new(n: usize) -> Self {
        Self {
            wi: std::array::from_fn(|_| vec![-7.0; n]),
            weight: vec![-7.0; n],
            pdf: vec![-7.0; n],
        }
    }

    pub fn out(&mut self) -> fastbrdf::batch::sample::SampleOut<'_> {
        let [x, y, z] = &mut self.wi;
        fastbrdf::batch::sample::SampleOut {
            wi: [x, y, z],
            weight: &mut self.weight,
            pdf: &mut self.pdf,
        }
    }

    /// Element `i`'s `wi`, weight and pdf as bits.
    pub fn bits_at(&self, i: usize) -> [u32; 5] {
        [
            self.wi[0][i],
            self.wi[1][i],
            self.wi[2][i],
            self.weight[i],
            self.pdf[i],
        ]
        .map(f32::to_bits)
    }

    /// Every element's [`Outs::bits_at`].
    pub fn bits(&self) -> Vec<[u32; 5]> {
        (0..self.pdf.len()).map(|i| self.bits_at(i)).collect()
    }
}
