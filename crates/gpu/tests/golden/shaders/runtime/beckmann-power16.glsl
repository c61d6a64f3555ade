// fastbrdf 0.1.0 (distribution): beckmann-power16
// Made by: fastbrdf shader --model beckmann-power16 --lang glsl --runtime-params
//
// Formula: max(0, 1 + ((2/m^2 - 4)/16)(cos theta_h - 1))^16 / (4 m^2)
// Source: seed 000 (D4, D8, D16); Lyon 1993
// Note: f32: 4.6e-6 (power4; check --full, alpha down to 0.005)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   beckmann-power16 vs beckmann-ct: max rel error <= 0.452 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   beckmann-power16 vs beckmann-ct: max rel error <= 2.65 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   beckmann-power16 vs beckmann-ct: max rel error <= 0.452 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   beckmann-power16 vs beckmann-ct: max rel error <= 2.65 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 8e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_alpha (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_beckmann_power16_(cos_h) with cos_h = n.h, then p_alpha; returns f32.

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

float fb_d_beckmann_power16_(float c, float s2_, float s, float scale) {
    float _e13 = fb_pow16_(max((1.0 + (s * (-(s2_) / (1.0 + c)))), 0.0));
    return (scale * _e13);
}

float fb_beckmann_power16_(float cos_h, float p_alpha) {
    float cc = min(cos_h, 1.0);
    float _e19 = fb_d_beckmann_power16_(cc, ((1.0 - cc) * (1.0 + cc)), (((2.0 / (p_alpha * p_alpha)) - 4.0) / 16.0), (0.25 / (p_alpha * p_alpha)));
    return ((cos_h >= FB_COS_MIN) ? _e19 : 0.0);
}
