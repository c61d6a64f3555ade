// fastbrdf 0.1.0 (lobe): rational
// Made by: fastbrdf shader --model rational --lang hlsl
//
// Formula: c / (a - b c), a = 2 n 0.5^(1/n), b = 2n - 2
// Source: seed 003 (fall-off zone approximation g)
// Note: denominator evaluated as 2n(q - c) + 2c for f32 accuracy
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   rational vs pow: max rel error <= 0.0138 over n in [2, 1000], where 0.42 < reference / peak < 0.5
//   rational vs pow: max rel error <= 0.0138 over n in [2, 100000], where 0.42 < reference / peak < 0.5
//   rational vs pow: max rel error <= 0.0386 over n in [2, 1000], where 0.37 < reference / peak < 0.42
//   rational vs pow: max rel error <= 0.0387 over n in [2, 100000], where 0.37 < reference / peak < 0.42
//   rational vs pow: max rel error <= 0.146 over n in [2, 1000], where 0.27 < reference / peak < 0.37
//   rational vs pow: max rel error <= 0.146 over n in [2, 100000], where 0.27 < reference / peak < 0.37
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_rational(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_rational(float c_1, float peak, float g)
{
    const float _e3 = fb_clamp01_(c_1);
    float y = (1.0 - _e3);
    return ((peak * _e3) / (1.0 + (g * y)));
}

float fb_rational(float c_2)
{
    const float _e3 = fb_lobe_rational(c_2, 1.5687428, 59.612225);
    return _e3;
}
