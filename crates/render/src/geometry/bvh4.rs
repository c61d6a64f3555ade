//! The CPU's 4-wide BVH: the binary SAH tree of [`TriMesh`](crate::geometry::TriMesh)
//! collapsed so each node holds up to four children's boxes as structure of arrays (one slab
//! test of four boxes in SSE2, the x86-64 baseline; a scalar fallback elsewhere), and each
//! leaf its up to four triangles as (vertex a, b - a, c - a) per lane (one Moller-Trumbore of
//! four triangles). The binary tree stays as it is (the GPU uploads it); this one is built
//! from it: every lane's box is one of its boxes (a subtree of at most four triangles becomes
//! one leaf with its box) or the union of neighbouring leaves' boxes, and the lane arithmetic
//! is the scalar code's (`geometry::slab`, `geometry::hit_triangle`), operation for
//! operation, so the same triangle is found with the same t, u, v, to the bit. Only exact
//! ties in t between two triangles of one 4-wide leaf may resolve otherwise (to the first in
//! `order`; the binary walk takes the one of the nearer box); tests/bvh.rs compares the two
//! walks bit for bit.
//!
//! Memory: a node (up to four boxes) is 128 bytes, a leaf (up to four triangles) 160: on
//! the face 72 bytes a triangle, beside the binary tree's 32 a node and 4 a triangle.

use super::{MAX_DEPTH, Node, Ray, half_area};
use glam::Vec3;
use std::mem::MaybeUninit;

/// Child reference: inner node index, or with [`LEAF_BIT`] a leaf block index (bits 0..29)
/// and its triangle count minus one (bits 29..31).
const LEAF_BIT: u32 = 1 << 31;

/// Stack entries: every node on the path from the root pushes at most 3 of its children, and
/// a path holds at most MAX_DEPTH nodes (each node of this tree is an inner node of the binary
/// tree, whose inner nodes lie at depth < MAX_DEPTH), so 3 * MAX_DEPTH <= 186 entries suffice
/// for any input.
const STACK: usize = 3 * MAX_DEPTH + 6;

/// Up to four children: boxes per axis and lane, and references.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct Node4 {
    lo: [[f32; 4]; 3],
    hi: [[f32; 4]; 3],
    child: [u32; 4],
    /// Lanes in use: bits 0..n.
    lanes: u32,
}

/// Up to four triangles: (a, b - a, c - a) per axis and lane, and each one's position in the
/// binary tree's `order`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(super) struct Leaf4 {
    pub(super) a: [[f32; 4]; 3],
    pub(super) e1: [[f32; 4]; 3],
    pub(super) e2: [[f32; 4]; 3],
    pub(super) index: [u32; 4],
}

impl Leaf4 {
    /// No triangles: every lane's edges are zero, so `hit4` never reports a lane unfilled.
    pub(super) const EMPTY: Self = Self {
        a: [[0.0; 4]; 3],
        e1: [[0.0; 4]; 3],
        e2: [[0.0; 4]; 3],
        index: [0; 4],
    };

    /// Puts triangle (a, b, c) at position `i` of `order` in lane `k`, as the BVH's leaves
    /// hold it: (a, b - a, c - a).
    #[inline]
    pub(super) fn set(&mut self, k: usize, [a, b, c]: [Vec3; 3], i: u32) {
        let (e1, e2) = (b - a, c - a);
        for ax in 0..3 {
            self.a[ax][k] = a[ax];
            self.e1[ax][k] = e1[ax];
            self.e2[ax][k] = e2[ax];
        }
        self.index[k] = i;
    }
}

/// The 4-wide BVH (empty for an empty mesh).
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh4 {
    nodes: Vec<Node4>,
    leaves: Vec<Leaf4>,
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod lanes {
    use std::arch::x86_64::*;

    /// Four f32 lanes.
    #[derive(Clone, Copy)]
    pub struct F4(__m128);

    // SAFETY (every `unsafe` below): SSE2 is part of the x86-64 baseline, and loads read a
    // whole `[f32; 4]`.
    impl F4 {
        #[inline(always)]
        pub fn splat(x: f32) -> Self {
            Self(unsafe { _mm_set1_ps(x) })
        }
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> Self {
            Self(unsafe { _mm_loadu_ps(a.as_ptr()) })
        }
        #[inline(always)]
        pub fn store(self) -> [f32; 4] {
            let mut a = [0.0; 4];
            unsafe { _mm_storeu_ps(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        pub fn add(self, b: Self) -> Self {
            Self(unsafe { _mm_add_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn sub(self, b: Self) -> Self {
            Self(unsafe { _mm_sub_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn mul(self, b: Self) -> Self {
            Self(unsafe { _mm_mul_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn div(self, b: Self) -> Self {
            Self(unsafe { _mm_div_ps(self.0, b.0) })
        }
        /// The correctly rounded square root per lane (SQRTPS), as `f32::sqrt`.
        #[inline(always)]
        pub fn sqrt(self) -> Self {
            Self(unsafe { _mm_sqrt_ps(self.0) })
        }
        /// `if self < b { self } else { b }` per lane (MINPS).
        #[inline(always)]
        pub fn min_first(self, b: Self) -> Self {
            Self(unsafe { _mm_min_ps(self.0, b.0) })
        }
        /// `if self > b { self } else { b }` per lane (MAXPS).
        #[inline(always)]
        pub fn max_first(self, b: Self) -> Self {
            Self(unsafe { _mm_max_ps(self.0, b.0) })
        }
        #[inline(always)]
        pub fn abs(self) -> Self {
            Self(unsafe { _mm_andnot_ps(_mm_set1_ps(-0.0), self.0) })
        }
        /// Bit k set where lane k satisfies `self < b` (ordered).
        #[inline(always)]
        pub fn lt(self, b: Self) -> u32 {
            unsafe { _mm_movemask_ps(_mm_cmplt_ps(self.0, b.0)) as u32 }
        }
        #[inline(always)]
        pub fn le(self, b: Self) -> u32 {
            unsafe { _mm_movemask_ps(_mm_cmple_ps(self.0, b.0)) as u32 }
        }
        #[inline(always)]
        pub fn gt(self, b: Self) -> u32 {
            unsafe { _mm_movemask_ps(_mm_cmpgt_ps(self.0, b.0)) as u32 }
        }
        #[inline(always)]
        pub fn ge(self, b: Self) -> u32 {
            unsafe { _mm_movemask_ps(_mm_cmpge_ps(self.0, b.0)) as u32 }
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
pub(crate) mod lanes {
    /// Four f32 lanes.
    #[derive(Clone, Copy)]
    pub struct F4([f32; 4]);

    impl F4 {
        #[inline(always)]
        fn map(self, b: Self, f: impl Fn(f32, f32) -> f32) -> Self {
            Self(std::array::from_fn(|k| f(self.0[k], b.0[k])))
        }
        #[inline(always)]
        fn bits(self, b: Self, f: impl Fn(f32, f32) -> bool) -> u32 {
            (0..4).map(|k| u32::from(f(self.0[k], b.0[k])) << k).sum()
        }
        pub fn splat(x: f32) -> Self {
            Self([x; 4])
        }
        pub fn load(a: &[f32; 4]) -> Self {
            Self(*a)
        }
        pub fn store(self) -> [f32; 4] {
            self.0
        }
        pub fn add(self, b: Self) -> Self {
            self.map(b, |x, y| x + y)
        }
        pub fn sub(self, b: Self) -> Self {
            self.map(b, |x, y| x - y)
        }
        pub fn mul(self, b: Self) -> Self {
            self.map(b, |x, y| x * y)
        }
        pub fn div(self, b: Self) -> Self {
            self.map(b, |x, y| x / y)
        }
        pub fn sqrt(self) -> Self {
            Self(self.0.map(f32::sqrt))
        }
        pub fn min_first(self, b: Self) -> Self {
            self.map(b, |x, y| if x < y { x } else { y })
        }
        pub fn max_first(self, b: Self) -> Self {
            self.map(b, |x, y| if x > y { x } else { y })
        }
        pub fn abs(self) -> Self {
            Self(self.0.map(f32::abs))
        }
        pub fn lt(self, b: Self) -> u32 {
            self.bits(b, |x, y| x < y)
        }
        pub fn le(self, b: Self) -> u32 {
            self.bits(b, |x, y| x <= y)
        }
        pub fn gt(self, b: Self) -> u32 {
            self.bits(b, |x, y| x > y)
        }
        pub fn ge(self, b: Self) -> u32 {
            self.bits(b, |x, y| x >= y)
        }
    }
}

use lanes::F4;

/// A ray splatted across lanes, with 1 / d.
pub(super) struct Ray4 {
    o: [F4; 3],
    d: [F4; 3],
    inv: [F4; 3],
}

impl Ray4 {
    #[inline(always)]
    pub(super) fn new(r: &Ray) -> Self {
        let inv = r.d.recip();
        let s = |v: Vec3| [F4::splat(v.x), F4::splat(v.y), F4::splat(v.z)];
        Self {
            o: s(r.o),
            d: s(r.d),
            inv: s(inv),
        }
    }
}

/// `geometry::slab` on four boxes: (lanes entered, entry distances).
#[inline(always)]
fn slab4(n: &Node4, r: &Ray4, t_min: F4, t_max: F4) -> (u32, F4) {
    const WIDEN: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
    let (mut near, mut far) = (t_min, t_max);
    for k in 0..3 {
        let a = F4::load(&n.lo[k]).sub(r.o[k]).mul(r.inv[k]);
        let b = F4::load(&n.hi[k]).sub(r.o[k]).mul(r.inv[k]);
        // `if a < b { (a, b) } else { (b, a) }`
        let (a, b) = (a.min_first(b), b.max_first(a));
        near = a.max_first(near);
        far = b.mul(F4::splat(WIDEN)).min_first(far);
    }
    (near.le(far) & n.lanes, near)
}

/// `geometry::hit_triangle` on four triangles: (lanes hit, t, u, v).
#[inline(always)]
pub(super) fn hit4(l: &Leaf4, r: &Ray4, t_min: F4, t_max: F4) -> (u32, F4, F4, F4) {
    let v3 = |a: &[[f32; 4]; 3]| [F4::load(&a[0]), F4::load(&a[1]), F4::load(&a[2])];
    let cross = |a: [F4; 3], b: [F4; 3]| {
        [
            a[1].mul(b[2]).sub(b[1].mul(a[2])),
            a[2].mul(b[0]).sub(b[2].mul(a[0])),
            a[0].mul(b[1]).sub(b[0].mul(a[1])),
        ]
    };
    let dot = |a: [F4; 3], b: [F4; 3]| a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]));
    let (a, e1, e2) = (v3(&l.a), v3(&l.e1), v3(&l.e2));
    let p = cross(r.d, e2);
    let det = dot(e1, p);
    let mut ok = !det.abs().lt(F4::splat(1e-12)) & 0xf;
    let inv = F4::splat(1.0).div(det);
    let s = [r.o[0].sub(a[0]), r.o[1].sub(a[1]), r.o[2].sub(a[2])];
    let u = dot(s, p).mul(inv);
    ok &= u.ge(F4::splat(0.0)) & u.le(F4::splat(1.0));
    let q = cross(s, e1);
    let v = dot(r.d, q).mul(inv);
    ok &= !(v.lt(F4::splat(0.0)) | u.add(v).gt(F4::splat(1.0)));
    let t = dot(e2, q).mul(inv);
    ok &= t.gt(t_min) & t.lt(t_max);
    (ok, t, u, v)
}

/// Of the lanes `ok` (not none) hit at `t`, the nearest; ties go to the first lane.
#[inline(always)]
pub(super) fn nearest_lane(ok: u32, t: &[f32; 4]) -> usize {
    let mut k = ok.trailing_zeros() as usize;
    let mut rest = ok & (ok - 1);
    while rest != 0 {
        let j = rest.trailing_zeros() as usize;
        if t[j] < t[k] {
            k = j;
        }
        rest &= rest - 1;
    }
    k
}

impl Bvh4 {
    /// Collapses the binary tree `nodes` (leaves indexing `order`): each node takes its
    /// binary children and repeatedly replaces the inner one of largest area by its two
    /// children, in place (so lanes keep the binary tree's left-to-right order), up to four.
    pub(crate) fn new(
        nodes: &[Node],
        order: &[u32],
        positions: &[Vec3],
        triangles: &[[u32; 3]],
    ) -> Self {
        let mut b = Self::default();
        if triangles.is_empty() {
            return b;
        }
        let tri = |i: usize| triangles[order[i] as usize].map(|v| positions[v as usize]);
        // Each binary node's triangles: a range of `order` (children are built after their
        // parent, so at higher indices).
        let mut spans: Vec<(u32, u32)> = nodes.iter().map(|n| (n.start, n.count)).collect();
        for i in (0..nodes.len()).rev() {
            if nodes[i].count == 0 {
                let l = nodes[i].start as usize;
                spans[i] = (spans[l].0, spans[l].1 + spans[l + 1].1);
            }
        }
        b.collapse(nodes, &spans, &tri, 0);
        b
    }

    /// Adds the node for binary node `i` (of more than four triangles, or the root of a small
    /// mesh, then a single leaf lane) and its subtree; returns its index. Lanes: the binary
    /// children (a subtree of at most four triangles as one leaf), the
    /// inner one of largest area replaced by its two children while fewer than four, and
    /// neighbouring leaves of at most four triangles together merged into one (their
    /// triangles are neighbours in `order`, as lanes keep the binary tree's left-to-right
    /// order; the lane's box is the union of theirs).
    fn collapse(
        &mut self,
        nodes: &[Node],
        spans: &[(u32, u32)],
        tri: &impl Fn(usize) -> [Vec3; 3],
        i: usize,
    ) -> u32 {
        // (box lo, box hi, binary node if inner, leaf start, leaf count); a subtree of at
        // most four triangles is one leaf (its box is the union of its leaves').
        let kid = |c: usize| {
            let (n, (start, count)) = (nodes[c], spans[c]);
            (n.lo, n.hi, (count > 4).then_some(c), start, count)
        };
        let mut kids = if spans[i].1 <= 4 {
            vec![kid(i)]
        } else {
            let l = nodes[i].start as usize;
            vec![kid(l), kid(l + 1)]
        };
        loop {
            while kids.len() < 4 {
                let widest = (0..kids.len())
                    .filter(|&k| kids[k].2.is_some())
                    .max_by(|&a, &b| {
                        let area = |k: usize| half_area(kids[k].0, kids[k].1);
                        area(a).total_cmp(&area(b))
                    });
                let Some(k) = widest else { break };
                let l = nodes[kids[k].2.unwrap_or_default()].start as usize;
                kids.splice(k..k + 1, [kid(l), kid(l + 1)]);
            }
            let before = kids.len();
            let mut merged: Vec<(Vec3, Vec3, Option<usize>, u32, u32)> = Vec::new();
            for k in kids {
                match merged.last_mut() {
                    Some(m) if m.2.is_none() && k.2.is_none() && m.4 + k.4 <= 4 => {
                        *m = (m.0.min(k.0), m.1.max(k.1), None, m.3, m.4 + k.4);
                    }
                    _ => merged.push(k),
                }
            }
            kids = merged;
            if kids.len() == before || !kids.iter().any(|k| k.2.is_some()) {
                break;
            }
        }
        let at = self.nodes.len();
        self.nodes.push(Node4 {
            lo: [[0.0; 4]; 3],
            hi: [[0.0; 4]; 3],
            child: [0; 4],
            lanes: (1 << kids.len()) - 1,
        });
        for (lane, &(lo, hi, inner, start, count)) in kids.iter().enumerate() {
            let child = if let Some(c) = inner {
                self.collapse(nodes, spans, tri, c)
            } else {
                let mut leaf = Leaf4::EMPTY;
                for k in 0..count as usize {
                    let i = start as usize + k;
                    leaf.set(k, tri(i), i as u32);
                }
                self.leaves.push(leaf);
                LEAF_BIT | (count - 1) << 29 | (self.leaves.len() - 1) as u32
            };
            let node = &mut self.nodes[at];
            for ax in 0..3 {
                node.lo[ax][lane] = lo[ax];
                node.hi[ax][lane] = hi[ax];
            }
            node.child[lane] = child;
        }
        at as u32
    }

    /// The leaf block and its lanes in use of a leaf reference.
    #[inline(always)]
    fn leaf(&self, c: u32) -> (&Leaf4, u32) {
        let lanes = (2 << ((c >> 29) & 3)) - 1;
        (&self.leaves[(c & ((1 << 29) - 1)) as usize], lanes)
    }

    /// The nearest hit with t in (t_min, t_max) as (t, position in `order`, u, v): of a
    /// node's children entered, the nearest entry is visited first and the others pushed
    /// farthest first, each skipped when popped if a hit nearer than its entry was found
    /// meanwhile; ties in entry, and in t within a leaf, go to the binary tree's left-to-right
    /// order.
    pub(crate) fn hit(
        &self,
        r: &Ray,
        t_min: f32,
        mut t_max: f32,
    ) -> Option<(f32, usize, f32, f32)> {
        if self.nodes.is_empty() {
            return None;
        }
        let r4 = Ray4::new(r);
        let tmin4 = F4::splat(t_min);
        let mut best = None;
        // Not zeroed (the zeroing showed at 5% of a face render): entries below `sp` are
        // written before they are read.
        let mut stack = [MaybeUninit::<(u32, f32)>::uninit(); STACK];
        let mut sp = 0;
        let mut c = 0u32;
        'walk: loop {
            if c & LEAF_BIT != 0 {
                let (leaf, lanes) = self.leaf(c);
                let (mut ok, t, u, v) = hit4(leaf, &r4, tmin4, F4::splat(t_max));
                ok &= lanes;
                if ok != 0 {
                    let t = t.store();
                    let k = nearest_lane(ok, &t);
                    t_max = t[k];
                    best = Some((t[k], leaf.index[k] as usize, u.store()[k], v.store()[k]));
                }
            } else {
                let node = &self.nodes[c as usize];
                let (mut hit, tn) = slab4(node, &r4, tmin4, F4::splat(t_max));
                if hit != 0 {
                    let tn = tn.store();
                    // Entered lanes sorted by entry (stable: ties keep lane order).
                    let mut near = [(0u32, 0.0f32); 4];
                    let mut m = 0;
                    while hit != 0 {
                        let k = hit.trailing_zeros() as usize;
                        hit &= hit - 1;
                        let e = (node.child[k], tn[k]);
                        let mut j = m;
                        while j > 0 && near[j - 1].1 > e.1 {
                            near[j] = near[j - 1];
                            j -= 1;
                        }
                        near[j] = e;
                        m += 1;
                    }
                    for &e in near[1..m].iter().rev() {
                        stack[sp].write(e);
                        sp += 1;
                    }
                    c = near[0].0;
                    continue;
                }
            }
            while sp > 0 {
                sp -= 1;
                // SAFETY: entry `sp` < the entries pushed was written by a push.
                let (n, t_near) = unsafe { stack[sp].assume_init() };
                if t_near <= t_max {
                    c = n;
                    continue 'walk;
                }
            }
            return best;
        }
    }

    /// Whether any triangle is hit with t in (t_min, t_max): stops at the first found.
    pub(crate) fn occluded(&self, r: &Ray, t_min: f32, t_max: f32) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let r4 = Ray4::new(r);
        let (tmin4, tmax4) = (F4::splat(t_min), F4::splat(t_max));
        let mut stack = [MaybeUninit::<u32>::uninit(); STACK];
        let mut sp = 0;
        let mut c = 0u32;
        loop {
            if c & LEAF_BIT != 0 {
                let (leaf, lanes) = self.leaf(c);
                if hit4(leaf, &r4, tmin4, tmax4).0 & lanes != 0 {
                    return true;
                }
            } else {
                let node = &self.nodes[c as usize];
                let mut hit = slab4(node, &r4, tmin4, tmax4).0;
                if hit != 0 {
                    c = node.child[hit.trailing_zeros() as usize];
                    hit &= hit - 1;
                    while hit != 0 {
                        stack[sp].write(node.child[hit.trailing_zeros() as usize]);
                        sp += 1;
                        hit &= hit - 1;
                    }
                    continue;
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            // SAFETY: entry `sp` < the entries pushed was written by a push.
            c = unsafe { stack[sp].assume_init() };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::TriMesh;

    /// Every position of `order` in exactly one leaf lane, leaves' lanes in use matching
    /// their references, and the memory per triangle (printed).
    fn check(what: &str, m: &TriMesh) {
        let b = &m.bvh4;
        let mut seen = vec![0u32; m.triangles.len()];
        let mut todo = vec![0u32];
        while let Some(c) = todo.pop() {
            let node = &b.nodes[c as usize];
            assert!(node.lanes != 0 && node.lanes < 16 && (node.lanes + 1).is_power_of_two());
            for k in 0..node.lanes.count_ones() as usize {
                let c = node.child[k];
                if c & LEAF_BIT != 0 {
                    let (leaf, lanes) = b.leaf(c);
                    for &i in &leaf.index[..lanes.count_ones() as usize] {
                        seen[i as usize] += 1;
                    }
                } else {
                    todo.push(c);
                }
            }
        }
        assert!(
            seen.iter().all(|&s| s == 1),
            "{what}: a triangle in no leaf or two"
        );
        let bytes = std::mem::size_of_val(&b.nodes[..]) + std::mem::size_of_val(&b.leaves[..]);
        let n = m.triangles.len();
        eprintln!(
            "{what}: {} nodes, {} leaves ({:.2} triangles each), {:.0} bytes a triangle",
            b.nodes.len(),
            b.leaves.len(),
            n as f64 / b.leaves.len() as f64,
            bytes as f64 / n as f64
        );
    }

    #[test]
    fn every_triangle_is_in_one_leaf_lane() {
        check("face", &crate::mesh::face());
        for n in 1..=9u32 {
            let positions: Vec<Vec3> = (0..3 * n)
                .map(|i| Vec3::new((i * 7 % 11) as f32, (i * 5 % 13) as f32, (i % 3) as f32))
                .collect();
            let triangles = (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
            let normals = vec![Vec3::Z; positions.len()];
            check(
                &format!("{n} triangles"),
                &TriMesh::new(positions, normals, Vec::new(), triangles),
            );
        }
    }
}
