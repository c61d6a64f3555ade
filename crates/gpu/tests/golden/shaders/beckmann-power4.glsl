// fastbrdf 0.1.0 (distribution): beckmann-power4
// Made by: fastbrdf shader --model beckmann-power4 --lang glsl
//
// Formula: max(0, 1 + ((2/m^2 - 4)/4)(cos theta_h - 1))^4 / (4 m^2)
// Source: seed 000 (D4, D8, D16); Lyon 1993
// Note: f32: 4.6e-6 (power4; check --full, alpha down to 0.005)
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   beckmann-power4 vs beckmann-ct: max rel error <= 0.438 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   beckmann-power4 vs beckmann-ct: max rel error <= 2.37 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   beckmann-power4 vs beckmann-ct: max rel error <= 0.438 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   beckmann-power4 vs beckmann-ct: max rel error <= 2.37 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 8e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_beckmann_power4_(cos_h) with cos_h = n.h; returns f32.

const float FB_COS_MIN = 9.536743e-7;


float fb_pow4_(float x) {
    float x2_ = (x * x);
    return (x2_ * x2_);
}

float fb_d_beckmann_power4_(float c, float s2_, float s, float scale) {
    float _e13 = fb_pow4_(max((1.0 + (s * (-(s2_) / (1.0 + c)))), 0.0));
    return (scale * _e13);
}

float fb_beckmann_power4_(float cos_h) {
    float cc = min(cos_h, 1.0);
    float _e10 = fb_d_beckmann_power4_(cc, ((1.0 - cc) * (1.0 + cc)), 4.5555553, 2.7777777);
    return ((cos_h >= FB_COS_MIN) ? _e10 : 0.0);
}
