// fastbrdf 0.1.0 (env): sheen-albedo-tuned
// Made by: fastbrdf shader --model sheen-albedo-tuned --lang hlsl --runtime-params
//
// Formula: max(0, exp((k0 + k1 mu) + (k2 + k3 mu) / sqrt(alpha)) + k4 alpha), 5 constants fitted against sheen-albedo per visibility
// Source: this project (fit_sheen_albedo example)
// Note: max abs 0.124 against sheen-albedo (charlie; mean 0.0114), 0.103 (neubelt; mean 0.0072); fastbrdf errors --model sheen-albedo-tuned --param v=V
// Parameters (this export: v = charlie):
//   v: the sheen visibility whose albedo: charlie (Estevez and Kulla's fitted Lambda) or neubelt (Neubelt and Pettineo) (one of charlie, neubelt, default charlie)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_sheen_albedo_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

float2 fb_sheen_e_clamp(float mu, float alpha)
{
    return float2(min(max(mu, 0.001), 1.0), min(max(alpha, 0.07), 1.0));
}

float fb_sheen_e_own(float mu_in, float alpha_in, float k0_, float k1_, float k2_, float k3_, float k4_)
{
    const float2 _e7 = fb_sheen_e_clamp(mu_in, alpha_in);
    float inv = (1.0 / sqrt(_e7.y));
    return max(((k4_ * _e7.y) + exp(((inv * ((_e7.x * k3_) + k2_)) + ((_e7.x * k1_) + k0_)))), 0.0);
}

float fb_sheen_albedo_tuned(float cos_v, float alpha_1)
{
    float v = ((cos_v > 0.0) ? min(cos_v, 1.0) : 0.0);
    float a = ((alpha_1 > 0.005) ? min(alpha_1, 1.0) : 0.005);
    const float _e19 = fb_sheen_e_own(v, a, -0.26377833, -0.5087462, 0.03881789, -1.3130189, 0.0497051);
    return _e19;
}
