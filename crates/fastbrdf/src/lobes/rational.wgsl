// WGSL twin of lobes/rational.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// rational (seed 003): level c / (n (xq - x) + c), x = c - 1, xq = level^(1/n) - 1, written
/// fold-proof as peak c / (1 + g y) with y = 1 - c (exact for c >= 0.5), d0 = 1 + n xq,
/// peak = level / d0 and g = (n - 1) / d0 (computed in f64, xq with expm1); level = 0.5 for
/// `rational`. The constant term is exactly 1 and the only other term multiplies y: a compiler
/// that expands g (1 - c) into g - g c and folds 1 + g (Mesa does, with literals) still gets
/// exactly 1 at c = 1 ((1 + g) - g is exact for g >= 1), where the seed's arrangement folded
/// into n xq + n, a constant of size n with a fraction: 3.4e-4 off at c = 1, n = 5000 (issue 11).
/// Cost: 2 mul, 2 add, 1 div.
fn fb_lobe_rational(c: f32, peak: f32, g: f32) -> f32 {
    let cc = fb_clamp01(c);
    let y = 1.0 - cc;
    return peak * cc / (1.0 + g * y);
}

/// cubic-rational (seed 003): the cubic above q = level^(1/n), the rational below.
fn fb_lobe_cubic_rational(c: f32, d1: f32, d2: f32, d3: f32, x1: f32, x2: f32, cut: f32,
                          peak: f32, g: f32, q: f32) -> f32 {
    let cc = fb_clamp01(c);
    let a = fb_lobe_cubic(cc, d1, d2, d3, x1, x2, cut);
    let b = fb_lobe_rational(cc, peak, g);
    return select(b, a, cc >= q);
}
