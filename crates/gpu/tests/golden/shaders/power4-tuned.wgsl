// fastbrdf 0.1.0 (lobe): power4-tuned
// Made by: fastbrdf shader --model power4-tuned --lang wgsl
//
// Formula: max(0, 1 + s(n)(c - 1))^4, s(n) = (n/4) R4(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power4-tuned vs pow: max abs error (relative to the peak) <= 0.117 over n in [1, 100000], whole domain
//   power4-tuned vs pow: max abs error (relative to the peak) <= 0.0333 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_power4_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

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

/// power4-tuned: max(0, 1 + s(n)(c - 1))^4, s(n) = (n/4) R4(1/n)
/// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs). Instance: n = 20.
fn fb_power4_tuned(c: f32) -> f32 {
    return fb_lobe_power4(c, 4.3693843f);
}
