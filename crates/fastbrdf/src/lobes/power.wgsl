// WGSL twin of lobes/power.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).
// "The header" in the doc comment below is lobes/mod.wgsl's.

/// power4/8/16 (seed 000's (1 + x/g)^g): max(1 + s (c - 1), 0)^g with s = n / g (tuned: s
/// from a minimax fit, fastbrdf::lobes::tuned), written 1 - s (1 - c): not the lerp shape
/// `1 + t (c - 1)` (see the header), and exactly 1 at c = 1. Cost: 1 mul, 2 add, log2(g) mul.
fn fb_lobe_power4(c: f32, s: f32) -> f32 {
    return fb_pow4(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

fn fb_lobe_power8(c: f32, s: f32) -> f32 {
    return fb_pow8(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}

fn fb_lobe_power16(c: f32, s: f32) -> f32 {
    return fb_pow16(max(1.0 - s * (1.0 - fb_clamp01(c)), 0.0));
}
