// fastbrdf 0.1.0 (fresnel): fresnel-schlick
// Made by: fastbrdf shader --model fresnel-schlick --lang glsl
//
// Formula: f0 + (f90 - f0)(1 - cos)^5
// Source: Schlick 1994 (f90: Filament's F_Schlick)
// Parameters (this export: f0 = 0.04, f90 = 1):
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_schlick(cos_vh) with cos_vh = v.h; returns f32.

float fb_clamp01_(float c) {
    return min(max(c, 0.0), 1.0);
}

float fb_f_schlick(float c_1, float f0_, float f90_) {
    float _e3 = fb_clamp01_(c_1);
    float m = (1.0 - _e3);
    float m2_ = (m * m);
    return (f0_ + ((f90_ - f0_) * ((m2_ * m2_) * m)));
}

float fb_fresnel_schlick(float cos_vh) {
    float c_2 = max(cos_vh, 0.0);
    float _e5 = fb_f_schlick(c_2, 0.04, 1.0);
    return _e5;
}
