// WGSL twin of lobes/schlick.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// schlick: c / (n - n c + c) (Schlick 1994). Cost: 1 mul, 2 add, 1 div.
fn fb_lobe_schlick(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    return x / (n * (1.0 - x) + x);
}

/// schlick-modified: 2 c / (1.25 (n - n c + 1.25 c)^2), as printed in seed 003 (peak 1.024).
fn fb_lobe_schlick_modified(c: f32, n: f32) -> f32 {
    let x = fb_clamp01(c);
    let d = n * (1.0 - x) + 1.25 * x;
    return 2.0 * x / (1.25 * (d * d));
}
