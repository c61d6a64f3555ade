// fastbrdf 0.1.0 (lobe): power8
// Made by: fastbrdf shader --model power8 --lang wgsl
//
// Formula: max(0, 1 + (n/8)(c - 1))^8
// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power8 vs pow: max abs error (relative to the peak) <= 0.344 over n in [1, 100000], whole domain
//   power8 vs pow: max rel error <= 0.194 over n in [1, 100000], epicentre (reference >= half its peak)
//   power8 vs pow: max abs error (relative to the peak) <= 0.0354 over n in [16, 100000], whole domain
//   power8 vs pow: max rel error <= 0.0314 over n in [16, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 5e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_power8(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// x^4, x^8 and x^16 by repeated squaring (twin: ops::pow2k).
fn fb_pow4(x: f32) -> f32 {
    let x2 = x * x;
    return x2 * x2;
}

fn fb_pow8(x: f32) -> f32 {
    let x4 = fb_pow4(x);
    return x4 * x4;
}

fn fb_lobe_power8(c: f32, s: f32) -> f32 {
    return fb_pow8(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

/// power8: max(0, 1 + (n/8)(c - 1))^8
/// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000. Instance: n = 20.
fn fb_power8(c: f32) -> f32 {
    return fb_lobe_power8(c, 2.5f);
}
