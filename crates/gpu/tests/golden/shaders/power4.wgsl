// fastbrdf 0.1.0 (lobe): power4
// Made by: fastbrdf shader --model power4 --lang wgsl
//
// Formula: max(0, 1 + (n/4)(c - 1))^4
// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power4 vs pow: max abs error (relative to the peak) <= 0.317 over n in [1, 100000], whole domain
//   power4 vs pow: max rel error <= 0.173 over n in [1, 100000], epicentre (reference >= half its peak)
//   power4 vs pow: max abs error (relative to the peak) <= 0.0738 over n in [16, 100000], whole domain
//   power4 vs pow: max rel error <= 0.0658 over n in [16, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 3e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_power4(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// x^4, x^8 and x^16 by repeated squaring (twin: ops::pow2k).
fn fb_pow4(x: f32) -> f32 {
    let x2 = x * x;
    return x2 * x2;
}

/// power4/8/16 (seed 000's (1 + x/g)^g): max(1 + s (c - 1), 0)^g with s = n / g (tuned: s
/// from a minimax fit, fastbrdf::lobes::tuned), written 1 - s (1 - c): not the lerp shape
/// `1 + t (c - 1)` (see the header), and exactly 1 at c = 1. Cost: 1 mul, 2 add, log2(g) mul.
fn fb_lobe_power4(c: f32, s: f32) -> f32 {
    return fb_pow4(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

/// power4: max(0, 1 + (n/4)(c - 1))^4
/// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000. Instance: n = 20.
fn fb_power4(c: f32) -> f32 {
    return fb_lobe_power4(c, 5.0f);
}
