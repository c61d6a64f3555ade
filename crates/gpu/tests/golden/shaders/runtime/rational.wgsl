// fastbrdf 0.1.0 (lobe): rational
// Made by: fastbrdf shader --model rational --lang wgsl --runtime-params
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
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_rational(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

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

/// ln 0.5, the level of cubic, rational and cubic-rational (seed 003).
const FB_RT_LN_HALF: f32 = -0.6931471805599453;

/// exp(x) - 1 without the cancellation of exp(x) - 1 near 0: Taylor to x^9 for |x| < 0.5
/// (truncation below 6e-10 relative), exp(x) - 1 beyond (|result| > 0.39: no cancellation).
fn fb_rt_expm1(x: f32) -> f32 {
    let s = x * (1.0 + x * (0.5 + x * (0.16666667 + x * (0.041666668 + x * (0.008333334
        + x * (0.0013888889 + x * (0.0001984127 + x * (0.000024801587
        + x * 0.0000027557319))))))));
    return select(exp(x) - 1.0, s, abs(x) < 0.5);
}

/// (peak, g) of seed 003's rational at level = q^n, xq = q - 1 (see fb_lobe_rational):
/// d0 = 1 + n xq, peak = level / d0, g = (n - 1) / d0.
fn fb_rt_rational_coefs(n: f32, level: f32, xq: f32) -> vec2<f32> {
    let d0 = 1.0 + n * xq;
    return vec2<f32>(level / d0, (n - 1.0) / d0);
}

/// rational (seed 003) with a runtime n: level 0.5.
fn fb_rt_rational(c: f32, n: f32) -> f32 {
    let r = fb_rt_rational_coefs(n, 0.5, fb_rt_expm1(FB_RT_LN_HALF / n));
    return fb_lobe_rational(c, r.x, r.y);
}

/// rational: c / (a - b c), a = 2 n 0.5^(1/n), b = 2n - 2
/// Source: seed 003 (fall-off zone approximation g). Instance: runtime parameters p_n; fixed: no parameters.
fn fb_rational(c: f32, p_n: f32) -> f32 {
    return fb_rt_rational(c, p_n);
}
