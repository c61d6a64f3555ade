//! A [`UserBrdf`] called in chunks of at most `batch` rows (the chunks in parallel), with the
//! lengths of what it returns checked and its errors named.

use fastbrdf::user::{SampleBatch, UserBrdf};
use rayon::prelude::*;

/// A model with its channel count and batch size.
pub struct Batched<'a> {
    pub model: &'a dyn UserBrdf,
    pub channels: usize,
    batch: usize,
    name: String,
}

impl<'a> Batched<'a> {
    /// `Err` when the model has no channels.
    pub fn new(model: &'a dyn UserBrdf, batch: usize) -> Result<Self, String> {
        let channels = model.channels();
        let name = model.name();
        if channels == 0 {
            return Err(format!("{name}: channels() is 0"));
        }
        Ok(Self {
            model,
            channels,
            batch: batch.max(1),
            name,
        })
    }

    fn err(&self, call: &str, e: String) -> String {
        format!("{}: {call} failed: {e}", self.name)
    }

    /// `f(wi[k], wo[k])`, `channels` numbers per row.
    pub fn eval(&self, wi: &[[f64; 3]], wo: &[[f64; 3]]) -> Result<Vec<f64>, String> {
        assert_eq!(wi.len(), wo.len());
        let c = self.channels;
        let mut out = vec![0.0; wi.len() * c];
        out.par_chunks_mut(self.batch * c)
            .zip(wi.par_chunks(self.batch).zip(wo.par_chunks(self.batch)))
            .try_for_each(|(o, (a, b))| self.model.eval(a, b, o))
            .map_err(|e| self.err("eval", e))?;
        Ok(out)
    }

    /// `f` at one fixed `wo` for every `wi`.
    pub fn eval_at(&self, wi: &[[f64; 3]], wo: [f64; 3]) -> Result<Vec<f64>, String> {
        self.eval(wi, &vec![wo; wi.len()])
    }

    /// `pdf(wo[k], wi[k])`.
    pub fn pdf(&self, wo: &[[f64; 3]], wi: &[[f64; 3]]) -> Result<Vec<f64>, String> {
        assert_eq!(wi.len(), wo.len());
        let mut out = vec![0.0; wi.len()];
        out.par_chunks_mut(self.batch)
            .zip(wo.par_chunks(self.batch).zip(wi.par_chunks(self.batch)))
            .try_for_each(|(o, (a, b))| self.model.pdf(a, b, o))
            .map_err(|e| self.err("pdf", e))?;
        Ok(out)
    }

    /// `pdf(wo, wi[k])` at one fixed `wo`.
    pub fn pdf_at(&self, wo: [f64; 3], wi: &[[f64; 3]]) -> Result<Vec<f64>, String> {
        self.pdf(&vec![wo; wi.len()], wi)
    }

    /// Samples for every `u` at one fixed `wo`, the chunks concatenated.
    pub fn sample_at(&self, wo: [f64; 3], u: &[[f64; 2]]) -> Result<SampleBatch, String> {
        let c = self.channels;
        let parts: Vec<SampleBatch> = u
            .par_chunks(self.batch)
            .map(|u| {
                let b = self.model.sample(&vec![wo; u.len()], u)?;
                let n = u.len();
                if b.valid.len() != n || b.wi.len() != n || b.pdf.len() != n {
                    return Err(format!(
                        "{n} rows asked, {} valid flags, {} directions and {} pdfs returned",
                        b.valid.len(),
                        b.wi.len(),
                        b.pdf.len()
                    ));
                }
                if b.weight.len() != n * c {
                    return Err(format!(
                        "{n} rows of {c} channels asked, {} weights returned",
                        b.weight.len()
                    ));
                }
                Ok(b)
            })
            .collect::<Result<_, String>>()
            .map_err(|e| self.err("sample", e))?;
        let mut all = SampleBatch::default();
        for p in parts {
            all.valid.extend(p.valid);
            all.wi.extend(p.wi);
            all.weight.extend(p.weight);
            all.pdf.extend(p.pdf);
        }
        Ok(all)
    }
}
