// fastbrdf 0.1.0 (distribution): beckmann
// Made by: fastbrdf shader --model beckmann --lang glsl
//
// Formula: exp(-tan^2 theta_h / alpha^2) / (pi alpha^2 cos^4 theta_h)
// Source: Beckmann & Spizzichino 1963; Walter et al. 2007 (normalisation of Mitsuba 3, pbrt)
// Note: integral of D cos theta_h over the hemisphere = 1; f32: 1.4e-6 at alpha = 0.01; anisotropic: cook-torrance's alpha_x, alpha_y
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 3e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_beckmann(cos_h) with cos_h = n.h; returns f32.

const float FB_COS_MIN = 9.536743e-7;


float fb_d_beckmann(float c, float s2_, float inv_alpha2_, float scale) {
    float inv_c2_ = (1.0 / (c * c));
    return ((scale * exp((-((s2_ * inv_c2_)) * inv_alpha2_))) * (inv_c2_ * inv_c2_));
}

float fb_beckmann(float cos_h) {
    float cc = min(cos_h, 1.0);
    float _e10 = fb_d_beckmann(cc, ((1.0 - cc) * (1.0 + cc)), 11.111111, 3.5367765);
    return ((cos_h >= FB_COS_MIN) ? _e10 : 0.0);
}
