use super::*;

/// A 64 x 32 test map of grey texels spread over four decades, with every fifth row
/// black (empty rows of the sampling tables), drawn by `Rng::new(id, pass)`.
pub(crate) fn rough_map(id: u32, pass: u32) -> EnvMap {
    let mut rng = Rng::new(id, pass);
    let texels = (0..64 * 32)
        .map(|i| {
            let x = rng.uniform();
            if i / 64 % 5 == 0 {
                Vec3::ZERO
            } else {
                Vec3::splat(x * x * x * 100.0)
            }
        })
        .collect();
    EnvMap::from_texels(64, 32, texels).unwrap()
}

#[test]
fn directions_and_map_positions_invert() {
    for &(u, v) in &[(0.1f32, 0.2f32), (0.5, 0.5), (0.9, 0.8), (0.3, 0.05)] {
        let (d, _) = uv_to_dir(u, v);
        let (u2, v2) = dir_to_uv(d);
        assert!((u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5, "{u},{v}");
    }
    assert!((uv_to_dir(0.5, 0.5).0 - Vec3::NEG_Z).length() < 1e-6);
    assert!((uv_to_dir(0.5, 0.0).0 - Vec3::Y).length() < 1e-6);
}

/// The density integrates to 1 over the sphere and matches what `sample` returns.
#[test]
fn the_sampling_density_is_normalised_and_consistent() {
    let map = EnvMap::sky();
    let n = 400;
    let sum: f64 = sphere_grid(n).map(|(d, dw)| map.pdf(d) as f64 * dw).sum();
    assert!((sum - 1.0).abs() < 0.02, "{sum}");
    let mut rng = Rng::new(7, 0);
    for _ in 0..1000 {
        let (d, l, p) = map.sample(rng.uniform(), rng.uniform());
        if p > 0.0 {
            assert!((map.pdf(d) - p).abs() <= 1e-3 * p, "{} vs {p}", map.pdf(d));
            assert_eq!(map.radiance(d), l);
        }
    }
}

/// The centres of a 2n x n grid over the map and their solid angles.
fn sphere_grid(n: usize) -> impl Iterator<Item = (Vec3, f64)> {
    (0..n).flat_map(move |i| {
        (0..2 * n).map(move |j| {
            let (u, v) = (
                (j as f32 + 0.5) / (2 * n) as f32,
                (i as f32 + 0.5) / n as f32,
            );
            let (d, st) = uv_to_dir(u, v);
            (
                d,
                ((2.0 * PI / (2 * n) as f32) * (PI / n as f32) * st) as f64,
            )
        })
    })
}

/// The sky's bright part is its sun: 122 texels, 39% of the weight, in a cone of about
/// 2.3 degrees about `SUN_DIR`. The light strategies' density integrates to 1 over the
/// bright texels and to 1 over the rest; `sample_bright` and `sample_rest` return it; the
/// bright draws fall on each texel in proportion to its weight (chi-square, 121 degrees of
/// freedom), the rest's on 16 x 16 blocks of texels in proportion to their weight without
/// the sun (chi-square) and never on a bright texel; a surface `bright_faces` turns away
/// sees no bright draw. Maps without a compact bright part, and `without_bright`, have
/// none, and draw their rest from the whole map.
#[test]
fn the_bright_strategy_is_the_sun_and_its_density_is_consistent() {
    let map = EnvMap::sky();
    let (count, share) = map.bright().expect("the sky has a sun");
    assert_eq!(count, 122);
    assert!((share - 0.390).abs() < 0.005, "{share}");
    let b = map.bright.as_ref().unwrap();
    assert!(b.axis.dot(Vec3::from(SUN_DIR).normalize()) > 0.9999);
    assert!(
        b.below < -(2.0f32.to_radians().sin()) && b.below > -0.06,
        "{}",
        b.below
    );
    // The density over the sphere, on a grid fine enough for the 2-degree disc.
    let (mut bright, mut rest) = (0.0f64, 0.0f64);
    for (d, dw) in sphere_grid(3000) {
        let (rgb, pdf) = map.lookup(d);
        let part = if lum(rgb) > b.threshold {
            &mut bright
        } else {
            &mut rest
        };
        *part += map.light_pdf(rgb, pdf) as f64 * dw;
    }
    assert!((bright - 1.0).abs() < 0.01, "{bright}");
    assert!((rest - 1.0).abs() < 0.002, "{rest}");
    let mut rng = Rng::new(3, 1);
    let mut hits = vec![0u32; map.cells.len()];
    let (draws, mut edge) = (200_000, 0);
    for _ in 0..draws {
        let (d, rgb, pdf) = map.sample_bright(rng.uniform(), rng.uniform()).unwrap();
        assert!(pdf > 0.0 && lum(rgb) > b.threshold);
        let (l, p) = map.lookup(d);
        // A draw at a texel's very edge may look up its neighbour (f32 rounding).
        if l != rgb {
            edge += 1;
            continue;
        }
        assert!((map.light_pdf(l, p) - pdf).abs() <= 1e-3 * pdf, "{pdf}");
        hits[map.texel_of(d).0] += 1;
    }
    assert!(edge < draws / 1000, "{edge} draws looked up another texel");
    let chi2: f64 = b
        .texels
        .iter()
        .zip(b.cdf.windows(2))
        .map(|(&i, c)| {
            let want = (c[1] - c[0]) as f64 * (draws - edge) as f64;
            (hits[i as usize] as f64 - want).powi(2) / want
        })
        .sum();
    assert!(
        chi2 < 121.0 + 6.0 * (2.0f64 * 121.0).sqrt(),
        "chi-square {chi2}"
    );
    assert_eq!(
        hits.iter().map(|&h| h as usize).sum::<usize>(),
        draws - edge
    );
    // The rest: by blocks of 16 x 16 texels, blocks expecting fewer than 10 draws pooled.
    let (w, bs) = (map.width as usize, 16);
    let blocks = |i: usize| (i / w / bs) * (w / bs) + (i % w) / bs;
    let mut want = vec![0.0f64; map.cells.len() / (bs * bs)];
    for (i, c) in map.cells.iter().enumerate() {
        if lum(c.rgb) <= b.threshold {
            want[blocks(i)] += c.mass as f64 * b.rest_ratio as f64;
        }
    }
    let (draws, mut got) = (400_000, vec![0u32; want.len()]);
    for _ in 0..draws {
        let (d, rgb, pdf) = map.sample_rest(rng.uniform(), rng.uniform());
        assert!(lum(rgb) <= b.threshold, "a rest draw on the sun");
        // Near the poles, sin theta from the direction's y loses digits to cancellation.
        let (l, p) = map.lookup(d);
        if l == rgb && pdf > 0.0 && d.y.abs() < 0.99 {
            assert!(
                (map.light_pdf(l, p) - pdf).abs() <= 1e-3 * pdf,
                "{pdf} at {d}"
            );
        }
        got[blocks(map.texel_of(d).0)] += 1;
    }
    let (mut chi2, mut bins, mut pool) = (0.0, 0, (0.0, 0.0));
    for (&p, &g) in want.iter().zip(&got) {
        let e = p * draws as f64;
        if e < 10.0 {
            pool = (pool.0 + e, pool.1 + g as f64);
        } else {
            chi2 += (g as f64 - e).powi(2) / e;
            bins += 1;
        }
    }
    chi2 += (pool.1 - pool.0).powi(2) / pool.0.max(1e-9);
    let df = bins as f64;
    assert!(
        chi2 < df + 6.0 * (2.0 * df).sqrt(),
        "chi-square {chi2} over {bins} blocks"
    );
    // Normals turned away: no draw above their horizon; normals facing: the sun's centre.
    for _ in 0..2000 {
        let z = 2.0 * rng.uniform() - 1.0;
        let phi = 2.0 * PI * rng.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let nrm = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        if !map.bright_faces(nrm) {
            for _ in 0..20 {
                let (d, ..) = map.sample_bright(rng.uniform(), rng.uniform()).unwrap();
                assert!(nrm.dot(d) <= 0.0, "{nrm} sees {d}");
            }
        }
    }
    assert!(map.bright_faces(Vec3::from(SUN_DIR).normalize()));
    assert!(!map.bright_faces(-Vec3::from(SUN_DIR).normalize()));
    // Without a bright part the rest is the whole map.
    let whole = EnvMap::sky().without_bright();
    for m in [&whole, &EnvMap::constant(Vec3::ONE), &rough_map(1, 2)] {
        assert!(m.bright().is_none());
        for _ in 0..100 {
            let (u1, u2) = (rng.uniform(), rng.uniform());
            assert_eq!(m.sample_rest(u1, u2), m.sample(u1, u2));
        }
    }
    assert_eq!(whole.tables(), map.tables());
    assert_eq!(whole.conditional.len(), whole.tables().1.len());
    // A map that is all its bright texel has no rest: drawn whole.
    let mut lone = vec![Vec3::ZERO; 32 * 16];
    lone[5 * 32 + 7] = Vec3::splat(100.0);
    let lone = EnvMap::from_texels(32, 16, lone).unwrap();
    assert!(lone.bright().is_none());
    assert!(lone.sample_rest(0.4, 0.6).2.is_finite());
}

/// Toy MIS: integral of x^2 over [0, 1] (1/3) from a uniform strategy and a linear one
/// (density 2x), one sample of each per estimate, by the balance and power heuristics:
/// the weights sum to 1 and the estimate is unbiased.
#[test]
fn mis_heuristics_combine_two_strategies_without_bias() {
    for h in [balance_heuristic, power_heuristic] {
        let mut rng = Rng::new(1, 2);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let xa = rng.uniform();
            let xb = rng.uniform().sqrt();
            let (pa_a, pb_a) = (1.0, 2.0 * xa);
            let (pa_b, pb_b) = (1.0, 2.0 * xb);
            assert!((h(pa_a, pb_a) + h(pb_a, pa_a) - 1.0).abs() < 1e-6);
            let fa = xa * xa * h(pa_a, pb_a) / pa_a;
            let fb = if pb_b > 0.0 {
                xb * xb * h(pb_b, pa_b) / pb_b
            } else {
                0.0
            };
            sum += (fa + fb) as f64;
        }
        let est = sum / n as f64;
        assert!((est - 1.0 / 3.0).abs() < 3e-3, "{est}");
    }
    // Narrow lobes' densities: no overflow (squares of 1e20 and 1e30 are infinite in f32).
    assert_eq!(power_heuristic(1e30, 1e20), 1.0);
    assert!(power_heuristic(1e20, 1e30) < 1e-19);
    assert!((power_heuristic(3e25, 3e25) - 0.5).abs() < 1e-7);
    assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    // The weight over the density is the heuristic's weight over the density, without
    // its overflow.
    for (p, q) in [(1.0f32, 2.0), (0.5, 0.0), (3.0, 1e-3)] {
        let w = power_weight_over_pdf(p, q);
        assert!((w * p - power_heuristic(p, q)).abs() < 1e-6, "{p} {q}");
    }
    assert!((power_weight_over_pdf(1e30, 1e20) * 1e30 - 1.0).abs() < 1e-6);
    assert_eq!(power_weight_over_pdf(0.0, 1.0), 0.0);
    assert_eq!(power_weight_over_pdf(1e-30, 1e30), 0.0);
}

/// The guided search finds the index a search of the whole table finds, to the bit, on
/// the sky (a tiny bright sun: long flat stretches and a steep step), a random map and a
/// map with black rows, for uniform numbers everywhere including the ends.
#[test]
fn the_guide_tables_change_no_sample() {
    let plain = |cdf: &[f32], u: f32| {
        let n = cdf.len() - 1;
        let u = u.clamp(0.0, 1.0 - f32::EPSILON) * cdf[n];
        cdf.partition_point(|&c| c <= u)
    };
    let mut rng = Rng::new(3, 2);
    for map in [EnvMap::sky(), rough_map(3, 1)] {
        let w = map.width as usize;
        let mut tables = vec![(&map.marginal[..], &map.marginal_guide[..])];
        let g = row_guide(w) + 1;
        for r in (0..map.height as usize).step_by(7) {
            tables.push((
                &map.conditional[r * (w + 1)..(r + 1) * (w + 1)],
                &map.conditional_guide[r * g..(r + 1) * g],
            ));
        }
        for (cdf, guide) in tables {
            let mut us: Vec<f32> = (0..20_000).map(|_| rng.uniform()).collect();
            us.extend([0.0, 1.0 - f32::EPSILON, 0.5, 1e-9]);
            us.extend(cdf.iter().copied()); // bin edges
            for u in us {
                let n = cdf.len() - 1;
                let uu = u.clamp(0.0, 1.0 - f32::EPSILON) * cdf[n];
                assert_eq!(search(cdf, guide, uu), plain(cdf, u), "u = {u}");
            }
        }
    }
}

#[test]
fn bad_maps_are_refused() {
    assert!(
        EnvMap::from_texels(4, 4, vec![Vec3::ONE; 16])
            .unwrap_err()
            .contains("2:1")
    );
    let mut t = vec![Vec3::ONE; 8];
    t[5] = Vec3::new(0.0, f32::NAN, 0.0);
    assert!(
        EnvMap::from_texels(4, 2, t.clone())
            .unwrap_err()
            .contains("NaN")
    );
    t[5] = Vec3::new(-1.0, 0.0, 0.0);
    assert!(
        EnvMap::from_texels(4, 2, t.clone())
            .unwrap_err()
            .contains("negative")
    );
    t[5] = Vec3::new(f32::INFINITY, 0.0, 0.0);
    assert!(
        EnvMap::from_texels(4, 2, t.clone())
            .unwrap_err()
            .contains("infinite")
    );
    // Finite in f32 but no radiance a map can hold (issue 27: 3e38 overflowed the render,
    // whose error blamed the model); the bound itself is accepted.
    t[5] = Vec3::new(1.0, 3e38, 1.0);
    let e = EnvMap::from_texels(4, 2, t.clone()).unwrap_err();
    assert!(
        e.contains("implausibly bright") && e.contains("(1, 1)"),
        "{e}"
    );
    t[5] = Vec3::splat(MAX_ENV_RADIANCE);
    assert!(EnvMap::from_texels(4, 2, t).is_ok());
    assert!(check_env_size(16384, 8192).unwrap_err().contains("at most"));
    // A black map still samples (sin theta alone).
    let m = EnvMap::from_texels(4, 2, vec![Vec3::ZERO; 8]).unwrap();
    assert!(m.sample(0.3, 0.6).2 > 0.0);
}
