// fastbrdf 0.1.0 (shadowing): neumann
// Made by: fastbrdf shader --model neumann --lang glsl --runtime-params
//
// Formula: G = NL NV / max(NL, NV) = min(NL, NV)
// Source: Neumann, Neumann & Szirmay-Kalos 1999, "Compact Metallic Reflectance Models"
// Note: one-sided (no cos_l): NV; no roughness parameter, so no exact twin
// Parameters (this export: no parameters):
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-7 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_neumann(cos_v, cos_l, cos_h, cos_vh): n.v, n.l, n.h, v.h; two-sided; returns f32.
// V form: fb_neumann_v, the same arguments, returns V = G / (4 cos_v cos_l), the visibility term engines multiply by D and F with no further denominator (Filament's V_SmithGGXCorrelated, Unreal's Vis_*).

float fb_g_neumann(float cos_v, float cos_l) {
    return min(min(cos_v, cos_l), 1.0);
}

float fb_neumann(float cos_v_1, float cos_l_1, float cos_h, float cos_vh) {
    float _e4 = fb_g_neumann(cos_v_1, cos_l_1);
    return (((cos_v_1 > 0.0) && (cos_l_1 > 0.0)) ? _e4 : 0.0);
}

float fb_neumann_v(float cos_v_2, float cos_l_2, float cos_h_1, float cos_vh_1) {
    float _e4 = fb_neumann(cos_v_2, cos_l_2, cos_h_1, cos_vh_1);
    return ((_e4 > 0.0) ? (_e4 / max(((4.0 * cos_v_2) * cos_l_2), 1.1754944e-38)) : 0.0);
}
