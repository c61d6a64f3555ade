// fastbrdf 0.1.0 (lobe): power8-tuned
// Made by: fastbrdf shader --model power8-tuned --lang wgsl
//
// Formula: max(0, 1 + s(n)(c - 1))^8, s(n) = (n/8) R8(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power8-tuned vs pow: max abs error (relative to the peak) <= 0.131 over n in [1, 100000], whole domain
//   power8-tuned vs pow: max abs error (relative to the peak) <= 0.0162 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_power8_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

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

/// power8-tuned: max(0, 1 + s(n)(c - 1))^8, s(n) = (n/8) R8(1/n)
/// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs). Instance: n = 20.
fn fb_power8_tuned(c: f32) -> f32 {
    return fb_lobe_power8(c, 2.3775923f);
}
