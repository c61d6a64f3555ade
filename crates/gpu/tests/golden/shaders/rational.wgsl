// fastbrdf 0.1.0 (lobe): rational
// Made by: fastbrdf shader --model rational --lang wgsl
//
// Formula: c / (a - b c), a = 2 n 0.5^(1/n), b = 2n - 2
// Source: seed 003 (fall-off zone approximation g)
// Note: denominator evaluated as 2n(q - c) + 2c for f32 accuracy
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   rational vs pow: max rel error <= 0.0138 over n in [2, 1000], where 0.42 < reference / peak < 0.5
//   rational vs pow: max rel error <= 0.0138 over n in [2, 100000], where 0.42 < reference / peak < 0.5
//   rational vs pow: max rel error <= 0.0386 over n in [2, 1000], where 0.37 < reference / peak < 0.42
//   rational vs pow: max rel error <= 0.0387 over n in [2, 100000], where 0.37 < reference / peak < 0.42
//   rational vs pow: max rel error <= 0.146 over n in [2, 1000], where 0.27 < reference / peak < 0.37
//   rational vs pow: max rel error <= 0.146 over n in [2, 100000], where 0.27 < reference / peak < 0.37
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_rational(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
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

/// rational: c / (a - b c), a = 2 n 0.5^(1/n), b = 2n - 2
/// Source: seed 003 (fall-off zone approximation g). Instance: n = 20.
fn fb_rational(c: f32) -> f32 {
    return fb_lobe_rational(c, 1.5687428f, 59.612225f);
}
