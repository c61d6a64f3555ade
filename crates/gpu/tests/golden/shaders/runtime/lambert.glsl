// fastbrdf 0.1.0 (brdf): lambert
// Made by: fastbrdf shader --model lambert --lang glsl --runtime-params
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
    vec3 h;
    float sin2_h;
    float cos_ih;
    vec3 wi;
    vec3 wo;
};
const float FB_COS_MIN = 9.536743e-7;


vec3 fb_rescale(vec3 v) {
    float l = dot(v, v);
    float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    bool safe = ((l >= 7.888609e-31) && (l <= 1.2676506e30));
    return ((safe || (m == 0.0)) ? v : (v / vec3(m)));
}

FbPair fb_pair(vec3 wi_raw, vec3 wo_raw) {
    vec3 _e2 = fb_rescale(wi_raw);
    vec3 _e3 = fb_rescale(wo_raw);
    float li = dot(_e2, _e2);
    float lo = dot(_e3, _e3);
    vec3 wi_1 = (_e2 * (1.0 / sqrt(li)));
    vec3 wo_1 = (_e3 * (1.0 / sqrt(lo)));
    vec3 s = (wi_1 + wo_1);
    float len = sqrt(dot(s, s));
    vec3 h = (s / vec3(len));
    bool valid = (((((li > 0.0) && (lo > 0.0)) && (wi_1.z >= FB_COS_MIN)) && (wo_1.z >= FB_COS_MIN)) && (len > 0.0));
    return FbPair(valid, wi_1.z, wo_1.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_1, wo_1);
}

float fb_lambert(vec3 wi, vec3 wo, float p_albedo) {
    FbPair _e3 = fb_pair(wi, wo);
    return (_e3.valid ? (p_albedo * 0.31830987) : 0.0);
}
