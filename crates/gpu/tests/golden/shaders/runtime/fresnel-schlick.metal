// fastbrdf 0.1.0 (fresnel): fresnel-schlick
// Made by: fastbrdf shader --model fresnel-schlick --lang msl --runtime-params
//
// Formula: f0 + (f90 - f0)(1 - cos)^5
// Source: Schlick 1994 (f90: Filament's F_Schlick)
// Parameters (this export: f0 = 0.04, f90 = 1):
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_f0, p_f90 (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_fresnel_schlick(cos_vh) with cos_vh = v.h, then p_f0, then p_f90; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_clamp01_(
    float c
) {
    return metal::min(metal::max(c, 0.0), 1.0);
}

float fb_f_schlick(
    float c_1,
    float f0_,
    float f90_
) {
    float _e3 = fb_clamp01_(c_1);
    float m = 1.0 - _e3;
    float m2_ = m * m;
    return f0_ + ((f90_ - f0_) * ((m2_ * m2_) * m));
}

float fb_fresnel_schlick(
    float cos_vh,
    float p_f0_,
    float p_f90_
) {
    float c_2 = metal::max(cos_vh, 0.0);
    float _e5 = fb_f_schlick(c_2, p_f0_, p_f90_);
    return _e5;
}
