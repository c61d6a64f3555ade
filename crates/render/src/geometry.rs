//! Rays, analytic spheres and planes, and triangle meshes with a bounding volume hierarchy.

pub(crate) mod bundle;
pub(crate) mod bvh4;
use bundle::Bundle;
use bvh4::Bvh4;
use glam::{Vec2, Vec3, Vec4};

/// A ray `o + t d`, `d` unit.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
}

/// What a ray hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub p: Vec3,
    /// Shading normal (interpolated for meshes), unit.
    pub n: Vec3,
    pub uv: Vec2,
    /// The interpolated tangent (xyz, w the bitangent's sign) of a mesh with tangents
    /// ([`TriMesh::tangents`]); zero elsewhere.
    pub tangent: Vec4,
    /// Index of the object in the scene.
    pub object: usize,
}

/// A sphere.
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    /// Nearest intersection with t in (t_min, t_max): (t, normal, uv).
    pub fn intersect(&self, r: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Vec3, Vec2)> {
        self.hit(r, t_min, t_max, true)
    }

    /// [`Sphere::intersect`], with the texture coordinates (an `atan2` and an `asin`) computed
    /// only when `uv` is set (zero otherwise).
    #[inline]
    pub fn hit(&self, r: &Ray, t_min: f32, t_max: f32, uv: bool) -> Option<(f32, Vec3, Vec2)> {
        let oc = r.o - self.center;
        let b = oc.dot(r.d);
        let c = oc.length_squared() - self.radius * self.radius;
        let disc = b * b - c;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        let t = if -b - s > t_min { -b - s } else { -b + s };
        if !(t > t_min && t < t_max) {
            return None;
        }
        let p = r.o + t * r.d;
        // One division (off the ray's dependency chain) instead of three: exact for the unit
        // sphere of the default scene, within an ulp of the quotient elsewhere.
        let n = (p - self.center) * (1.0 / self.radius);
        let uv = if uv {
            Vec2::new(
                0.5 + n.z.atan2(n.x) / std::f32::consts::TAU,
                0.5 - n.y.clamp(-1.0, 1.0).asin() / std::f32::consts::PI,
            )
        } else {
            Vec2::ZERO
        };
        Some((t, n, uv))
    }
}

/// An infinite plane through `point` with normal `normal`.
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    pub point: Vec3,
    pub normal: Vec3,
}

impl Plane {
    /// Intersection with t in (t_min, t_max): (t, normal, uv).
    pub fn intersect(&self, r: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Vec3, Vec2)> {
        self.hit(r, t_min, t_max, true)
    }

    /// [`Plane::intersect`], with the texture coordinates computed only when `uv` is set
    /// (zero otherwise).
    #[inline]
    pub fn hit(&self, r: &Ray, t_min: f32, t_max: f32, uv: bool) -> Option<(f32, Vec3, Vec2)> {
        let denom = self.normal.dot(r.d);
        if denom.abs() < 1e-8 {
            return None;
        }
        let t = (self.point - r.o).dot(self.normal) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        if !uv {
            return Some((t, self.normal, Vec2::ZERO));
        }
        let p = r.o + t * r.d;
        let (tu, tv) = self.normal.any_orthonormal_pair();
        Some((
            t,
            self.normal,
            Vec2::new((p - self.point).dot(tu), (p - self.point).dot(tv)),
        ))
    }
}

/// A triangle mesh with per-vertex normals and texture coordinates, and a BVH.
#[derive(Clone, Debug)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
    /// Per-vertex tangents (xyz, w the bitangent's sign: a glTF mesh's, for its normal
    /// texture and anisotropy), or empty. Set after [`TriMesh::new`]; read by
    /// [`TriMesh::hit_tangent`].
    pub tangents: Vec<Vec4>,
    nodes: Vec<Node>,
    order: Vec<u32>,
    /// The CPU's traversal structure, collapsed from `nodes` (see `geometry::bvh4`).
    pub(crate) bvh4: Bvh4,
}

/// Entries of the binary tree's traversal stack (`TriMesh::hit_binary`, `occluded_binary` and
/// the GPU's shadow rays, which walk as `occluded_binary`; `geometry::bvh4` holds 3 *
/// [`MAX_DEPTH`]). The binary walks keep one child per inner node on their path: at most depth
/// entries, and the build keeps every depth at most [`MAX_DEPTH`] = 62 for ANY input of up to
/// 2^32 triangles, so the stack never fills; see [`TriMesh::new`] for the argument.
pub const BVH_STACK: usize = 64;

/// Largest depth of the BVH (edges from the root to the deepest leaf): depth + 1 entries fit
/// in [`BVH_STACK`].
pub const MAX_DEPTH: usize = BVH_STACK - 2;

/// Most triangles in a leaf.
pub const LEAF: usize = 4;

/// SAH bins along the longest axis of a node's triangle centroids.
const BINS: usize = 16;

/// Cost of visiting an inner node (its two slab tests), relative to one triangle test.
const TRAVERSAL_COST: f32 = 1.0;

/// A BVH node (public for the GPU renderer, which uploads the tree for its shadow rays).
#[derive(Clone, Copy, Debug)]
pub struct Node {
    pub lo: Vec3,
    pub hi: Vec3,
    /// Leaf: first triangle in `order` and count; inner: left child index (right = left + 1).
    pub start: u32,
    pub count: u32,
}

const EMPTY: Node = Node {
    lo: Vec3::ZERO,
    hi: Vec3::ZERO,
    start: 0,
    count: 0,
};

/// The median split's height (edges) over `n` triangles: 0 for a leaf (n <= LEAF), else
/// ceil(log2(ceil(n / LEAF))), as each split leaves at most ceil(n / 2) on either side
/// (ceil(ceil(n / LEAF) / 2) = ceil(ceil(n / 2) / LEAF), so each level lowers the log by one).
fn median_height(n: usize) -> usize {
    let leaves = n.div_ceil(LEAF).max(1);
    leaves.next_power_of_two().trailing_zeros() as usize
}

/// Surface area of a box (half of it; only ratios matter).
pub(crate) fn half_area(lo: Vec3, hi: Vec3) -> f32 {
    let e = (hi - lo).max(Vec3::ZERO);
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// Builder state: per-triangle bounds and centroids, indexed by triangle.
struct Build<'a> {
    bounds: &'a [(Vec3, Vec3)],
    centroids: &'a [Vec3],
    order: &'a mut [u32],
    nodes: Vec<Node>,
    /// [`MAX_DEPTH`] (smaller in a unit test of the cap).
    max_depth: usize,
}

impl Build<'_> {
    fn build(&mut self, node: usize, start: usize, end: usize, depth: usize) {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let (mut clo, mut chi) = (lo, hi);
        for &t in &self.order[start..end] {
            let (a, b) = self.bounds[t as usize];
            lo = lo.min(a);
            hi = hi.max(b);
            let c = self.centroids[t as usize];
            clo = clo.min(c);
            chi = chi.max(c);
        }
        let n = end - start;
        let leaf = Node {
            lo,
            hi,
            start: start as u32,
            count: n as u32,
        };
        if n <= 1 {
            self.nodes[node] = leaf;
            return;
        }
        // SAH only while both children could still finish by median splits within MAX_DEPTH
        // (each holds at most n - 1 triangles); otherwise the median split, which keeps
        // depth + median_height(n) <= MAX_DEPTH (see `TriMesh::new`).
        let sah = depth + 1 + median_height(n - 1) <= self.max_depth;
        let mid = match sah
            .then(|| self.sah(start, end, lo, hi, clo, chi))
            .flatten()
        {
            Some(Some(mid)) => mid,
            // A leaf is cheaper, the centroids coincide, or SAH is off: a leaf if allowed.
            _ if n <= LEAF => {
                self.nodes[node] = leaf;
                return;
            }
            _ => self.median(start, end, clo, chi),
        };
        let left = self.nodes.len();
        self.nodes.push(EMPTY);
        self.nodes.push(EMPTY);
        self.nodes[node] = Node {
            lo,
            hi,
            start: left as u32,
            count: 0,
        };
        self.build(left, start, mid, depth + 1);
        self.build(left + 1, mid, end, depth + 1);
    }

    /// The binned SAH decision for `order[start..end]` (bounds `lo..hi`, centroid bounds
    /// `clo..chi`): `Some(Some(mid))` after partitioning at the cheapest bin boundary,
    /// `Some(None)` when a leaf is cheaper than any split, `None` when the centroids coincide
    /// (no bin boundary separates them).
    fn sah(
        &mut self,
        start: usize,
        end: usize,
        lo: Vec3,
        hi: Vec3,
        clo: Vec3,
        chi: Vec3,
    ) -> Option<Option<usize>> {
        let ext = chi - clo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        if ext[axis].is_nan() || ext[axis] <= 0.0 {
            return None;
        }
        let (base, scale) = (clo[axis], BINS as f32 / ext[axis]);
        // `as` saturates (and maps NaN to 0), so every centroid lands in 0..BINS.
        let bin = |c: Vec3| (((c[axis] - base) * scale) as usize).min(BINS - 1);
        let empty = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let mut bins = [(0usize, empty); BINS];
        for &t in &self.order[start..end] {
            let b = &mut bins[bin(self.centroids[t as usize])];
            let (a, z) = self.bounds[t as usize];
            b.0 += 1;
            b.1 = (b.1.0.min(a), b.1.1.max(z));
        }
        // Right-to-left sweep: area and count right of each boundary.
        let mut right = [(0usize, 0.0f32); BINS];
        let (mut count, mut bx) = (0, empty);
        for i in (1..BINS).rev() {
            count += bins[i].0;
            bx = (bx.0.min(bins[i].1.0), bx.1.max(bins[i].1.1));
            right[i] = (count, half_area(bx.0, bx.1));
        }
        let (mut count, mut bx) = (0, empty);
        let mut best = (f32::INFINITY, 0);
        for i in 0..BINS - 1 {
            count += bins[i].0;
            bx = (bx.0.min(bins[i].1.0), bx.1.max(bins[i].1.1));
            let (rc, ra) = right[i + 1];
            if count == 0 || rc == 0 {
                continue;
            }
            let cost = count as f32 * half_area(bx.0, bx.1) + rc as f32 * ra;
            if cost < best.0 {
                best = (cost, i);
            }
        }
        let n = end - start;
        let area = half_area(lo, hi);
        if best.0 == f32::INFINITY {
            return None;
        }
        if n <= LEAF && n as f32 * area <= TRAVERSAL_COST * area + best.0 {
            return Some(None);
        }
        // Partition: bins 0..=best.1 to the left.
        let (mut i, mut j) = (start, end);
        while i < j {
            if bin(self.centroids[self.order[i] as usize]) <= best.1 {
                i += 1;
            } else {
                j -= 1;
                self.order.swap(i, j);
            }
        }
        Some(Some(i))
    }

    /// Splits `order[start..end]` at its middle index, by centroid along the centroid bounds'
    /// longest axis: each side gets half the triangles whatever their positions.
    fn median(&mut self, start: usize, end: usize, clo: Vec3, chi: Vec3) -> usize {
        let ext = chi - clo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        let c = self.centroids;
        self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            c[a as usize][axis].total_cmp(&c[b as usize][axis])
        });
        mid
    }
}

/// The slab test's far-bound widening, 1 + 2 gamma(3) (see [`slab`]); the GPU writes its bits.
pub const SLAB_WIDEN: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Entry and exit distances of `r` (with `inv` = 1 / r.d) through a node's box, clipped to
/// (t_min, t_max); `None` when it misses. The exit is widened by 2 gamma(3) (PBRT's bound on
/// the slab test's rounding), so a box is never missed where a triangle inside it is hit. An
/// axis whose distances are NaN (0 * inf: the ray runs parallel to that axis's slabs, in the
/// plane of one) constrains nothing (the comparisons below ignore a NaN first operand), so
/// such a box is kept.
#[inline(always)]
fn slab(n: &Node, o: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
    #[inline(always)]
    fn axis(lo: f32, hi: f32, o: f32, inv: f32, near: f32, far: f32) -> (f32, f32) {
        let (a, b) = ((lo - o) * inv, (hi - o) * inv);
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let bw = b * SLAB_WIDEN;
        (
            if a > near { a } else { near },
            if bw < far { bw } else { far },
        )
    }
    let (tn, tf) = axis(n.lo.x, n.hi.x, o.x, inv.x, t_min, t_max);
    let (tn, tf) = axis(n.lo.y, n.hi.y, o.y, inv.y, tn, tf);
    let (tn, tf) = axis(n.lo.z, n.hi.z, o.z, inv.z, tn, tf);
    (tn <= tf).then_some(tn)
}

impl TriMesh {
    /// Builds the BVH: binned SAH (16 bins along the longest axis of the node's triangle
    /// centroids, leaves of up to [`LEAF`] triangles where a leaf is cheaper than any split),
    /// falling back to a median split near the depth limit.
    ///
    /// Depth bound, for ANY input (coincident triangles, stacked copies, up to 2^32
    /// triangles): let h(n) = ceil(log2(ceil(n / LEAF))) (0 for n <= LEAF) be the height of
    /// a median split of n triangles (split at the middle index, not a position, so each side
    /// holds at most ceil(n / 2) even where centroids coincide, and h(ceil(n / 2)) = h(n) - 1).
    /// Invariant: a node at depth d with n triangles has d + h(n) <= MAX_DEPTH = 62. At the
    /// root d = 0 and h(n) <= 30. A node takes a SAH split only if d + 1 + h(n - 1) <=
    /// MAX_DEPTH (each non-empty side holds at most n - 1); otherwise the median split gives
    /// children d + 1 + h(n) - 1. So every leaf is at depth <= 62 and a walk's stack holds at
    /// most 63 <= [`BVH_STACK`] entries. SAH stops only on pathological inputs (a 2^23-triangle
    /// mesh has h = 21, so SAH runs to depth 41). Building costs O(n) per level: O(n log n)
    /// for balanced splits, O(n * 62) at worst.
    pub fn new(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        uvs: Vec<Vec2>,
        triangles: Vec<[u32; 3]>,
    ) -> Self {
        Self::with_max_depth(positions, normals, uvs, triangles, MAX_DEPTH)
    }

    /// [`TriMesh::new`] with the depth limit `max_depth` (>= h(n), see there).
    fn with_max_depth(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        uvs: Vec<Vec2>,
        triangles: Vec<[u32; 3]>,
        max_depth: usize,
    ) -> Self {
        let mut m = Self {
            positions,
            normals,
            uvs,
            triangles,
            tangents: Vec::new(),
            nodes: Vec::new(),
            order: Vec::new(),
            bvh4: Bvh4::default(),
        };
        let n = m.triangles.len();
        let bounds: Vec<(Vec3, Vec3)> = (0..n as u32).map(|t| m.tri_bounds(t)).collect();
        let centroids: Vec<Vec3> = bounds.iter().map(|&(a, b)| 0.5 * (a + b)).collect();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let mut b = Build {
            bounds: &bounds,
            centroids: &centroids,
            order: &mut order,
            nodes: vec![EMPTY],
            max_depth,
        };
        b.build(0, 0, n, 0);
        m.nodes = b.nodes;
        m.order = order;
        m.bvh4 = Bvh4::new(&m.nodes, &m.order, &m.positions, &m.triangles);
        m
    }

    /// The triangle at position `i` of `order` as (first vertex, b - a, c - a). (Storing these
    /// contiguously in BVH order, 36 bytes a triangle, made no difference measurable above
    /// the noise on the face or a 200k-triangle torus: benches/bvh.rs.)
    #[inline(always)]
    fn tri_at(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.triangles[self.order[i] as usize].map(|i| self.positions[i as usize]);
        [a, b - a, c - a]
    }

    fn tri_bounds(&self, t: u32) -> (Vec3, Vec3) {
        let [a, b, c] = self.triangles[t as usize].map(|i| self.positions[i as usize]);
        (a.min(b).min(c), a.max(b).max(c))
    }

    /// The BVH's nodes (the root first; see [`Node`]) and the triangle order its leaves index
    /// into, as [`TriMesh::hit_binary`] traverses them (the GPU renderer's shadow rays use them
    /// too; [`TriMesh::hit`] walks a 4-wide tree collapsed from them).
    pub fn bvh(&self) -> (&[Node], &[u32]) {
        (&self.nodes, &self.order)
    }

    /// The BVH's depth: edges from the root to the deepest leaf (at most [`MAX_DEPTH`]).
    pub fn depth(&self) -> usize {
        let mut depth = 0;
        let mut todo = vec![(0usize, 0usize)];
        while let Some((i, d)) = todo.pop() {
            depth = depth.max(d);
            let n = self.nodes[i];
            if n.count == 0 && !self.triangles.is_empty() {
                todo.push((n.start as usize, d + 1));
                todo.push((n.start as usize + 1, d + 1));
            }
        }
        depth
    }

    /// Axis-aligned bounds of the mesh.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.nodes[0].lo, self.nodes[0].hi)
    }

    /// Nearest intersection with t in (t_min, t_max): (t, interpolated normal, uv).
    pub fn intersect(&self, r: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Vec3, Vec2)> {
        self.hit(r, t_min, t_max, true)
    }

    /// [`TriMesh::intersect`], with the texture coordinates interpolated only when `uv` is set
    /// (zero otherwise). Through the 4-wide BVH (`geometry::bvh4`): the same hit as
    /// [`TriMesh::hit_binary`], to the bit.
    #[inline]
    pub fn hit(&self, r: &Ray, t_min: f32, t_max: f32, uv: bool) -> Option<(f32, Vec3, Vec2)> {
        self.shade(self.bvh4.hit(r, t_min, t_max)?, uv)
    }

    /// The nearest hit as [`TriMesh::hit`] finds it (t, position in `order`, u, v): through
    /// `bundle` where it covers the ray (`geometry::bundle`: the same hit), else the BVH.
    #[inline]
    fn nearest_in(
        &self,
        bundle: Option<&Bundle>,
        r: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, usize, f32, f32)> {
        match bundle.and_then(|b| b.nearest(r, t_min, t_max)) {
            Some(found) => found,
            None => self.bvh4.hit(r, t_min, t_max),
        }
    }

    /// [`TriMesh::hit`] and the interpolated tangent (zero without [`TriMesh::tangents`]): the
    /// same hit, normal and uv.
    #[inline]
    pub fn hit_tangent(
        &self,
        r: &Ray,
        t_min: f32,
        t_max: f32,
        uv: bool,
    ) -> Option<(f32, Vec3, Vec2, Vec4)> {
        self.hit_tangent_in(None, r, t_min, t_max, uv)
    }

    /// [`TriMesh::hit_tangent`] through `bundle` where it covers the ray (the same hit).
    #[inline]
    pub(crate) fn hit_tangent_in(
        &self,
        bundle: Option<&Bundle>,
        r: &Ray,
        t_min: f32,
        t_max: f32,
        uv: bool,
    ) -> Option<(f32, Vec3, Vec2, Vec4)> {
        let found = self.nearest_in(bundle, r, t_min, t_max)?;
        let (t, n, uv) = self.shade(found, uv)?;
        let tangent = if self.tangents.is_empty() {
            Vec4::ZERO
        } else {
            let (_, i, u, v) = found;
            let [a, b, c] = self.triangles[self.order[i] as usize];
            let t3 = |k: u32| self.tangents[k as usize];
            let s = t3(a) * (1.0 - u - v) + t3(b) * u + t3(c) * v;
            // The sign is the first corner's (a triangle's corners share it in any sane file).
            s.truncate().extend(t3(a).w)
        };
        Some((t, n, uv, tangent))
    }

    /// [`TriMesh::hit`] through the binary tree (the GPU's layout; kept to compare against
    /// and to time in benches/bvh.rs). Ordered traversal: of an inner node's children the
    /// nearer box is visited first and the farther one pushed with its entry distance,
    /// skipped when popped if a hit nearer than that entry was found meanwhile.
    #[doc(hidden)]
    pub fn hit_binary(
        &self,
        r: &Ray,
        t_min: f32,
        t_max: f32,
        uv: bool,
    ) -> Option<(f32, Vec3, Vec2)> {
        self.shade(self.nearest_binary(r, t_min, t_max)?, uv)
    }

    /// The nearest hit through the binary tree: (t, position in `order`, u, v).
    fn nearest_binary(
        &self,
        r: &Ray,
        t_min: f32,
        mut t_max: f32,
    ) -> Option<(f32, usize, f32, f32)> {
        if self.triangles.is_empty() {
            return None;
        }
        let inv = r.d.recip();
        slab(&self.nodes[0], r.o, inv, t_min, t_max)?;
        let mut best: Option<(f32, usize, f32, f32)> = None;
        let mut stack = [(0u32, 0.0f32); BVH_STACK];
        let mut sp = 0;
        let mut node = 0u32;
        'walk: loop {
            let nd = &self.nodes[node as usize];
            if nd.count > 0 {
                let first = nd.start as usize;
                for i in first..first + nd.count as usize {
                    if let Some((t, u, v)) = hit_triangle(&self.tri_at(i), r, t_min, t_max) {
                        t_max = t;
                        best = Some((t, i, u, v));
                    }
                }
            } else {
                let (l, rt) = (nd.start, nd.start + 1);
                let hl = slab(&self.nodes[l as usize], r.o, inv, t_min, t_max);
                let hr = slab(&self.nodes[rt as usize], r.o, inv, t_min, t_max);
                match (hl, hr) {
                    (Some(a), Some(b)) => {
                        let (near, far, t_far) = if a <= b { (l, rt, b) } else { (rt, l, a) };
                        if sp < BVH_STACK {
                            stack[sp] = (far, t_far);
                            sp += 1;
                        }
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = rt;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            while sp > 0 {
                sp -= 1;
                let (n, t_near) = stack[sp];
                if t_near <= t_max {
                    node = n;
                    continue 'walk;
                }
            }
            break;
        }
        best
    }

    /// The normal and texture coordinates at a hit (t, position in `order`, u, v).
    #[inline]
    fn shade(&self, (t, i, u, v): (f32, usize, f32, f32), uv: bool) -> Option<(f32, Vec3, Vec2)> {
        let tri = self.order[i];
        let [a, b, c] = self.triangles[tri as usize];
        let w = 1.0 - u - v;
        let n = (self.normals[a as usize] * w
            + self.normals[b as usize] * u
            + self.normals[c as usize] * v)
            .normalize_or_zero();
        let n = if n == Vec3::ZERO {
            self.face_normal(tri)
        } else {
            n
        };
        let uv = if !uv {
            Vec2::ZERO
        } else if self.uvs.is_empty() {
            Vec2::new(u, v)
        } else {
            self.uvs[a as usize] * w + self.uvs[b as usize] * u + self.uvs[c as usize] * v
        };
        Some((t, n, uv))
    }

    /// Whether any triangle is hit with t in (t_min, t_max): a shadow ray, which stops at the
    /// first hit found rather than the nearest (through the 4-wide BVH, `geometry::bvh4`).
    #[inline]
    pub fn occluded(&self, r: &Ray, t_min: f32, t_max: f32) -> bool {
        self.bvh4.occluded(r, t_min, t_max)
    }

    /// [`TriMesh::occluded`] through `bundle` where it covers the ray (the same answer).
    #[inline]
    pub(crate) fn occluded_in(
        &self,
        bundle: Option<&Bundle>,
        r: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> bool {
        bundle
            .and_then(|b| b.occluded(r, t_min, t_max))
            .unwrap_or_else(|| self.bvh4.occluded(r, t_min, t_max))
    }

    /// [`TriMesh::occluded`] through the binary tree (see [`TriMesh::hit_binary`]).
    #[doc(hidden)]
    pub fn occluded_binary(&self, r: &Ray, t_min: f32, t_max: f32) -> bool {
        if self.triangles.is_empty() {
            return false;
        }
        let inv = r.d.recip();
        if slab(&self.nodes[0], r.o, inv, t_min, t_max).is_none() {
            return false;
        }
        let mut stack = [0u32; BVH_STACK];
        let mut sp = 0;
        let mut node = 0u32;
        loop {
            let nd = &self.nodes[node as usize];
            if nd.count > 0 {
                let first = nd.start as usize;
                let mut leaf = first..first + nd.count as usize;
                if leaf.any(|i| hit_triangle(&self.tri_at(i), r, t_min, t_max).is_some()) {
                    return true;
                }
            } else {
                let (l, rt) = (nd.start, nd.start + 1);
                let hl = slab(&self.nodes[l as usize], r.o, inv, t_min, t_max).is_some();
                let hr = slab(&self.nodes[rt as usize], r.o, inv, t_min, t_max).is_some();
                if hl || hr {
                    if hl && hr && sp < BVH_STACK {
                        stack[sp] = rt;
                        sp += 1;
                    }
                    node = if hl { l } else { rt };
                    continue;
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            node = stack[sp];
        }
    }

    /// The unit geometric normal of triangle `tri` (by its winding).
    pub fn face_normal(&self, tri: u32) -> Vec3 {
        let [a, b, c] = self.triangles[tri as usize].map(|i| self.positions[i as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    }
}

/// Moller-Trumbore on a triangle stored as (first vertex, b - a, c - a): (t, u, v) with t in
/// (t_min, t_max).
#[inline(always)]
fn hit_triangle(tri: &[Vec3; 3], r: &Ray, t_min: f32, t_max: f32) -> Option<(f32, f32, f32)> {
    let [a, e1, e2] = *tri;
    let p = r.d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = r.o - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = r.d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > t_min && t < t_max).then_some((t, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Clusters of stacked triangles at sizes and positions growing by 1.5: SAH splits off a
    /// few clusters per level, so its tree is deeper than a median split's.
    fn nested() -> TriMesh {
        let mut positions = Vec::new();
        for g in 0..60 {
            let s = 1.5f32.powi(g);
            for _ in 0..8 {
                positions.extend([Vec3::new(s, 0.0, 0.0), Vec3::new(2.0 * s, 0.0, 0.1 * s)]);
                positions.push(Vec3::new(s, s, 0.0));
            }
        }
        let n = positions.len() as u32 / 3;
        let triangles = (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let normals = vec![Vec3::Z; positions.len()];
        TriMesh::with_max_depth(positions, normals, Vec::new(), triangles, 1 << 20)
    }

    /// The depth cap holds where SAH alone goes deeper, and the capped tree finds the same
    /// hits.
    #[test]
    fn the_depth_cap_bounds_a_deeper_sah_tree() {
        let free = nested();
        let n = free.triangles.len();
        let cap = median_height(n) + 2;
        assert!(free.depth() > cap, "SAH depth {} <= {cap}", free.depth());
        let m = TriMesh::with_max_depth(
            free.positions.clone(),
            free.normals.clone(),
            Vec::new(),
            free.triangles.clone(),
            cap,
        );
        assert!(m.depth() <= cap, "depth {} > cap {cap}", m.depth());
        let mut order = m.order.clone();
        order.sort_unstable();
        assert_eq!(order, (0..n as u32).collect::<Vec<_>>());
        let mut hits = 0;
        for k in 0..200 {
            let [a, b, c] = m.triangles[k * 7 % n].map(|i| m.positions[i as usize]);
            let (u, v) = ((k % 10) as f32 * 0.09, (k / 10 % 10) as f32 * 0.05);
            // Points on a triangle, and some beside it.
            let target = a + u * (b - a) + v * (c - a) + (k % 3) as f32 * 0.3 * (a - c);
            let o = target + Vec3::new(0.1, 0.2, 10.0) * (1.0 + target.x);
            let r = Ray {
                o,
                d: (target - o).normalize(),
            };
            let (a, b) = (
                free.intersect(&r, 0.0, f32::INFINITY),
                m.intersect(&r, 0.0, f32::INFINITY),
            );
            assert_eq!(a.map(|h| h.0), b.map(|h| h.0), "ray {k}");
            assert_eq!(free.occluded(&r, 0.0, f32::INFINITY), a.is_some());
            assert_eq!(m.occluded(&r, 0.0, f32::INFINITY), a.is_some());
            hits += usize::from(a.is_some());
        }
        assert!(hits > 50, "{hits} of 200 rays hit");
    }
}
