//! Models that are not in the registry (issue 31): a user's shader (a BRDF Explorer `.brdf`
//! file or a WGSL/GLSL function, evaluated on the GPU by `fastbrdf-gpu`), a Python object (the
//! Python package), and, through [`Builtin`], every registry BRDF. One batch interface for all
//! of them, so that `fastbrdf conform`, the renderer and the analyses take any of them alike.
//!
//! Conventions are the library's: local shading frame with the normal along +z, `wi` and `wo`
//! pointing away from the surface, `f` without the cosine factor. Calls are batched because
//! the evaluators behind them are (a GPU dispatch, a numpy call): a caller hands over thousands
//! of directions at once, never one.

use crate::model::Brdf;
use crate::sample::Strategy;
use crate::spec::ModelSpec;

/// What a batch of [`UserBrdf::sample`] drew: row `k` for `wo[k]`, `u[k]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleBatch {
    /// Whether row `k` is a sample (`false`: the sampler gave none, its missing mass).
    pub valid: Vec<bool>,
    /// The drawn direction (unspecified where not valid).
    pub wi: Vec<[f64; 3]>,
    /// `f(wi, wo) cos theta_i / pdf` as the sampler reports it, `channels()` numbers per row.
    pub weight: Vec<f64>,
    /// The solid-angle density the sampler reports for `wi`.
    pub pdf: Vec<f64>,
}

/// A BRDF evaluated in batches. Implementations: [`Builtin`] (a registry model), the GPU
/// evaluator of a user's shader (`fastbrdf_gpu::user`), a Python object (the Python package).
pub trait UserBrdf: Send + Sync {
    /// How users name it: the registry id and parameters, `file:PATH`, a Python class name.
    fn name(&self) -> String;
    /// Numbers per direction pair: 1 (grey) or 3 (R, G, B).
    fn channels(&self) -> usize;
    /// `f(wi[k], wo[k])` into `out[k * channels .. (k + 1) * channels]`. Inputs are taken as
    /// given (not normalised, not clamped): checking what a model does with odd inputs is
    /// the point of `conform`. An error is the evaluator's own message.
    fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]], out: &mut [f64]) -> Result<(), String>;
    /// Whether [`Self::sample`] and [`Self::pdf`] are implemented.
    fn samples(&self) -> bool {
        false
    }
    /// Draws `wi` given `wo[k]` and `u[k]` in [0, 1)^2.
    fn sample(&self, wo: &[[f64; 3]], u: &[[f64; 2]]) -> Result<SampleBatch, String> {
        let _ = (wo, u);
        Err(format!("{} does not sample", self.name()))
    }
    /// The solid-angle density of [`Self::sample`]'s `wi[k]` given `wo[k]`, into `out[k]`.
    fn pdf(&self, wo: &[[f64; 3]], wi: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        let _ = (wo, wi, out);
        Err(format!("{} does not sample", self.name()))
    }
}

/// A registry BRDF (each channel of a coloured spec) as a [`UserBrdf`], in f64, sampled by
/// `strategy` (its default with [`Strategy::Auto`]).
pub struct Builtin {
    spec: ModelSpec,
    channels: Vec<Box<dyn Brdf<f64>>>,
    strategy: Strategy,
}

impl Builtin {
    /// The BRDF of `spec`; an error when `spec` is not a full BRDF or `strategy` does not
    /// apply to it.
    pub fn new(spec: &ModelSpec, strategy: Strategy) -> crate::Result<Self> {
        let mut channels = Vec::new();
        for c in spec.channel_specs() {
            match c.model::<f64>()? {
                crate::Model::Brdf(b) => channels.push(b),
                _ => {
                    return Err(crate::Error::WrongKind {
                        model: spec.id().to_string(),
                        expected: "brdf".into(),
                        found: spec.kind().name().into(),
                    });
                }
            }
        }
        let strategy = channels[0]
            .resolve(strategy)
            .map_err(|e| crate::Error::InvalidParam {
                model: spec.id().to_string(),
                param: "strategy".into(),
                value: strategy.name().into(),
                expected: e,
            })?;
        Ok(Self {
            spec: spec.clone(),
            channels,
            strategy,
        })
    }

    /// The spec it evaluates.
    pub fn spec(&self) -> &ModelSpec {
        &self.spec
    }

    /// The strategy it samples by (never `Auto`).
    pub fn strategy(&self) -> Strategy {
        self.strategy
    }
}

impl UserBrdf for Builtin {
    fn name(&self) -> String {
        let pairs = self.spec.pairs();
        if pairs.is_empty() {
            self.spec.id().to_string()
        } else {
            let p: Vec<String> = pairs.iter().map(|(k, v)| format!("{k}={v}")).collect();
            format!("{} {}", self.spec.id(), p.join(" "))
        }
    }
    fn channels(&self) -> usize {
        self.channels.len()
    }
    fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        let c = self.channels.len();
        check_rows(wi.len(), wo.len(), out.len(), c)?;
        for (k, (a, b)) in wi.iter().zip(wo).enumerate() {
            for (j, m) in self.channels.iter().enumerate() {
                out[k * c + j] = m.eval(*a, *b);
            }
        }
        Ok(())
    }
    fn samples(&self) -> bool {
        true
    }
    /// The first channel's sampler (a coloured spec's channels share their lobe shape); the
    /// weight of every channel is that channel's `f cos / pdf`.
    fn sample(&self, wo: &[[f64; 3]], u: &[[f64; 2]]) -> Result<SampleBatch, String> {
        if wo.len() != u.len() {
            return Err(format!("{} wo rows but {} u rows", wo.len(), u.len()));
        }
        let c = self.channels.len();
        let mut b = SampleBatch {
            valid: vec![false; wo.len()],
            wi: vec![[0.0; 3]; wo.len()],
            weight: vec![0.0; wo.len() * c],
            pdf: vec![0.0; wo.len()],
        };
        for (k, (o, uu)) in wo.iter().zip(u).enumerate() {
            if let Some(s) = self.channels[0].sample(*o, *uu, self.strategy) {
                b.valid[k] = true;
                b.wi[k] = s.wi;
                b.pdf[k] = s.pdf;
                b.weight[k * c] = s.weight;
                for j in 1..c {
                    b.weight[k * c + j] =
                        self.channels[j].eval(s.wi, *o) * s.wi[2].max(0.0) / s.pdf;
                }
            }
        }
        Ok(b)
    }
    fn pdf(&self, wo: &[[f64; 3]], wi: &[[f64; 3]], out: &mut [f64]) -> Result<(), String> {
        check_rows(wo.len(), wi.len(), out.len(), 1)?;
        for (k, (o, i)) in wo.iter().zip(wi).enumerate() {
            out[k] = self.channels[0].pdf(*o, *i, self.strategy);
        }
        Ok(())
    }
}

/// `Err` unless `a == b` and `out == a * channels`.
pub fn check_rows(a: usize, b: usize, out: usize, channels: usize) -> Result<(), String> {
    if a != b {
        return Err(format!("{a} rows of one direction but {b} of the other"));
    }
    if out != a * channels {
        return Err(format!(
            "output holds {out} numbers; {a} rows of {channels} need {}",
            a * channels
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_builtin_evaluates_and_samples_as_its_model() {
        let spec = ModelSpec::parse("cook-torrance", &[("alpha", "0.3")]).unwrap();
        let b = Builtin::new(&spec, Strategy::Auto).unwrap();
        let crate::Model::Brdf(m) = spec.model::<f64>().unwrap() else {
            panic!()
        };
        let wi = [[0.3, 0.1, 0.9], [0.0, 0.6, 0.8]];
        let wo = [[-0.2, 0.0, 0.97], [0.1, -0.5, 0.86]];
        let mut out = [0.0; 2];
        b.eval(&wi, &wo, &mut out).unwrap();
        for (k, v) in out.iter().enumerate() {
            assert_eq!(*v, m.eval(wi[k], wo[k]));
        }
        let s = b.sample(&wo, &[[0.2, 0.7], [0.9, 0.1]]).unwrap();
        let mut p = [0.0; 2];
        b.pdf(&wo, &s.wi, &mut p).unwrap();
        for (k, v) in p.iter().enumerate() {
            assert!(s.valid[k]);
            assert!((v - s.pdf[k]).abs() <= 1e-9 * v);
        }
        assert!(b.eval(&wi, &wo, &mut [0.0; 3]).is_err());
        assert!(b.name().starts_with("cook-torrance"), "{}", b.name());
    }

    #[test]
    fn a_lobe_is_not_a_builtin_brdf() {
        let spec = ModelSpec::parse("flog", &[]).unwrap();
        let e = Builtin::new(&spec, Strategy::Auto).err().unwrap();
        assert!(e.to_string().contains("flog"), "{e}");
    }
}
