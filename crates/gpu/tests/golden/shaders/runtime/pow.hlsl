// fastbrdf 0.1.0 (lobe): pow
// Made by: fastbrdf shader --model pow --lang hlsl --runtime-params
//
// Formula: c^n
// Source: Phong 1975; Blinn 1977 (reference lobe of seeds 000, 001, 003)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 2e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_pow(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

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

float fb_powr(float x_1, float y)
{
    const float _e4 = fb_log2_(max(x_1, 1e-30));
    return ((x_1 > 0.0) ? exp2((y * _e4)) : 0.0);
}

float fb_lobe_pow(float c_1, float n)
{
    const float _e2 = fb_clamp01_(c_1);
    const float _e3 = fb_powr(_e2, n);
    return _e3;
}

float fb_pow(float c_2, float p_n)
{
    const float _e2 = fb_lobe_pow(c_2, p_n);
    return _e2;
}
