//! The BVH's shape on meshes that defeat spatial splits (issue 27: many overlapping and
//! coincident triangles): every triangle in exactly one leaf, leaves of at most `LEAF`
//! triangles, depth at most ceil(log2(ceil(n / LEAF))) + 1, so the traversal stack
//! (`BVH_STACK`, shared with the GPU's shadow rays) never fills; and nearest hits through
//! such a mesh are the brute-force answer.

use fastbrdf_render::geometry::{BVH_STACK, LEAF, Ray, TriMesh};
use glam::{Vec2, Vec3};

fn mesh(tris: &[[Vec3; 3]]) -> TriMesh {
    let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
    let normals = tris
        .iter()
        .flat_map(|t| [(t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero(); 3])
        .collect();
    let triangles = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    TriMesh::new(positions, normals, Vec::<Vec2>::new(), triangles)
}

/// (depth, largest leaf), checking that every triangle is in exactly one leaf.
fn shape(m: &TriMesh) -> (usize, usize) {
    let (nodes, order) = m.bvh();
    let mut seen = vec![0u32; order.len()];
    let (mut depth, mut leaf) = (0, 0);
    let mut todo = vec![(0usize, 1usize)];
    while let Some((i, d)) = todo.pop() {
        depth = depth.max(d);
        let n = nodes[i];
        if n.count > 0 || order.len() <= LEAF {
            leaf = leaf.max(n.count as usize);
            for &t in &order[n.start as usize..(n.start + n.count) as usize] {
                seen[t as usize] += 1;
            }
        } else {
            todo.push((n.start as usize, d + 1));
            todo.push((n.start as usize + 1, d + 1));
        }
    }
    assert!(
        seen.iter().all(|&c| c == 1),
        "a triangle in no leaf or in two"
    );
    (depth, leaf)
}

fn bound(n: usize) -> usize {
    (n.div_ceil(LEAF) as f64).log2().ceil() as usize + 1
}

/// A PCG-style hash to [0, 1).
fn rand(i: u32) -> f32 {
    let mut x = i.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    x = ((x >> ((x >> 28) + 4)) ^ x).wrapping_mul(277_803_737);
    ((x >> 22) ^ x) as f32 / 4_294_967_296.0
}

#[test]
fn coincident_overlapping_and_degenerate_triangles_build_a_shallow_tree() {
    let few = [
        [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        [
            Vec3::new(-1.0, 0.5, 0.3),
            Vec3::new(1.0, 0.4, -0.3),
            Vec3::new(0.1, -0.8, 0.1),
        ],
        [
            Vec3::new(-0.3, -0.2, 0.6),
            Vec3::new(0.5, -0.1, 0.5),
            Vec3::new(0.1, 0.6, 0.9),
        ],
    ];
    let n = 150_000;
    let cases: Vec<(&str, Vec<[Vec3; 3]>)> = vec![
        (
            "50k copies of 3 triangles",
            (0..n).map(|i| few[i % 3]).collect(),
        ),
        ("one triangle 150k times", vec![few[0]; n]),
        (
            "150k points (zero-area triangles at one point)",
            vec![[Vec3::ONE; 3]; n],
        ),
        (
            "150k large random triangles through one box",
            (0..n as u32)
                .map(|i| {
                    let p = |k: u32| {
                        Vec3::new(
                            rand(9 * i + 3 * k),
                            rand(9 * i + 3 * k + 1),
                            rand(9 * i + 3 * k + 2),
                        ) * 2.0
                            - 1.0
                    };
                    [p(0), p(1), p(2)]
                })
                .collect(),
        ),
        ("one triangle", vec![few[0]]),
        ("five triangles", vec![few[1]; 5]),
    ];
    for (what, tris) in cases {
        let m = mesh(&tris);
        let (depth, leaf) = shape(&m);
        eprintln!("{what}: depth {depth}, largest leaf {leaf}");
        assert!(leaf <= LEAF, "{what}: a leaf of {leaf}");
        assert!(
            depth <= bound(tris.len()),
            "{what}: depth {depth} > {}",
            bound(tris.len())
        );
        assert!(depth < BVH_STACK, "{what}: depth {depth} fills the stack");
    }
}

/// Nearest hits through a stack of coincident and overlapping triangles: the brute-force
/// answer (the first of the nearest, as every triangle of a stack is hit at the same t).
#[test]
fn nearest_hits_through_a_stack_are_the_brute_force_ones() {
    let tris: Vec<[Vec3; 3]> = (0..3000u32)
        .map(|i| {
            let z = (i % 7) as f32 * 0.1;
            let s = 0.5 + rand(i);
            [
                Vec3::new(-s, -s, z),
                Vec3::new(s, -s, z + 0.05),
                Vec3::new(0.0, s, z - 0.05),
            ]
        })
        .collect();
    let m = mesh(&tris);
    for k in 0..200u32 {
        let o = Vec3::new(rand(3 * k) - 0.5, rand(3 * k + 1) - 0.5, 5.0);
        let d = Vec3::new(0.05 * (rand(3 * k + 2) - 0.5), 0.0, -1.0).normalize();
        let r = Ray { o, d };
        let got = m.intersect(&r, 1e-4, f32::INFINITY).map(|h| h.0);
        let single = |t: &[Vec3; 3]| mesh(&[*t]).intersect(&r, 1e-4, f32::INFINITY).map(|h| h.0);
        let want = tris.iter().filter_map(single).min_by(f32::total_cmp);
        assert_eq!(got, want, "ray {k}");
    }
}
