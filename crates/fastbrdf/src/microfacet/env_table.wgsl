// WGSL twin of microfacet/env_table.rs (see microfacet/mod.wgsl): the split-sum terms read from
// a table (the tables themselves: env_table::wgsl_source, generated).

/// v as stored at `bits` and read back (as env_table::quantise): unorm8, binary16 (round to
/// nearest even) or float32.
fn fb_env_quantise(v: f32, bits: u32) -> f32 {
    if (bits == 8u) {
        return round(clamp(v, 0.0, 1.0) * 255.0) * (1.0 / 255.0);
    }
    if (bits == 16u) {
        if (v < 6.1035156e-5) {
            return round(v * 16777216.0) * (1.0 / 16777216.0);
        }
        let b = bitcast<u32>(v);
        return bitcast<f32>((b + 0xfffu + ((b >> 13u) & 1u)) & ~0x1fffu);
    }
    return v;
}

/// Texel coordinate of u on a side of n texels, clamped to the edge centres: (index, weight)
/// (as env_table::coord).
fn fb_env_table_coord(u: f32, n: i32) -> vec2<f32> {
    let s = min(max(u * f32(n) - 0.5, 0.0), f32(n - 1));
    let i = min(floor(s), f32(n - 2));
    return vec2<f32>(i, s - i);
}

/// Bilinear weights and the four texels' (stored) values -> the fetch.
fn fb_env_table_mix(c: vec4<f32>, t00: f32, t10: f32, t01: f32, t11: f32, bits: u32) -> f32 {
    let a = fb_env_quantise(t00, bits);
    let b = fb_env_quantise(t10, bits);
    let c0 = fb_env_quantise(t01, bits);
    let d = fb_env_quantise(t11, bits);
    let r0 = a + (b - a) * c.y;
    let r1 = c0 + (d - c0) * c.y;
    return r0 + (r1 - r0) * c.w;
}

/// The fetch's texel coordinates at (cos_v, sqrt(alpha)): (i, tx, j, ty).
fn fb_env_table_at(cos_v: f32, alpha: f32, n: i32) -> vec4<f32> {
    return vec4<f32>(fb_env_table_coord(cos_v, n), fb_env_table_coord(sqrt(alpha), n));
}

/// env-brdf-table, size 16.
fn fb_env_table_16(cos_v: f32, alpha: f32, bits: u32, bias: bool) -> f32 {
    let c = fb_env_table_at(cos_v, alpha, 16);
    let k = 2 * (i32(c.z) * 16 + i32(c.x)) + select(0, 1, bias);
    // One local copy: a compiler may materialise a constant array once per dynamic access.
    var t = FB_ENV_TABLE_16;
    return fb_env_table_mix(c, t[k], t[k + 2], t[k + 32], t[k + 34], bits);
}

/// env-brdf-table, size 32.
fn fb_env_table_32(cos_v: f32, alpha: f32, bits: u32, bias: bool) -> f32 {
    let c = fb_env_table_at(cos_v, alpha, 32);
    let k = 2 * (i32(c.z) * 32 + i32(c.x)) + select(0, 1, bias);
    // One local copy: a compiler may materialise a constant array once per dynamic access.
    var t = FB_ENV_TABLE_32;
    return fb_env_table_mix(c, t[k], t[k + 2], t[k + 64], t[k + 66], bits);
}

/// env-brdf-table, size 64.
fn fb_env_table_64(cos_v: f32, alpha: f32, bits: u32, bias: bool) -> f32 {
    let c = fb_env_table_at(cos_v, alpha, 64);
    let k = 2 * (i32(c.z) * 64 + i32(c.x)) + select(0, 1, bias);
    // One local copy: a compiler may materialise a constant array once per dynamic access.
    var t = FB_ENV_TABLE_64;
    return fb_env_table_mix(c, t[k], t[k + 2], t[k + 128], t[k + 130], bits);
}

/// env-brdf-table, size 128.
fn fb_env_table_128(cos_v: f32, alpha: f32, bits: u32, bias: bool) -> f32 {
    let c = fb_env_table_at(cos_v, alpha, 128);
    let k = 2 * (i32(c.z) * 128 + i32(c.x)) + select(0, 1, bias);
    // One local copy: a compiler may materialise a constant array once per dynamic access.
    var t = FB_ENV_TABLE_128;
    return fb_env_table_mix(c, t[k], t[k + 2], t[k + 256], t[k + 258], bits);
}
