// fastbrdf 0.1.0 (distribution): ggx
// Made by: fastbrdf shader --model ggx --lang hlsl
//
// Formula: alpha^2 / (pi cos^4 theta_h (alpha^2 + tan^2 theta_h)^2) = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2)
// Source: Trowbridge & Reitz 1975; Walter et al. 2007, eq. 33 (GGX)
// Note: integral of D cos theta_h over the hemisphere = 1; no cancellation at small alpha (alpha^2 cos^2 + sin^2); anisotropic: cook-torrance's alpha_x, alpha_y
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_ggx(cos_h) with cos_h = n.h; returns f32.

static const float FB_COS_MIN = 9.536743e-7;

float fb_d_ggx(float c, float s2_, float alpha2_, float scale)
{
    float t = ((alpha2_ * (c * c)) + s2_);
    return (scale / (t * t));
}

float fb_ggx(float cos_h)
{
    float cc = min(cos_h, 1.0);
    const float _e10 = fb_d_ggx(cc, ((1.0 - cc) * (1.0 + cc)), 0.09, 0.02864789);
    return ((cos_h >= FB_COS_MIN) ? _e10 : 0.0);
}
