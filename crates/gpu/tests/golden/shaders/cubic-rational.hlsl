// fastbrdf 0.1.0 (lobe): cubic-rational
// Made by: fastbrdf shader --model cubic-rational --lang hlsl
//
// Formula: cubic(c) for c >= 0.5^(1/n), rational(c) below
// Source: seed 003 (epicentre + fall-off design)
// Note: cost is the cubic branch; the rational branch is 2 mul, 3 add, 1 div
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic-rational vs pow: max abs error (relative to the peak) <= 0.102 over n in [2, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_cubic_rational(c) with c the cosine to the lobe's axis, clamped to [0, 1]; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_lobe_cubic(float c_1, float d1_, float d2_, float d3_, float x1_, float x2_, float cut)
{
    const float _e7 = fb_clamp01_(c_1);
    float y = (1.0 - _e7);
    float p = (1.0 - (y * (d1_ - ((y + x1_) * (d2_ - ((y + x2_) * d3_))))));
    return ((_e7 < cut) ? 0.0 : max(p, 0.0));
}

float fb_lobe_rational(float c_2, float peak, float g)
{
    const float _e3 = fb_clamp01_(c_2);
    float y_1 = (1.0 - _e3);
    return ((peak * _e3) / (1.0 + (g * y_1)));
}

float fb_lobe_cubic_rational(float c_3, float d1_1, float d2_1, float d3_1, float x1_1, float x2_1, float cut_1, float peak_1, float g_1, float q)
{
    const float _e10 = fb_clamp01_(c_3);
    const float _e11 = fb_lobe_cubic(_e10, d1_1, d2_1, d3_1, x1_1, x2_1, cut_1);
    const float _e12 = fb_lobe_rational(_e10, peak_1, g_1);
    return ((_e10 >= q) ? _e11 : _e12);
}

float fb_cubic_rational(float c_4)
{
    const float _e10 = fb_lobe_cubic_rational(c_4, 14.678394, 126.98999, 116.80814, -0.03406367, -0.03406367, 0.92097706, 1.5687428, 59.612225, 0.9659363);
    return _e10;
}
