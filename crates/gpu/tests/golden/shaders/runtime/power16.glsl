// fastbrdf 0.1.0 (lobe): power16
// Made by: fastbrdf shader --model power16 --lang glsl --runtime-params
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
// Entry: fb_power16_(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_pow4_(float x) {
    float x2_ = (x * x);
    return (x2_ * x2_);
}

float fb_pow8_(float x_1) {
    float _e1 = fb_pow4_(x_1);
    return (_e1 * _e1);
}

float fb_pow16_(float x_2) {
    float _e1 = fb_pow8_(x_2);
    return (_e1 * _e1);
}

float fb_lobe_power16_(float c_1, float s) {
    float _e2 = fb_clamp01_(c_1);
    float _e10 = fb_pow16_(max((1.0 - (s * (1.0 - _e2))), 0.0));
    return _e10;
}

float fb_power16_(float c_2, float p_n) {
    float _e4 = fb_lobe_power16_(c_2, (p_n / 16.0));
    return _e4;
}
