// fastbrdf 0.1.0 (env): env-brdf-approx-tuned
// Made by: fastbrdf shader --model env-brdf-approx-tuned --lang glsl
//
// Formula: env-brdf-approx's form, its 11 constants refitted minimax against env-brdf
// Source: this project (fit_env_brdf example)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-approx-tuned vs env-brdf: max abs error (relative to the peak) <= 0.339 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_env_brdf_approx_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

float fb_env_approx(float cos_v, float alpha, float k[11], bool bias) {
    float r = sqrt(alpha);
    float px = ((r * k[0]) + k[4]);
    float py = ((r * k[1]) + k[5]);
    float a004_ = ((min((px * px), exp2((k[8] * cos_v))) * px) + py);
    float v = (bias ? ((k[10] * a004_) + ((r * k[3]) + k[7])) : ((k[9] * a004_) + ((r * k[2]) + k[6])));
    return max(v, 0.0);
}

float fb_env_brdf_approx_tuned(float cos_v_1, float alpha_1) {
    float v_1 = ((cos_v_1 > 0.0) ? min(cos_v_1, 1.0) : 0.0);
    float a = ((alpha_1 > 0.005) ? min(alpha_1, 1.0) : 0.005);
    float _e27 = fb_env_approx(v_1, a, float[11](-1.072325, -0.028393, -0.488609, 0.023184, 1.040579, 0.040344, 1.129695, -0.038556, -9.478977, -0.965804, 1.019101), false);
    return _e27;
}
