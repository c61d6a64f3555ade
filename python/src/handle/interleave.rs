//! Deinterleaving f32 rows of 3 and 2 values into columns, and interleaving 3 columns back:
//! the copies between numpy's (N, 3) / (N, 2) arrays and the structure-of-arrays kernels.
//! With AVX-512, 16 rows per step through two-source permutes (`vpermt2ps`); elsewhere a
//! plain loop. Copies only: the values are the same bits on every path
//! (python/tests/test_batch_threads.py compares C-contiguous inputs, copied here, with
//! transposed, strided and reversed ones, read by `Soa::load`'s per-column path).

/// Whether this CPU runs the AVX-512 copies (checked once).
#[cfg(target_arch = "x86_64")]
fn avx512() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::is_x86_feature_detected!("avx512f"))
}

/// Lane `j` of the permutes that pick component `c` of rows of `k` values from three
/// registers `a`, `b`, `c` of 16 (the first from `a` and `b`, the second from that and
/// `c`): `(first, second)` indices.
#[cfg(target_arch = "x86_64")]
const fn split_idx(k: usize, c: usize) -> ([i32; 16], [i32; 16]) {
    let (mut first, mut second) = ([0i32; 16], [0i32; 16]);
    let mut j = 0;
    while j < 16 {
        let g = k * j + c;
        if g < 32 {
            first[j] = g as i32;
            second[j] = j as i32;
        } else {
            second[j] = 16 + (g - 32) as i32;
        }
        j += 1;
    }
    (first, second)
}

/// Rows of 3 (`src`, 3 values a row) into columns `x`, `y`, `z` (one value a row each).
pub(crate) fn split3(src: &[f32], [x, y, z]: [&mut [f32]; 3]) {
    let n = x.len();
    assert!(src.len() == 3 * n && y.len() == n && z.len() == n);
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if avx512() {
        // SAFETY: AVX-512F is present (checked above); the lengths are asserted.
        done = unsafe { split3_avx512(src, x, y, z) };
    }
    for (i, r) in src[3 * done..].chunks_exact(3).enumerate() {
        let i = done + i;
        (x[i], y[i], z[i]) = (r[0], r[1], r[2]);
    }
}

/// Rows of 2 into columns `x`, `y`.
pub(crate) fn split2(src: &[f32], [x, y]: [&mut [f32]; 2]) {
    let n = x.len();
    assert!(src.len() == 2 * n && y.len() == n);
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if avx512() {
        // SAFETY: as in `split3`.
        done = unsafe { split2_avx512(src, x, y) };
    }
    for (i, r) in src[2 * done..].chunks_exact(2).enumerate() {
        let i = done + i;
        (x[i], y[i]) = (r[0], r[1]);
    }
}

/// Columns `x`, `y`, `z` into rows of 3 (`dst`).
pub(crate) fn join3([x, y, z]: [&[f32]; 3], dst: &mut [f32]) {
    let n = x.len();
    assert!(dst.len() == 3 * n && y.len() == n && z.len() == n);
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if avx512() {
        // SAFETY: as in `split3`.
        done = unsafe { join3_avx512(x, y, z, dst) };
    }
    for (i, r) in dst[3 * done..].chunks_exact_mut(3).enumerate() {
        let i = done + i;
        r.copy_from_slice(&[x[i], y[i], z[i]]);
    }
}

/// The whole steps of 16 rows of [`split3`]; returns the rows done.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn split3_avx512(src: &[f32], x: &mut [f32], y: &mut [f32], z: &mut [f32]) -> usize {
    use std::arch::x86_64::*;
    const I: [([i32; 16], [i32; 16]); 3] = [split_idx(3, 0), split_idx(3, 1), split_idx(3, 2)];
    let n = x.len() / 16 * 16;
    let idx = I.map(|(a, b)| unsafe {
        (
            _mm512_loadu_si512(a.as_ptr().cast()),
            _mm512_loadu_si512(b.as_ptr().cast()),
        )
    });
    let outs = [x.as_mut_ptr(), y.as_mut_ptr(), z.as_mut_ptr()];
    let mut i = 0;
    while i < n {
        // SAFETY: rows i..i + 16 are in bounds (n is at most the row count).
        unsafe {
            let p = src.as_ptr().add(3 * i);
            let (a, b, c) = (
                _mm512_loadu_ps(p),
                _mm512_loadu_ps(p.add(16)),
                _mm512_loadu_ps(p.add(32)),
            );
            for (k, (i1, i2)) in idx.iter().enumerate() {
                let t = _mm512_permutex2var_ps(a, *i1, b);
                _mm512_storeu_ps(outs[k].add(i), _mm512_permutex2var_ps(t, *i2, c));
            }
        }
        i += 16;
    }
    n
}

/// The whole steps of 16 rows of [`split2`]; returns the rows done.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn split2_avx512(src: &[f32], x: &mut [f32], y: &mut [f32]) -> usize {
    use std::arch::x86_64::*;
    const EVEN: [i32; 16] = split_idx(2, 0).0;
    const ODD: [i32; 16] = split_idx(2, 1).0;
    let n = x.len() / 16 * 16;
    // SAFETY: 16 i32 each.
    let (e, o) = unsafe {
        (
            _mm512_loadu_si512(EVEN.as_ptr().cast()),
            _mm512_loadu_si512(ODD.as_ptr().cast()),
        )
    };
    let mut i = 0;
    while i < n {
        // SAFETY: rows i..i + 16 are in bounds.
        unsafe {
            let p = src.as_ptr().add(2 * i);
            let (a, b) = (_mm512_loadu_ps(p), _mm512_loadu_ps(p.add(16)));
            _mm512_storeu_ps(x.as_mut_ptr().add(i), _mm512_permutex2var_ps(a, e, b));
            _mm512_storeu_ps(y.as_mut_ptr().add(i), _mm512_permutex2var_ps(a, o, b));
        }
        i += 16;
    }
    n
}

/// Lane `j` of the permutes that build the `r`-th register of 16 interleaved values (of rows
/// of 3) from columns `x`, `y` (the first, indices into x | y) and then `z` (the second).
#[cfg(target_arch = "x86_64")]
const fn join_idx(r: usize) -> ([i32; 16], [i32; 16]) {
    let (mut first, mut second) = ([0i32; 16], [0i32; 16]);
    let mut j = 0;
    while j < 16 {
        let g = 16 * r + j;
        let (row, comp) = (g / 3, g % 3);
        match comp {
            0 => {
                first[j] = row as i32;
                second[j] = j as i32;
            }
            1 => {
                first[j] = 16 + row as i32;
                second[j] = j as i32;
            }
            _ => second[j] = 16 + row as i32,
        }
        j += 1;
    }
    (first, second)
}

/// The whole steps of 16 rows of [`join3`]; returns the rows done.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn join3_avx512(x: &[f32], y: &[f32], z: &[f32], dst: &mut [f32]) -> usize {
    use std::arch::x86_64::*;
    const I: [([i32; 16], [i32; 16]); 3] = [join_idx(0), join_idx(1), join_idx(2)];
    let n = x.len() / 16 * 16;
    let idx = I.map(|(a, b)| unsafe {
        (
            _mm512_loadu_si512(a.as_ptr().cast()),
            _mm512_loadu_si512(b.as_ptr().cast()),
        )
    });
    let mut i = 0;
    while i < n {
        // SAFETY: rows i..i + 16 are in bounds. The rows of register r lie within
        // 16 r / 3 .. 16 (r + 1) / 3 + 1, at most 16 rows from i.
        unsafe {
            let (a, b, c) = (
                _mm512_loadu_ps(x.as_ptr().add(i)),
                _mm512_loadu_ps(y.as_ptr().add(i)),
                _mm512_loadu_ps(z.as_ptr().add(i)),
            );
            let p = dst.as_mut_ptr().add(3 * i);
            for (r, (i1, i2)) in idx.iter().enumerate() {
                let t = _mm512_permutex2var_ps(a, *i1, b);
                _mm512_storeu_ps(p.add(16 * r), _mm512_permutex2var_ps(t, *i2, c));
            }
        }
        i += 16;
    }
    n
}
