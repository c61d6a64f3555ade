//! Batches over the rows of numpy arrays, spread over the calling thread and rayon's pool
//! ([`fastbrdf::par::for_each_part`]).
//!
//! Inputs are (N, k) arrays read in place whatever their strides (C-contiguous rows, a
//! transposed (k, N) array, a broadcast row of stride 0), deinterleaved [`CHUNK`] rows at a
//! time into per-thread structure-of-arrays buffers ([`Soa`]). Outputs are C-contiguous and
//! written in disjoint chunks ([`for_chunks`], [`for_chunks3`]). The chunks are fixed by the
//! row count alone, never by the thread count, and each element's value depends only on its
//! own inputs: results do not depend on the number of threads.

use super::interleave;
use crate::arrays::CHUNK;
use numpy::ndarray::{ArrayView2, s};
use std::any::TypeId;
use std::ops::Range;

/// (N, k) rows of any strides.
pub(crate) type Rows<'a, T> = ArrayView2<'a, T>;

/// One thread's buffers: `K` columns of [`CHUNK`] values, allocated when first needed (inputs
/// read in place as columns never need them).
pub(crate) struct Soa<T, const K: usize>([Vec<T>; K]);

impl<T: Copy + Default + 'static, const K: usize> Soa<T, K> {
    pub(crate) fn new() -> Self {
        Self(std::array::from_fn(|_| Vec::new()))
    }

    /// The buffers at their full size.
    fn sized(&mut self) -> &mut [Vec<T>; K] {
        if self.0.iter().any(|c| c.len() < CHUNK) {
            for c in &mut self.0 {
                c.resize(CHUNK, T::default());
            }
        }
        &mut self.0
    }

    /// The `K` columns of rows `r` of `v` (at most [`CHUNK`] rows): read in place where each
    /// column of those rows is contiguous (a column-major array, e.g. `np.asfortranarray`, the
    /// transpose of a C-contiguous (k, N) array: the layout Mitsuba and Dr.Jit keep), else
    /// copied into the buffers.
    pub(crate) fn load<'s, 'a: 's>(&'s mut self, v: &Rows<'a, T>, r: Range<usize>) -> [&'s [T]; K] {
        if let Some(cols) = columns(v, r.clone()) {
            return cols;
        }
        let len = r.len();
        self.sized();
        if let (Some(all), Some(cols)) = (v.as_slice(), f32s(&mut self.0)) {
            // C-contiguous f32 rows of 3 or 2: the vectorised copies.
            let all = f32s_of(&all[K * r.start..K * r.end]);
            match cols {
                [x, y, z] => interleave::split3(all, [&mut x[..len], &mut y[..len], &mut z[..len]]),
                [x, y] => interleave::split2(all, [&mut x[..len], &mut y[..len]]),
                _ => unreachable!(),
            }
        } else if let Some(all) = v.as_slice() {
            // C-contiguous: one pass over the rows.
            let mut cols: [&mut [T]; K] = self.0.each_mut().map(|c| &mut c[..len]);
            for (j, row) in all[K * r.start..K * r.end].chunks_exact(K).enumerate() {
                for (c, col) in cols.iter_mut().enumerate() {
                    col[j] = row[c];
                }
            }
        } else {
            for (c, col) in self.0.iter_mut().enumerate() {
                for (d, x) in col[..len].iter_mut().zip(v.slice(s![r.clone(), c])) {
                    *d = *x;
                }
            }
        }
        self.0.each_ref().map(|c| &c[..len])
    }

    /// The buffers as `len` writable values each (outputs of a structure-of-arrays kernel).
    pub(crate) fn cols_mut(&mut self, len: usize) -> [&mut [T]; K] {
        self.sized().each_mut().map(|c| &mut c[..len])
    }

    /// The first `len` values of the buffers interleaved into `out` (`K` values a row).
    pub(crate) fn store(&self, out: &mut [T]) {
        let len = out.len() / K;
        if let Some([x, y, z]) = f32s_ref(&self.0) {
            let out = f32s_mut(out);
            return interleave::join3([&x[..len], &y[..len], &z[..len]], out);
        }
        let cols = self.0.each_ref().map(|c| &c[..len]);
        for (j, row) in out.chunks_exact_mut(K).enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                *x = cols[c][j];
            }
        }
    }
}

/// Rows `r` of `v`'s `K` columns in place, where each is contiguous (row stride 1, more than
/// one row; a single row is a C-contiguous row, copied as one), else `None`.
pub(crate) fn columns<'a, T, const K: usize>(
    v: &Rows<'a, T>,
    r: Range<usize>,
) -> Option<[&'a [T]; K]> {
    if v.strides()[0] != 1 || r.len() < 2 || v.ncols() != K {
        return None;
    }
    assert!(r.end <= v.nrows(), "rows {r:?} of {}", v.nrows());
    let (base, step) = (v.as_ptr(), v.strides()[1]);
    Some(std::array::from_fn(|c| {
        // SAFETY: element (i, c) of the view lies at `base + i + c * step` (row stride 1,
        // whatever the sign of `step`), and rows `r` are within the view's rows (asserted), so
        // these `r.len()` elements are the view's, borrowed for `'a` as the view is.
        unsafe {
            std::slice::from_raw_parts(base.offset(c as isize * step + r.start as isize), r.len())
        }
    }))
}

/// Asks the CPU to bring rows `r` of `v` (C-contiguous only; else nothing) into its caches,
/// one prefetch per 64-byte line: the fused passes call it for their next rows before
/// computing the current ones, so that the memory reads overlap the arithmetic.
pub(crate) fn prefetch<T>(v: &Rows<'_, T>, r: Range<usize>) {
    #[cfg(target_arch = "x86_64")]
    if let Some(all) = v.as_slice() {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let k = v.ncols();
        let (lo, hi) = ((k * r.start).min(all.len()), (k * r.end).min(all.len()));
        let bytes = all[lo..hi].as_ptr_range();
        let mut p = bytes.start.cast::<i8>();
        while p < bytes.end.cast() {
            // SAFETY: a prefetch never faults, and `p` points into `all`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p) };
            p = p.wrapping_add(64);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (v, r);
}

/// The columns as f32 when `T` is f32 and there are 2 or 3 of them (the vectorised copies'
/// cases), else `None`.
fn f32s<T: 'static, const K: usize>(cols: &mut [Vec<T>; K]) -> Option<&mut [Vec<f32>]> {
    if TypeId::of::<T>() == TypeId::of::<f32>() && (K == 2 || K == 3) {
        // SAFETY: `T` is `f32`.
        Some(unsafe { &mut *(cols.as_mut_slice() as *mut [Vec<T>] as *mut [Vec<f32>]) })
    } else {
        None
    }
}

/// [`f32s`] read-only, 3 columns only.
fn f32s_ref<T: 'static, const K: usize>(cols: &[Vec<T>; K]) -> Option<&[Vec<f32>; 3]> {
    if TypeId::of::<T>() == TypeId::of::<f32>() && K == 3 {
        // SAFETY: `T` is `f32` and `K` is 3.
        Some(unsafe { &*(cols as *const [Vec<T>; K] as *const [Vec<f32>; 3]) })
    } else {
        None
    }
}

/// A slice of `T` that is f32 (checked by the caller through [`f32s`]) as f32.
fn f32s_of<T: 'static>(v: &[T]) -> &[f32] {
    assert_eq!(TypeId::of::<T>(), TypeId::of::<f32>());
    // SAFETY: `T` is `f32`.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast(), v.len()) }
}

/// [`f32s_of`], writable.
fn f32s_mut<T: 'static>(v: &mut [T]) -> &mut [f32] {
    assert_eq!(TypeId::of::<T>(), TypeId::of::<f32>());
    // SAFETY: `T` is `f32`.
    unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast(), v.len()) }
}

/// Runs `f(scratch, rows, out)` over `out` cut into chunks of [`CHUNK`] rows of `w` values,
/// `rows` counted from `first`: on this thread when there is one chunk, else over rayon's
/// threads, `init` making each worker's scratch. The first error (of any chunk) is returned.
pub(crate) fn for_chunks<T: Send, S, E: Send>(
    first: usize,
    (out, w): (&mut [T], usize),
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, Range<usize>, &mut [T]) -> Result<(), E> + Sync + Send,
) -> Result<(), E> {
    let n = out.len() / w;
    if n <= CHUNK {
        return f(&mut init(), first..first + n, out);
    }
    let parts: Vec<_> = out.chunks_mut(w * CHUNK).enumerate().collect();
    fastbrdf::par::for_each_part(parts, init, |s, (i, o)| {
        let lo = first + i * CHUNK;
        f(s, lo..lo + o.len() / w, o)
    })
}

/// Three outputs of widths `w` (rows counted as by the first), as [`for_chunks`].
pub(crate) type Outs3<'a, T> = (&'a mut [T], &'a mut [T], &'a mut [T]);

/// [`for_chunks`] over three outputs of the same row count (widths `w`).
pub(crate) fn for_chunks3<T: Send, S, E: Send>(
    first: usize,
    (a, b, c): Outs3<'_, T>,
    w: [usize; 3],
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, Range<usize>, Outs3<'_, T>) -> Result<(), E> + Sync + Send,
) -> Result<(), E> {
    let n = a.len() / w[0];
    if n <= CHUNK {
        return f(&mut init(), first..first + n, (a, b, c));
    }
    let parts: Vec<_> = a
        .chunks_mut(w[0] * CHUNK)
        .zip(b.chunks_mut(w[1] * CHUNK))
        .zip(c.chunks_mut(w[2] * CHUNK))
        .enumerate()
        .collect();
    fastbrdf::par::for_each_part(parts, init, |s, (i, ((a, b), c))| {
        let lo = first + i * CHUNK;
        f(s, lo..lo + b.len() / w[1], (a, b, c))
    })
}
