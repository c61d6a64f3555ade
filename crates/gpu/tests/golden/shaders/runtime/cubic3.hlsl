// fastbrdf 0.1.0 (lobe): cubic3
// Made by: fastbrdf shader --model cubic3 --lang hlsl --runtime-params
//
// Formula: a c^3 + b c^2 + c' c through (1, 1), (0.5^(1/n), 0.5), ((1/18)^(1/n), 1/18); 0 below its local minimum and where negative
// Source: seed 003 (three-point variant, Q = 0.5, G = 1/18)
// Note: for f32 accuracy, evaluated on the CPU by Horner in (c - 1) with coefficients from the Newton form, on the GPU in the Newton form in 1 - c (fold-proof)
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.0215 over n in [4, 1000], epicentre (reference >= half its peak)
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.0217 over n in [4, 100000], epicentre (reference >= half its peak)
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.108 over n in [4, 1000], whole domain
//   cubic3 vs pow: max abs error (relative to the peak) <= 0.109 over n in [4, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_cubic3_(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

struct FbRtCubic {
    float d1_;
    float d2_;
    float d3_;
    float x1_;
    float x2_;
    float xcut;
};

static const float FB_RT_LN_HALF = -0.6931472;
static const float FB_RT_LN_G18_ = -2.8903718;

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

float fb_rt_expm1_(float x)
{
    float s = (x * (1.0 + (x * (0.5 + (x * (0.16666667 + (x * (0.041666668 + (x * (0.008333334 + (x * (0.0013888889 + (x * (0.0001984127 + (x * (2.4801588e-5 + (x * 2.7557319e-6)))))))))))))))));
    return ((abs(x) < 0.5) ? s : (exp(x) - 1.0));
}

FbRtCubic ConstructFbRtCubic(float arg0, float arg1, float arg2, float arg3, float arg4, float arg5) {
    FbRtCubic ret = (FbRtCubic)0;
    ret.d1_ = arg0;
    ret.d2_ = arg1;
    ret.d3_ = arg2;
    ret.x1_ = arg3;
    ret.x2_ = arg4;
    ret.xcut = arg5;
    return ret;
}

FbRtCubic fb_rt_cubic_finish(float d1_1, float d2_1, float d3_1, float x1_1, float x2_1)
{
    bool local = (bool)0;
    bool local_1 = (bool)0;
    bool local_2 = (bool)0;
    bool local_3 = (bool)0;
    bool local_4 = (bool)0;
    bool local_5 = (bool)0;
    bool local_6 = (bool)0;
    bool local_7 = (bool)0;

    float al = ((d1_1 - (d2_1 * x1_1)) + ((d3_1 * x1_1) * x2_1));
    float be = (d2_1 - (d3_1 * (x1_1 + x2_1)));
    float a = (3.0 * d3_1);
    float b = (2.0 * be);
    float disc = ((b * b) - ((4.0 * a) * al));
    float q = (-0.5 * (b + (((b >= 0.0) ? 1.0 : -1.0) * sqrt(max(disc, 0.0)))));
    bool lin = (a == 0.0);
    float r1_ = (lin ? (-(al) / ((b == 0.0) ? 1.0 : b)) : (q / (lin ? 1.0 : a)));
    float r2_ = (al / ((q == 0.0) ? 1.0 : q));
    if ((lin ? (b != 0.0) : (disc >= 0.0))) {
        local = (r1_ > -1.0);
    } else {
        local = false;
    }
    bool _e61 = local;
    if (_e61) {
        local_1 = (r1_ < x1_1);
    } else {
        local_1 = false;
    }
    bool _e66 = local_1;
    if (_e66) {
        local_2 = ((b + ((2.0 * a) * r1_)) > 0.0);
    } else {
        local_2 = false;
    }
    bool ok1_ = local_2;
    if ((disc >= 0.0)) {
        local_3 = !(lin);
    } else {
        local_3 = false;
    }
    bool _e83 = local_3;
    if (_e83) {
        local_4 = (q != 0.0);
    } else {
        local_4 = false;
    }
    bool _e89 = local_4;
    if (_e89) {
        local_5 = (r2_ > -1.0);
    } else {
        local_5 = false;
    }
    bool _e95 = local_5;
    if (_e95) {
        local_6 = (r2_ < x1_1);
    } else {
        local_6 = false;
    }
    bool _e100 = local_6;
    if (_e100) {
        local_7 = ((b + ((2.0 * a) * r2_)) > 0.0);
    } else {
        local_7 = false;
    }
    bool ok2_ = local_7;
    float xcut = max((ok1_ ? r1_ : -1.0), (ok2_ ? r2_ : -1.0));
    const FbRtCubic fbrtcubic = ConstructFbRtCubic(d1_1, d2_1, d3_1, x1_1, x2_1, xcut);
    return fbrtcubic;
}

FbRtCubic fb_rt_three_point(float n)
{
    const float _e3 = fb_rt_expm1_((FB_RT_LN_HALF / n));
    const float _e6 = fb_rt_expm1_((FB_RT_LN_G18_ / n));
    float f0r = (-0.5 / _e3);
    float frl = (-0.44444445 / (_e6 - _e3));
    float flm = (0.055555556 / (1.0 + _e6));
    float f0rl = ((frl - f0r) / _e6);
    float frlm = ((frl - flm) / (1.0 + _e3));
    const FbRtCubic _e23 = fb_rt_cubic_finish(f0r, f0rl, (f0rl - frlm), _e3, _e6);
    const FbRtCubic fbrtcubic_1 = _e23;
    return fbrtcubic_1;
}

float fb_rt_cubic3_(float c_2, float n_1)
{
    const FbRtCubic _e2 = fb_rt_three_point(n_1);
    const float _e11 = fb_lobe_cubic(c_2, _e2.d1_, _e2.d2_, _e2.d3_, _e2.x1_, _e2.x2_, (1.0 + _e2.xcut));
    return _e11;
}

float fb_cubic3_(float c_3, float p_n)
{
    const float _e2 = fb_rt_cubic3_(c_3, p_n);
    return _e2;
}
