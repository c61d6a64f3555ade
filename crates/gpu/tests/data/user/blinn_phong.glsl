// A normalised Blinn-Phong lobe over a Lambert base, three channels: an example of fastbrdf's
// GLSL function format (docs/book/src/user-shaders.md). Desktop GLSL as BRDF Explorer writes
// it: integer literals where floats are meant, ternaries.
//
// param float n 1 1000 50
// param color ks 1 1 1
// param color kd 0.5 0.25 0.125
// param bool diffuse 1

const float PI = 3.14159265358979;

// Directions with a NaN or infinite component give 0, tested on the bits: a GPU may assume
// that floats are never NaN and fold a comparison with one (lavapipe does).
bool nonFinite(vec3 v)
{
    uvec3 b = floatBitsToUint(v) & 0x7fffffffu;
    return any(greaterThanEqual(b, uvec3(0x7f800000u)));
}

vec3 brdf(vec3 wi, vec3 wo)
{
    if (nonFinite(wi) || nonFinite(wo) || wi.z <= 0 || wo.z <= 0) return vec3(0);
    vec3 h = normalize(wi + wo);
    float spec = (n + 8) / (8 * PI) * pow(max(h.z, 0), n);
    return (diffuse ? kd / PI : vec3(0)) + ks * spec;
}
