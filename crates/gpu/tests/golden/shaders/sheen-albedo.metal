// fastbrdf 0.1.0 (env): sheen-albedo
// Made by: fastbrdf shader --model sheen-albedo --lang msl
//
// Formula: E(mu, alpha) = integral of D_charlie V cos_i over the hemisphere (sheen colour 1), product Gauss-Legendre 48 x 48 in (cos_i, phi); mu in [0.001, 1], alpha in [0.07, 1]
// Source: Estevez and Kulla 2017 (Charlie D and V); Neubelt and Pettineo 2013 (V); KHR_materials_sheen (albedo scaling)
// Note: ops are per quadrature point (2304 points, plus 48 visibility terms); within 1e-4 of adaptive quadrature; the reference of the sheen rows of the DFG ledger
// Parameters (this export: v = charlie):
//   v: the sheen visibility whose albedo: charlie (Estevez and Kulla's fitted Lambda) or neubelt (Neubelt and Pettineo) (one of charlie, neubelt, default charlie)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_sheen_albedo(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;

struct type_2 {
    metal::float2 inner[48];
};
struct type_3 {
    float inner[5];
};
constant type_2 FB_SHEEN_GL48_ = type_2 {{metal::float2(0.00061449636, 0.001576673), metal::float2(0.0032349138, 0.003663777), metal::float2(0.007937708, 0.0057386174), metal::float2(0.014704204, 0.007789658), metal::float2(0.023506148, 0.00980808), metal::float2(0.034306653, 0.011785381), metal::float2(0.04706043, 0.013713255), metal::float2(0.06171399, 0.015583614), metal::float2(0.07820587, 0.017388612), metal::float2(0.0964669, 0.019120676), metal::float2(0.116420485, 0.020772541), metal::float2(0.13798293, 0.02233728), metal::float2(0.1610638, 0.023808328), metal::float2(0.1855663, 0.025179518), metal::float2(0.21138763, 0.026445094), metal::float2(0.23841952, 0.027599752), metal::float2(0.26654854, 0.028638646), metal::float2(0.29565677, 0.02955742), metal::float2(0.32562205, 0.03035222), metal::float2(0.35631874, 0.031019712), metal::float2(0.3876181, 0.031557094), metal::float2(0.41938883, 0.03196212), metal::float2(0.45149764, 0.03223308), metal::float2(0.48380992, 0.03236885), metal::float2(0.5161901, 0.03236885), metal::float2(0.5485023, 0.03223308), metal::float2(0.58061117, 0.03196212), metal::float2(0.6123819, 0.031557094), metal::float2(0.6436812, 0.031019712), metal::float2(0.6743779, 0.03035222), metal::float2(0.70434326, 0.02955742), metal::float2(0.7334514, 0.028638646), metal::float2(0.76158047, 0.027599752), metal::float2(0.78861237, 0.026445094), metal::float2(0.8144337, 0.025179518), metal::float2(0.8389362, 0.023808328), metal::float2(0.8620171, 0.02233728), metal::float2(0.8835795, 0.020772541), metal::float2(0.9035331, 0.019120676), metal::float2(0.9217941, 0.017388612), metal::float2(0.938286, 0.015583614), metal::float2(0.95293957, 0.013713255), metal::float2(0.96569335, 0.011785381), metal::float2(0.97649384, 0.00980808), metal::float2(0.9852958, 0.007789658), metal::float2(0.9920623, 0.0057386174), metal::float2(0.9967651, 0.003663777), metal::float2(0.9993855, 0.001576673)}};

metal::float2 fb_sheen_e_clamp(
    float mu,
    float alpha
) {
    return metal::float2(metal::min(metal::max(mu, 0.001), 1.0), metal::min(metal::max(alpha, 0.07), 1.0));
}

float fb_sheen_l(
    float x,
    type_3 l
) {
    return ((l.inner[0] / (1.0 + (l.inner[1] * metal::pow(metal::max(x, 0.0), l.inner[2])))) + (l.inner[3] * x)) + l.inner[4];
}

float fb_sheen_v_neubelt(
    float cos_o,
    float cos_i
) {
    return 1.0 / (4.0 * ((cos_i + cos_o) - (cos_i * cos_o)));
}

float fb_sheen_lambda(
    float mu_1,
    type_3 l_1,
    float l_half
) {
    if (mu_1 < 0.5) {
        float _e5 = fb_sheen_l(mu_1, l_1);
        return metal::exp(_e5);
    }
    float _e11 = fb_sheen_l(1.0 - mu_1, l_1);
    return metal::exp((2.0 * l_half) - _e11);
}

float fb_sheen_v_charlie(
    float cos_o_1,
    float cos_i_1,
    type_3 l_2,
    float l_half_1
) {
    float _e4 = fb_sheen_lambda(cos_o_1, l_2, l_half_1);
    float _e5 = fb_sheen_lambda(cos_i_1, l_2, l_half_1);
    float s = 1.0 + (_e4 + _e5);
    return 1.0 / (s * (4.0 * (cos_o_1 * cos_i_1)));
}

float fb_sheen_d(
    float sin2_h,
    float norm,
    float expo
) {
    return norm * metal::pow(metal::max(sin2_h, 0.0), expo);
}

float fb_sheen_e_quadrature(
    float mu_in,
    float alpha_in,
    bool charlie
) {
    type_2 nodes = FB_SHEEN_GL48_;
    float sum = 0.0;
    int i = 0;
    float v = {};
    float inner = {};
    int j = {};
    metal::float2 _e3 = fb_sheen_e_clamp(mu_in, alpha_in);
    float mu_2 = _e3.x;
    float a = _e3.y;
    float t = (1.0 - a) * (1.0 - a);
    type_3 l_3 = type_3 {{21.5473 + (3.7772 * t), 3.82987 + (-0.50552 * t), 0.19823 + (-0.03022 * t), -1.9776 + (0.70367 * t), -4.32054 + (-0.53913 * t)}};
    float _e33 = fb_sheen_l(0.5, l_3);
    float norm_1 = (2.0 + (1.0 / a)) / 6.2831855;
    float expo_1 = 0.5 / a;
    float so = metal::sqrt(metal::max(1.0 - (mu_2 * mu_2), 0.0));
    uint2 loop_bound = uint2(4294967295u);
    bool loop_init = true;
    while(true) {
        if (metal::all(loop_bound == uint2(0u))) { break; }
        loop_bound -= uint2(loop_bound.y == 0u, 1u);
        if (!loop_init) {
            int _e118 = i;
            i = as_type<int>(as_type<uint>(_e118) + as_type<uint>(1));
        }
        loop_init = false;
        int _e54 = i;
        if (_e54 < 48) {
        } else {
            break;
        }
        {
            int _e57 = i;
            float ct = nodes.inner[_e57].x;
            float st = metal::sqrt(metal::max(1.0 - (ct * ct), 0.0));
            float _e67 = fb_sheen_v_neubelt(mu_2, ct);
            v = _e67;
            if (charlie) {
                float _e69 = fb_sheen_v_charlie(mu_2, ct, l_3, _e33);
                v = _e69;
            }
            inner = 0.0;
            j = 0;
            uint2 loop_bound_1 = uint2(4294967295u);
            bool loop_init_1 = true;
            while(true) {
                if (metal::all(loop_bound_1 == uint2(0u))) { break; }
                loop_bound_1 -= uint2(loop_bound_1.y == 0u, 1u);
                if (!loop_init_1) {
                    int _e104 = j;
                    j = as_type<int>(as_type<uint>(_e104) + as_type<uint>(1));
                }
                loop_init_1 = false;
                int _e74 = j;
                if (_e74 < 48) {
                } else {
                    break;
                }
                {
                    int _e77 = j;
                    float _e80 = nodes.inner[_e77].x;
                    float phi = 3.1415927 * _e80;
                    float hx = (st * metal::cos(phi)) + so;
                    float hy = st * metal::sin(phi);
                    float hz = ct + mu_2;
                    float s2_ = (hx * hx) + (hy * hy);
                    float _e92 = inner;
                    int _e93 = j;
                    float _e96 = nodes.inner[_e93].y;
                    float _e100 = fb_sheen_d(s2_ / (s2_ + (hz * hz)), norm_1, expo_1);
                    inner = _e92 + (_e96 * _e100);
                }
            }
            float _e106 = sum;
            int _e107 = i;
            float _e110 = nodes.inner[_e107].y;
            float _e111 = v;
            float _e114 = inner;
            sum = _e106 + (((_e110 * _e111) * ct) * _e114);
        }
    }
    float _e120 = sum;
    return _e120 * 6.2831855;
}

float fb_sheen_albedo(
    float cos_v,
    float alpha_1
) {
    float v_1 = (cos_v > 0.0) ? metal::min(cos_v, 1.0) : 0.0;
    float a_1 = (alpha_1 > 0.005) ? metal::min(alpha_1, 1.0) : 0.005;
    float _e15 = fb_sheen_e_quadrature(v_1, a_1, true);
    return _e15;
}
