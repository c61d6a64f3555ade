// fastbrdf 0.1.0 (fresnel): fresnel-conductor
// Made by: fastbrdf shader --model fresnel-conductor --lang hlsl
//
// Formula: (R_s + R_p) / 2 for complex index eta + i k, exact
// Source: Fresnel equations; pbrt-v3 FrConductor
// Parameters (this export: eta = 1.5, k = 0):
//   eta: relative index of refraction (real part) (range [0.01, 10], default 1.5)
//   k: extinction coefficient (imaginary part of the index, conductors) (range [0, 20], default 0)
// Error bounds: none documented (an exact model or a reference).
// Precision: f32 on the CPU within 1e-6 of f64 (mixed error); on GPUs see fastbrdf's tests/parity.rs (WGSL exp2/log2/pow are looser than libm; compilers may reassociate).
// Coefficients are literals computed in f64 for these parameters; for other values re-export, or pass them as uniforms (a compiler cannot fold those into reassociated, less accurate expressions).
// Entry: fb_fresnel_conductor(cos_vh) with cos_vh = v.h; returns f32.

float fb_clamp01_(float c)
{
    return min(max(c, 0.0), 1.0);
}

float fb_f_conductor(float c_in, float eta, float k)
{
    const float _e3 = fb_clamp01_(c_in);
    float cos2_ = (_e3 * _e3);
    float sin2_ = (1.0 - cos2_);
    float eta2_ = (eta * eta);
    float k2_ = (k * k);
    float t0_ = ((eta2_ - k2_) - sin2_);
    float a2b2_ = sqrt(((t0_ * t0_) + ((4.0 * eta2_) * k2_)));
    float t1_ = (a2b2_ + cos2_);
    float a = sqrt(max((0.5 * (a2b2_ + t0_)), 0.0));
    float t2_ = ((2.0 * _e3) * a);
    float rs = ((t1_ - t2_) / (t1_ + t2_));
    float t3_ = ((cos2_ * a2b2_) + (sin2_ * sin2_));
    float t4_ = (t2_ * sin2_);
    float rp = ((rs * (t3_ - t4_)) / (t3_ + t4_));
    const float _e41 = fb_clamp01_(((rp + rs) * 0.5));
    return _e41;
}

float fb_fresnel_conductor(float cos_vh)
{
    float c_1 = max(cos_vh, 0.0);
    const float _e5 = fb_f_conductor(c_1, 1.5, 0.0);
    return _e5;
}
