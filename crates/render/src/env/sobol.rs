//! The Sobol sampler's uniform numbers of a whole wavefront at once ([`fill`]): the numbers of
//! `sobol_burley::sample_4d`, to the bit, for every hit of an environment pass.
//!
//! Why not `sample_4d` per hit: the environment pass draws two 4D points per hit and pass,
//! about 37 ns each on this project's benchmark machine (a bit-by-bit loop over the scrambled
//! index, then the Owen scramble's multiplies in SSE2, which lacks a 32-bit multiply): 12% of
//! an environment render. Here the same arithmetic (Burley 2020, through the crate's public
//! `parts`) runs branch-free over the hits (a fixed 16-step loop over the index's bits,
//! masked), so the compiler vectorises it across hits, with AVX2 where the CPU has it.

use crate::hash::pcg;
use sobol_burley::parts::{hash, owen_scramble_rev, sobol_rev, u32_to_f32_norm};

/// The second sequence's seed: `pcg(seed ^ SECOND)` (the BRDF's pair, then the bright texels').
const SECOND: u32 = 0x68bc_21eb;

/// The direction vectors of dimensions 0 to 3 for the index's top 16 bits (the crate uses no
/// more: 2^16 points per seed), bit-reversed as `sobol_rev` XORs them.
fn directions() -> [[u32; 4]; 16] {
    std::array::from_fn(|b| std::array::from_fn(|d| sobol_rev(0x8000_0000 >> b, d as u32)))
}

/// Dimensions 0 to `D - 1` of point `k_rev` (bit-reversed) of the sequence seeded by `seed`:
/// `sobol_burley::sample_4d(k, 0, seed)`'s first `D` numbers.
#[inline(always)]
fn point<const D: usize>(k_rev: u32, seed: u32, dirs: &[[u32; 4]; 16]) -> [f32; D] {
    let index = owen_scramble_rev(k_rev, hash(seed ^ 0x79c6_8e4a));
    let mut sobol = [0u32; D];
    for (b, dir) in dirs.iter().enumerate() {
        let mask = 0u32.wrapping_sub((index >> (31 - b)) & 1);
        for d in 0..D {
            sobol[d] ^= dir[d] & mask;
        }
    }
    let seed = seed.wrapping_mul(0x9c8f_2d3b);
    const SALT: [u32; 4] = [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8];
    std::array::from_fn(|d| {
        let scrambled = owen_scramble_rev(sobol[d], hash(seed ^ SALT[d]));
        u32_to_f32_norm(scrambled.reverse_bits())
    })
}

/// The eight numbers of each hit of `ids` in `pass`, appended to `out` column by column:
/// point `pass mod 2^16` of the sequence seeded by `pcg(id ^ pcg(pass >> 16))` (its four
/// dimensions), then the four of the sequence seeded by `pcg(seed ^ 0x68bc21eb)`; the numbers
/// of `render::environment::uniforms` with the Sobol sampler.
pub fn fill(ids: &[u32], pass: u32, out: &mut [Vec<f32>; 8]) {
    let start = out[0].len();
    for col in out.iter_mut() {
        col.resize(start + ids.len(), 0.0);
    }
    let cols = out.each_mut().map(|c| &mut c[start..]);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        unsafe { fill_avx2(ids, pass, cols) };
        return;
    }
    fill_with(ids, pass, cols);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn fill_avx2(ids: &[u32], pass: u32, cols: [&mut [f32]; 8]) {
    fill_with(ids, pass, cols);
}

#[inline(always)]
fn fill_with(ids: &[u32], pass: u32, cols: [&mut [f32]; 8]) {
    let dirs = directions();
    let k_rev = (pass & 0xffff).reverse_bits();
    let high = pcg(pass >> 16);
    let n = ids.len();
    let [a0, a1, a2, a3, b0, b1, b2, b3] = cols.map(|c| &mut c[..n]);
    for j in 0..n {
        let seed = pcg(ids[j] ^ high);
        let a = point::<4>(k_rev, seed, &dirs);
        let b = point::<4>(k_rev, pcg(seed ^ SECOND), &dirs);
        (a0[j], a1[j], a2[j], a3[j]) = (a[0], a[1], a[2], a[3]);
        (b0[j], b1[j], b2[j], b3[j]) = (b[0], b[1], b[2], b[3]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bit for bit `sample_4d`'s numbers, for passes across the 2^16 boundary and ids of every
    /// size, appended after what `out` held.
    #[test]
    fn the_wavefront_is_sample_4d_to_the_bit() {
        let ids: Vec<u32> = (0..997u32)
            .map(|i| i.wrapping_mul(2_654_435_761) ^ (i << 3))
            .chain([0, u32::MAX])
            .collect();
        for pass in [0u32, 1, 2, 3, 7, 255, 4096, 65_535, 65_536, 65_537, 1 << 20] {
            let mut out: [Vec<f32>; 8] = std::array::from_fn(|_| vec![9.0]);
            fill(&ids, pass, &mut out);
            for (j, &id) in ids.iter().enumerate() {
                let seed = pcg(id ^ pcg(pass >> 16));
                let k = pass & 0xffff;
                let a = sobol_burley::sample_4d(k, 0, seed);
                let b = sobol_burley::sample_4d(k, 0, pcg(seed ^ SECOND));
                let want = [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]];
                for (c, col) in out.iter().enumerate() {
                    assert_eq!(col[0], 9.0);
                    assert_eq!(
                        col[j + 1].to_bits(),
                        want[c].to_bits(),
                        "id {id}, pass {pass}, dimension {c}"
                    );
                }
            }
        }
    }
}
