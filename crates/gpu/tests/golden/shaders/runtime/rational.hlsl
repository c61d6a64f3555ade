// fastbrdf 0.1.0 (lobe): rational
// Made by: fastbrdf shader --model rational --lang hlsl --runtime-params
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
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_rational(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

static const float FB_RT_LN_HALF = -0.6931472;

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

float fb_rt_expm1_(float x)
{
    float s = (x * (1.0 + (x * (0.5 + (x * (0.16666667 + (x * (0.041666668 + (x * (0.008333334 + (x * (0.0013888889 + (x * (0.0001984127 + (x * (2.4801588e-5 + (x * 2.7557319e-6)))))))))))))))));
    return ((abs(x) < 0.5) ? s : (exp(x) - 1.0));
}

float2 fb_rt_rational_coefs(float n, float level, float xq)
{
    float d0_ = (1.0 + (n * xq));
    return float2((level / d0_), ((n - 1.0) / d0_));
}

float fb_rt_rational(float c_2, float n_1)
{
    const float _e5 = fb_rt_expm1_((FB_RT_LN_HALF / n_1));
    const float2 _e6 = fb_rt_rational_coefs(n_1, 0.5, _e5);
    const float _e9 = fb_lobe_rational(c_2, _e6.x, _e6.y);
    return _e9;
}

float fb_rational(float c_3, float p_n)
{
    const float _e2 = fb_rt_rational(c_3, p_n);
    return _e2;
}
