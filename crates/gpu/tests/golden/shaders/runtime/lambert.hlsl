// fastbrdf 0.1.0 (brdf): lambert
// Made by: fastbrdf shader --model lambert --lang hlsl --runtime-params
//
// Formula: albedo / pi
// Source: Lambert 1760
// Parameters (this export: albedo = 1):
//   albedo: directional-hemispherical reflectance (range [0, 1], default 1)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_albedo (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_lambert(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_albedo; returns f32.

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
    float3 wi_1 = (_e2 * (1.0 / sqrt(li)));
    float3 wo_1 = (_e3 * (1.0 / sqrt(lo)));
    float3 s = (wi_1 + wo_1);
    float len = sqrt(dot(s, s));
    float3 h = (s / (len).xxx);
    bool valid = (((((li > 0.0) & (lo > 0.0)) & (wi_1.z >= FB_COS_MIN)) & (wo_1.z >= FB_COS_MIN)) & (len > 0.0));
    const FbPair fbpair = ConstructFbPair(valid, wi_1.z, wo_1.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_1, wo_1);
    return fbpair;
}

float fb_lambert(float3 wi, float3 wo, float p_albedo)
{
    const FbPair _e3 = fb_pair(wi, wo);
    return (_e3.valid ? (p_albedo * 0.31830987) : 0.0);
}
