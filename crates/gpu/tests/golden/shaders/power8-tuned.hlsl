// fastbrdf 0.1.0 (lobe): power8-tuned
// Made by: fastbrdf shader --model power8-tuned --lang hlsl
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
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_power8_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_pow4_(float x)
{
    float x2_ = (x * x);
    return (x2_ * x2_);
}

float fb_pow8_(float x_1)
{
    const float _e1 = fb_pow4_(x_1);
    return (_e1 * _e1);
}

float fb_lobe_power8_(float c_1, float s)
{
    const float _e2 = fb_clamp01_(c_1);
    const float _e10 = fb_pow8_(max((1.0 - (s * (1.0 - _e2))), 0.0));
    return _e10;
}

float fb_power8_tuned(float c_2)
{
    const float _e2 = fb_lobe_power8_(c_2, 2.3775923);
    return _e2;
}
