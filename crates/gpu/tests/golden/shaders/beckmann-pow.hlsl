// fastbrdf 0.1.0 (distribution): beckmann-pow
// Made by: fastbrdf shader --model beckmann-pow --lang hlsl
//
// Formula: cos^(2/m^2 - 4) theta_h / (4 m^2)
// Source: seed 000 ('one function' D)
// Note: unbounded as cos theta_h -> 0 for m > 1/sqrt(2) (negative exponent), by the seed's construction
// Parameters (this export: alpha = 0.3):
//   alpha: RMS microfacet slope m (range [0.005, 1], default 0.3)
// Documented error bounds (measured by `fastbrdf check`):
//   beckmann-pow vs beckmann-ct: max rel error <= 0.403 over alpha in [0.05, 0.6], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 4.65 over alpha in [0.05, 1], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 0.403 over alpha in [0.005, 0.6], epicentre (reference >= half its peak)
//   beckmann-pow vs beckmann-ct: max rel error <= 4.65 over alpha in [0.005, 1], epicentre (reference >= half its peak)
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_beckmann_pow(cos_h) with cos_h = n.h; returns f32.

static const float FB_COS_MIN = 9.536743e-7;

float fb_log2_(float x)
{
    float t = ((x - 1.0) / (x + 1.0));
    float t2_ = (t * t);
    float s = (t * (2.0 + (t2_ * (0.6666667 + (t2_ * (0.4 + (t2_ * (0.2857143 + (t2_ * (0.22222222 + (t2_ * (0.18181819 + (t2_ * 0.15384614)))))))))))));
    return ((x >= 0.5) ? (s * 1.442695) : log2(x));
}

float fb_powr(float x_1, float y)
{
    const float _e4 = fb_log2_(max(x_1, 1e-30));
    return ((x_1 > 0.0) ? exp2((y * _e4)) : 0.0);
}

float fb_d_beckmann_pow(float c, float e, float scale)
{
    const float _e3 = fb_powr(c, e);
    return (scale * _e3);
}

float fb_beckmann_pow(float cos_h)
{
    float cc = min(cos_h, 1.0);
    const float _e5 = fb_d_beckmann_pow(cc, 18.222221, 2.7777777);
    return ((cos_h >= FB_COS_MIN) ? _e5 : 0.0);
}
