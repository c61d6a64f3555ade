//! The benchmark's inputs: 64-byte aligned buffers of cosines, direction pairs and
//! roughnesses, deterministic.

use fastbrdf::Kind;
use fastbrdf::accuracy::splitmix;
use fastbrdf::batch::Input;
use rayon::prelude::*;

/// `len` floats starting on a 64-byte boundary (a cache line, one AVX-512 vector). Every
/// timed loop reads and writes these: where a buffer starts decides whether each vector load
/// and store straddles two cache lines, and with a `Vec` of its own per side (16-byte
/// aligned by the allocator) the C peers' `cubic` and `schlick` rates moved by up to 40%
/// from one run to the next (issue 13). Written by hand: `Vec::as_ptr().align_offset` and
/// a slice are all it takes (no unsafe code).
pub struct Aligned {
    buf: Vec<f32>,
    off: usize,
    len: usize,
}

impl Aligned {
    /// `len` zeros.
    pub fn zeroed(len: usize) -> Self {
        let buf = vec![0.0f32; len + 15];
        // `align_offset` may decline (usize::MAX): the buffer is then merely unaligned, which
        // costs speed, not correctness.
        let off = match buf.as_ptr().align_offset(64) {
            o if o < 16 => o,
            _ => 0,
        };
        Self { buf, off, len }
    }

    /// A copy of `v`.
    pub fn from_slice(v: &[f32]) -> Self {
        let mut a = Self::zeroed(v.len());
        a.copy_from_slice(v);
        a
    }
}

impl std::ops::Deref for Aligned {
    type Target = [f32];
    fn deref(&self) -> &[f32] {
        &self.buf[self.off..self.off + self.len]
    }
}

impl std::ops::DerefMut for Aligned {
    fn deref_mut(&mut self) -> &mut [f32] {
        &mut self.buf[self.off..self.off + self.len]
    }
}

/// Benchmark inputs of one size: cosines uniform in [0, 1] (uniform in solid angle),
/// direction pairs uniform over the upper hemisphere, and roughnesses `alpha` uniform in
/// [0.005, 1] (the split-sum terms' second input, beside `cos`).
pub struct Inputs {
    pub cos: Aligned,
    pub dirs: [Aligned; 6],
    pub alpha: Aligned,
}

impl Inputs {
    /// `n` cosines and `n` direction pairs, deterministic.
    pub fn new(n: usize) -> Self {
        // Each column is written in place into its aligned buffer (no Vec to copy from: the
        // large batch is 16M elements a column).
        let fill = |f: &(dyn Fn(usize) -> f32 + Sync)| {
            let mut a = Aligned::zeroed(n);
            a.par_iter_mut().enumerate().for_each(|(i, o)| *o = f(i));
            a
        };
        let cos = fill(&|i| {
            let mut s = i as u64 * 7 + 1;
            splitmix(&mut s) as f32
        });
        let pairs: Vec<[f32; 6]> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut s = (i as u64) << 20 | 12345;
                let mut dir = || {
                    let z = splitmix(&mut s).max(1e-3);
                    let r = (1.0 - z * z).sqrt();
                    let phi = std::f64::consts::TAU * splitmix(&mut s);
                    [(r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32]
                };
                let (a, b) = (dir(), dir());
                [a[0], a[1], a[2], b[0], b[1], b[2]]
            })
            .collect();
        let dirs = std::array::from_fn(|k| fill(&|i| pairs[i][k]));
        let alpha = fill(&|i| {
            let mut s = i as u64 * 13 + 5;
            (0.005 + 0.995 * splitmix(&mut s)) as f32
        });
        Self { cos, dirs, alpha }
    }

    /// The batch input of a model of `kind`: its first `len` elements.
    pub fn input(&self, kind: Kind, len: usize) -> Input<'_> {
        match kind {
            Kind::Brdf => Input::Dirs(std::array::from_fn(|k| &self.dirs[k][..len])),
            Kind::Env => Input::Env([&self.cos[..len], &self.alpha[..len]]),
            _ => Input::Cos(&self.cos[..len]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aligned_buffers_start_on_a_cache_line_and_hold_their_values() {
        for len in [0usize, 1, 15, 16, 4096, 4097] {
            let v: Vec<f32> = (0..len).map(|i| i as f32 * 0.5).collect();
            let a = Aligned::from_slice(&v);
            assert_eq!(&a[..], &v[..]);
            // `align_offset` may decline in principle (then only speed suffers); on the
            // platforms we build for it does not.
            assert_eq!(a.as_ptr() as usize % 64, 0, "len {len}");
            let mut z = Aligned::zeroed(len);
            assert!(z.iter().all(|x| *x == 0.0) && z.len() == len);
            z.copy_from_slice(&v);
            assert_eq!(&z[..], &v[..]);
        }
    }
}
