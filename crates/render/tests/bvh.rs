//! The BVH (binned SAH, median split near the depth limit; ordered traversal; any-hit shadow
//! rays) against brute force: every triangle in exactly one leaf, leaves of at most `LEAF`
//! triangles, depth at most `MAX_DEPTH` (so depth + 1 entries fit in `BVH_STACK`, shared with
//! the GPU's shadow rays) on inputs that defeat spatial splits (issue 27: coincident and
//! stacked triangles; here also nested clusters that make SAH peel one cluster per level);
//! nearest hits equal to testing every triangle (same t; the same triangle's normal unless two
//! triangles are hit at that same t); `occluded` = a brute-force hit exists in the range.

use fastbrdf_render::geometry::{BVH_STACK, LEAF, MAX_DEPTH, Ray, TriMesh};
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

/// (depth in edges, largest leaf), checking that every triangle is in exactly one leaf.
fn shape(m: &TriMesh) -> (usize, usize) {
    let (nodes, order) = m.bvh();
    let mut seen = vec![0u32; order.len()];
    let (mut depth, mut leaf) = (0, 0);
    let mut todo = vec![(0usize, 0usize)];
    while let Some((i, d)) = todo.pop() {
        depth = depth.max(d);
        let n = nodes[i];
        if n.count > 0 || order.is_empty() {
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
    assert_eq!(depth, m.depth());
    (depth, leaf)
}

/// A PCG-style hash to [0, 1).
fn rand(i: u32) -> f32 {
    let mut x = i.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    x = ((x >> ((x >> 28) + 4)) ^ x).wrapping_mul(277_803_737);
    ((x >> 22) ^ x) as f32 / 4_294_967_296.0
}

fn rand3(i: u32) -> Vec3 {
    Vec3::new(rand(3 * i), rand(3 * i + 1), rand(3 * i + 2))
}

const FEW: [[Vec3; 3]; 3] = [
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

/// `n` random triangles with vertices in [-1, 1]^3 (large, overlapping).
fn soup(n: u32, seed: u32) -> Vec<[Vec3; 3]> {
    (0..n)
        .map(|i| [0, 1, 2].map(|k| rand3(seed + 3 * i + k) * 2.0 - 1.0))
        .collect()
}

/// A strip of `n` thin triangles along x, 1e-3 wide.
fn strip(n: u32) -> Vec<[Vec3; 3]> {
    (0..n)
        .map(|i| {
            let x = i as f32 * 0.01;
            [
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x + 0.01, 0.0, 0.0),
                Vec3::new(x + 0.005, 1e-3, 0.0),
            ]
        })
        .collect()
}

/// `groups` clusters of `copies` stacked triangles, cluster i of size and position 1.5^i:
/// SAH splits off a few clusters per level (deeper than a median split; the unit test in
/// geometry.rs shows the depth cap holding on such a tree).
fn nested(groups: u32, copies: u32) -> Vec<[Vec3; 3]> {
    (0..groups)
        .flat_map(|g| {
            let s = 1.5f32.powi(g as i32);
            let t = [
                Vec3::new(s, 0.0, 0.0),
                Vec3::new(2.0 * s, 0.0, 0.1 * s),
                Vec3::new(s, s, 0.0),
            ];
            std::iter::repeat_n(t, copies as usize)
        })
        .collect()
}

#[test]
fn adversarial_inputs_keep_the_depth_within_the_stack() {
    let n = 150_000;
    let cases: Vec<(&str, Vec<[Vec3; 3]>)> = vec![
        (
            "50k copies of 3 triangles",
            (0..n).map(|i| FEW[i % 3]).collect(),
        ),
        ("one triangle 150k times", vec![FEW[0]; n]),
        (
            "150k points (zero-area triangles at one point)",
            vec![[Vec3::ONE; 3]; n],
        ),
        (
            "150k large random triangles through one box",
            soup(n as u32, 0),
        ),
        ("a strip of 100k thin triangles", strip(100_000)),
        ("100 nested clusters of 2000 copies", nested(100, 2000)),
        ("one triangle", vec![FEW[0]]),
        ("five triangles", vec![FEW[1]; 5]),
    ];
    for (what, tris) in cases {
        let m = mesh(&tris);
        let (depth, leaf) = shape(&m);
        eprintln!("{what}: depth {depth}, largest leaf {leaf}");
        assert!(leaf <= LEAF, "{what}: a leaf of {leaf}");
        assert!(depth <= MAX_DEPTH, "{what}: depth {depth} > {MAX_DEPTH}");
        assert!(depth < BVH_STACK, "{what}: depth {depth} fills the stack");
        // The 4-wide BVH collapsed from these trees (its stack bound is 3 * MAX_DEPTH) finds
        // the binary tree's hits.
        let (lo, hi) = m.bounds();
        for k in 0..64u32 {
            let o = lo + (rand3(k) * 3.0 - 1.0) * (hi - lo).max(Vec3::splat(1e-3));
            let r = Ray {
                o,
                d: (lo + rand3(k + 99) * (hi - lo) - o).normalize_or(Vec3::Z),
            };
            let bits = |h: Option<(f32, Vec3, Vec2)>| h.map(|h| (h.0.to_bits(), h.1.to_array()));
            assert_eq!(
                bits(m.hit(&r, 0.0, f32::INFINITY, true)),
                bits(m.hit_binary(&r, 0.0, f32::INFINITY, true)),
                "{what}: ray {k}"
            );
            assert_eq!(
                m.occluded(&r, 0.0, f32::INFINITY),
                m.occluded_binary(&r, 0.0, f32::INFINITY)
            );
        }
    }
    let empty = mesh(&[]);
    assert_eq!(empty.depth(), 0);
    let r = Ray {
        o: Vec3::ZERO,
        d: Vec3::X,
    };
    assert!(empty.intersect(&r, 0.0, f32::INFINITY).is_none());
    assert!(!empty.occluded(&r, 0.0, f32::INFINITY));
}

/// Checks `m` against each of its triangles alone on `rays` random rays aimed into its bounds
/// (half at points on its triangles, a third axis-aligned), with the range (t_min, t_max) varied.
fn check_against_brute_force(what: &str, m: &TriMesh, rays: u32, seed: u32) {
    let singles: Vec<TriMesh> = m
        .triangles
        .iter()
        .map(|t| {
            TriMesh::new(
                t.map(|i| m.positions[i as usize]).to_vec(),
                t.map(|i| m.normals[i as usize]).to_vec(),
                Vec::new(),
                vec![[0, 1, 2]],
            )
        })
        .collect();
    let (lo, hi) = m.bounds();
    let (c, ext) = (0.5 * (lo + hi), (hi - lo).max(Vec3::splat(1e-3)));
    let (mut hits, mut ties) = (0, 0);
    for k in 0..rays {
        let s = seed + 4 * k;
        // Half the rays aim at a point on a triangle, half at a point of the bounds.
        let target = if k % 2 == 0 {
            lo + rand3(s) * (hi - lo)
        } else {
            let [a, b, c] =
                m.triangles[k as usize / 2 % m.triangles.len()].map(|i| m.positions[i as usize]);
            let (u, v) = (rand(s + 5), rand(s + 6));
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            a + u * (b - a) + v * (c - a)
        };
        let (o, d) = if k % 3 == 0 {
            let axis = (k / 3 % 3) as usize;
            let mut d = Vec3::ZERO;
            d[axis] = if rand(s + 7) < 0.5 { -1.0 } else { 1.0 };
            (target - 2.0 * ext.max_element() * d, d)
        } else {
            let o = c + (rand3(s + 1) * 2.0 - 1.0) * 2.0 * ext;
            (o, (target - o).normalize())
        };
        let r = Ray { o, d };
        let (t_min, t_max) = match k % 4 {
            0 => (1e-4, f32::INFINITY),
            1 => (0.0, 3.0 * ext.max_element() * rand(s + 2)),
            2 => (2.0 * ext.max_element() * rand(s + 2), f32::INFINITY),
            _ => (1e-4, 2.0 * ext.max_element()),
        };
        let all: Vec<(f32, Vec3)> = singles
            .iter()
            .filter_map(|t| t.intersect(&r, t_min, t_max).map(|h| (h.0, h.1)))
            .collect();
        let want = all.iter().map(|h| h.0).min_by(f32::total_cmp);
        let got = m.intersect(&r, t_min, t_max);
        assert_eq!(got.map(|h| h.0), want, "{what}: ray {k} {r:?}");
        assert_eq!(
            m.occluded(&r, t_min, t_max),
            want.is_some(),
            "{what}: ray {k} occluded"
        );
        if let (Some(g), Some(t)) = (got, want) {
            hits += 1;
            let at_t: Vec<Vec3> = all.iter().filter(|h| h.0 == t).map(|h| h.1).collect();
            if at_t.len() == 1 {
                assert_eq!(g.1, at_t[0], "{what}: ray {k}: another triangle's normal");
            } else {
                ties += 1;
                assert!(
                    at_t.contains(&g.1),
                    "{what}: ray {k}: not one of the nearest"
                );
            }
        }
    }
    eprintln!("{what}: {hits} of {rays} rays hit, {ties} at tied nearest t");
    assert!(hits > rays / 4, "{what}: too few rays hit to test anything");
}

#[test]
fn nearest_hits_and_shadow_rays_are_the_brute_force_ones() {
    let face = fastbrdf_render::mesh::face();
    check_against_brute_force("face", &face, 1500, 1);
    check_against_brute_force("soup", &mesh(&soup(2000, 17)), 600, 2);
    check_against_brute_force("coincident", &mesh(&vec![FEW[2]; 300]), 300, 3);
    let stacked: Vec<[Vec3; 3]> = (0..1200).map(|i| FEW[i % 3]).collect();
    check_against_brute_force("stacked copies", &mesh(&stacked), 600, 4);
    check_against_brute_force("strip", &mesh(&strip(1000)), 600, 5);
    check_against_brute_force("nested", &mesh(&nested(40, 20)), 600, 6);
    check_against_brute_force("one triangle", &mesh(&[FEW[1]]), 300, 7);
    check_against_brute_force("two triangles", &mesh(&FEW[..2]), 300, 8);
    check_against_brute_force("three triangles", &mesh(&FEW), 300, 9);
}

/// The CPU's 4-wide BVH (`hit`, `occluded`) against the binary tree it is collapsed from
/// (`hit_binary`, `occluded_binary`): the same t, normal and uv to the bit, on meshes whose
/// 4-wide nodes have 1 to 4 children (1 to 9 triangles, whose leaves hold 1 to 4) and on the
/// larger ones above, rays as in `check_against_brute_force` plus rays from inside.
#[test]
fn the_4_wide_bvh_finds_the_binary_trees_hits_to_the_bit() {
    let mut cases: Vec<(String, TriMesh)> = (1..=9)
        .map(|n| (format!("{n} random"), mesh(&soup(n, 100 * n))))
        .collect();
    cases.push(("face".into(), fastbrdf_render::mesh::face()));
    cases.push(("soup".into(), mesh(&soup(3000, 11))));
    cases.push(("strip".into(), mesh(&strip(700))));
    cases.push(("nested".into(), mesh(&nested(30, 7))));
    let stacked: Vec<[Vec3; 3]> = (0..500).map(|i| FEW[i % 3]).collect();
    cases.push(("stacked".into(), mesh(&stacked)));
    for (what, m) in &cases {
        let (lo, hi) = m.bounds();
        let ext = (hi - lo).max(Vec3::splat(1e-3));
        let mut hits = 0;
        for k in 0..2000u32 {
            let o = lo + (rand3(7 * k) * 3.0 - 1.0) * ext;
            let d = if k % 5 == 0 {
                let mut d = Vec3::ZERO;
                d[(k / 5 % 3) as usize] = if k % 2 == 0 { 1.0 } else { -1.0 };
                d
            } else {
                (lo + rand3(7 * k + 3) * ext - o).normalize()
            };
            let r = Ray { o, d };
            let (t_min, t_max) = match k % 3 {
                0 => (1e-4, f32::INFINITY),
                1 => (0.0, ext.max_element() * rand(7 * k + 6) * 2.0),
                _ => (ext.max_element() * rand(7 * k + 6), f32::INFINITY),
            };
            let want = m.hit_binary(&r, t_min, t_max, true);
            let got = m.hit(&r, t_min, t_max, true);
            let bits = |h: Option<(f32, Vec3, Vec2)>| {
                h.map(|(t, n, uv)| {
                    (
                        t.to_bits(),
                        n.to_array().map(f32::to_bits),
                        uv.to_array().map(f32::to_bits),
                    )
                })
            };
            assert_eq!(bits(got), bits(want), "{what}: ray {k} {r:?}");
            assert_eq!(
                m.occluded(&r, t_min, t_max),
                m.occluded_binary(&r, t_min, t_max),
                "{what}: ray {k} occluded"
            );
            hits += usize::from(got.is_some());
        }
        eprintln!("{what}: {hits} of 2000 rays hit");
        assert!(hits > 100, "{what}: too few rays hit to test anything");
    }
}

/// Nearest hits through a stack of coincident and overlapping triangles: the brute-force
/// answer (every triangle of a stack is hit at the same t).
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
        assert_eq!(m.occluded(&r, 1e-4, f32::INFINITY), want.is_some());
    }
}
