// fastbrdf 0.1.0 (brdf): blinn-phong
// Made by: fastbrdf shader --model blinn-phong --lang glsl --runtime-params
//
// Formula: coef(n) lobe(n . h) / (4 wi . h) (energy) or lobe(n . h) (none)
// Source: Blinn 1977; Torrance & Sparrow 1967 (microfacet form); seed 001 (coef by Int(n))
// Note: ops are the wrapper's, add the lobe's; albedo <= 1 with norm = energy; f32: cos_h rounded once to f32 moves flog-normalized-clamped near its zero by up to 0.3 at n = 1e4 and by its whole height 1 above n ~ 2e4, times coef(n) / (4 wi.h): 265 at n = 1e4 (check --full), up to the peak 1914 at n = 1e5; 2 for flog-normalized
// Parameters (this export: lobe = pow, n = 20, norm = energy):
//   lobe: lobe id (one of pow, schlick, schlick-modified, gauss, flog, flog-normalized, flog-normalized-clamped, cubic, cubic3, rational, cubic-rational, power4, power8, power16, sg, ue4-phong-approx, power4-tuned, power8-tuned, power16-tuned, sg-tuned, cubic-rational-tuned, default pow)
//   n: specular exponent (range [1, 100000], default 20)
//   norm: energy: coef(n) = 1 / (2 pi Int(n)); none: the bare lobe (one of energy, none, default energy)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 2e3 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_n (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_blinn_phong(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor, then p_n; returns f32.

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


float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

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
    vec3 wi_1 = (_e2 * (1.0 / sqrt(li)));
    vec3 wo_1 = (_e3 * (1.0 / sqrt(lo)));
    vec3 s_1 = (wi_1 + wo_1);
    float len = sqrt(dot(s_1, s_1));
    vec3 h = (s_1 / vec3(len));
    bool valid = (((((li > 0.0) && (lo > 0.0)) && (wi_1.z >= FB_COS_MIN)) && (wo_1.z >= FB_COS_MIN)) && (len > 0.0));
    return FbPair(valid, wi_1.z, wo_1.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_1, wo_1);
}

float fb_lobe_pow(float c_1, float n) {
    float _e2 = fb_clamp01_(c_1);
    float _e3 = fb_powr(_e2, n);
    return _e3;
}

float fb_blinn_phong(vec3 wi, vec3 wo, float p_n) {
    FbPair _e3 = fb_pair(wi, wo);
    float _e10 = fb_lobe_pow(_e3.h.z, p_n);
    float v_1 = ((((p_n + 2.0) * 0.15915494) * _e10) / (4.0 * _e3.cos_ih));
    return (_e3.valid ? v_1 : 0.0);
}
