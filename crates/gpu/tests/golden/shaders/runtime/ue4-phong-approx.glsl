// fastbrdf 0.1.0 (lobe): ue4-phong-approx
// Made by: fastbrdf shader --model ue4-phong-approx --lang glsl --runtime-params
//
// Formula: exp2(1.4427 (n + 0.775)(c - 1))
// Source: Unreal Engine 4 mobile shading (PhongApprox), Karis 2014
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   ue4-phong-approx vs pow: max abs error (relative to the peak) <= 0.17 over n in [1, 100000], whole domain
//   ue4-phong-approx vs pow: max abs error (relative to the peak) <= 0.0097 over n in [16, 100000], whole domain
//   ue4-phong-approx vs pow: max rel error <= 0.183 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_ue4_phong_approx(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_exp2_(float c_1, float k) {
    float _e2 = fb_clamp01_(c_1);
    return exp2((k * (_e2 - 1.0)));
}

float fb_ue4_phong_approx(float c_2, float p_n) {
    float _e6 = fb_lobe_exp2_(c_2, (1.4427 * (p_n + 0.775)));
    return _e6;
}
