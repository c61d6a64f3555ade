// WGSL twin of lobes/pow.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// pow: c^n, the Phong/Blinn-Phong reference (Phong 1975), as fb_powr (exp2 of n fb_log2(c),
/// not WGSL's pow, whose log2 near 1 cost about 2n ulp: 6.4e-4 at n = 10000 on lavapipe, and
/// issue 11 reported the same on real GPUs). Cost: 1 exp2, 1 log2 (fb_log2's branch below
/// 0.5, evaluated by the select), 1 div, 10 mul, 8 add.
fn fb_lobe_pow(c: f32, n: f32) -> f32 {
    return fb_powr(fb_clamp01(c), n);
}
