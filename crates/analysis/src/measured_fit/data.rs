//! The sampled measurements: MERL's valid bins within [`MAX_THETA_DEG`] of the normal, a
//! fixed-seed subsample.

use super::{MAX_THETA_DEG, SEED};
use fastbrdf::measured::{self, MeasuredBrdf};

/// The sampled measurements: directions (unit, local frame) and R, G, B values.
#[derive(Clone, Debug)]
pub struct Data {
    pub wi: Vec<[f64; 3]>,
    pub wo: Vec<[f64; 3]>,
    pub value: Vec<[f64; 3]>,
    /// Valid bins within [`MAX_THETA_DEG`] before subsampling.
    pub eligible: usize,
}

/// SplitMix64: a small, well-known generator, enough for a deterministic subsample.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

impl Data {
    /// At most `samples` of the eligible bins of `b` (see the module documentation), in bin
    /// order, chosen by a fixed-seed partial Fisher-Yates shuffle. `samples = 0`: all.
    pub fn from_measured(b: &MeasuredBrdf, samples: usize) -> Self {
        let cos_max = MAX_THETA_DEG.to_radians().cos();
        let mut eligible = Vec::new();
        for i in 0..measured::SAMPLES {
            if (0..3).any(|c| b.sample(c, i) < 0.0) {
                continue;
            }
            let (th, td, pd) = measured::bin_of(i);
            let (a, d, p) = measured::bin_centre(th, td, pd);
            let (wi, wo) = measured::from_half_diff(a, d, p);
            if wi[2] >= cos_max && wo[2] >= cos_max {
                eligible.push(i);
            }
        }
        let total = eligible.len();
        if samples > 0 && samples < total {
            let mut rng = SplitMix(SEED);
            for k in 0..samples {
                let j = k + (rng.next() % (total - k) as u64) as usize;
                eligible.swap(k, j);
            }
            eligible.truncate(samples);
            eligible.sort_unstable();
        }
        let mut d = Data {
            wi: Vec::with_capacity(eligible.len()),
            wo: Vec::with_capacity(eligible.len()),
            value: Vec::with_capacity(eligible.len()),
            eligible: total,
        };
        for i in eligible {
            let (th, td, pd) = measured::bin_of(i);
            let (a, dd, p) = measured::bin_centre(th, td, pd);
            let (wi, wo) = measured::from_half_diff(a, dd, p);
            d.wi.push(wi);
            d.wo.push(wo);
            d.value.push([0, 1, 2].map(|c| b.sample(c, i)));
        }
        d
    }

    pub fn len(&self) -> usize {
        self.wi.len()
    }

    pub fn is_empty(&self) -> bool {
        self.wi.is_empty()
    }
}
