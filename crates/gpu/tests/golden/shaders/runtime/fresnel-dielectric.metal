// fastbrdf 0.1.0 (fresnel): fresnel-dielectric
// Made by: fastbrdf shader --model fresnel-dielectric --lang msl --runtime-params
//
// Formula: (r_par^2 + r_perp^2) / 2, exact, with total internal reflection
// Source: Fresnel equations; pbrt-v3 FrDielectric
// Parameters (this export: eta = 1.5):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_eta (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_fresnel_dielectric(cos_vh) with cos_vh = v.h, then p_eta; returns f32.

// language: metal2.0
#include <metal_stdlib>
#include <simd/simd.h>

using metal::uint;


float fb_f_dielectric_e(
    float c_in,
    float eta,
    float e
) {
    float c = (c_in >= 0.00000000000000000086736174) ? metal::min(c_in, 1.0) : 0.00000000000000000086736174;
    float c2_ = c * c;
    float s = metal::sqrt(metal::max(-(e), 0.0));
    float g2_ = (e < 0.0) ? ((c - s) * (c + s)) : (e + c2_);
    float g = metal::sqrt(metal::max(g2_, 0.0));
    float eta2_ = eta * eta;
    float d_perp = c + g;
    float r_perp = -(e) / (d_perp * d_perp);
    float d_par = (eta2_ * c) + g;
    float sin2_ = (1.0 - c) * (1.0 + c);
    float brewster = (e < 0.0) ? (g2_ - (eta2_ * sin2_)) : ((eta2_ * c2_) - sin2_);
    float r_par = (e * brewster) / (d_par * d_par);
    float f = metal::min(((r_par * r_par) + (r_perp * r_perp)) * 0.5, 1.0);
    return (g2_ <= 0.0) ? 1.0 : f;
}

float fb_fresnel_dielectric(
    float cos_vh,
    float p_eta
) {
    float c_1 = metal::max(cos_vh, 0.0);
    float _e9 = fb_f_dielectric_e(c_1, p_eta, (p_eta - 1.0) * (p_eta + 1.0));
    return _e9;
}
