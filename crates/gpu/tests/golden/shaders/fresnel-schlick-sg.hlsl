// fastbrdf 0.1.0 (fresnel): fresnel-schlick-sg
// Made by: fastbrdf shader --model fresnel-schlick-sg --lang hlsl
//
// Formula: f0 + (f90 - f0) 2^((-5.55473 cos - 6.98316) cos)
// Source: Karis 2013, Real Shading in Unreal Engine 4 (spherical-Gaussian Schlick)
// Parameters (this export: f0 = 0.04, f90 = 1):
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
// Documented error bounds (measured by `fastbrdf check`):
//   fresnel-schlick-sg vs fresnel-schlick: max abs error (relative to the peak) <= 0.00378 over f0 in [0, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_schlick_sg(cos_vh) with cos_vh = v.h; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_f_schlick_sg(float c_in, float f0_, float f90_, float a, float b)
{
    const float _e5 = fb_clamp01_(c_in);
    return (f0_ + ((f90_ - f0_) * exp2((((a * _e5) + b) * _e5))));
}

float fb_fresnel_schlick_sg(float cos_vh)
{
    float c_1 = max(cos_vh, 0.0);
    const float _e7 = fb_f_schlick_sg(c_1, 0.04, 1.0, -5.55473, -6.98316);
    return _e7;
}
