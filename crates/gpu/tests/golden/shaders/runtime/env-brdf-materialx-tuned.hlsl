// fastbrdf 0.1.0 (env): env-brdf-materialx-tuned
// Made by: fastbrdf shader --model env-brdf-materialx-tuned --lang hlsl --runtime-params
//
// Formula: env-brdf-materialx's form, its 2 x 17 free constants refitted against env-brdf (max and mean both below MaterialX's)
// Source: this project (fit_env_rational example)
// Parameters (this export: term = scale):
//   term: which split-sum term: the scale of f0 or the bias (albedo = f0 scale + bias) (one of scale, bias, default scale)
// Documented error bounds (measured by `fastbrdf check`):
//   env-brdf-materialx-tuned vs env-brdf: max abs error (relative to the peak) <= 0.0797 over alpha in [0.005, 1], whole domain
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Runtime parameters: none (the model has no numeric parameter) (f32, after the inputs; the parameters above are only the defaults of this export). Coefficients are computed in the shader in f32: closed forms inline, the rest by the fb_rt_* functions (cubic shapes, rational nodes, normalisation integrals), whose added f32 error fastbrdf measures per model (ARCHITECTURE.md, 'Runtime parameters'). Values outside a parameter's range are not checked in the shader.
// Entry: fb_env_brdf_materialx_tuned(cos_v, alpha): n.v and the GGX roughness alpha (the look-up table's axes); specular albedo = f0 scale + bias; returns f32.

float fb_env_rational_poly(float x, float y, float c[9])
{
    float p0_ = ((y * ((y * c[5]) + c[2])) + c[0]);
    float p1_ = ((y * ((y * c[7]) + c[3])) + c[1]);
    float p2_ = ((y * ((y * c[8]) + c[6])) + c[4]);
    return ((x * ((x * p2_) + p1_)) + p0_);
}

float fb_env_rational(float cos_v, float alpha, float num[9], float den[9])
{
    const float _e4 = fb_env_rational_poly(cos_v, alpha, num);
    const float _e5 = fb_env_rational_poly(cos_v, alpha, den);
    return max((_e4 / _e5), 0.0);
}

typedef float ret_Constructarray9_float_[9];
ret_Constructarray9_float_ Constructarray9_float_(float arg0, float arg1, float arg2, float arg3, float arg4, float arg5, float arg6, float arg7, float arg8) {
    float ret[9] = { arg0, arg1, arg2, arg3, arg4, arg5, arg6, arg7, arg8 };
    return ret;
}

float fb_env_brdf_materialx_tuned(float cos_v_1, float alpha_1)
{
    float v = ((cos_v_1 > 0.0) ? min(cos_v_1, 1.0) : 0.0);
    float a = ((alpha_1 > 0.005) ? min(alpha_1, 1.0) : 0.005);
    const float _e34 = fb_env_rational(v, a, Constructarray9_float_(0.085452, -0.191066, 10.218748, 0.90751, 28.483358, -8.181671, -24.73793, 17.28328, -6.033422), Constructarray9_float_(1.0, -1.180156, 8.80378, 14.385899, 27.73535, -7.465713, -33.963554, 14.708145, 34.39794));
    return _e34;
}
