// fastbrdf 0.1.0 (fresnel): fresnel-schlick-sg-tuned
// Made by: fastbrdf shader --model fresnel-schlick-sg-tuned --lang wgsl --runtime-params
//
// Formula: f0 + (f90 - f0) 2^((a cos + b) cos), a, b minimax against (1 - cos)^5
// Source: this project: Karis's form refitted (fit_fresnel_sg example)
// Parameters (this export: f0 = 0.04, f90 = 1):
//   f0: reflectance at normal incidence (Schlick) (range [0, 1], default 0.04)
//   f90: reflectance at grazing incidence (Schlick; 1 is Schlick's own form) (range [0, 1], default 1)
// Documented error bounds (measured by `fastbrdf check`):
//   fresnel-schlick-sg-tuned vs fresnel-schlick: max abs error (relative to the peak) <= 0.00341 over f0 in [0, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: p_f0, p_f90 (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_fresnel_schlick_sg_tuned(cos_vh) with cos_vh = v.h, then p_f0, then p_f90; returns f32.

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

/// fresnel-schlick-sg-tuned: f0 + (f90 - f0) 2^((a cos + b) cos), a, b minimax against (1 - cos)^5
/// Source: this project: Karis's form refitted (fit_fresnel_sg example). Instance: runtime parameters p_f0, p_f90; fixed: no parameters.
fn fb_fresnel_schlick_sg_tuned(cos_vh: f32, p_f0: f32, p_f90: f32) -> f32 {
    let c = max(cos_vh, 0.0);
    return fb_f_schlick_sg(c, (p_f0), (p_f90), -5.551343f, -6.99612f);
}
