// fastbrdf 0.1.0 (lobe): pow
// Made by: fastbrdf shader --model pow --lang wgsl
//
// Formula: c^n
// Source: Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_pow(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

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

/// x^y for x in [0, 1] (any finite y): exp2(y fb_log2(x)), and 0 at x = 0 (callers with
/// y < 0 cut x = 0 away). WGSL's pow is exp2(y log2(x))
/// with the built-in log2 (2^-21 absolute near 1), which a large y turns into about 2y ulp of
/// relative error near x = 1 (issue 11: twice the "n ulp" once documented, on real GPUs at
/// n = 5000..10000); fb_log2's relative error keeps y log2(x) to a few ulp, so the result is
/// within a few ulp of the exact power where it is not negligible. At x = 1, exactly 1.
fn fb_powr(x: f32, y: f32) -> f32 {
    return select(0.0, exp2(y * fb_log2(max(x, 1e-30))), x > 0.0);
}

/// pow: c^n, the Phong/Blinn-Phong reference (Phong 1975), as fb_powr (exp2 of n fb_log2(c),
/// not WGSL's pow, whose log2 near 1 cost about 2n ulp: 6.4e-4 at n = 10000 on lavapipe, and
/// issue 11 reported the same on real GPUs). Cost: 1 exp2, 1 log2 (fb_log2's branch below
/// 0.5, evaluated by the select), 1 div, 10 mul, 8 add.
fn fb_lobe_pow(c: f32, n: f32) -> f32 {
    return fb_powr(fb_clamp01(c), n);
}

/// pow: c^n
/// Source: Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003). Instance: n = 20.
fn fb_pow(c: f32) -> f32 {
    return fb_lobe_pow(c, 20.0f);
}
