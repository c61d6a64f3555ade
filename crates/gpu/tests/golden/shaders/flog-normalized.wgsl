// fastbrdf 0.1.0 (lobe): flog-normalized
// Made by: fastbrdf shader --model flog-normalized --lang wgsl
//
// Formula: coef(n) flog(c), coef(n) = 0.197 (n + 1.24) + 0.068 / (0.64 + n)
// Source: seed 001, section III (coef fitted with TuringBot)
// Note: no clamp: a normalised lobe exceeds 1 near the peak for n > ~3; f32: coef(n) (~0.2 n) times the rounding of flog near its zero, where the value is ~1 and the peak coef(n): 1.5e-4 at n = 10000, 1.55e-3 at n = 1e5 (8e-8 of the peak)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 2e-3 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_flog_normalized(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// log2(x) with a small relative error for x in [0.5, 1] too, where WGSL's built-in log2 is
/// only held to 2^-21 absolute (relative error unbounded as x -> 1): 2 atanh(t) / ln 2 with
/// t = (x - 1) / (x + 1) in [-1/3, 0], x - 1 exact (Sterbenz), series to t^13 (truncation
/// 5e-9 relative). Below 0.5 the built-in. The CPU kernels' log2 is 0.5 ulp (an f64 series).
fn fb_log2(x: f32) -> f32 {
    let t = (x - 1.0) / (x + 1.0);
    let t2 = t * t;
    let s = t * (2.0 + t2 * (0.6666667 + t2 * (0.4 + t2 * (0.2857143 + t2 * (0.22222222
        + t2 * (0.18181818 + t2 * 0.15384615))))));
    return select(log2(x), s * 1.442695, x >= 0.5);
}

/// flog family (seed 001): coef * (1 - log2(1 - n log2 c) / 2), clipped at 0, and at 1 when
/// clamp_to_one (the seed's GLSL). flog: coef = 1; flog-normalized: coef = 0.197 (n + 1.24) +
/// 0.068 / (0.64 + n). The inner log2 is fb_log2: near c = 1 the lobe's slope is ~n / ln 2
/// per unit of log2 c, so the built-in's absolute error would cost 9% at n = 10000.
fn fb_lobe_flog(c: f32, n: f32, coef: f32, clamp_to_one: bool) -> f32 {
    let x = fb_clamp01(c);
    let f = 1.0 - 0.5 * log2(1.0 - n * fb_log2(max(x, 1e-30)));
    var v = max(coef * f, 0.0);
    if clamp_to_one {
        v = min(v, 1.0);
    }
    return select(0.0, v, x > 0.0);
}

/// flog-normalized: coef(n) flog(c), coef(n) = 0.197 (n + 1.24) + 0.068 / (0.64 + n)
/// Source: seed 001, section III (coef fitted with TuringBot). Instance: n = 20.
fn fb_flog_normalized(c: f32) -> f32 {
    return fb_lobe_flog(c, 20.0f, 4.1875744f, false);
}
