// fastbrdf 0.1.0 (fresnel): fresnel-schlick
// Made by: fastbrdf shader --model fresnel-schlick --lang wgsl
//
// Formula: f0 + (f90 - f0)(1 - cos)^5
// Source: Schlick 1994 (f90: Filament's F_Schlick)
// Parameters (this export: f0 = 0.04, f90 = 1):
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_schlick(cos_vh) with cos_vh = v.h; returns f32.

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
/// Source: Schlick 1994 (f90: Filament's F_Schlick). Instance: f0 = 0.04, f90 = 1.
fn fb_fresnel_schlick(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_schlick(c, 0.04f, 1.0f);
}
