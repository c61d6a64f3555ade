// fastbrdf 0.1.0 (lobe): cubic-rational-tuned
// Made by: fastbrdf shader --model cubic-rational-tuned --lang msl --runtime-params
//
// Formula: seed 003's cubic above c^n = Q(n), its rational below, Q(n) = Rq(1/n)
// Source: fastbrdf: minimax-tuned coefficient (lobes/tuned.rs)
// Note: coefficient from a closed form fitted to per-n minimax optima
// Parameters (this export: n = 20):
//   n: specular exponent (range [1, 100000], default 20)
// Documented error bounds (measured by `fastbrdf check`):
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.283 over n in [1, 100000], whole domain
//   cubic-rational-tuned vs pow: max abs error (relative to the peak) <= 0.0415 over n in [8, 100000], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_cubic_rational_tuned(c) with c the cosine to the lobe's axis, clamped to [0, 1], then p_n; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct FbRtCubic {
    float d1_;
    float d2_;
    float d3_;
    float x1_;
    float x2_;
    float xcut;
};
constant float FB_RT_LN2_ = 0.6931472;

float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_log2_(
    float x
) {
    float t = (x - 1.0) / (x + 1.0);
    float t2_ = t * t;
    float s = t * (2.0 + (t2_ * (0.6666667 + (t2_ * (0.4 + (t2_ * (0.2857143 + (t2_ * (0.22222222 + (t2_ * (0.18181819 + (t2_ * 0.15384614))))))))))));
    return (x >= 0.5) ? (s * 1.442695) : metal::log2(x);
}

float fb_lobe_cubic(
    float c_1,
    float d1_,
    float d2_,
    float d3_,
    float x1_,
    float x2_,
    float cut
) {
    float _e7 = fb_clamp01_(c_1);
    float y = 1.0 - _e7;
    float p = 1.0 - (y * (d1_ - ((y + x1_) * (d2_ - ((y + x2_) * d3_)))));
    return (_e7 < cut) ? 0.0 : metal::max(p, 0.0);
}

float fb_lobe_rational(
    float c_2,
    float peak,
    float g
) {
    float _e3 = fb_clamp01_(c_2);
    float y_1 = 1.0 - _e3;
    return (peak * _e3) / (1.0 + (g * y_1));
}

float fb_lobe_cubic_rational(
    float c_3,
    float d1_1,
    float d2_1,
    float d3_1,
    float x1_1,
    float x2_1,
    float cut_1,
    float peak_1,
    float g_1,
    float q
) {
    float _e10 = fb_clamp01_(c_3);
    float _e11 = fb_lobe_cubic(_e10, d1_1, d2_1, d3_1, x1_1, x2_1, cut_1);
    float _e12 = fb_lobe_rational(_e10, peak_1, g_1);
    return (_e10 >= q) ? _e11 : _e12;
}

float fb_rt_expm1_(
    float x_1
) {
    float s_1 = x_1 * (1.0 + (x_1 * (0.5 + (x_1 * (0.16666667 + (x_1 * (0.041666668 + (x_1 * (0.008333334 + (x_1 * (0.0013888889 + (x_1 * (0.0001984127 + (x_1 * (0.000024801588 + (x_1 * 0.0000027557319))))))))))))))));
    return (metal::abs(x_1) < 0.5) ? s_1 : (metal::exp(x_1) - 1.0);
}

float fb_rt_ln(
    float x_2
) {
    uint bits = as_type<uint>(x_2);
    float fract = as_type<float>((bits & 8388607u) | 1056964608u);
    int exp = as_type<int>(as_type<uint>(static_cast<int>((bits >> 23u) & 255u)) - as_type<uint>(126));
    bool low = fract < 0.70710677;
    float f = low ? (2.0 * fract) : fract;
    float e = static_cast<float>(exp) - (low ? 1.0 : 0.0);
    float _e26 = fb_log2_(f);
    return (e * FB_RT_LN2_) + (_e26 * FB_RT_LN2_);
}

FbRtCubic fb_rt_cubic_finish(
    float d1_2,
    float d2_2,
    float d3_2,
    float x1_2,
    float x2_2
) {
    bool local = {};
    bool local_1 = {};
    bool local_2 = {};
    bool local_3 = {};
    bool local_4 = {};
    bool local_5 = {};
    bool local_6 = {};
    bool local_7 = {};
    float al = (d1_2 - (d2_2 * x1_2)) + ((d3_2 * x1_2) * x2_2);
    float be = d2_2 - (d3_2 * (x1_2 + x2_2));
    float a = 3.0 * d3_2;
    float b = 2.0 * be;
    float disc = (b * b) - ((4.0 * a) * al);
    float q_1 = -0.5 * (b + (((b >= 0.0) ? 1.0 : -1.0) * metal::sqrt(metal::max(disc, 0.0))));
    bool lin = a == 0.0;
    float r1_ = lin ? (-(al) / ((b == 0.0) ? 1.0 : b)) : (q_1 / (lin ? 1.0 : a));
    float r2_ = al / ((q_1 == 0.0) ? 1.0 : q_1);
    if (lin ? (b != 0.0) : (disc >= 0.0)) {
        local = r1_ > -1.0;
    } else {
        local = false;
    }
    bool _e61 = local;
    if (_e61) {
        local_1 = r1_ < x1_2;
    } else {
        local_1 = false;
    }
    bool _e66 = local_1;
    if (_e66) {
        local_2 = (b + ((2.0 * a) * r1_)) > 0.0;
    } else {
        local_2 = false;
    }
    bool ok1_ = local_2;
    if (disc >= 0.0) {
        local_3 = !(lin);
    } else {
        local_3 = false;
    }
    bool _e83 = local_3;
    if (_e83) {
        local_4 = q_1 != 0.0;
    } else {
        local_4 = false;
    }
    bool _e89 = local_4;
    if (_e89) {
        local_5 = r2_ > -1.0;
    } else {
        local_5 = false;
    }
    bool _e95 = local_5;
    if (_e95) {
        local_6 = r2_ < x1_2;
    } else {
        local_6 = false;
    }
    bool _e100 = local_6;
    if (_e100) {
        local_7 = (b + ((2.0 * a) * r2_)) > 0.0;
    } else {
        local_7 = false;
    }
    bool ok2_ = local_7;
    float xcut = metal::max(ok1_ ? r1_ : -1.0, ok2_ ? r2_ : -1.0);
    return FbRtCubic {d1_2, d2_2, d3_2, x1_2, x2_2, xcut};
}

FbRtCubic fb_rt_hermite(
    float n,
    float level,
    float xq
) {
    float q_2 = 1.0 + xq;
    float s_2 = (n * level) / q_2;
    float f0q = (level - 1.0) / xq;
    float fqm = level / q_2;
    float f0qq = (s_2 - f0q) / xq;
    float fqqm = (s_2 - fqm) / q_2;
    FbRtCubic _e16 = fb_rt_cubic_finish(f0q, f0qq, f0qq - fqqm, xq, xq);
    return _e16;
}

metal::float2 fb_rt_rational_coefs(
    float n_1,
    float level_1,
    float xq_1
) {
    float d0_ = 1.0 + (n_1 * xq_1);
    return metal::float2(level_1 / d0_, (n_1 - 1.0) / d0_);
}

float fb_rt_cubic_rational_at(
    float c_4,
    float n_2,
    float level_2,
    float ln_level
) {
    float _e5 = fb_rt_expm1_(ln_level / n_2);
    FbRtCubic _e6 = fb_rt_hermite(n_2, level_2, _e5);
    metal::float2 _e7 = fb_rt_rational_coefs(n_2, level_2, _e5);
    float _e20 = fb_lobe_cubic_rational(c_4, _e6.d1_, _e6.d2_, _e6.d3_, _e6.x1_, _e6.x2_, 1.0 + _e6.xcut, _e7.x, _e7.y, 1.0 + _e5);
    return _e20;
}

float fb_rt_cubic_rational_level(
    float n_3
) {
    float x_3 = 1.0 / n_3;
    float r = 0.2037858 + (x_3 * (-0.35406178 + (x_3 * (-0.17166191 + (x_3 * (-1.7353249 + (x_3 * 2.0826526)))))));
    return metal::clamp(r, 0.02, 0.9);
}

float fb_rt_cubic_rational_tuned(
    float c_5,
    float n_4
) {
    float _e2 = fb_rt_cubic_rational_level(n_4);
    float _e3 = fb_rt_ln(_e2);
    float _e4 = fb_rt_cubic_rational_at(c_5, n_4, _e2, _e3);
    return _e4;
}

float fb_cubic_rational_tuned(
    float c_6,
    float p_n
) {
    float _e2 = fb_rt_cubic_rational_tuned(c_6, p_n);
    return _e2;
}
