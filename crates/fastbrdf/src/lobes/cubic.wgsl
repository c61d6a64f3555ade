// WGSL twin of lobes/cubic.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// cubic and cubic3 (seed 003): the clipped cubic in Newton form in x = c - 1,
/// p = 1 + x (d1 + (x - x1)(d2 + (x - x2) d3)), 0 below `cut` (its local minimum) and where
/// negative. Coefficients: fastbrdf::lobes::cubic::CubicShape (f64). Cost: 3 mul, 4 add.
fn fb_lobe_cubic(c: f32, d1: f32, d2: f32, d3: f32, x1: f32, x2: f32, cut: f32) -> f32 {
    let cc = fb_clamp01(c);
    // In y = 1 - c = -x: p = 1 - y (d1 - (y + x1)(d2 - (y + x2) d3)). No `1 + t (c - 1)`
    // shape for a compiler to take for a lerp (Mesa lowers those to (1 - t) + t c, which
    // cancels when t ~ n), and exactly 1 at c = 1 whatever it reassociates.
    let y = 1.0 - cc;
    let p = 1.0 - y * (d1 - (y + x1) * (d2 - (y + x2) * d3));
    return select(max(p, 0.0), 0.0, cc < cut);
}
