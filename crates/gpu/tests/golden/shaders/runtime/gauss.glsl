// fastbrdf 0.1.0 (lobe): gauss
// Made by: fastbrdf shader --model gauss --lang glsl --runtime-params
//
// Formula: exp(-n theta^2 / 2), theta = acos(c)
// Source: seed 001 (Gauss BRDF, its reference [10])
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   gauss vs pow: max abs error (relative to the peak) <= 0.292 over n in [1, 100000], whole domain
//   gauss vs pow: max rel error <= 0.156 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_gauss(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_acos(float x) {
    float p = (1.5707963 + (x * (-0.2145988 + (x * (0.08897899 + (x * (-0.050174303 + (x * (0.03089188 + (x * (-0.017088126 + (x * (0.00667009 + (x * -0.0012624911))))))))))))));
    return (sqrt(max((1.0 - x), 0.0)) * p);
}

float fb_lobe_gauss(float c_1, float half_n) {
    float _e2 = fb_clamp01_(c_1);
    float _e3 = fb_acos(_e2);
    return exp((-(half_n) * (_e3 * _e3)));
}

float fb_gauss(float c_2, float p_n) {
    float _e4 = fb_lobe_gauss(c_2, (0.5 * p_n));
    return _e4;
}
