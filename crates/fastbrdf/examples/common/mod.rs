//! What the timing examples share (`mod common;` in each): the median of timed rounds and the
//! direction pairs of `fastbrdf::accuracy::direction_pairs` as six f32 columns.

/// The median of `v` (the upper one of an even count).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// `direction_pairs(n, seed)` as structure of arrays: `wi` x, y, z, `wo` x, y, z in f32.
pub fn pair_columns(n: usize, seed: u64) -> Vec<Vec<f32>> {
    let pairs = fastbrdf::accuracy::direction_pairs(n, seed);
    (0..6)
        .map(|k| {
            pairs
                .iter()
                .map(|(a, b)| if k < 3 { a[k] } else { b[k - 3] } as f32)
                .collect()
        })
        .collect()
}
