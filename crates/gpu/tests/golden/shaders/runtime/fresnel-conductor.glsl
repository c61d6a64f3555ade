// fastbrdf 0.1.0 (fresnel): fresnel-conductor
// Made by: fastbrdf shader --model fresnel-conductor --lang glsl --runtime-params
//
// Formula: (R_s + R_p) / 2 for complex index eta + i k, exact
// Source: Fresnel equations; pbrt-v3 FrConductor
// Parameters (this export: eta = 1.5, k = 0):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
//   k: extinction coefficient (imaginary part of the index, conductors) (range [0, 20], default 0)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_eta, p_k (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_fresnel_conductor(cos_vh) with cos_vh = v.h, then p_eta, then p_k; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_f_conductor(float c_in, float eta, float k) {
    float c_1 = ((c_in >= 8.6736174e-19) ? min(c_in, 1.0) : 8.6736174e-19);
    float c2_ = (c_1 * c_1);
    float s2_ = ((1.0 - c_1) * (1.0 + c_1));
    float p = ((k * k) + ((1.0 - eta) * (1.0 + eta)));
    float sp = sqrt(max(p, 0.0));
    float t0_ = ((p > 0.0) ? ((c_1 - sp) * (c_1 + sp)) : ((((eta - 1.0) * (eta + 1.0)) - (k * k)) + c2_));
    float ek = ((2.0 * eta) * k);
    float at0_ = abs(t0_);
    float den = (sqrt(((t0_ * t0_) + (ek * ek))) + at0_);
    float q = ((den > 0.0) ? (((0.5 * ek) * ek) / den) : 0.0);
    float big = (at0_ + q);
    float a2_ = ((t0_ >= 0.0) ? big : q);
    float b2_ = ((t0_ >= 0.0) ? q : big);
    float a = sqrt(a2_);
    float rs = ((((a - c_1) * (a - c_1)) + b2_) / (((a + c_1) * (a + c_1)) + b2_));
    float bc2_ = (b2_ * c2_);
    float ac = (a * c_1);
    float rp = ((rs * (((ac - s2_) * (ac - s2_)) + bc2_)) / (((ac + s2_) * (ac + s2_)) + bc2_));
    float _e88 = fb_clamp01_(((rp + rs) * 0.5));
    return _e88;
}

float fb_fresnel_conductor(float cos_vh, float p_eta, float p_k) {
    float c_2 = max(cos_vh, 0.0);
    float _e5 = fb_f_conductor(c_2, p_eta, p_k);
    return _e5;
}
