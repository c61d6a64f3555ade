// fastbrdf 0.1.0 (brdf): cook-torrance
// Made by: fastbrdf shader --model cook-torrance --param d=ggx --param alpha=0.2 --param f=conductor --param eta=0.18299,0.42108,1.3734 --param k=3.4242,2.3459,1.7704 --lang glsl
//
// Formula: F(wi.h) D(h) G(wi, wo) / (4 cos_i cos_o) [+ Kulla-Conty's f_ms | x Filament's 1 + F(1) (1 / E(cos_o) - 1)]
// Source: Cook & Torrance 1982; Walter et al. 2007; seeds 000 and 001 (denominators)
// Note: ops exclude D, G, F and the pair set-up; equals Mitsuba 3 roughconductor eval / cos_o; f32: 1e-5 except with f = dielectric/conductor at eta << 1, where F is a near-step at the critical angle and wi.h rounded once to f32 can double it (1.0 at eta = 0.01); anisotropic (alpha_x, alpha_y, d = beckmann(-ct)/ggx, a Smith g): f32 1.4e-6 measured with f = none/schlick (1e-5 documented)
// Parameters (this export: alpha = 0.2, d = ggx, denominator = 4, eta = 0.18299, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 3.4242, ms = none, remap = alpha-half):
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
// Entry: fb_cook_torrance_rgb(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns a 3-vector (R, G, B).
// Colour: per-channel parameters make three grey instances, fb_cook_torrance_r, fb_cook_torrance_g, fb_cook_torrance_b (channels R, G, B at 650, 550, 450 nm; the parameters above are the R channel's), and fb_cook_torrance_rgb with the same inputs, returning the three as a vector.
//   R (650 nm): alpha = 0.2, d = ggx, denominator = 4, eta = 0.18299, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 3.4242, ms = none, remap = alpha-half
//   G (550 nm): alpha = 0.2, d = ggx, denominator = 4, eta = 0.42108, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 2.3459, ms = none, remap = alpha-half
//   B (450 nm): alpha = 0.2, d = ggx, denominator = 4, eta = 1.3734, f = conductor, f0 = 0.04, f90 = 1, g = smith-ggx, k = 1.7704, ms = none, remap = alpha-half

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
    vec3 wi_4 = (_e2 * (1.0 / sqrt(li)));
    vec3 wo_4 = (_e3 * (1.0 / sqrt(lo)));
    vec3 s = (wi_4 + wo_4);
    float len = sqrt(dot(s, s));
    vec3 h = (s / vec3(len));
    bool valid = (((((li > 0.0) && (lo > 0.0)) && (wi_4.z >= FB_COS_MIN)) && (wo_4.z >= FB_COS_MIN)) && (len > 0.0));
    return FbPair(valid, wi_4.z, wo_4.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_4, wo_4);
}

float fb_d_ggx(float c_1, float s2_, float alpha2_, float scale) {
    float t = ((alpha2_ * (c_1 * c_1)) + s2_);
    return (scale / (t * t));
}

float fb_ggx_s(float c_2, float alpha2_1) {
    float s2_1 = ((1.0 - c_2) * (1.0 + c_2));
    return (sqrt(((c_2 * c_2) + (alpha2_1 * s2_1))) / c_2);
}

float fb_g1_smith_ggx(float c_3, float alpha2_2) {
    float _e2 = fb_ggx_s(c_3, alpha2_2);
    return ((c_3 >= 1.0) ? 1.0 : (2.0 / (1.0 + _e2)));
}

float fb_f_conductor(float c_in, float eta, float k) {
    float c_4 = ((c_in >= 8.6736174e-19) ? min(c_in, 1.0) : 8.6736174e-19);
    float c2_ = (c_4 * c_4);
    float s2_2 = ((1.0 - c_4) * (1.0 + c_4));
    float p = ((k * k) + ((1.0 - eta) * (1.0 + eta)));
    float sp = sqrt(max(p, 0.0));
    float t0_ = ((p > 0.0) ? ((c_4 - sp) * (c_4 + sp)) : ((((eta - 1.0) * (eta + 1.0)) - (k * k)) + c2_));
    float ek = ((2.0 * eta) * k);
    float at0_ = abs(t0_);
    float den = (sqrt(((t0_ * t0_) + (ek * ek))) + at0_);
    float q = ((den > 0.0) ? (((0.5 * ek) * ek) / den) : 0.0);
    float big = (at0_ + q);
    float a2_ = ((t0_ >= 0.0) ? big : q);
    float b2_ = ((t0_ >= 0.0) ? q : big);
    float a = sqrt(a2_);
    float rs = ((((a - c_4) * (a - c_4)) + b2_) / (((a + c_4) * (a + c_4)) + b2_));
    float bc2_ = (b2_ * c2_);
    float ac = (a * c_4);
    float rp = ((rs * (((ac - s2_2) * (ac - s2_2)) + bc2_)) / (((ac + s2_2) * (ac + s2_2)) + bc2_));
    float _e88 = fb_clamp01_(((rp + rs) * 0.5));
    return _e88;
}

float fb_cook_torrance_r(vec3 wi, vec3 wo) {
    FbPair _e2 = fb_pair(wi, wo);
    float _e8 = fb_d_ggx(_e2.h.z, _e2.sin2_h, 0.04, 0.012732396);
    float d = ((_e2.h.z >= FB_COS_MIN) ? _e8 : 0.0);
    float _e17 = fb_g1_smith_ggx(_e2.cos_o, 0.04);
    float _e20 = fb_g1_smith_ggx(_e2.cos_i, 0.04);
    float g = (_e17 * _e20);
    float _e25 = fb_f_conductor(_e2.cos_ih, 0.18299, 3.4242);
    float v_1 = ((((_e25 * d) * g) * 0.25) / (_e2.cos_i * _e2.cos_o));
    return (_e2.valid ? v_1 : 0.0);
}

float fb_cook_torrance_g(vec3 wi_1, vec3 wo_1) {
    FbPair _e2 = fb_pair(wi_1, wo_1);
    float _e8 = fb_d_ggx(_e2.h.z, _e2.sin2_h, 0.04, 0.012732396);
    float d_1 = ((_e2.h.z >= FB_COS_MIN) ? _e8 : 0.0);
    float _e17 = fb_g1_smith_ggx(_e2.cos_o, 0.04);
    float _e20 = fb_g1_smith_ggx(_e2.cos_i, 0.04);
    float g_1 = (_e17 * _e20);
    float _e25 = fb_f_conductor(_e2.cos_ih, 0.42108, 2.3459);
    float v_2 = ((((_e25 * d_1) * g_1) * 0.25) / (_e2.cos_i * _e2.cos_o));
    return (_e2.valid ? v_2 : 0.0);
}

float fb_cook_torrance_b(vec3 wi_2, vec3 wo_2) {
    FbPair _e2 = fb_pair(wi_2, wo_2);
    float _e8 = fb_d_ggx(_e2.h.z, _e2.sin2_h, 0.04, 0.012732396);
    float d_2 = ((_e2.h.z >= FB_COS_MIN) ? _e8 : 0.0);
    float _e17 = fb_g1_smith_ggx(_e2.cos_o, 0.04);
    float _e20 = fb_g1_smith_ggx(_e2.cos_i, 0.04);
    float g_2 = (_e17 * _e20);
    float _e25 = fb_f_conductor(_e2.cos_ih, 1.3734, 1.7704);
    float v_3 = ((((_e25 * d_2) * g_2) * 0.25) / (_e2.cos_i * _e2.cos_o));
    return (_e2.valid ? v_3 : 0.0);
}

vec3 fb_cook_torrance_rgb(vec3 wi_3, vec3 wo_3) {
    float _e2 = fb_cook_torrance_r(wi_3, wo_3);
    float _e3 = fb_cook_torrance_g(wi_3, wo_3);
    float _e4 = fb_cook_torrance_b(wi_3, wo_3);
    return vec3(_e2, _e3, _e4);
}
