// fastbrdf 0.1.0 (lobe): power8-tuned
// Made by: fastbrdf shader --model power8-tuned --lang wgsl --runtime-params
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
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_power8_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

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
/// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs). Instance: runtime parameters p_n; fixed: no parameters.
fn fb_power8_tuned(c: f32, p_n: f32) -> f32 {
    return fb_lobe_power8(c, (select(p_n / 8.0 * (0.9199561781740374 + (1.0 / p_n) * (0.6097038399198138 + (1.0 / p_n) * (0.23314613228065026 + (1.0 / p_n) * (0.10535350267920722 + (1.0 / p_n) * -0.07112774182709858)))), 1.0, p_n == 8.0)));
}
