// fastbrdf 0.1.0 (env): env-brdf
// Made by: fastbrdf shader --model env-brdf --lang hlsl --runtime-params
//
// Formula: scale/bias = integral of (1 - (1 - v.h)^5) or (1 - v.h)^5 times D_ggx G2_correlated / (4 cos_v cos_l) cos_l dl
// Source: Karis 2013 (split sum); Heitz 2014 (height-correlated Smith); Filament's DFG
// Note: ops are per quadrature point (1152 points, plus 48 acos); product Gauss-Legendre rule, within 2e-3 of adaptive quadrature for cos_v >= 0.001
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

static const float FB_GL24_X[12] = { 0.9951872, 0.9747286, 0.93827456, 0.88641554, 0.82000196, 0.74012417, 0.64809364, 0.5454215, 0.43379351, 0.31504267, 0.19111887, 0.064056896 };
static const float FB_GL24_W[12] = { 0.01234123, 0.02853139, 0.044277437, 0.059298586, 0.07334648, 0.086190164, 0.097618654, 0.10744427, 0.115505666, 0.12167047, 0.12583746, 0.1279382 };

float fb_env_cos(float x)
{
    float p = -1.6059044e-10;

    float y = (x - 1.5707964);
    float y2_ = (y * y);
    float _e6 = p;
    p = ((_e6 * y2_) + 2.5052108e-8);
    float _e10 = p;
    p = ((_e10 * y2_) - 2.7557319e-6);
    float _e14 = p;
    p = ((_e14 * y2_) + 0.0001984127);
    float _e18 = p;
    p = ((_e18 * y2_) - 0.008333334);
    float _e22 = p;
    p = ((_e22 * y2_) + 0.16666667);
    float _e26 = p;
    p = ((_e26 * y2_) - 1.0);
    float _e30 = p;
    return (y * _e30);
}

float fb_env_ring(float u, float w, float wu, bool full, float mu, float alpha, float sv, float mlv, bool bias)
{
    float pm = 3.1415927;
    float q = (float)0;
    float acc = 0.0;
    int i = int(0);
    float sgn = (float)0;

    float a2_ = (alpha * alpha);
    float d = (w + (a2_ * u));
    float ch = sqrt((w / d));
    float sh = (alpha * sqrt((u / d)));
    if (!(full)) {
        float qd = (((2.0 * ch) * sh) * sv);
        q = (mu * (((a2_ * u) - w) / d));
        float _e29 = q;
        q = ((qd > 0.0) ? (_e29 / qd) : 1.0);
        float _e35 = q;
        q = min(max(_e35, -1.0), 1.0);
        float _e40 = q;
        pm = acos(_e40);
    }
    uint2 loop_bound = uint2(4294967295u, 4294967295u);
    bool loop_init = true;
    while(true) {
        if (all(loop_bound == uint2(0u, 0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            int _e123 = i;
            i = asint(asuint(_e123) + asuint(int(1)));
        }
        loop_init = false;
        int _e46 = i;
        if ((_e46 < int(12))) {
        } else {
            break;
        }
        {
            sgn = -1.0;
            uint2 loop_bound_1 = uint2(4294967295u, 4294967295u);
            bool loop_init_1 = true;
            while(true) {
                if (all(loop_bound_1 == uint2(0u, 0u))) { break; }
                loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
                if (!loop_init_1) {
                    float _e119 = sgn;
                    sgn = (_e119 + 2.0);
                }
                loop_init_1 = false;
                float _e51 = sgn;
                if ((_e51 <= 1.0)) {
                } else {
                    break;
                }
                {
                    float _e54 = pm;
                    float _e55 = sgn;
                    int _e57 = i;
                    float phi = (_e54 * (0.5 * ((_e55 * FB_GL24_X[min(uint(_e57), 11u)]) + 1.0)));
                    const float _e66 = fb_env_cos(phi);
                    float vh = (((sv * sh) * _e66) + (mu * ch));
                    float cl = max((((2.0 * vh) * ch) - mu), 9.094947e-13);
                    float tl2_ = (((1.0 - cl) * (1.0 + cl)) / (cl * cl));
                    float ll = ((a2_ * tl2_) / (2.0 * (sqrt((1.0 + (a2_ * tl2_))) + 1.0)));
                    float g_over_mu = (1.0 / ((mu * (1.0 + ll)) + mlv));
                    float m = max((1.0 - vh), 0.0);
                    float f5_ = ((((m * m) * m) * m) * m);
                    float wf = (bias ? f5_ : (1.0 - f5_));
                    float _e110 = acc;
                    int _e112 = i;
                    acc = (_e110 + ((((FB_GL24_W[min(uint(_e112), 11u)] * wf) * vh) * g_over_mu) / ch));
                }
            }
        }
    }
    float _e125 = acc;
    float _e126 = pm;
    return (((_e125 * _e126) * 0.5) * wu);
}

float fb_env_dfg(float cos_v, float alpha_1, bool bias_1)
{
    float sum = 0.0;
    int i_1 = int(0);
    float sgn_1 = (float)0;

    float mu_1 = max(cos_v, 9.536743e-7);
    float a2_1 = (alpha_1 * alpha_1);
    float sv_1 = sqrt(max(((1.0 - mu_1) * (1.0 + mu_1)), 0.0));
    float mlv_1 = (((a2_1 * sv_1) * sv_1) / (2.0 * (sqrt(((mu_1 * mu_1) + ((a2_1 * sv_1) * sv_1))) + mu_1)));
    float t1_ = (mu_1 / (1.0 + sv_1));
    float t12_ = (t1_ * t1_);
    float u1_ = (t12_ / (a2_1 + t12_));
    float w1_ = (a2_1 / (a2_1 + t12_));
    float u2_ = (1.0 / (1.0 + (a2_1 * t12_)));
    float w2_ = ((a2_1 * t12_) / (1.0 + (a2_1 * t12_)));
    float du = (w1_ - w2_);
    uint2 loop_bound_2 = uint2(4294967295u, 4294967295u);
    bool loop_init_2 = true;
    while(true) {
        if (all(loop_bound_2 == uint2(0u, 0u))) { break; }
        loop_bound_2 -= uint2(loop_bound_2.y == 0u, 1u);
        if (!loop_init_2) {
            int _e103 = i_1;
            i_1 = asint(asuint(_e103) + asuint(int(1)));
        }
        loop_init_2 = false;
        int _e48 = i_1;
        if ((_e48 < int(12))) {
        } else {
            break;
        }
        {
            sgn_1 = -1.0;
            uint2 loop_bound_3 = uint2(4294967295u, 4294967295u);
            bool loop_init_3 = true;
            while(true) {
                if (all(loop_bound_3 == uint2(0u, 0u))) { break; }
                loop_bound_3 -= uint2(loop_bound_3.y == 0u, 1u);
                if (!loop_init_3) {
                    float _e99 = sgn_1;
                    sgn_1 = (_e99 + 2.0);
                }
                loop_init_3 = false;
                float _e53 = sgn_1;
                if ((_e53 <= 1.0)) {
                } else {
                    break;
                }
                {
                    float _e56 = sgn_1;
                    int _e58 = i_1;
                    float t = (0.5 * ((_e56 * FB_GL24_X[min(uint(_e58), 11u)]) + 1.0));
                    float _e65 = sgn_1;
                    int _e67 = i_1;
                    float tc = (0.5 * (1.0 - (_e65 * FB_GL24_X[min(uint(_e67), 11u)])));
                    int _e75 = i_1;
                    float wt = (0.5 * FB_GL24_W[min(uint(_e75), 11u)]);
                    float _e79 = sum;
                    const float _e85 = fb_env_ring((u1_ * t), (w1_ + (u1_ * tc)), (u1_ * wt), true, mu_1, alpha_1, sv_1, mlv_1, bias_1);
                    sum = (_e79 + _e85);
                    float tt = ((du * t) * t);
                    float _e89 = sum;
                    const float _e97 = fb_env_ring((u2_ - tt), (w2_ + tt), (((du * 2.0) * t) * wt), false, mu_1, alpha_1, sv_1, mlv_1, bias_1);
                    sum = (_e89 + _e97);
                }
            }
        }
    }
    float _e105 = sum;
    return max((_e105 * 0.31830987), 0.0);
}

float fb_env_brdf(float cos_v_1, float alpha_2)
{
    float v = ((cos_v_1 > 0.0) ? min(cos_v_1, 1.0) : 0.0);
    float a = ((alpha_2 > 0.005) ? min(alpha_2, 1.0) : 0.005);
    const float _e15 = fb_env_dfg(v, a, false);
    return _e15;
}
