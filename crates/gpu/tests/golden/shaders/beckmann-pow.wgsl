// fastbrdf 0.1.0 (distribution): beckmann-pow
// Made by: fastbrdf shader --model beckmann-pow --lang wgsl
//
// Formula: cos^(2/m^2 - 4) theta_h / (4 m^2)
// Source: seed 000 ('one function' D)
// Note: unbounded as cos theta_h -> 0 for m > 1/sqrt(2) (negative exponent), by the seed's construction
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   beckmann-pow vs beckmann-ct: max rel error <= 0.403 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 4.65 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 0.403 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 4.65 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_beckmann_pow(cos_h) with cos_h = n.h; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

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

/// beckmann-pow (seed 000): scale cos^e, e = 2 / alpha^2 - 4 (one power instead of exp;
/// fb_powr, accurate near cos = 1 where e reaches 19996 at alpha = 0.01).
fn fb_d_beckmann_pow(c: f32, e: f32, scale: f32) -> f32 {
    return scale * fb_powr(c, e);
}

/// beckmann-pow: cos^(2/m^2 - 4) theta_h / (4 m^2)
/// Source: seed 000 ('one function' D). Instance: alpha = 0.3.
fn fb_beckmann_pow(cos_h: f32) -> f32 {
    let cc = min(cos_h, 1.0);
    let d = fb_d_beckmann_pow(cc, 18.222221f, 2.7777777f);
    return select(0.0, d, cos_h >= FB_COS_MIN);
}
