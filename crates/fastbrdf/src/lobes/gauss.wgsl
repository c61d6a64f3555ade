// WGSL twin of lobes/gauss.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// gauss: exp(-(n/2) acos(c)^2), the Gaussian lobe. half_n = n / 2.
fn fb_lobe_gauss(c: f32, half_n: f32) -> f32 {
    let t = fb_acos(fb_clamp01(c));
    return exp(-half_n * (t * t));
}
