/*
 * The C peers of `fastbrdf bench` (issue 13): each lobe or distribution as the plain loop a
 * performance-minded C programmer would write, compiled by build.rs with the system compiler
 * at -O3 -march=native -ffast-math (so GCC may vectorise powf/expf/exp2f through glibc's
 * libmvec). No intrinsics, no hand vectorisation: the compiler does what it does.
 *
 * Every function reads n cosines from x and writes n values to out. Parameters that depend
 * only on the model's own parameters (rates, coefficients) are computed once by the caller,
 * as a user would hoist them out of the loop.
 */
#include <math.h>
#include <stddef.h>

/* c^n, plain powf: a user has no simple clamp here. At n = 200, c^n is subnormal or 0 for
 * c < 0.645 (most of a uniform batch), where libmvec's powf falls back to scalar calls; that
 * cost is part of what this peer measures. */
void peer_pow(const float *x, float *out, size_t n, float e)
{
    for (size_t i = 0; i < n; i++)
        out[i] = powf(x[i], e);
}

/* exp2(rate (c - 1)), rate = n / ln 2 (the spherical-Gaussian form). The exponent is clamped
 * at -126 (2^-126 is the smallest normal float), as for Beckmann below: at n = 200 the
 * unclamped argument underflows for c < 0.69, and libmvec's exp2f then takes its scalar
 * fallback for the whole vector (measured 40x slower on uniform cosines). */
void peer_sg(const float *x, float *out, size_t n, float rate)
{
    for (size_t i = 0; i < n; i++) {
        float e = rate * (x[i] - 1.0f);
        out[i] = exp2f(e > -126.0f ? e : -126.0f);
    }
}

/* max(0, 1 + k (c - 1))^g by squarings, k = n / g */
void peer_power4(const float *x, float *out, size_t n, float k)
{
    for (size_t i = 0; i < n; i++) {
        float b = 1.0f + k * (x[i] - 1.0f);
        b = b > 0.0f ? b : 0.0f;
        b *= b;
        b *= b;
        out[i] = b;
    }
}

void peer_power8(const float *x, float *out, size_t n, float k)
{
    for (size_t i = 0; i < n; i++) {
        float b = 1.0f + k * (x[i] - 1.0f);
        b = b > 0.0f ? b : 0.0f;
        b *= b;
        b *= b;
        b *= b;
        out[i] = b;
    }
}

void peer_power16(const float *x, float *out, size_t n, float k)
{
    for (size_t i = 0; i < n; i++) {
        float b = 1.0f + k * (x[i] - 1.0f);
        b = b > 0.0f ? b : 0.0f;
        b *= b;
        b *= b;
        b *= b;
        b *= b;
        out[i] = b;
    }
}

/* Seed 003's Hermite cubic as the seed prints it, a c^3 + b c^2 + d c (d = 1 - a - b), by
 * Horner, clipped: 0 below the cubic's local minimum `cut` and wherever it is negative. */
void peer_cubic(const float *x, float *out, size_t n, float a, float b, float d, float cut)
{
    for (size_t i = 0; i < n; i++) {
        float c = x[i];
        float p = ((a * c + b) * c + d) * c;
        out[i] = (c > cut && p > 0.0f) ? p : 0.0f;
    }
}

/* Schlick 1994: c / (n - n c + c) */
void peer_schlick(const float *x, float *out, size_t n, float e)
{
    for (size_t i = 0; i < n; i++) {
        float c = x[i];
        out[i] = c / (e - e * c + c);
    }
}

/* Beckmann D(cos_h) = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4), with inv_a2 = 1 / alpha^2
 * and scale = 1 / (pi alpha^2). The exponent is clamped at -87 (exp(-87) is about 1.6e-38,
 * the bottom of the normal floats): the result there is 0 to f32 precision anyway, and
 * libmvec's expf takes a slow scalar path for arguments that underflow. */
void peer_beckmann(const float *x, float *out, size_t n, float inv_a2, float scale)
{
    for (size_t i = 0; i < n; i++) {
        float c = x[i];
        float c2 = c * c;
        float e = -(1.0f - c2) / c2 * inv_a2;
        e = e > -87.0f ? e : -87.0f;
        out[i] = c > 0.0f ? scale * expf(e) / (c2 * c2) : 0.0f;
    }
}

/* GGX (Trowbridge-Reitz) D(cos_h) = alpha^2 / (pi ((alpha^2 - 1) cos^2 + 1)^2), in the form
 * engines print (UE4, Filament's reference): a2m1 = alpha^2 - 1 and scale = alpha^2 / pi
 * hoisted by the caller. (This form cancels near cos = 1 at small alpha: at the benchmark's
 * alpha = 0.3 it is within 2e-6 of f64; fastbrdf's alpha^2 cos^2 + sin^2 does not cancel.)
 * Like the other peers it has no domain rules: for 0 < c < 2^-20 (fastbrdf's COS_MIN, where
 * the model is 0) it returns about alpha^2 / pi, and it grows for c > 1; the benchmark's
 * cosines never fall there. */
void peer_ggx(const float *x, float *out, size_t n, float a2m1, float scale)
{
    for (size_t i = 0; i < n; i++) {
        float c = x[i];
        float d = c * c * a2m1 + 1.0f;
        out[i] = c > 0.0f ? scale / (d * d) : 0.0f;
    }
}
