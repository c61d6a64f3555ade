// fastbrdf 0.1.0 (fresnel): fresnel-schlick-sg
// Made by: fastbrdf shader --model fresnel-schlick-sg --lang wgsl
//
// Formula: f0 + (f90 - f0) 2^((-5.55473 cos - 6.98316) cos)
// Source: Karis 2013, Real Shading in Unreal Engine 4 (spherical-Gaussian Schlick)
// Parameters (this export: f0 = 0.04, f90 = 1):
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
// Documented error bounds (measured by `fastbrdf check`):
//   fresnel-schlick-sg vs fresnel-schlick: max abs error (relative to the peak) <= 0.00378 over f0 in [0, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_fresnel_schlick_sg(cos_vh) with cos_vh = v.h; returns f32.

/// Clamps a cosine to [0, 1] (twin: ops::clamp01).
fn fb_clamp01(c: f32) -> f32 {
    return min(max(c, 0.0), 1.0);
}

/// fresnel-schlick-sg(-tuned) (Karis 2013): f0 + (f90 - f0) 2^((a c + b) c), a, b fixed by
/// the id (Karis's -5.55473, -6.98316, or their minimax refit).
fn fb_f_schlick_sg(c_in: f32, f0: f32, f90: f32, a: f32, b: f32) -> f32 {
    let c = fb_clamp01(c_in);
    return f0 + (f90 - f0) * exp2((a * c + b) * c);
}

/// fresnel-schlick-sg: f0 + (f90 - f0) 2^((-5.55473 cos - 6.98316) cos)
/// Source: Karis 2013, Real Shading in Unreal Engine 4 (spherical-Gaussian Schlick). Instance: f0 = 0.04, f90 = 1.
fn fb_fresnel_schlick_sg(cos_vh: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_schlick_sg(c, 0.04f, 1.0f, -5.55473f, -6.98316f);
}
