// fastbrdf 0.1.0 (lobe): schlick-modified
// Made by: fastbrdf shader --model schlick-modified --lang hlsl --runtime-params
//
// Formula: 2 c / (1.25 (n - n c + 1.25 c)^2)
// Source: seed 001, its reference [15] (Romanyuk et al.)
// Note: implemented as printed in seed 001; its value at c = 1 is 1.024, not 1
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   schlick-modified vs pow: max abs error (relative to the peak) <= 0.133 over n in [1, 1000], whole domain
//   schlick-modified vs pow: max abs error (relative to the peak) <= 0.133 over n in [1, 100000], whole domain
// Precision: f32 on the CPU within 4e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_schlick_modified(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_schlick_modified(float c_1, float n)
{
    const float _e2 = fb_clamp01_(c_1);
    float d = ((n * (1.0 - _e2)) + (1.25 * _e2));
    return ((2.0 * _e2) / (1.25 * (d * d)));
}

float fb_schlick_modified(float c_2, float p_n)
{
    const float _e2 = fb_lobe_schlick_modified(c_2, p_n);
    return _e2;
}
