// fastbrdf 0.1.0 (env): env-brdf-materialx
// Made by: fastbrdf shader --model env-brdf-materialx --lang glsl --runtime-params
//
// Formula: x = cos_v, y = alpha, P(x, y) = biquadratic (9 terms); scale = P_a / P_b, bias = P_c / P_d, clamped at 0
// Source: MaterialX mx_ggx_dir_albedo_analytic (libraries/pbrlib/genglsl/lib/mx_microfacet_specular.glsl, main at 0aa65a1)
// Note: fitted by MaterialX to Monte Carlo data of GGX with height-correlated Smith (alpha, not perceptual roughness, is its second input)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-materialx vs env-brdf: max abs error (relative to the peak) <= 0.0864 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_materialx(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

float fb_env_rational_poly(float x, float y, float c[9]) {
    float p0_ = ((y * ((y * c[5]) + c[2])) + c[0]);
    float p1_ = ((y * ((y * c[7]) + c[3])) + c[1]);
    float p2_ = ((y * ((y * c[8]) + c[6])) + c[4]);
    return ((x * ((x * p2_) + p1_)) + p0_);
}

float fb_env_rational(float cos_v, float alpha, float num[9], float den[9]) {
    float _e4 = fb_env_rational_poly(cos_v, alpha, num);
    float _e5 = fb_env_rational_poly(cos_v, alpha, den);
    return max((_e4 / _e5), 0.0);
}

float fb_env_brdf_materialx(float cos_v_1, float alpha_1) {
    float v = ((cos_v_1 > 0.0) ? min(cos_v_1, 1.0) : 0.0);
    float a = ((alpha_1 > 0.005) ? min(alpha_1, 1.0) : 0.005);
    float _e34 = fb_env_rational(v, a, float[9](0.10031, -0.63301, 9.74995, -2.02075, 29.38247, -8.24713, -26.5151, 19.98406, -5.41717), float[9](1.0, -1.76427, 8.26501, 11.5484, 28.99991, -7.50867, -36.16186, 15.85408, 33.4155));
    return _e34;
}
