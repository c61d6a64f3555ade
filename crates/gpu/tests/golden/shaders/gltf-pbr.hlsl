// fastbrdf 0.1.0 (brdf): gltf-pbr
// Made by: fastbrdf shader --model gltf-pbr --lang hlsl
//
// Formula: mix(sheen_color D_s V_s + S [(1 - m)((1 - F_d) diffuse + F_d D G / 4 cos_i cos_o) + m F_m D G / 4 cos_i cos_o], D_c G_c / 4 cos_i cos_o, clearcoat F_c(cos_o))
// Source: glTF 2.0 Appendix B; KHR_materials_ior, _specular, _clearcoat, _sheen, _anisotropy; Estevez & Kulla 2017; Burley 2012
// Note: ops exclude D, G and F; the whole material (diffuse included): a renderer gives it kd = 0, ks = 1; f32: 3.5e-2 found by the adversarial search (tests/precision.rs) at cos 1e-6 with anisotropy, where the stretch of directions rounded to f32 dominates
// Parameters (this export: anisotropy = 0, anisotropy_rotation = 0, base_color = 1, clearcoat = 0, clearcoat_roughness = 0, d = ggx, diffuse = lambert, f = schlick, g = smith-ggx-correlated, ior = 1.5, metallic = 1, ms = none, roughness = 1, sheen_albedo = table, sheen_color = 0, sheen_roughness = 0, sheen_v = charlie, spec_albedo = fresnel, specular = 1, specular_color = 1):
//   base_color: baseColorFactor (R,G,B for a colour) (range [0, 1], default 1)
//   metallic: metallicFactor (range [0, 1], default 1)
//   roughness: roughnessFactor; alpha = max(roughness^2, 0.005) (range [0, 1], default 1)
//   ior: KHR_materials_ior: the dielectric's index of refraction (range [1, 5], default 1.5)
//   specular: KHR_materials_specular: specularFactor (range [0, 1], default 1)
//   specular_color: KHR_materials_specular: specularColorFactor (F0 colour) (range [0, 10], default 1)
//   clearcoat: KHR_materials_clearcoat: clearcoatFactor (range [0, 1], default 0)
//   clearcoat_roughness: KHR_materials_clearcoat: clearcoatRoughnessFactor (range [0, 1], default 0)
//   sheen_color: KHR_materials_sheen: sheenColorFactor (range [0, 1], default 0)
//   sheen_roughness: KHR_materials_sheen: sheenRoughnessFactor (at least 0.07 in the lobe) (range [0, 1], default 0)
//   sheen_max: max3(sheenColor), which the sheen's albedo scaling uses (set from an R,G,B sheen_color; else sheen_color) (range [0, 1], default -)
//   anisotropy: KHR_materials_anisotropy: anisotropyStrength (range [0, 1], default 0)
//   anisotropy_rotation: KHR_materials_anisotropy: anisotropyRotation (radians from the tangent, the frame's x axis) (range [-6.283185307179586, 6.283185307179586], default 0)
//   d: microfacet distribution of the base and the coat (one of ggx, beckmann, default ggx)
//   g: shadowing-masking term of the base and the coat (the exact height-correlated Smith term first, then the shortcuts engines use) (one of smith-ggx-correlated, smith-ggx-correlated-fast, smith-ggx-correlated-fast-tuned, smith-ggx-joint-approx, smith-ggx, schlick-ggx, smith, default smith-ggx-correlated)
//   f: the curve of every Schlick Fresnel term (one of schlick, schlick-sg, schlick-sg-tuned, default schlick)
//   diffuse: the base's diffuse lobe (one of lambert, burley, default lambert)
//   sheen_v: sheen visibility: Charlie's fit (Estevez and Kulla 2017) or Neubelt and Pettineo's (one of charlie, neubelt, default charlie)
//   spec_albedo: what weights the dielectric's diffuse: fresnel (glTF's 1 - F(v.h)), or the specular albedo scaling 1 - E(cos) with E from a DFG ledger row: table (env-brdf-table, 32 x 32 half float), materialx (env-brdf-materialx), karis (env-brdf-approx); needs d = ggx, g = smith-ggx-correlated (one of fresnel, table, materialx, karis, default fresnel)
//   ms: energy compensation for multiple scattering: none, kulla-conty (Kulla and Conty 2017), filament (Filament's, view direction wo only; not reciprocal); needs d = ggx, g = smith-ggx-correlated (one of none, kulla-conty, filament, default none)
//   sheen_albedo: the sheen's directional albedo E: 32 x 32 table of the quadrature, the analytic fit, or no scaling (one of table, fit, none, default table)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 5e-2 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or use --runtime-params (parameters as arguments, coefficients computed in the shader in f32).
// Entry: fb_gltf_pbr(wi, wo): directions in the local frame (normal +z, need not be unit), value without the cosine factor; returns f32.

struct FbPair {
    bool valid;
    float cos_i;
    float cos_o;
    int _pad3_0;
    float3 h;
    float sin2_h;
    float cos_ih;
    int _pad6_0;
    int _pad6_1;
    int _pad6_2;
    float3 wi;
    int _pad7_0;
    float3 wo;
    int _end_pad_0;
};

static const float FB_COS_MIN = 9.536743e-7;

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float3 fb_rescale(float3 v)
{
    float l = dot(v, v);
    float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    bool safe = ((l >= 7.888609e-31) & (l <= 1.2676506e30));
    return ((safe | (m == 0.0)) ? v : (v / (m).xxx));
}

FbPair ConstructFbPair(bool arg0, float arg1, float arg2, float3 arg3, float arg4, float arg5, float3 arg6, float3 arg7) {
    FbPair ret = (FbPair)0;
    ret.valid = arg0;
    ret.cos_i = arg1;
    ret.cos_o = arg2;
    ret.h = arg3;
    ret.sin2_h = arg4;
    ret.cos_ih = arg5;
    ret.wi = arg6;
    ret.wo = arg7;
    return ret;
}

FbPair fb_pair(float3 wi_raw, float3 wo_raw)
{
    const float3 _e2 = fb_rescale(wi_raw);
    const float3 _e3 = fb_rescale(wo_raw);
    float li = dot(_e2, _e2);
    float lo = dot(_e3, _e3);
    float3 wi_1 = (_e2 * (1.0 / sqrt(li)));
    float3 wo_1 = (_e3 * (1.0 / sqrt(lo)));
    float3 s = (wi_1 + wo_1);
    float len = sqrt(dot(s, s));
    float3 h = (s / (len).xxx);
    bool valid = (((((li > 0.0) & (lo > 0.0)) & (wi_1.z >= FB_COS_MIN)) & (wo_1.z >= FB_COS_MIN)) & (len > 0.0));
    const FbPair fbpair = ConstructFbPair(valid, wi_1.z, wo_1.z, h, ((h.x * h.x) + (h.y * h.y)), (0.5 * len), wi_1, wo_1);
    return fbpair;
}

float fb_d_ggx(float c_1, float s2_, float alpha2_, float scale)
{
    float t = ((alpha2_ * (c_1 * c_1)) + s2_);
    return (scale / (t * t));
}

float fb_ggx_s(float c_2, float alpha2_1)
{
    float s2_1 = ((1.0 - c_2) * (1.0 + c_2));
    return (sqrt(((c_2 * c_2) + (alpha2_1 * s2_1))) / c_2);
}

float fb_g_smith_ggx_correlated(float cos_v, float cos_l, float alpha2_2)
{
    float v_2 = min(cos_v, 1.0);
    float l_1 = min(cos_l, 1.0);
    const float _e7 = fb_ggx_s(v_2, alpha2_2);
    const float _e8 = fb_ggx_s(l_1, alpha2_2);
    return (2.0 / (_e7 + _e8));
}

float fb_f_schlick(float c_3, float f0_, float f90_)
{
    const float _e3 = fb_clamp01_(c_3);
    float m_1 = (1.0 - _e3);
    float m2_ = (m_1 * m_1);
    return (f0_ + ((f90_ - f0_) * ((m2_ * m2_) * m_1)));
}

float fb_gltf_pbr(float3 wi, float3 wo)
{
    float v_1 = (float)0;

    const FbPair _e2 = fb_pair(wi, wo);
    const float _e8 = fb_d_ggx(_e2.h.z, _e2.sin2_h, 1.0, 0.31830987);
    float d = ((_e2.h.z >= FB_COS_MIN) ? _e8 : 0.0);
    const float _e18 = fb_g_smith_ggx_correlated(_e2.cos_o, _e2.cos_i, 1.0);
    float denom = (4.0 * (_e2.cos_i * _e2.cos_o));
    float spec = ((d * _e18) / denom);
    const float _e29 = fb_f_schlick(_e2.cos_ih, 0.04, 1.0);
    const float _e33 = fb_f_schlick(_e2.cos_ih, 1.0, 1.0);
    v_1 = (((1.0 - 1.0) * (((1.0 - _e29) * 0.31830987) + (_e29 * spec))) + ((1.0 * _e33) * spec));
    float _e48 = v_1;
    return (_e2.valid ? _e48 : 0.0);
}
