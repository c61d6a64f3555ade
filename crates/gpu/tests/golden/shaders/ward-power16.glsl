// fastbrdf 0.1.0 (brdf): ward-power16
// Made by: fastbrdf shader --model ward-power16 --lang glsl
//
// Formula: max(0, 1 + (2/alpha^2/16)(cos theta_h - 1))^16 / (4 pi alpha^2 sqrt(cos_i cos_o))
// Source: seed 000 (g = 16 form of the exponential)
// Note: isotropic only
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   ward-power16 vs ward: max rel error <= 0.142 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   ward-power16 vs ward: max rel error <= 0.549 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   ward-power16 vs ward: max rel error <= 0.142 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   ward-power16 vs ward: max rel error <= 0.549 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 1e-5 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_ward_power16_(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

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


float fb_pow4_(float x) {
    float x2_ = (x * x);
    return (x2_ * x2_);
}

float fb_pow8_(float x_1) {
    float _e1 = fb_pow4_(x_1);
    return (_e1 * _e1);
}

float fb_pow16_(float x_2) {
    float _e1 = fb_pow8_(x_2);
    return (_e1 * _e1);
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

float fb_brdf_ward_power16_(vec3 wi, vec3 wo, float s, float scale) {
    FbPair _e4 = fb_pair(wi, wo);
    float _e17 = fb_pow16_(max((1.0 + (s * (-(_e4.sin2_h) / (1.0 + _e4.h.z)))), 0.0));
    return (_e4.valid ? ((scale * _e17) / sqrt((_e4.cos_i * _e4.cos_o))) : 0.0);
}

float fb_ward_power16_(vec3 wi_1, vec3 wo_1) {
    float _e4 = fb_brdf_ward_power16_(wi_1, wo_1, 1.3888888, 0.88419414);
    return _e4;
}
