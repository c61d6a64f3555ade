//! A model outside the registry ([`fastbrdf::user::UserBrdf`]: a user's shader evaluated on
//! the GPU, a Python object) shaded as an RGB BRDF, one evaluator call per batch of the
//! renderer's direction pairs (issue 31). The whole BRDF, diffuse part included (BRDF
//! Explorer's files are whole BRDFs), so a scene gives it the weights 0, 1 as it does measured
//! data.

use crate::scene::RgbBrdf;
use fastbrdf::user::UserBrdf;
use std::sync::{Arc, Mutex};

/// A [`UserBrdf`] as an [`RgbBrdf`]: grey models give the same value in R, G and B. The first
/// evaluator error is kept (and the batch shaded black) for [`RgbBrdf::failure`]: the batch
/// methods cannot return it, the caller asks after the render.
pub struct UserRgb {
    brdf: Arc<dyn UserBrdf>,
    failure: Mutex<Option<String>>,
}

impl UserRgb {
    pub fn new(brdf: Arc<dyn UserBrdf>) -> Self {
        Self {
            brdf,
            failure: Mutex::new(None),
        }
    }

    /// The model it shades.
    pub fn brdf(&self) -> &Arc<dyn UserBrdf> {
        &self.brdf
    }

    fn fail(&self, e: String) {
        let mut f = self.failure.lock().unwrap_or_else(|p| p.into_inner());
        if f.is_none() {
            *f = Some(e);
        }
    }
}

impl RgbBrdf for UserRgb {
    fn eval_rgb(&self, wi: [f32; 3], wo: [f32; 3]) -> [f32; 3] {
        let mut out = Vec::with_capacity(1);
        let c = |i: usize| -> [f32; 1] { [if i < 3 { wi[i] } else { wo[i - 3] }] };
        let cols = [c(0), c(1), c(2), c(3), c(4), c(5)];
        self.eval_rgb_batch(cols.each_ref().map(|x| &x[..]), &mut out);
        out[0]
    }

    fn eval_rgb_batch(&self, cols: [&[f32]; 6], out: &mut Vec<[f32; 3]>) {
        let n = cols[0].len();
        out.clear();
        out.resize(n, [0.0; 3]);
        if n == 0 {
            return;
        }
        let dir = |k: usize, o: usize| [cols[o][k], cols[o + 1][k], cols[o + 2][k]].map(f64::from);
        let wi: Vec<[f64; 3]> = (0..n).map(|k| dir(k, 0)).collect();
        let wo: Vec<[f64; 3]> = (0..n).map(|k| dir(k, 3)).collect();
        let c = self.brdf.channels();
        let mut v = vec![0.0; n * c];
        if let Err(e) = self.brdf.eval(&wi, &wo, &mut v) {
            self.fail(format!("{}: {e}", self.brdf.name()));
            return;
        }
        for (k, o) in out.iter_mut().enumerate() {
            *o = if c == 3 {
                [v[3 * k] as f32, v[3 * k + 1] as f32, v[3 * k + 2] as f32]
            } else {
                [v[k * c] as f32; 3]
            };
        }
    }

    fn failure(&self) -> Option<String> {
        self.failure
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fastbrdf::ModelSpec;
    use fastbrdf::sample::Strategy;
    use fastbrdf::user::Builtin;

    #[test]
    fn a_builtin_shades_as_its_model_in_every_channel() {
        let spec = ModelSpec::parse("cook-torrance", &[("alpha", "0.3")]).unwrap();
        let b = Builtin::new(&spec, Strategy::Auto).unwrap();
        let fastbrdf::Model::Brdf(m) = spec.model::<f64>().unwrap() else {
            panic!()
        };
        let u = UserRgb::new(Arc::new(b));
        let (wi, wo) = ([0.3f32, 0.1, 0.9], [-0.2f32, 0.05, 0.97]);
        let want = m.eval(wi.map(f64::from), wo.map(f64::from)) as f32;
        assert_eq!(u.eval_rgb(wi, wo), [want; 3]);
        assert!(u.failure().is_none());
    }

    /// An evaluator that fails: the batch is black and the failure kept.
    struct Broken;
    impl UserBrdf for Broken {
        fn name(&self) -> String {
            "broken".into()
        }
        fn channels(&self) -> usize {
            1
        }
        fn eval(&self, _: &[[f64; 3]], _: &[[f64; 3]], _: &mut [f64]) -> Result<(), String> {
            Err("device lost".into())
        }
    }

    #[test]
    fn a_failure_is_kept_for_the_caller() {
        let u = UserRgb::new(Arc::new(Broken));
        assert_eq!(u.eval_rgb([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]), [0.0; 3]);
        assert_eq!(u.failure().as_deref(), Some("broken: device lost"));
    }
}
