// fastbrdf 0.1.0 (brdf): ward-pow
// Made by: fastbrdf shader --model ward-pow --lang glsl --runtime-params
//
// Formula: cos^(2/alpha^2) theta_h / (4 pi alpha^2 sqrt(cos_i cos_o))
// Source: seed 000 (exp replaced by one power)
// Note: isotropic only; f32: cos_h^(2/alpha^2) of a cosine rounded to f32 has a relative error up to (2/alpha^2) 2^-25 (6e-4 at alpha = 0.01, 2.4e-3 at alpha = 0.005)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   ward-pow vs ward: max rel error <= 0.108 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   ward-pow vs ward: max rel error <= 0.396 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   ward-pow vs ward: max rel error <= 0.108 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   ward-pow vs ward: max rel error <= 0.396 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 2.5e-3 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_ward_pow(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_alpha; returns f32.

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


float fb_log2_(float x) {
    float t = ((x - 1.0) / (x + 1.0));
    float t2_ = (t * t);
    float s = (t * (2.0 + (t2_ * (0.6666667 + (t2_ * (0.4 + (t2_ * (0.2857143 + (t2_ * (0.22222222 + (t2_ * (0.18181819 + (t2_ * 0.15384614)))))))))))));
    return ((x >= 0.5) ? (s * 1.442695) : log2(x));
}

float fb_powr(float x_1, float y) {
    float _e4 = fb_log2_(max(x_1, 1e-30));
    return ((x_1 > 0.0) ? exp2((y * _e4)) : 0.0);
}

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
    vec3 wi_2 = (_e2 * (1.0 / sqrt(li)));
    vec3 wo_2 = (_e3 * (1.0 / sqrt(lo)));
    vec3 s_1 = (wi_2 + wo_2);
    float len = sqrt(dot(s_1, s_1));
    vec3 h = (s_1 / vec3(len));
    bool valid = (((((li > 0.0) && (lo > 0.0)) && (wi_2.z >= FB_COS_MIN)) && (wo_2.z >= FB_COS_MIN)) && (len > 0.0));
    return FbPair(valid, wi_2.z, wo_2.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_2, wo_2);
}

float fb_brdf_ward_pow(vec3 wi, vec3 wo, float e, float scale) {
    FbPair _e4 = fb_pair(wi, wo);
    float _e7 = fb_powr(_e4.h.z, e);
    return (_e4.valid ? ((scale * _e7) / sqrt((_e4.cos_i * _e4.cos_o))) : 0.0);
}

float fb_ward_pow(vec3 wi_1, vec3 wo_1, float p_alpha) {
    float _e9 = fb_brdf_ward_pow(wi_1, wo_1, (2.0 / (p_alpha * p_alpha)), (0.07957747 / (p_alpha * p_alpha)));
    return _e9;
}
