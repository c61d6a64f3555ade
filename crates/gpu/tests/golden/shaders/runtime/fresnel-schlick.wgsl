// fastbrdf 0.1.0 (fresnel): fresnel-schlick
// Made by: fastbrdf shader --model fresnel-schlick --lang wgsl --runtime-params
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

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// fresnel-schlick (Schlick 1994): f0 + (f90 - f0)(1 - c)^5.
fn fb_f_schlick(c: f32, f0: f32, f90: f32) -> f32 {
    let m = 1.0 - fb_clamp01(c);
    let m2 = m * m;
    return f0 + (f90 - f0) * (m2 * m2 * m);
}

/// fresnel-schlick: f0 + (f90 - f0)(1 - cos)^5
/// Source: Schlick 1994 (f90: Filament's F_Schlick). Instance: runtime parameters p_f0, p_f90; fixed: no parameters.
fn fb_fresnel_schlick(cos_vh: f32, p_f0: f32, p_f90: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_schlick(c, (p_f0), (p_f90));
}
