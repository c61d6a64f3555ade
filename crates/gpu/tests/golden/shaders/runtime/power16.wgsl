// fastbrdf 0.1.0 (lobe): power16
// Made by: fastbrdf shader --model power16 --lang wgsl --runtime-params
//
// Formula: max(0, 1 + (n/16)(c - 1))^16
// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   power16 vs pow: max abs error (relative to the peak) <= 0.357 over n in [1, 100000], whole domain
//   power16 vs pow: max rel error <= 0.204 over n in [1, 100000], epicentre (reference >= half its peak)
//   power16 vs pow: max abs error (relative to the peak) <= 0.0173 over n in [16, 100000], whole domain
//   power16 vs pow: max rel error <= 0.0154 over n in [16, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_power16(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

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

fn fb_pow16(x: f32) -> f32 {
    let x8 = fb_pow8(x);
    return x8 * x8;
}

fn fb_lobe_power16(c: f32, s: f32) -> f32 {
    return fb_pow16(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

/// power16: max(0, 1 + (n/16)(c - 1))^16
/// Source: Lyon 1993, 'Phong shading reformulation for hardware renderer simplification'; seed 000. Instance: runtime parameters p_n; fixed: no parameters.
fn fb_power16(c: f32, p_n: f32) -> f32 {
    return fb_lobe_power16(c, (p_n / 16.0));
}
