// WGSL twin of microfacet/smith_ggx.rs (see microfacet/mod.wgsl).

/// sqrt(1 + alpha^2 tan^2) = sqrt(c^2 + alpha^2 (1 - c)(1 + c)) / c, for the GGX Smith terms
/// (1 + Lambda = (1 + S) / 2; no S - 1 is formed).
fn fb_ggx_s(c: f32, alpha2: f32) -> f32 {
    let s2 = (1.0 - c) * (1.0 + c);
    return sqrt(c * c + alpha2 * s2) / c;
}

/// smith-ggx (Walter et al. 2007, eq. 34): G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)); 1 at c >= 1.
fn fb_g1_smith_ggx(c: f32, alpha2: f32) -> f32 {
    return select(2.0 / (1.0 + fb_ggx_s(c, alpha2)), 1.0, c >= 1.0);
}

/// smith-ggx-correlated (Heitz 2014, eq. 99): 1 / (1 + Lambda(v) + Lambda(l)) = 2 / (S(v) + S(l)).
fn fb_g_smith_ggx_correlated(cos_v: f32, cos_l: f32, alpha2: f32) -> f32 {
    let v = min(cos_v, 1.0);
    let l = min(cos_l, 1.0);
    return 2.0 / (fb_ggx_s(v, alpha2) + fb_ggx_s(l, alpha2));
}

/// The smallest normal f32, for the fast forms' underflowed denominators (0, not NaN).
const FB_F32_MIN_NORMAL: f32 = 1.1754943508222875e-38;

/// smith-ggx-correlated-fast (Hammon 2017, Filament's mix form): 4 NL NV V,
/// V = 0.5 / mix(2 NL NV, NL + NV, alpha); om = 1 - alpha.
fn fb_g_smith_ggx_correlated_fast(cos_v: f32, cos_l: f32, alpha: f32, om: f32) -> f32 {
    let v = min(cos_v, 1.0);
    let l = min(cos_l, 1.0);
    let two_vl = 2.0 * (v * l);
    let den = two_vl * om + (v + l) * alpha;
    return two_vl / max(den, FB_F32_MIN_NORMAL);
}

/// smith-ggx-joint-approx (Unreal's Vis_SmithJointApprox, the same function as Hammon's):
/// 4 NL NV V, V = 0.5 / (NL (NV (1 - a) + a) + NV (NL (1 - a) + a)); om = 1 - a.
fn fb_g_smith_ggx_joint_approx(cos_v: f32, cos_l: f32, a: f32, om: f32) -> f32 {
    let v = min(cos_v, 1.0);
    let l = min(cos_l, 1.0);
    let vis_v = l * (v * om + a);
    let vis_l = v * (l * om + a);
    return 2.0 * (v * l) / max(vis_v + vis_l, FB_F32_MIN_NORMAL);
}

/// schlick-ggx (Schlick 1994; Karis 2013): G1 = c / (c (1 - k) + k); om = 1 - k; 1 at c >= 1.
fn fb_g1_schlick_ggx(c: f32, k: f32, om: f32) -> f32 {
    return select(c / (c * om + k), 1.0, c >= 1.0);
}
