// fastbrdf 0.1.0 (distribution): beckmann-power8
// Made by: fastbrdf shader --model beckmann-power8 --lang wgsl
//
// Formula: max(0, 1 + ((2/m^2 - 4)/8)(cos theta_h - 1))^8 / (4 m^2)
// Source: seed 000 (D4, D8, D16); Lyon 1993
// Note: f32: 4.6e-6 (power4; check --full, alpha down to 0.005)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   beckmann-power8 vs beckmann-ct: max rel error <= 0.447 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   beckmann-power8 vs beckmann-ct: max rel error <= 2.55 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   beckmann-power8 vs beckmann-ct: max rel error <= 0.447 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   beckmann-power8 vs beckmann-ct: max rel error <= 2.55 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 8e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_beckmann_power8(cos_h) with cos_h = n.h; returns f32.

/// Cosines below this give zero in distributions and BRDFs: 2^-20, exact in f32 and f64
/// (Rust twin: fastbrdf::vec3::COS_MIN).
const FB_COS_MIN: f32 = 9.5367431640625e-7;

/// x^4, x^8 and x^16 by repeated squaring (twin: ops::pow2k).
fn fb_pow4(x: f32) -> f32 {
    let x2 = x * x;
    return x2 * x2;
}

fn fb_pow8(x: f32) -> f32 {
    let x4 = fb_pow4(x);
    return x4 * x4;
}

fn fb_d_beckmann_power8(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow8(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}

/// beckmann-power8: max(0, 1 + ((2/m^2 - 4)/8)(cos theta_h - 1))^8 / (4 m^2)
/// Source: seed 000 (D4, D8, D16); Lyon 1993. Instance: alpha = 0.3.
fn fb_beckmann_power8(cos_h: f32) -> f32 {
    let cc = min(cos_h, 1.0);
    let d = fb_d_beckmann_power8(cc, (1.0 - cc) * (1.0 + cc), 2.2777777f, 2.7777777f);
    return select(0.0, d, cos_h >= FB_COS_MIN);
}
