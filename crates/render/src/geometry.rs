//! Rays, analytic spheres and planes, and triangle meshes with a bounding volume hierarchy.

use glam::{Vec2, Vec3};

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
        let n = (p - self.center) / self.radius;
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
    nodes: Vec<Node>,
    order: Vec<u32>,
}

/// Entries of the traversal stack (`TriMesh::hit`, and the GPU renderer's shadow rays, which
/// use the same size). A depth-first walk holds at most depth + 1 entries, and the median
/// split's depth is at most ceil(log2(ceil(n / LEAF))) + 1 whatever the triangles (it halves
/// the count, so coincident or overlapping triangles cannot make it deeper): 31 for 2^32
/// triangles, so the stack never fills.
pub const BVH_STACK: usize = 64;

/// Most triangles in a leaf.
pub const LEAF: usize = 4;

/// A BVH node (public for the GPU renderer, which uploads the tree for its shadow rays).
#[derive(Clone, Copy, Debug)]
pub struct Node {
    pub lo: Vec3,
    pub hi: Vec3,
    /// Leaf: first triangle in `order` and count; inner: left child index (right = left + 1).
    pub start: u32,
    pub count: u32,
}

impl TriMesh {
    /// Builds the BVH (median split on the longest axis of the node's bounds, by centroid,
    /// leaves of up to [`LEAF`] triangles). The split is at the median index, not a position,
    /// so each child holds half the triangles even when their centroids coincide (stacked
    /// copies): the depth is logarithmic in the count (see [`BVH_STACK`]).
    pub fn new(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        uvs: Vec<Vec2>,
        triangles: Vec<[u32; 3]>,
    ) -> Self {
        let mut m = Self {
            positions,
            normals,
            uvs,
            triangles,
            nodes: Vec::new(),
            order: Vec::new(),
        };
        m.order = (0..m.triangles.len() as u32).collect();
        let n = m.order.len();
        m.nodes.push(Node {
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            start: 0,
            count: 0,
        });
        m.build(0, 0, n);
        m
    }

    fn tri_bounds(&self, t: u32) -> (Vec3, Vec3) {
        let [a, b, c] = self.triangles[t as usize].map(|i| self.positions[i as usize]);
        (a.min(b).min(c), a.max(b).max(c))
    }

    fn build(&mut self, node: usize, start: usize, end: usize) {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for i in start..end {
            let (a, b) = self.tri_bounds(self.order[i]);
            lo = lo.min(a);
            hi = hi.max(b);
        }
        if end - start <= LEAF {
            self.nodes[node] = Node {
                lo,
                hi,
                start: start as u32,
                count: (end - start) as u32,
            };
            return;
        }
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (start + end) / 2;
        let centroid = |m: &Self, t: u32| {
            let (a, b) = m.tri_bounds(t);
            (a + b)[axis]
        };
        let mut slice: Vec<u32> = self.order[start..end].to_vec();
        slice.sort_by(|&a, &b| centroid(self, a).total_cmp(&centroid(self, b)));
        self.order[start..end].copy_from_slice(&slice);
        let left = self.nodes.len();
        self.nodes.push(Node {
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            start: 0,
            count: 0,
        });
        self.nodes.push(Node {
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            start: 0,
            count: 0,
        });
        self.nodes[node] = Node {
            lo,
            hi,
            start: left as u32,
            count: 0,
        };
        self.build(left, start, mid);
        self.build(left + 1, mid, end);
    }

    /// The BVH's nodes (the root first; see [`Node`]) and the triangle order its leaves index
    /// into, as [`TriMesh::hit`] traverses them (the GPU renderer's shadow rays use them too).
    pub fn bvh(&self) -> (&[Node], &[u32]) {
        (&self.nodes, &self.order)
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
    /// (zero otherwise).
    pub fn hit(&self, r: &Ray, t_min: f32, mut t_max: f32, uv: bool) -> Option<(f32, Vec3, Vec2)> {
        let inv = r.d.recip();
        let mut best: Option<(f32, u32, f32, f32)> = None;
        let mut stack = [0u32; BVH_STACK];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = self.nodes[stack[sp] as usize];
            // Slab test.
            let t0 = (node.lo - r.o) * inv;
            let t1 = (node.hi - r.o) * inv;
            let tn = t0.min(t1).max_element().max(t_min);
            let tf = t0.max(t1).min_element().min(t_max);
            if tn > tf {
                continue;
            }
            if node.count > 0 {
                for &tri in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    if let Some((t, u, v)) = self.hit_triangle(tri, r, t_min, t_max) {
                        t_max = t;
                        best = Some((t, tri, u, v));
                    }
                }
            } else if sp + 2 <= stack.len() {
                stack[sp] = node.start;
                stack[sp + 1] = node.start + 1;
                sp += 2;
            }
        }
        let (t, tri, u, v) = best?;
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

    /// The unit geometric normal of triangle `tri` (by its winding).
    pub fn face_normal(&self, tri: u32) -> Vec3 {
        let [a, b, c] = self.triangles[tri as usize].map(|i| self.positions[i as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// Moller-Trumbore.
    fn hit_triangle(&self, tri: u32, r: &Ray, t_min: f32, t_max: f32) -> Option<(f32, f32, f32)> {
        let [a, b, c] = self.triangles[tri as usize].map(|i| self.positions[i as usize]);
        let e1 = b - a;
        let e2 = c - a;
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
}
