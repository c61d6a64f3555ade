// fastbrdf 0.1.0 (distribution): beckmann-pow
// Made by: fastbrdf shader --model beckmann-pow --lang wgsl
//
// Formula: cos^(2/m^2 - 4) theta_h / (4 m^2)
// Source: seed 000 ('one function' D)
// Note: unbounded as cos theta_h -> 0 for m > 1/sqrt(2) (negative exponent), by the seed's construction
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.01, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   beckmann-pow vs beckmann-ct: max rel error <= 0.403 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 4.65 over alpha in [0.05, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_beckmann_pow(cos_h) with cos_h = n.h; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// beckmann-pow (seed 000): scale cos^e, e = 2 / alpha^2 - 4 (one power instead of exp).
fn fb_d_beckmann_pow(c: f32, e: f32, scale: f32) -> f32 {
    return scale * pow(c, e);
}

/// beckmann-pow: cos^(2/m^2 - 4) theta_h / (4 m^2)
/// Source: seed 000 ('one function' D). Instance: alpha = 0.3.
fn fb_beckmann_pow(cos_h: f32) -> f32 {
    let cc = min(cos_h, 1.0);
    let d = fb_d_beckmann_pow(cc, 18.222221f, 2.7777777f);
    return select(0.0, d, cos_h >= FB_COS_MIN);
}
