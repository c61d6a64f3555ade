// fastbrdf 0.1.0 (lobe): cubic-rational-tuned
// Made by: fastbrdf shader --model cubic-rational-tuned --lang wgsl
//
// Formula: seed 003's cubic above c^n = Q(n), its rational below, Q(n) = Rq(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.283 over n in [1, 100000], whole domain
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.0415 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_cubic_rational_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

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

/// cubic-rational-tuned: seed 003's cubic above c^n = Q(n), its rational below, Q(n) = Rq(1/n)
/// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs). Instance: n = 20.
fn fb_cubic_rational_tuned(c: f32) -> f32 {
    return fb_lobe_cubic_rational(c, 10.0814085f, 74.83417f, 70.66397f, -0.08079728f, -0.08079728f, 0.8885781f, -0.30108127f, -30.846884f, 0.91920274f);
}
