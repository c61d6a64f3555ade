// fastbrdf 0.1.0 (lobe): flog-normalized
// Made by: fastbrdf shader --model flog-normalized --lang hlsl
//
// Formula: coef(n) flog(c), coef(n) = 0.197 (n + 1.24) + 0.068 / (0.64 + n)
// Source: seed 001, section III (coef fitted with TuringBot)
// Note: no clamp: a normalised lobe exceeds 1 near the peak for n > ~3; f32: coef(n) (~0.2 n) times the rounding of flog near its zero, where the value is ~1 and the peak coef(n): 1.5e-4 at n = 10000, 1.55e-3 at n = 1e5 (8e-8 of the peak)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 2e-3 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_flog_normalized(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_log2_(float x)
{
    float t = ((x - 1.0) / (x + 1.0));
    float t2_ = (t * t);
    float s = (t * (2.0 + (t2_ * (0.6666667 + (t2_ * (0.4 + (t2_ * (0.2857143 + (t2_ * (0.22222222 + (t2_ * (0.18181819 + (t2_ * 0.15384614)))))))))))));
    return ((x >= 0.5) ? (s * 1.442695) : log2(x));
}

float fb_lobe_flog(float c_1, float n, float coef, bool clamp_to_one)
{
    float v = (float)0;

    const float _e4 = fb_clamp01_(c_1);
    const float _e7 = fb_log2_(max(_e4, 1e-30));
    float f = (1.0 - (0.5 * log2((1.0 - (n * _e7)))));
    v = max((coef * f), 0.0);
    if (clamp_to_one) {
        float _e20 = v;
        v = min(_e20, 1.0);
    }
    float _e23 = v;
    return ((_e4 > 0.0) ? _e23 : 0.0);
}

float fb_flog_normalized(float c_2)
{
    const float _e4 = fb_lobe_flog(c_2, 20.0, 4.1875744, false);
    return _e4;
}
