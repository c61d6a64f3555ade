// fastbrdf 0.1.0 (fresnel): fresnel-dielectric
// Made by: fastbrdf shader --model fresnel-dielectric --lang glsl
//
// Formula: (r_par^2 + r_perp^2) / 2, exact, with total internal reflection
// Source: Fresnel equations; pbrt-v3 FrDielectric
// Parameters (this export: eta = 1.5):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_fresnel_dielectric(cos_vh) with cos_vh = v.h; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_f_dielectric(float c_in, float eta) {
    float _e2 = fb_clamp01_(c_in);
    float sin2_t = ((1.0 - (_e2 * _e2)) / (eta * eta));
    float cos_t = sqrt(max((1.0 - sin2_t), 0.0));
    float r_par = (((eta * _e2) - cos_t) / ((eta * _e2) + cos_t));
    float r_perp = ((_e2 - (eta * cos_t)) / (_e2 + (eta * cos_t)));
    float f = (((r_par * r_par) + (r_perp * r_perp)) * 0.5);
    return ((sin2_t >= 1.0) ? 1.0 : f);
}

float fb_fresnel_dielectric(float cos_vh) {
    float c_1 = max(cos_vh, 0.0);
    float _e4 = fb_f_dielectric(c_1, 1.5);
    return _e4;
}
