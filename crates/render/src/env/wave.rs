//! Staged draws and look-ups over a wavefront: [`EnvMap::sample_many`] and
//! [`EnvMap::lookup_many`], the same values as [`EnvMap::sample`] and [`EnvMap::lookup`] one
//! by one, to the bit.
//!
//! Why stages. On a large map the cells (16 B per texel: 8 MB for the built-in sky) and the
//! rows of the conditional tables (4 KB each) are not in cache: a draw reads a guide entry,
//! then one or two lines of its row, then a cell, each load depending on the one before, and
//! a look-up reads a cell. One sample at a time, these misses come one after another (the
//! draws and look-ups were 45% of an environment render). Staged, each step runs over the
//! whole wavefront and prefetches what the next step reads, so that the misses of all the
//! wavefront's samples overlap.

use super::{EnvMap, Part, bin_of, bucket, guide_range, row_guide, sample_cdf};
use glam::Vec3;

/// Asks for the cache line holding `p` (no effect where the target has no prefetch).
#[inline(always)]
fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads no memory the program sees and faults on no address.
    #[allow(unused_unsafe)]
    unsafe {
        use core::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Per-worker buffers of the staged draws and look-ups, reused from call to call.
#[derive(Default)]
pub struct Wave {
    /// Per draw: its row and place in it, its row of the conditional tables, its uniform
    /// number scaled by the row's total and its guide bucket (`usize::MAX`: none, search the
    /// row).
    row: Vec<(u32, f32)>,
    table: Vec<u32>,
    col_u: Vec<(f32, usize)>,
    /// Per draw: the range of its row that holds its column; per look-up: its texel and
    /// sin theta.
    range: Vec<(u32, u32)>,
    /// Per draw or look-up: its texel, sin theta and (draws) direction.
    texel: Vec<u32>,
    st: Vec<f32>,
    dir: Vec<Vec3>,
}

/// Defines `fn $name` running its body compiled for AVX2 where the CPU has it (8 lanes for
/// the trigonometry of the stages below, which the compiler vectorises), else for the
/// target's baseline: the same arithmetic either way (no fused multiply-adds), so the same
/// bits.
macro_rules! with_avx2 {
    ($name:ident($($arg:ident: $ty:ty),*) $body:block) => {
        fn $name($($arg: $ty),*) {
            #[inline(always)]
            fn body($($arg: $ty),*) $body
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                fn avx2($($arg: $ty),*) {
                    body($($arg),*)
                }
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: the CPU has AVX2 (checked just above).
                    unsafe { avx2($($arg),*) };
                    return;
                }
            }
            body($($arg),*)
        }
    };
}

with_avx2!(texels_of(map: &EnvMap, dirs: &[Vec3], texel: &mut [u32], st: &mut [f32]) {
    for ((d, t), s) in dirs.iter().zip(texel.iter_mut()).zip(st.iter_mut()) {
        let (i, sin) = map.texel_of(*d);
        (*t, *s) = (i as u32, sin);
    }
});

with_avx2!(dirs_of(
    map: &EnvMap,
    row: &[(u32, f32)],
    col: &[(u32, u32)],
    dir: &mut [Vec3],
    texel: &mut [u32],
    st: &mut [f32]
) {
    let w = map.width;
    for ((((&(r, fr), &(c, fc)), d), t), s) in row
        .iter()
        .zip(col)
        .zip(dir.iter_mut())
        .zip(texel.iter_mut())
        .zip(st.iter_mut())
    {
        let (dd, sin) = map.drawn_dir(r as usize, fr, c as usize, f32::from_bits(fc));
        (*d, *t, *s) = (dd, r * w + c, sin);
    }
});

with_avx2!(cosine_dirs(n: &[Vec3], u1: &[f32], u2: &[f32], dir: &mut [Vec3], cos: &mut [f32]) {
    for ((((n, a), b), d), c) in n.iter().zip(u1).zip(u2).zip(dir.iter_mut()).zip(cos.iter_mut()) {
        let l = super::cosine_sample(*n, *a, *b);
        (*d, *c) = (l, n.dot(l));
    }
});

/// [`super::cosine_sample`] about each unit normal of `n` by the numbers `u1`, `u2`, and its
/// cosine to the normal, written to `dir` and `cos` (as long as `n`): vectorised (the
/// sample's frame, square roots, `sin_cos` and normalisation were 7% of an environment render
/// one hit at a time).
pub fn cosine_many(n: &[Vec3], u1: &[f32], u2: &[f32], dir: &mut Vec<Vec3>, cos: &mut Vec<f32>) {
    assert!(
        u1.len() == n.len() && u2.len() == n.len(),
        "one u1 and u2 per normal"
    );
    dir.resize(n.len(), Vec3::ZERO);
    cos.resize(n.len(), 0.0);
    cosine_dirs(n, u1, u2, dir, cos);
}

impl EnvMap {
    /// [`EnvMap::sample`] of each pair (`u1[j]`, `u2[j]`), appended to `out` in order: the
    /// rows first (the marginal table is small and stays in cache), then the rows' guide
    /// entries, the ranges of the rows they give, the columns and the cells, each step
    /// prefetching what the next reads.
    pub fn sample_many(
        &self,
        u1: &[f32],
        u2: &[f32],
        wave: &mut Wave,
        out: &mut Vec<(Vec3, Vec3, f32)>,
    ) {
        self.draw_many(Part::Whole, u1, u2, wave, out);
    }

    /// [`EnvMap::sample_rest`] of each pair, as [`EnvMap::sample_many`].
    pub fn sample_rest_many(
        &self,
        u1: &[f32],
        u2: &[f32],
        wave: &mut Wave,
        out: &mut Vec<(Vec3, Vec3, f32)>,
    ) {
        self.draw_many(Part::Rest, u1, u2, wave, out);
    }

    fn draw_many(
        &self,
        part: Part,
        u1: &[f32],
        u2: &[f32],
        wave: &mut Wave,
        out: &mut Vec<(Vec3, Vec3, f32)>,
    ) {
        assert_eq!(u1.len(), u2.len(), "one u2 per u1");
        let w = self.width as usize;
        let g = row_guide(w);
        let (marginal, marginal_guide, rows, scale) = self.part(part);
        let Wave {
            row,
            table,
            col_u,
            range,
            ..
        } = wave;
        row.clear();
        table.clear();
        col_u.clear();
        range.clear();
        for (&a, &b) in u1.iter().zip(u2) {
            let (r, fr) = sample_cdf(marginal, marginal_guide, a);
            let t = rows.map_or(r, |rows| rows[r] as usize);
            let total = self.row_total[t];
            let u = b.clamp(0.0, 1.0 - f32::EPSILON) * total;
            let k = bucket(total, g, u);
            if let Some(k) = k {
                let guide = &self.conditional_guide[t * (g + 1)..];
                prefetch(guide.as_ptr().wrapping_add(k.saturating_sub(1)));
                prefetch(guide.as_ptr().wrapping_add((k + 2).min(g)));
            }
            row.push((r as u32, fr));
            table.push(t as u32);
            col_u.push((u, k.unwrap_or(usize::MAX)));
        }
        for (&r, &(_, k)) in table.iter().zip(col_u.iter()) {
            let r = r as usize;
            let cdf = &self.conditional[r * (w + 1)..(r + 1) * (w + 1)];
            let (lo, hi) = if k == usize::MAX {
                (0, w + 1)
            } else {
                guide_range(&self.conditional_guide[r * (g + 1)..(r + 1) * (g + 1)], k)
            };
            prefetch(cdf.as_ptr().wrapping_add(lo));
            prefetch(cdf.as_ptr().wrapping_add(hi.saturating_sub(1)));
            range.push((lo as u32, hi as u32));
        }
        // The columns: the search within the range, then the cell's prefetch; the columns
        // are kept in `range` (column, place in it as bits).
        let drawn = row.iter().zip(table.iter()).zip(col_u.iter());
        for (((&(r, _), &t), &(u, _)), rg) in drawn.zip(range.iter_mut()) {
            let t = t as usize;
            let cdf = &self.conditional[t * (w + 1)..(t + 1) * (w + 1)];
            let (lo, hi) = (rg.0 as usize, rg.1 as usize);
            let p = lo + cdf[lo..hi].partition_point(|&c| c <= u);
            let (c, fc) = bin_of(cdf, p, u);
            prefetch(self.cells.as_ptr().wrapping_add(r as usize * w + c));
            *rg = (c as u32, fc.to_bits());
        }
        // The directions (vectorised), then the cells.
        let n = row.len();
        let (texel, st, dir) = (&mut wave.texel, &mut wave.st, &mut wave.dir);
        texel.resize(n, 0);
        st.resize(n, 0.0);
        dir.resize(n, Vec3::ZERO);
        dirs_of(self, row, range, dir, texel, st);
        out.extend(
            dir.iter()
                .zip(texel.iter())
                .zip(st.iter())
                .map(|((&d, &i), &s)| {
                    let (rgb, pdf) = self.cell_at(i as usize, s);
                    (d, rgb, pdf * scale)
                }),
        );
    }

    /// [`EnvMap::lookup`] of each unit direction of `dirs`, appended to `out` in order: the
    /// texels first (vectorised), then their cells' prefetches, then the cells.
    pub fn lookup_many(&self, dirs: &[Vec3], wave: &mut Wave, out: &mut Vec<(Vec3, f32)>) {
        let (texel, st) = (&mut wave.texel, &mut wave.st);
        texel.resize(dirs.len(), 0);
        st.resize(dirs.len(), 0.0);
        texels_of(self, dirs, texel, st);
        for &i in texel.iter() {
            prefetch(self.cells.as_ptr().wrapping_add(i as usize));
        }
        out.extend(
            texel
                .iter()
                .zip(st.iter())
                .map(|(&i, &s)| self.cell_at(i as usize, s)),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::env::Rng;

    /// The vectorised cosine directions are `cosine_sample`'s to the bit.
    #[test]
    fn the_cosine_stage_changes_no_value() {
        let mut rng = Rng::new(2, 4);
        let mut n: Vec<Vec3> = (0..1001)
            .map(|_| {
                let (u, v) = (rng.uniform(), rng.uniform());
                crate::env::uv_to_dir(u, v).0
            })
            .collect();
        n.extend([Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z, Vec3::X]);
        let u1: Vec<f32> = n.iter().map(|_| rng.uniform()).collect();
        let mut u2: Vec<f32> = n.iter().map(|_| rng.uniform()).collect();
        u2[0] = 0.0;
        let (mut dir, mut cos) = (Vec::new(), Vec::new());
        cosine_many(&n, &u1, &u2, &mut dir, &mut cos);
        for j in 0..n.len() {
            let l = crate::env::cosine_sample(n[j], u1[j], u2[j]);
            assert_eq!((dir[j], cos[j]), (l, n[j].dot(l)), "{}", n[j]);
        }
    }

    /// The staged draws and look-ups are the one-by-one ones to the bit, on the sky, a map
    /// with black rows and the constant map, including the ends of the unit interval.
    #[test]
    fn the_stages_change_no_value() {
        let mut rng = Rng::new(5, 10);
        let maps = [
            EnvMap::sky(),
            crate::env::tests::rough_map(5, 9),
            EnvMap::constant(Vec3::ONE),
        ];
        let mut wave = Wave::default();
        for map in maps {
            let mut u1: Vec<f32> = (0..5000).map(|_| rng.uniform()).collect();
            let mut u2: Vec<f32> = (0..5000).map(|_| rng.uniform()).collect();
            u1.extend([0.0, 1.0 - f32::EPSILON, 0.0, 1.0, 0.5]);
            u2.extend([0.0, 0.0, 1.0 - f32::EPSILON, 1.0, 1e-9]);
            let mut out = vec![(Vec3::ONE, Vec3::ONE, 7.0)];
            map.sample_many(&u1, &u2, &mut wave, &mut out);
            assert_eq!(out.len(), u1.len() + 1);
            for (j, (&a, &b)) in u1.iter().zip(&u2).enumerate() {
                assert_eq!(out[j + 1], map.sample(a, b), "u = ({a}, {b})");
            }
            out.truncate(1);
            map.sample_rest_many(&u1, &u2, &mut wave, &mut out);
            for (j, (&a, &b)) in u1.iter().zip(&u2).enumerate() {
                assert_eq!(out[j + 1], map.sample_rest(a, b), "rest, u = ({a}, {b})");
            }
            let dirs: Vec<Vec3> = out.iter().map(|o| o.0).chain([Vec3::Y, -Vec3::Y]).collect();
            let mut looked = Vec::new();
            map.lookup_many(&dirs, &mut wave, &mut looked);
            for (d, l) in dirs.iter().zip(&looked) {
                assert_eq!(*l, map.lookup(*d), "{d}");
            }
        }
    }
}
