// fastbrdf 0.1.0 (fresnel): fresnel-none
// Made by: fastbrdf shader --model fresnel-none --lang wgsl --runtime-params
//
// Formula: 1
// Source: -
// Parameters (this export: no parameters):
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_fresnel_none(cos_vh) with cos_vh = v.h; returns f32.


/// fresnel-none: 1
/// Source: -. Instance: runtime parameters none; fixed: no parameters.
fn fb_fresnel_none(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return 1.0f;
}
