// fastbrdf 0.1.0 (brdf): cook-torrance
// Made by: fastbrdf shader --model cook-torrance --lang hlsl
//
// Formula: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators)
// Note: ops exclude D, G, F and the pair set-up; equals Mitsuba 3 roughconductor eval / cos_o; f32: 1e-5 except with f = dielectric/conductor at eta << 1, where F is a near-step at the critical angle and wi.h rounded once to f32 can double it (1.0 at eta = 0.01); anisotropic (alpha_x, alpha_y, d = beckmann(-ct)/ggx, a Smith g): f32 1.4e-6 measured with f = none/schlick (1e-5 documented)
// Parameters (this export: alpha = 0.3, d = beckmann, denominator = 4, eta = 1.5, f = none, f0 = 0.04, f90 = 1, g = smith, k = 0, ms = none, remap = alpha-half):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
//   d: microfacet distribution id (one of beckmann, beckmann-ct, beckmann-pow, beckmann-power4, beckmann-power8, beckmann-power16, ggx, default beckmann)
//   g: shadowing-masking term; when not given, the Smith term of d (smith for the Beckmann family, smith-ggx for ggx) (one of v-cavity, smith, smith-rational, smith-beckmann-correlated, smith-ggx, smith-ggx-correlated, smith-ggx-correlated-fast, smith-ggx-correlated-fast-tuned, smith-ggx-joint-approx, schlick-ggx, kelemen, neumann, default smith)
//   f: Fresnel term (one of none, schlick, schlick-sg, schlick-sg-tuned, dielectric, conductor, default none)
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
//   k: extinction coefficient (imaginary part of the index, conductors) (range [0, 20], default 0)
//   denominator: 4 cos_i cos_o (microfacet theory), cos_i cos_o (seed 000), pi cos_i cos_o (seed 001) (one of 4, seed-000, seed-001, default 4)
//   ms: energy compensation for multiple scattering: none, kulla-conty (Kulla and Conty 2017), filament (Filament's, view direction wo only; not reciprocal); needs d = ggx, g = smith-ggx-correlated (one of none, kulla-conty, filament, default none)
//   alpha_x: anisotropic slope along x (with alpha_y; replaces alpha); needs d = beckmann(-ct) or ggx, a Smith g, ms = none (range [0.005, 1], default -)
//   alpha_y: anisotropic slope along y (with alpha_x; replaces alpha); needs d = beckmann(-ct) or ggx, a Smith g, ms = none (range [0.005, 1], default -)
//   remap: Schlick's k: alpha / 2, or Unreal's (sqrt(alpha) + 1)^2 / 8 (needs g = schlick-ggx) (one of alpha-half, ue4, default alpha-half)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 3e0 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_cook_torrance(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

struct FbPair {
    bool valid;
    float cos_i;
    float cos_o;
    int _pad3_0;
    float3 h;
    float sin2_h;
    float cos_ih;
    int _pad6_0;
    int _pad6_1;
    int _pad6_2;
    float3 wi;
    int _pad7_0;
    float3 wo;
    int _end_pad_0;
};

static const float FB_COS_MIN = 9.536743e-7;
static const float FB_INV_SQRT_PI = 0.5641896;

float3 fb_rescale(float3 v)
{
    float l = dot(v, v);
    float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    bool safe = ((l >= 7.888609e-31) & (l <= 1.2676506e30));
    return ((safe | (m == 0.0)) ? v : (v / (m).xxx));
}

FbPair ConstructFbPair(bool arg0, float arg1, float arg2, float3 arg3, float arg4, float arg5, float3 arg6, float3 arg7) {
    FbPair ret = (FbPair)0;
    ret.valid = arg0;
    ret.cos_i = arg1;
    ret.cos_o = arg2;
    ret.h = arg3;
    ret.sin2_h = arg4;
    ret.cos_ih = arg5;
    ret.wi = arg6;
    ret.wo = arg7;
    return ret;
}

FbPair fb_pair(float3 wi_raw, float3 wo_raw)
{
    const float3 _e2 = fb_rescale(wi_raw);
    const float3 _e3 = fb_rescale(wo_raw);
    float li = dot(_e2, _e2);
    float lo = dot(_e3, _e3);
    float3 wi_1 = (_e2 * (1.0 / sqrt(li)));
    float3 wo_1 = (_e3 * (1.0 / sqrt(lo)));
    float3 s = (wi_1 + wo_1);
    float len = sqrt(dot(s, s));
    float3 h = (s / (len).xxx);
    bool valid = (((((li > 0.0) & (lo > 0.0)) & (wi_1.z >= FB_COS_MIN)) & (wo_1.z >= FB_COS_MIN)) & (len > 0.0));
    const FbPair fbpair = ConstructFbPair(valid, wi_1.z, wo_1.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_1, wo_1);
    return fbpair;
}

float fb_d_beckmann(float c, float s2_, float inv_alpha2_, float scale)
{
    float inv_c2_ = (1.0 / (c * c));
    return ((scale * exp((-((s2_ * inv_c2_)) * inv_alpha2_))) * (inv_c2_ * inv_c2_));
}

float fb_erfc(float x)
{
    float t = (1.0 / (1.0 + (0.5 * x)));
    float p = (-1.2655122 + (t * (1.0000237 + (t * (0.37409195 + (t * (0.09678418 + (t * (-0.18628806 + (t * (0.27886808 + (t * (-1.135204 + (t * (1.4885159 + (t * (-0.82215226 + (t * 0.17087276))))))))))))))))));
    return (t * exp(((-(x) * x) + p)));
}

float fb_g1_smith(float c_1, float alpha)
{
    float sin_ = sqrt(max(((1.0 - c_1) * (1.0 + c_1)), 0.0));
    float a = (c_1 / (alpha * sin_));
    const float _e18 = fb_erfc(a);
    float lambda = (0.5 * (((exp((-(a) * a)) * FB_INV_SQRT_PI) / a) - _e18));
    return ((c_1 >= 1.0) ? 1.0 : (1.0 / (1.0 + lambda)));
}

float fb_cook_torrance(float3 wi, float3 wo)
{
    const FbPair _e2 = fb_pair(wi, wo);
    const float _e8 = fb_d_beckmann(_e2.h.z, _e2.sin2_h, 11.111111, 3.5367765);
    float d = ((_e2.h.z >= FB_COS_MIN) ? _e8 : 0.0);
    const float _e17 = fb_g1_smith(_e2.cos_o, 0.3);
    const float _e20 = fb_g1_smith(_e2.cos_i, 0.3);
    float g = (_e17 * _e20);
    float v_1 = ((((1.0 * d) * g) * 0.25) / (_e2.cos_i * _e2.cos_o));
    return (_e2.valid ? v_1 : 0.0);
}
