//! Question (issue 30): what do the BVH's build, nearest-hit rays and shadow rays cost? On
//! the embedded face (`--mesh face`, 898 triangles) and a generated wavy torus (200k
//! triangles): the build, 65536 primary rays (a grid over the mesh's bounds, from the front,
//! `TriMesh::hit`), and from each hit point a shadow ray towards the default key light's
//! direction (`TriMesh::occluded`, any hit). One thread. The `*_binary` variants walk the
//! binary SAH tree (the GPU's layout) instead of the CPU's 4-wide BVH collapsed from it.
//! Run: `cargo bench -p fastbrdf-render --bench bvh`.

use fastbrdf_render::geometry::{Ray, TriMesh};
use glam::{Vec2, Vec3};

fn main() {
    divan::main();
}

/// A torus of 2 * u * v triangles with a wavy tube (so rays graze and shadow it).
fn torus(u: u32, v: u32) -> TriMesh {
    let mut positions = Vec::new();
    for i in 0..u {
        let a = std::f32::consts::TAU * i as f32 / u as f32;
        for j in 0..v {
            let b = std::f32::consts::TAU * j as f32 / v as f32;
            let r = 0.35 * (1.0 + 0.15 * (7.0 * a).sin() * (5.0 * b).cos());
            let w = 1.0 + r * b.cos();
            positions.push(Vec3::new(w * a.cos(), r * b.sin(), w * a.sin()));
        }
    }
    let p = |i: u32, j: u32| (i % u) * v + j % v;
    let triangles: Vec<[u32; 3]> = (0..u)
        .flat_map(|i| {
            (0..v).flat_map(move |j| {
                [
                    [p(i, j), p(i + 1, j), p(i + 1, j + 1)],
                    [p(i, j), p(i + 1, j + 1), p(i, j + 1)],
                ]
            })
        })
        .collect();
    let normals = vec![Vec3::Y; positions.len()];
    TriMesh::new(positions, normals, Vec::<Vec2>::new(), triangles)
}

fn mesh(name: &str) -> TriMesh {
    match name {
        "face" => fastbrdf_render::mesh::face(),
        _ => torus(500, 200),
    }
}

/// 256 x 256 rays towards -z (tilted) over the mesh's bounds.
fn primary(m: &TriMesh) -> Vec<Ray> {
    let (lo, hi) = m.bounds();
    let d = Vec3::new(0.1, -0.3, -1.0).normalize();
    (0..256 * 256)
        .map(|k| {
            let (x, y) = ((k % 256) as f32 / 255.0, (k / 256) as f32 / 255.0);
            let target = Vec3::new(
                lo.x + x * (hi.x - lo.x),
                lo.y + y * (hi.y - lo.y),
                0.5 * (lo.z + hi.z),
            );
            Ray {
                o: target - 4.0 * (hi - lo).max_element() * d,
                d,
            }
        })
        .collect()
}

const NAMES: [&str; 2] = ["face", "torus"];

#[divan::bench(args = NAMES, sample_count = 10)]
fn build(bencher: divan::Bencher, name: &str) {
    let m = mesh(name);
    bencher.bench(|| {
        TriMesh::new(
            m.positions.clone(),
            m.normals.clone(),
            m.uvs.clone(),
            m.triangles.clone(),
        )
    });
}

#[divan::bench(args = NAMES, sample_count = 20)]
fn nearest(bencher: divan::Bencher, name: &str) {
    let m = mesh(name);
    let rays = primary(&m);
    bencher.bench(|| {
        rays.iter()
            .filter_map(|r| m.hit(r, 1e-4, f32::INFINITY, false))
            .map(|h| h.0)
            .sum::<f32>()
    });
}

#[divan::bench(args = NAMES, sample_count = 20)]
fn nearest_binary(bencher: divan::Bencher, name: &str) {
    let m = mesh(name);
    let rays = primary(&m);
    bencher.bench(|| {
        rays.iter()
            .filter_map(|r| m.hit_binary(r, 1e-4, f32::INFINITY, false))
            .map(|h| h.0)
            .sum::<f32>()
    });
}

#[divan::bench(args = NAMES, sample_count = 20)]
fn shadow(bencher: divan::Bencher, name: &str) {
    shadow_with(bencher, name, TriMesh::occluded);
}

#[divan::bench(args = NAMES, sample_count = 20)]
fn shadow_binary(bencher: divan::Bencher, name: &str) {
    shadow_with(bencher, name, TriMesh::occluded_binary);
}

fn shadow_with(
    bencher: divan::Bencher,
    name: &str,
    occluded: fn(&TriMesh, &Ray, f32, f32) -> bool,
) {
    let m = mesh(name);
    let l = Vec3::new(0.4, 0.8, 0.45).normalize();
    let rays: Vec<Ray> = primary(&m)
        .iter()
        .filter_map(|r| {
            let (t, n, _) = m.hit(r, 1e-4, f32::INFINITY, false)?;
            Some(Ray {
                o: r.o + t * r.d + 1e-4 * n,
                d: l,
            })
        })
        .collect();
    bencher.bench(|| {
        rays.iter()
            .filter(|r| occluded(&m, r, 1e-4, f32::INFINITY))
            .count()
    });
}
