// WGSL twin of microfacet/beckmann_pow.rs (see microfacet/mod.wgsl).

/// beckmann-pow (seed 000): scale cos^e, e = 2 / alpha^2 - 4 (one power instead of exp;
/// fb_powr, accurate near cos = 1 where e reaches 19996 at alpha = 0.01).
fn fb_d_beckmann_pow(c: f32, e: f32, scale: f32) -> f32 {
    return scale * fb_powr(c, e);
}

/// beckmann-power4/8/16 (seed 000): scale max(1 + s (cos - 1), 0)^g, s = (2 / alpha^2 - 4) / g;
/// cos - 1 computed as -sin^2 / (1 + cos) (no cancellation).
fn fb_d_beckmann_power4(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow4(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}

fn fb_d_beckmann_power8(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow8(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}

fn fb_d_beckmann_power16(c: f32, s2: f32, s: f32, scale: f32) -> f32 {
    return scale * fb_pow16(max(1.0 + s * (-s2 / (1.0 + c)), 0.0));
}
