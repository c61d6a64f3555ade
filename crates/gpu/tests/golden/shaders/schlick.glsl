// fastbrdf 0.1.0 (lobe): schlick
// Made by: fastbrdf shader --model schlick --lang glsl
//
// Formula: c / (n - n c + c)
// Source: Schlick 1994, 'A fast alternative to Phong's specular model'; seeds 001, 003
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   schlick vs pow: max abs error (relative to the peak) <= 0.204 over n in [1, 1000], whole domain
//   schlick vs pow: max abs error (relative to the peak) <= 0.204 over n in [1, 100000], whole domain
//   schlick vs pow: max rel error <= 0.182 over n in [1, 1000], epicentre (reference >= half its peak)
//   schlick vs pow: max rel error <= 0.182 over n in [1, 100000], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_schlick(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_schlick(float c_1, float n) {
    float _e2 = fb_clamp01_(c_1);
    return (_e2 / ((n * (1.0 - _e2)) + _e2));
}

float fb_schlick(float c_2) {
    float _e2 = fb_lobe_schlick(c_2, 20.0);
    return _e2;
}
