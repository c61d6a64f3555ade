// fastbrdf 0.1.0 (fresnel): fresnel-none
// Made by: fastbrdf shader --model fresnel-none --lang hlsl
//
// Formula: 1
// Source: -
// Parameters (this export: no parameters):
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_none(cos_vh) with cos_vh = v.h; returns f32.

float fb_fresnel_none(float cos_vh)
{
    float c = max(cos_vh, 0.0);
    return 1.0;
}
