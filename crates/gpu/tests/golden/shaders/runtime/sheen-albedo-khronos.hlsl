// fastbrdf 0.1.0 (env): sheen-albedo-khronos
// Made by: fastbrdf shader --model sheen-albedo-khronos --lang hlsl --runtime-params
//
// Formula: 0.65584461 (1 - mu)^3 + 1 / (4.16526551 + exp(-7.97291361 sqrt(alpha) + 6.33516894))
// Source: Enterprise PBR 2022x (directional_albedo_sheen); the Khronos reference renderers
// Note: max abs 0.329 against sheen-albedo (charlie; mean 0.031) at grazing, alpha 0.07; 0.894 against neubelt's (gltf-pbr's sheen_albedo = fit reads it with either visibility); fastbrdf errors --model sheen-albedo-khronos
// Parameters (this export: no parameters):
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_sheen_albedo_khronos(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

float2 fb_sheen_e_clamp(float mu, float alpha)
{
    return float2(min(max(mu, 0.001), 1.0), min(max(alpha, 0.07), 1.0));
}

float fb_sheen_e_fit(float mu_in, float alpha_in, float k0_, float k1_, float k2_, float k3_)
{
    const float2 _e6 = fb_sheen_e_clamp(mu_in, alpha_in);
    float m = (1.0 - _e6.x);
    return ((k0_ * ((m * m) * m)) + (1.0 / (k1_ + exp(((k2_ * sqrt(_e6.y)) + k3_)))));
}

float fb_sheen_albedo_khronos(float cos_v, float alpha_1)
{
    float v = ((cos_v > 0.0) ? min(cos_v, 1.0) : 0.0);
    float a = ((alpha_1 > 0.005) ? min(alpha_1, 1.0) : 0.005);
    const float _e18 = fb_sheen_e_fit(v, a, 0.6558446, 4.1652656, -7.9729137, 6.335169);
    return _e18;
}
