// fastbrdf 0.1.0 (brdf): blinn-phong
// Made by: fastbrdf shader --model blinn-phong --lang glsl
//
// Formula: coef(n) lobe(n . h) / (4 wi . h) (energy) or lobe(n . h) (none)
// Source: Blinn 1977; Torrance & Sparrow 1967 (microfacet form); seed 001 (coef by Int(n))
// Note: ops are the wrapper's, add the lobe's; albedo <= 1 with norm = energy; f32: cos_h rounded once to f32 moves flog-normalized-clamped near its zero by up to 0.3, times coef(n) / (4 wi.h): 265 at n = 10000 (check --full); 2 for flog-normalized
// Parameters (this export: lobe = pow, n = 20, norm = energy):
//   lobe: lobe id (one of pow, schlick, schlick-modified, gauss, flog, flog-normalized, flog-normalized-clamped, cubic, cubic3, rational, cubic-rational, power4, power8, power16, sg, ue4-phong-approx, power4-tuned, power8-tuned, power16-tuned, sg-tuned, cubic-rational-tuned, default pow)
//   n: specular exponent (range [1, 10000], default 20)
//   norm: energy: coef(n) = 1 / (2 pi Int(n)); none: the bare lobe (one of energy, none, default energy)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 6e2 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_blinn_phong(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

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

FbPair fb_pair(vec3 wi_in, vec3 wo_in) {
    float li = dot(wi_in, wi_in);
    float lo = dot(wo_in, wo_in);
    vec3 wi_1 = (wi_in * (1.0 / sqrt(li)));
    vec3 wo_1 = (wo_in * (1.0 / sqrt(lo)));
    vec3 s = (wi_1 + wo_1);
    float len = sqrt(dot(s, s));
    vec3 h = (s / vec3(len));
    bool valid = (((((li > 0.0) && (lo > 0.0)) && (wi_1.z >= FB_COS_MIN)) && (wo_1.z >= FB_COS_MIN)) && (len > 0.0));
    return FbPair(valid, wi_1.z, wo_1.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_1, wo_1);
}

float fb_lobe_pow(float c_1, float n) {
    float _e2 = fb_clamp01_(c_1);
    return ((_e2 > 0.0) ? pow(_e2, n) : 0.0);
}

float fb_blinn_phong(vec3 wi, vec3 wo) {
    FbPair _e2 = fb_pair(wi, wo);
    float _e7 = fb_lobe_pow(_e2.h.z, 20.0);
    float v = ((3.5014088 * _e7) / (4.0 * _e2.cos_ih));
    return (_e2.valid ? v : 0.0);
}
