// fastbrdf 0.1.0 (brdf): ward
// Made by: fastbrdf shader --model ward --lang hlsl --runtime-params
//
// Formula: exp(-(h_x^2/ax^2 + h_y^2/ay^2)/h_z^2) / (4 pi ax ay sqrt(cos_i cos_o))
// Source: Ward 1992, 'Measuring and modeling anisotropic reflection'
// Note: albedo <= 1 up to 85 degrees; exceeds 1 within ~0.5 degree of grazing (1.50 at 89.9 degrees, alpha = 1)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
//   alpha_x: anisotropic slope along x (with alpha_y; replaces alpha) (range [0.005, 1], default -)
//   alpha_y: anisotropic slope along y (with alpha_x; replaces alpha) (range [0.005, 1], default -)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-5 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_ward(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_alpha; returns f32.

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
    float3 wi_2 = (_e2 * (1.0 / sqrt(li)));
    float3 wo_2 = (_e3 * (1.0 / sqrt(lo)));
    float3 s = (wi_2 + wo_2);
    float len = sqrt(dot(s, s));
    float3 h = (s / (len).xxx);
    bool valid = (((((li > 0.0) & (lo > 0.0)) & (wi_2.z >= FB_COS_MIN)) & (wo_2.z >= FB_COS_MIN)) & (len > 0.0));
    const FbPair fbpair = ConstructFbPair(valid, wi_2.z, wo_2.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_2, wo_2);
    return fbpair;
}

float fb_brdf_ward(float3 wi, float3 wo, float inv_ax2_, float inv_ay2_, float scale)
{
    const FbPair _e5 = fb_pair(wi, wo);
    float lobe = exp((-((((_e5.h.x * _e5.h.x) * inv_ax2_) + ((_e5.h.y * _e5.h.y) * inv_ay2_))) / (_e5.h.z * _e5.h.z)));
    return (_e5.valid ? ((scale * lobe) / sqrt((_e5.cos_i * _e5.cos_o))) : 0.0);
}

float fb_ward(float3 wi_1, float3 wo_1, float p_alpha)
{
    const float _e12 = fb_brdf_ward(wi_1, wo_1, (1.0 / (p_alpha * p_alpha)), (1.0 / (p_alpha * p_alpha)), (0.07957747 / (p_alpha * p_alpha)));
    return _e12;
}
