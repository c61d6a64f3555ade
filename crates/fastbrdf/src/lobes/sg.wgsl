// WGSL twin of lobes/sg.rs (how lobes are arranged for the GPU: lobes/mod.wgsl).

/// sg, sg-tuned, ue4-phong-approx: 2^(k (c - 1)), the spherical Gaussian. sg: k = n / ln 2;
/// ue4-phong-approx: k = 1.4427 (n + 0.775) (Karis 2013). Cost: 1 mul, 1 add, 1 exp2.
fn fb_lobe_exp2(c: f32, k: f32) -> f32 {
    return exp2(k * (fb_clamp01(c) - 1.0));
}
