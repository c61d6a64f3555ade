//! Bundles: a mesh's triangles binned for one family of coherent rays, those leaving one
//! point (the camera's primary rays: an item buffer, Weghorst, Hooper and Greenberg 1984) or
//! those running along one direction (a directional light's shadow rays: a light buffer,
//! Haines and Greenberg 1986). Every triangle is projected onto a plane where each ray of the
//! family is a point (a ray from the eye by its slopes d.r / d.f, d.u / d.f; a ray along d by
//! its origin's coordinates across d), and listed in the cells of a uniform grid its
//! projection's box (widened by a margin far above f32 rounding) covers, sorted by depth and
//! packed four to a block as the 4-wide BVH's leaves pack them (`bvh4::Leaf4`). A ray then
//! reads one cell: the same Moller-Trumbore (`bvh4::hit4`) on the triangles it can meet,
//! nearest first, and stops once the rest lie beyond its nearest hit (primary rays) or behind
//! its origin (shadow rays), where the BVH walks from the root.
//!
//! Exactness: a triangle a ray hits has its projection's box over the ray's point, so it is
//! in the ray's cell, and the lanes' arithmetic is the BVH's: the same triangle with the same
//! t, u, v, to the bit (this module's tests compare the two on the face, random soups,
//! stacked copies, slivers and a soup with huge triangles, from cameras outside and inside
//! them). As between the two BVH walks, only exact ties in t may resolve otherwise (a ray
//! exactly through an edge two triangles share, as on the face's symmetry seam at an odd image
//! width), and a hit that rounding alone makes (a ray within ~1e-6 radians of an edge-on
//! triangle's plane, where Moller-Trumbore's answer is noise) could be missed by one and found
//! by the other. `Scene::views` builds a mesh's bundles per render, for meshes with enough
//! pixels a triangle to pay for the build.
//!
//! A ray the bundle does not cover (another origin or direction, a slope outside the
//! camera's window, an origin far from the mesh) gets `None`: the caller asks the BVH. A
//! triangle over more than [`WIDE`] cells (or crossing the eye's plane) is tested for every
//! ray instead; with more than [`MOST_WIDE`] of them, or more than [`ENTRIES`] cell entries a
//! triangle or [`MOST_ENTRIES`] in all, no bundle is built (memory stays linear in the mesh,
//! at most 160 MiB).

use super::bvh4::{Leaf4, Ray4, hit4, lanes::F4, nearest_lane};
use super::{Ray, TriMesh};
use glam::Vec3;

/// Grid cells per binned triangle (on the face's default render 1 and 2 took the same time,
/// 4 took 4% more).
const CELLS_PER_TRIANGLE: f32 = 2.0;

/// A triangle over more cells than this is tested for every ray.
const WIDE: u64 = 64;

/// Most triangles tested for every ray; beyond, no bundle.
const MOST_WIDE: usize = 16;

/// Most cell entries a triangle, on average, and in all (40 bytes each); beyond, no bundle.
const ENTRIES: u64 = 16;
const MOST_ENTRIES: u64 = 1 << 22;

/// Largest cell count per axis.
const MOST_CELLS: u32 = 4096;

/// The box of slopes (d.r / d.f, d.u / d.f) of the rays from `eye` through `points`, padded
/// far above their rounding (1e-4, relative: a tenth of a pixel at 512 pixels over 30
/// degrees, where the slopes' rounding is ~1e-7), `(f, r, u)` the camera's frame: it holds
/// the slopes of every ray through their convex hull. `None` if a point lies less than
/// `near` in front of the eye.
pub(crate) fn slope_box(
    eye: Vec3,
    (f, r, u): (Vec3, Vec3, Vec3),
    points: impl IntoIterator<Item = Vec3>,
    near: f32,
) -> Option<([f32; 2], [f32; 2])> {
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for p in points {
        let q = p - eye;
        let z = q.dot(f);
        if z.is_nan() || z < near {
            return None;
        }
        let s = [q.dot(r) / z, q.dot(u) / z];
        for k in 0..2 {
            lo[k] = lo[k].min(s[k]);
            hi[k] = hi[k].max(s[k]);
        }
    }
    let pad = 1e-4
        * (1.0
            + lo[0]
                .abs()
                .max(hi[0].abs())
                .max(lo[1].abs().max(hi[1].abs())));
    Some(([lo[0] - pad, lo[1] - pad], [hi[0] + pad, hi[1] + pad]))
}

/// What the rays of a bundle share.
#[derive(Clone, Copy, Debug)]
enum Shared {
    /// Rays leaving `eye`, placed by their slopes (d.r / d.f, d.u / d.f), `f`, `r`, `u`
    /// orthonormal; rays with slopes beyond `window` are not covered.
    Origin {
        eye: Vec3,
        f: Vec3,
        r: Vec3,
        u: Vec3,
        window: [f32; 2],
    },
    /// Rays along `d` (unit), placed by their origin's (o.a, o.b), `a`, `b` across `d`;
    /// origins beyond `reach` in any coordinate are not covered.
    Direction {
        d: Vec3,
        a: Vec3,
        b: Vec3,
        reach: f32,
    },
}

/// Where a triangle goes.
enum Place {
    /// Nowhere: no covered ray can meet it.
    Skip,
    /// Tested for every ray.
    Wide,
    /// In the cells over the box `lo..=hi`, sorted by `key`.
    Box {
        lo: [f32; 2],
        hi: [f32; 2],
        key: f32,
    },
}

/// A mesh's triangles binned for one family of rays (see the module's text).
pub(crate) struct Bundle {
    shared: Shared,
    /// The grid: its extent and cells per unit and per axis.
    lo: [f32; 2],
    hi: [f32; 2],
    scale: [f32; 2],
    n: [u32; 2],
    /// Per cell, its blocks `blocks[start[c]..start[c + 1]]`, in ascending `key`: the
    /// least distance along the eye's forward axis of a block's triangles (rays from the eye),
    /// or minus the most distance along the direction (rays along it; those nearest the light
    /// first).
    start: Vec<u32>,
    blocks: Vec<Leaf4>,
    key: Vec<f32>,
    /// Slack on `key` comparisons for its rounding.
    margin: f32,
    /// Triangles tested for every ray.
    wide: Vec<Leaf4>,
}

impl Bundle {
    /// The bundle of rays leaving `eye`, `(f, r, u)` the camera's forward, right and up
    /// vectors (orthonormal), covering rays whose slopes lie within `window` (tan of the half
    /// angles). `None` where the mesh does not suit it (see the module's text).
    pub(crate) fn from_eye(
        m: &TriMesh,
        eye: Vec3,
        (f, r, u): (Vec3, Vec3, Vec3),
        window: [f32; 2],
    ) -> Option<Self> {
        let scale = m
            .positions
            .iter()
            .fold(eye.abs().max_element(), |s, p| s.max(p.abs().max_element()));
        // Depths this close to the eye's plane (or behind it, but not wholly) make slopes
        // without bound: such a triangle is tested for every ray.
        let near = 1e-4 * (1.0 + scale);
        let w = [window[0] * 1.01, window[1] * 1.01];
        let place = |tri: [Vec3; 3]| {
            let z = tri.map(|p| (p - eye).dot(f));
            if z.iter().all(|&z| z < -near) {
                // Behind the eye: a ray with d.f > 0 meets only points in front.
                return Place::Skip;
            }
            if z.iter().any(|&z| z < near) {
                return Place::Wide;
            }
            let Some((lo, hi)) = slope_box(eye, (f, r, u), tri, near) else {
                return Place::Wide;
            };
            if lo[0] > w[0] || hi[0] < -w[0] || lo[1] > w[1] || hi[1] < -w[1] {
                return Place::Skip;
            }
            Place::Box {
                lo: [lo[0].max(-w[0]), lo[1].max(-w[1])],
                hi: [hi[0].min(w[0]), hi[1].min(w[1])],
                key: z[0].min(z[1]).min(z[2]),
            }
        };
        let shared = Shared::Origin {
            eye,
            f,
            r,
            u,
            window: w,
        };
        Self::build(m, shared, 1e-5 * (1.0 + scale), place)
    }

    /// The bundle of rays along `d` (unit) from origins within 16 times the mesh's largest
    /// coordinate (plus one). `None` where the mesh does not suit it.
    pub(crate) fn along(m: &TriMesh, d: Vec3) -> Option<Self> {
        let scale = m
            .positions
            .iter()
            .fold(0.0f32, |s, p| s.max(p.abs().max_element()));
        let (a, b) = d.any_orthonormal_pair();
        let reach = 16.0 * (1.0 + scale);
        // The projection's rounding (and d.a's, times a distance within the reach) is ~1e-6
        // of the reach.
        let pad = 1e-4 * (1.0 + scale);
        let place = |tri: [Vec3; 3]| {
            let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
            for p in tri {
                let s = [p.dot(a), p.dot(b)];
                for k in 0..2 {
                    lo[k] = lo[k].min(s[k]);
                    hi[k] = hi[k].max(s[k]);
                }
            }
            let depth = tri.map(|p| p.dot(d));
            Place::Box {
                lo: [lo[0] - pad, lo[1] - pad],
                hi: [hi[0] + pad, hi[1] + pad],
                key: -depth[0].max(depth[1]).max(depth[2]),
            }
        };
        let shared = Shared::Direction { d, a, b, reach };
        Self::build(m, shared, 1e-4 * (1.0 + scale), place)
    }

    /// Bins the triangles of `m` (by position in its BVH's `order`) where `place` puts them.
    fn build(
        m: &TriMesh,
        shared: Shared,
        margin: f32,
        place: impl Fn([Vec3; 3]) -> Place,
    ) -> Option<Self> {
        let tri = |i: usize| m.triangles[m.order[i] as usize].map(|v| m.positions[v as usize]);
        let count = m.triangles.len();
        let mut boxes = Vec::with_capacity(count);
        let mut wide = Vec::new();
        let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for i in 0..count {
            match place(tri(i)) {
                Place::Skip => {}
                Place::Wide => wide.push(i as u32),
                Place::Box { lo: l, hi: h, key } => {
                    if !(l[0] <= h[0] && l[1] <= h[1] && key.is_finite()) {
                        // Not finite (NaN positions): the BVH answers such a mesh.
                        return None;
                    }
                    for k in 0..2 {
                        lo[k] = lo[k].min(l[k]);
                        hi[k] = hi[k].max(h[k]);
                    }
                    boxes.push((i as u32, l, h, key));
                }
            }
        }
        let mut b = Self {
            shared,
            lo,
            hi,
            scale: [0.0; 2],
            n: [1, 1],
            start: vec![0],
            blocks: Vec::new(),
            key: Vec::new(),
            margin,
            wide: Vec::new(),
        };
        if !boxes.is_empty() {
            let (gw, gh) = (
                (hi[0] - lo[0]).max(f32::MIN_POSITIVE),
                (hi[1] - lo[1]).max(f32::MIN_POSITIVE),
            );
            // Square cells, CELLS_PER_TRIANGLE of them a triangle, but no smaller than half
            // the median box's longer side (where triangles overlap densely, a grid by count
            // alone would list each in many cells).
            let mut sides: Vec<f32> = boxes
                .iter()
                .map(|(_, l, h, _)| (h[0] - l[0]).max(h[1] - l[1]))
                .collect();
            let mid = sides.len() / 2;
            let median = *sides.select_nth_unstable_by(mid, f32::total_cmp).1;
            let side = (gw * gh / (CELLS_PER_TRIANGLE * boxes.len() as f32))
                .sqrt()
                .max(0.5 * median);
            let nx = ((gw / side).ceil() as u32).clamp(1, MOST_CELLS);
            let ny = ((gh / side).ceil() as u32).clamp(1, MOST_CELLS);
            b.n = [nx, ny];
            b.scale = [nx as f32 / gw, ny as f32 / gh];
            if !(b.scale[0].is_finite() && b.scale[1].is_finite()) {
                return None;
            }
            // Each box's cell range; too many cells: tested for every ray.
            let mut ranges = Vec::with_capacity(boxes.len());
            let mut entries = 0u64;
            for &(i, l, h, key) in &boxes {
                let (x0, y0) = b.cell_xy(l[0], l[1]);
                let (x1, y1) = b.cell_xy(h[0], h[1]);
                let n = u64::from(x1 - x0 + 1) * u64::from(y1 - y0 + 1);
                if n > WIDE {
                    wide.push(i);
                } else {
                    entries += n;
                    ranges.push((i, [x0, y0, x1, y1], key));
                }
            }
            if entries > (ENTRIES * count as u64 + 4096).min(MOST_ENTRIES) {
                return None;
            }
            // Counting sort into the cells, then each cell by key.
            let cells = (nx * ny) as usize;
            let mut first = vec![0u32; cells + 1];
            for (_, [x0, y0, x1, y1], _) in &ranges {
                for y in *y0..=*y1 {
                    for x in *x0..=*x1 {
                        first[(y * nx + x) as usize + 1] += 1;
                    }
                }
            }
            for c in 0..cells {
                first[c + 1] += first[c];
            }
            let mut fill = first.clone();
            let mut listed = vec![(0.0f32, 0u32); entries as usize];
            for &(i, [x0, y0, x1, y1], key) in &ranges {
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let c = (y * nx + x) as usize;
                        listed[fill[c] as usize] = (key, i);
                        fill[c] += 1;
                    }
                }
            }
            b.start = Vec::with_capacity(cells + 1);
            b.start.push(0);
            let blocks = (0..cells)
                .map(|c| (first[c + 1] - first[c]).div_ceil(4) as usize)
                .sum();
            b.blocks.reserve_exact(blocks);
            b.key.reserve_exact(blocks);
            for c in 0..cells {
                let list = &mut listed[first[c] as usize..first[c + 1] as usize];
                // Stable: equal keys keep the BVH's order.
                list.sort_by(|x, y| x.0.total_cmp(&y.0));
                for chunk in list.chunks(4) {
                    let mut leaf = Leaf4::EMPTY;
                    for (k, &(_, i)) in chunk.iter().enumerate() {
                        leaf.set(k, tri(i as usize), i);
                    }
                    b.blocks.push(leaf);
                    b.key.push(chunk[0].0);
                }
                b.start.push(b.blocks.len() as u32);
            }
        }
        if wide.len() > MOST_WIDE {
            return None;
        }
        for chunk in wide.chunks(4) {
            let mut leaf = Leaf4::EMPTY;
            for (k, &i) in chunk.iter().enumerate() {
                leaf.set(k, tri(i as usize), i);
            }
            b.wide.push(leaf);
        }
        Some(b)
    }

    /// The cell (column, row) of a point of the grid's extent (clamped to the grid: the
    /// same monotone arithmetic for boxes and rays, so a point of a box lies in its range).
    #[inline(always)]
    fn cell_xy(&self, x: f32, y: f32) -> (u32, u32) {
        let cx = ((x - self.lo[0]) * self.scale[0]).max(0.0) as u32;
        let cy = ((y - self.lo[1]) * self.scale[1]).max(0.0) as u32;
        (cx.min(self.n[0] - 1), cy.min(self.n[1] - 1))
    }

    /// The blocks of the cell over (x, y): none outside the grid's extent.
    #[inline(always)]
    fn cell(&self, x: f32, y: f32) -> (&[Leaf4], &[f32]) {
        if !(x >= self.lo[0] && x <= self.hi[0] && y >= self.lo[1] && y <= self.hi[1]) {
            return (&[], &[]);
        }
        let (cx, cy) = self.cell_xy(x, y);
        let c = (cy * self.n[0] + cx) as usize;
        let (s, e) = (self.start[c] as usize, self.start[c + 1] as usize);
        (&self.blocks[s..e], &self.key[s..e])
    }

    /// Of a bundle of rays from the eye: the box of slopes (lower, upper corner) outside which
    /// a ray it covers meets no triangle; `None` if it holds triangles tested for every ray
    /// (or runs along a direction). Empty (lower above upper) for no triangle.
    pub(crate) fn slopes(&self) -> Option<([f32; 2], [f32; 2])> {
        match self.shared {
            Shared::Origin { .. } if self.wide.is_empty() => Some((self.lo, self.hi)),
            _ => None,
        }
    }

    /// The nearest hit with t in (t_min, t_max) as (t, position in `order`, u, v), as
    /// `Bvh4::hit` finds it; `None` if the bundle does not cover the ray.
    #[inline]
    pub(crate) fn nearest(
        &self,
        ray: &Ray,
        t_min: f32,
        mut t_max: f32,
    ) -> Option<Option<(f32, usize, f32, f32)>> {
        let Shared::Origin {
            eye,
            f,
            r,
            u,
            window,
        } = self.shared
        else {
            return None;
        };
        let df = ray.d.dot(f);
        if ray.o != eye || df.is_nan() || df <= 1e-2 {
            return None;
        }
        // One division: the slopes' rounding either way is far inside the boxes' margin.
        let inv = 1.0 / df;
        let (x, y) = (ray.d.dot(r) * inv, ray.d.dot(u) * inv);
        if !(x.abs() <= window[0] && y.abs() <= window[1]) {
            return None;
        }
        let (blocks, keys) = self.cell(x, y);
        if blocks.is_empty() && self.wide.is_empty() {
            return Some(None);
        }
        let r4 = Ray4::new(ray);
        let tmin4 = F4::splat(t_min);
        let mut best = None;
        let mut test = |leaf: &Leaf4, t_max: &mut f32| {
            let (ok, t, u, v) = hit4(leaf, &r4, tmin4, F4::splat(*t_max));
            if ok != 0 {
                let t = t.store();
                let k = nearest_lane(ok, &t);
                *t_max = t[k];
                best = Some((t[k], leaf.index[k] as usize, u.store()[k], v.store()[k]));
            }
        };
        for leaf in &self.wide {
            test(leaf, &mut t_max);
        }
        for (leaf, &key) in blocks.iter().zip(keys) {
            // The rest lie at depths from `key` on: at t >= key / df.
            if key > t_max * df * (1.0 + 1e-5) + self.margin {
                break;
            }
            test(leaf, &mut t_max);
        }
        Some(best)
    }

    /// Whether any triangle is hit with t in (t_min, t_max), as `Bvh4::occluded` answers;
    /// `None` if the bundle does not cover the ray.
    #[inline]
    pub(crate) fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<bool> {
        let Shared::Direction { d, a, b, reach } = self.shared else {
            return None;
        };
        if ray.d != d || !ray.o.is_finite() || ray.o.abs().max_element() > reach {
            return None;
        }
        let (blocks, keys) = self.cell(ray.o.dot(a), ray.o.dot(b));
        // A block whose triangles all lie behind t_min (less than the origin's depth plus
        // t_min along d) cannot be hit, nor can the ones after it.
        let limit = -(ray.o.dot(d) + t_min) + self.margin;
        if keys.first().is_none_or(|&k| k > limit) && self.wide.is_empty() {
            return Some(false);
        }
        let r4 = Ray4::new(ray);
        let (tmin4, tmax4) = (F4::splat(t_min), F4::splat(t_max));
        if self.wide.iter().any(|l| hit4(l, &r4, tmin4, tmax4).0 != 0) {
            return Some(true);
        }
        for (leaf, &key) in blocks.iter().zip(keys) {
            if key > limit {
                break;
            }
            if hit4(leaf, &r4, tmin4, tmax4).0 != 0 {
                return Some(true);
            }
        }
        Some(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;
    use glam::Vec2;

    /// A uniform number in [0, 1) from a 64-bit state (splitmix64).
    fn rand(state: &mut u64) -> f32 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn rand3(s: &mut u64) -> Vec3 {
        Vec3::new(rand(s), rand(s), rand(s))
    }

    fn mesh(tris: &[[Vec3; 3]]) -> TriMesh {
        let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
        let normals = vec![Vec3::Z; positions.len()];
        let triangles = (0..tris.len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        TriMesh::new(positions, normals, Vec::<Vec2>::new(), triangles)
    }

    /// `n` random triangles of sizes up to `size` in the unit cube.
    fn soup(n: usize, size: f32, seed: u64) -> Vec<[Vec3; 3]> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                let c = rand3(&mut s);
                [
                    c,
                    c + (rand3(&mut s) - 0.5) * size,
                    c + (rand3(&mut s) - 0.5) * size,
                ]
            })
            .collect()
    }

    /// The test meshes: the face, random soups, stacked copies (ties in t), a strip of
    /// slivers, and a soup with a few triangles much larger than the rest (tested for every
    /// ray). (A soup of 400 triangles each over half the cube would list each in hundreds of
    /// cells: no bundle, `many_large_triangles_leave_the_rays_to_the_bvh`.)
    fn meshes() -> Vec<(&'static str, TriMesh, bool)> {
        let copies = soup(1000, 0.06, 9);
        let stacked: Vec<[Vec3; 3]> = (0..2000).map(|i| copies[i % 1000]).collect();
        let strip: Vec<[Vec3; 3]> = (0..600)
            .map(|i| {
                let x = i as f32 / 600.0;
                [
                    Vec3::new(x, 0.0, 0.3 * x),
                    Vec3::new(x + 1.0 / 600.0, 0.0, 0.3 * x),
                    Vec3::new(x, 1.0, 0.5),
                ]
            })
            .collect();
        let mut wide = soup(1500, 0.08, 5);
        wide.extend(soup(6, 3.0, 6));
        // The third field: whether a bundle must be built (the strip's slivers each cross
        // the whole mesh, so from most directions they are all "wide": the BVH's rays).
        vec![
            ("face", crate::mesh::face(), true),
            ("soup", mesh(&soup(3000, 0.1, 1)), true),
            ("larger soup", mesh(&soup(400, 0.25, 2)), true),
            ("stacked", mesh(&stacked), true),
            ("strip", mesh(&strip), false),
            ("wide", mesh(&wide), true),
        ]
    }

    /// The bundle's nearest hit against the 4-wide BVH's: the same t to the bit and, unless
    /// two triangles are hit at exactly that t (stacked copies), the same triangle, u and v.
    fn same_hit(
        m: &TriMesh,
        got: Option<(f32, usize, f32, f32)>,
        want: Option<(f32, usize, f32, f32)>,
    ) -> bool {
        match (got, want) {
            (None, None) => true,
            (Some(g), Some(w)) if g.0.to_bits() == w.0.to_bits() => {
                (g.1 == w.1 && g.2.to_bits() == w.2.to_bits() && g.3.to_bits() == w.3.to_bits())
                    || m.tri_at(g.1) != m.tri_at(w.1)
            }
            _ => false,
        }
    }

    #[test]
    fn rays_from_the_eye_meet_the_bvhs_hits_to_the_bit() {
        let mut s = 11u64;
        for (what, m, must) in meshes() {
            let (lo, hi) = m.bounds();
            let ext = (hi - lo).max_element();
            // The framing camera, cameras around the mesh, and cameras inside its box (where
            // triangles cross the eye's plane or lie behind it).
            let mut cameras = vec![Camera::framing(lo, hi, -Vec3::Z, 30.0)];
            for k in 0..6 {
                let dir = (rand3(&mut s) - 0.5).normalize();
                cameras.push(Camera::framing(lo, hi, dir, 20.0 + 10.0 * k as f32));
            }
            for _ in 0..3 {
                let eye = lo + rand3(&mut s) * (hi - lo);
                cameras.push(Camera {
                    eye,
                    target: eye + (rand3(&mut s) - 0.5),
                    up: Vec3::Y,
                    fov_y_deg: 60.0,
                });
            }
            let (mut covered, mut hits, mut built) = (0, 0, 0);
            for (c, cam) in cameras.iter().enumerate() {
                let (w, h) = (64, 48);
                let rays = cam.rays(w, h);
                let (f, r, u, th) = cam.frame();
                let aspect = w as f32 / h as f32;
                let Some(b) = Bundle::from_eye(&m, cam.eye, (f, r, u), [th * aspect, th]) else {
                    continue;
                };
                built += 1;
                for k in 0..4000 {
                    // Across the image and a little beyond it (not covered: the BVH's).
                    let x = (rand(&mut s) * 1.2 - 0.1) * w as f32;
                    let y = (rand(&mut s) * 1.2 - 0.1) * h as f32;
                    let ray = rays.ray(x, y);
                    let (t_min, t_max) = match k % 4 {
                        0 => (1e-4, f32::INFINITY),
                        1 => (0.0, ext * rand(&mut s) * 3.0),
                        2 => (ext * rand(&mut s) * 2.0, f32::INFINITY),
                        _ => (1e-4, f32::INFINITY),
                    };
                    let want = m.bvh4.hit(&ray, t_min, t_max);
                    if let Some(got) = b.nearest(&ray, t_min, t_max) {
                        covered += 1;
                        hits += usize::from(got.is_some());
                        assert!(
                            same_hit(&m, got, want),
                            "{what}: camera {c}, ray {k} {ray:?} ({t_min}, {t_max}): {got:?}, the BVH {want:?}"
                        );
                    }
                }
                // Another origin, or a ray along another direction: not covered.
                let moved = Ray {
                    o: cam.eye + Vec3::X * 1e-3,
                    d: f,
                };
                assert!(b.nearest(&moved, 0.0, f32::INFINITY).is_none());
            }
            eprintln!(
                "{what}: {built} of {} cameras bundled, {covered} rays covered, {hits} hit",
                cameras.len()
            );
            // The three cameras inside the box see triangles across the eye's plane.
            assert!(
                !must || (built >= 7 && hits > 300),
                "{what}: too little tested"
            );
        }
    }

    #[test]
    fn rays_along_a_direction_meet_the_bvhs_occlusion() {
        let mut s = 23u64;
        for (what, m, must) in meshes() {
            let (lo, hi) = m.bounds();
            let mut dirs = vec![
                Vec3::new(-0.45, 0.55, 0.7).normalize(),
                Vec3::X,
                -Vec3::Y,
                Vec3::Z,
            ];
            dirs.extend((0..4).map(|_| (rand3(&mut s) - 0.5).normalize()));
            let (mut covered, mut blocked, mut open) = (0, 0, 0);
            for (c, &d) in dirs.iter().enumerate() {
                let Some(b) = Bundle::along(&m, d) else {
                    assert!(!must, "{what}: no bundle along {d}");
                    continue;
                };
                for k in 0..4000 {
                    // Points on the triangles, lifted along their normal towards d as the
                    // renderer's shadow rays are, and points anywhere around the mesh.
                    let o = if k % 3 > 0 {
                        let i = (rand(&mut s) * m.triangles.len() as f32) as usize;
                        let [a, e1, e2] = m.tri_at(i.min(m.triangles.len() - 1));
                        let (u, v) = (rand(&mut s), rand(&mut s));
                        let (u, v) = if u + v > 1.0 {
                            (1.0 - u, 1.0 - v)
                        } else {
                            (u, v)
                        };
                        let n = e1.cross(e2).normalize_or_zero();
                        let n = if n.dot(d) < 0.0 { -n } else { n };
                        let eps = 1e-4 * (1.0 + a.abs().max_element());
                        a + u * e1 + v * e2 + n * eps
                    } else {
                        lo + (rand3(&mut s) * 1.4 - 0.2) * (hi - lo)
                    };
                    let ray = Ray { o, d };
                    let (t_min, t_max) = match k % 4 {
                        2 => (0.0, (hi - lo).max_element() * rand(&mut s)),
                        _ => (1e-4, f32::INFINITY),
                    };
                    let want = m.bvh4.occluded(&ray, t_min, t_max);
                    let got = b.occluded(&ray, t_min, t_max);
                    assert_eq!(got, Some(want), "{what}: direction {c}, ray {k} {ray:?}");
                    covered += 1;
                    if want {
                        blocked += 1;
                    } else {
                        open += 1;
                    }
                }
                // Another direction, or an origin beyond the reach: not covered.
                assert!(b.occluded(&Ray { o: lo, d: -d }, 0.0, 1.0).is_none());
                let far = Ray {
                    o: Vec3::splat(1e6),
                    d,
                };
                assert!(b.occluded(&far, 0.0, 1.0).is_none());
            }
            eprintln!("{what}: {covered} shadow rays, {blocked} blocked, {open} open");
            assert!(
                !must || (blocked > 1000 && open > 1000),
                "{what}: too little tested"
            );
        }
    }

    /// More very large triangles than [`MOST_WIDE`]: no bundle (the BVH answers); a few:
    /// tested for every ray.
    #[test]
    fn many_large_triangles_leave_the_rays_to_the_bvh() {
        let mut tris = soup(1000, 0.05, 3);
        tris.extend(soup(4, 4.0, 4));
        let b = Bundle::along(&mesh(&tris), Vec3::Z).expect("a few large triangles");
        assert!(!b.wide.is_empty() && b.wide.len() <= 1);
        tris.extend(soup(2 * MOST_WIDE, 4.0, 5));
        assert!(Bundle::along(&mesh(&tris), Vec3::Z).is_none());
    }

    /// The face's bundles for its default render (camera and key light), and the blocks a
    /// 512 x 512 image's rays read: at most a couple per ray (printed).
    #[test]
    fn the_faces_rays_read_few_blocks() {
        let m = crate::mesh::face();
        let (lo, hi) = m.bounds();
        let cam = Camera::framing(lo, hi, -Vec3::Z, 30.0);
        let rays = cam.rays(512, 512);
        let (f, r, u, th) = cam.frame();
        let b = Bundle::from_eye(&m, cam.eye, (f, r, u), [th, th]).expect("the eye's bundle");
        let l = Vec3::new(-0.45, 0.55, 0.7).normalize();
        let s = Bundle::along(&m, l).expect("the light's bundle");
        let Shared::Direction { a, b: bb, .. } = s.shared else {
            unreachable!()
        };
        let (mut read, mut hits, mut shadow_read) = (0, 0, 0);
        for y in 0..512 {
            for x in 0..512 {
                let ray = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
                let df = ray.d.dot(f);
                let found = b.nearest(&ray, 1e-4, f32::INFINITY).expect("covered");
                let t_max = found.map_or(f32::INFINITY, |h| h.0);
                let (_, keys) = b.cell(ray.d.dot(r) / df, ray.d.dot(u) / df);
                read += keys
                    .iter()
                    .take_while(|&&k| k <= t_max * df * (1.0 + 1e-5) + b.margin)
                    .count();
                if let Some((t, ..)) = found {
                    hits += 1;
                    let o = ray.o + t * ray.d - ray.d * 1e-3;
                    let (_, keys) = s.cell(o.dot(a), o.dot(bb));
                    let limit = -(o.dot(l) + 1e-4) + s.margin;
                    shadow_read += keys.iter().take_while(|&&k| k <= limit).count();
                }
            }
        }
        let (per_ray, per_shadow) = (read as f64 / hits as f64, shadow_read as f64 / hits as f64);
        eprintln!(
            "face: eye grid {:?}, {} blocks; light grid {:?}, {} blocks; {hits} of 512 x 512 rays hit, {per_ray:.2} blocks read a hit, {per_shadow:.2} a shadow ray at most",
            b.n,
            b.blocks.len(),
            s.n,
            s.blocks.len()
        );
        assert!(hits > 50_000 && per_ray < 3.0 && per_shadow < 4.0);
    }
}
