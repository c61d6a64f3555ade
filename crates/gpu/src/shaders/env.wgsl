// fastbrdf GPU renderer: environment light. Spliced after render.wgsl only when the scene has
// an environment (crates/gpu/src/render/env.rs), so the module of an environment-less scene
// is unchanged. Everything it adds lives in bind group 3:
//
//   @group(3) @binding(0) uniform EnvParams (48 bytes)
//   @group(3) @binding(1) texture_2d<f32> (Rgba32Float, read with textureLoad): per texel,
//                         rgb radiance and a = its probability mass under the light
//                         strategies x width x height (EnvMap::light_pdf)
//   @group(3) @binding(2) storage array<f32>: the marginal CDF over rows (height + 1
//                         entries), then per row the conditional CDF over its columns
//                         (width + 1 entries each), then the bright texels' section
//                         (env.rs, `sun_section`; its first entry 0 where there are none)
//   @group(3) @binding(3) texture_2d<f32> (Rgba32Float, textureLoad): the split-sum mode's
//                         prefiltered maps, level after level (render/split_sum.rs)
//
// The module ends with `rd_dfg(cos_v, alpha) -> vec2<f32>` (split_sum.rs): the split-sum's
// scale and bias from an environment model's twin, or a stub in the sampled mode.
//
// The estimator (twin of crates/render/src/render/environment.rs, but for its BRDF
// sampling: the GPU has the models' values, not their samplers): per primary hit and pass,
// one direction drawn from the map (its importance tables; where the map has a compact bright
// part, a sun, one from the rest of the map and one from the bright texels, the CPU's two
// light strategies with disjoint densities), one cosine-weighted about the
// shading normal and, with a specular term, one from a GGX lobe of the model's roughness
// about the view's mirror (env.weights.z; 0: none), combined by the balance heuristic over the
// whole integrand (diffuse and specular): each contributes
// L (base cos / pi + ks f cos) / (pdf_light + cos / pi + pdf_lobe), times the pass weight, with
// the CPU's shadow rule (`visible`). The map and cosine strategies cover every direction the
// integrand is non-zero in (the map's density is positive wherever its radiance is), so the
// sum is unbiased whatever the lobe, and converges to the CPU's picture.
//
// Random numbers: the CPU's (environment.rs, `uniforms`), either sampler: Owen-scrambled
// Sobol points (sobol_burley's `sample_4d`, its first four dimensions, ported with their
// direction numbers) or the independent sampler (`env::Rng`: a PCG hash of the sample id
// and the pass), the sample id `(pixel y * width + pixel x) * N^2 + subsample` as on the CPU:
// the same eight numbers per sample and pass as the CPU's map, cosine, BRDF and bright
// directions take.
// Deterministic, and a draw with passes [first, first + count) adds new samples to earlier
// ones.

/// The environment's parameters of one draw.
struct EnvParams {
    /// Map width and height; the first pass of this draw and how many passes it takes.
    size: vec4<u32>,
    /// Weight of each pass's estimate (1 / passes of the whole render); weight of the direct
    /// light, ambient and background (1 in the draw that includes them, else 0); the lobe
    /// strategy's GGX roughness (sampled mode; 0: none) or the split-sum's alpha; its f0.
    weights: vec4<f32>,
    /// The sampler (0: Sobol, 1: independent); the mode (0: sampled, 1: split-sum); the
    /// prefiltered maps' level width and height.
    options: vec4<u32>,
}

@group(3) @binding(0) var<uniform> env: EnvParams;
@group(3) @binding(1) var env_map: texture_2d<f32>;
@group(3) @binding(2) var<storage, read> env_cdf: array<f32>;
@group(3) @binding(3) var env_pre: texture_2d<f32>;

// ---- random numbers (twins: hash::pcg, env::Rng) -------------------------------------------

fn rd_pcg(x: u32) -> u32 {
    let s = x * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

/// Rng::new(id, pass)'s state.
fn rd_rng(id: u32, pass_index: u32) -> u32 {
    return rd_pcg(id ^ rd_pcg(pass_index + 0x9e3779b9u));
}

/// Rng::uniform: a number in [0, 1).
fn rd_uniform(state: ptr<function, u32>) -> f32 {
    *state = rd_pcg(*state);
    return f32(*state >> 8u) * (1.0 / 16777216.0);
}

// Sobol points (twin: sobol_burley 0.5's `sample_4d(index, 0, seed)`, parts.rs): the
// bit-reversed direction numbers of its dimensions 0 to 3, Burley's hash-based Owen
// scrambling with the crate's constants, and its float conversion.
var<private> RD_SOBOL_REV: array<vec4<u32>, 16> = array<vec4<u32>, 16>(
    vec4<u32>(0x00000001u, 0x00000001u, 0x00000001u, 0x00000001u),
    vec4<u32>(0x00000002u, 0x00000003u, 0x00000003u, 0x00000003u),
    vec4<u32>(0x00000004u, 0x00000005u, 0x00000006u, 0x00000004u),
    vec4<u32>(0x00000008u, 0x0000000fu, 0x00000009u, 0x0000000au),
    vec4<u32>(0x00000010u, 0x00000011u, 0x00000017u, 0x0000001fu),
    vec4<u32>(0x00000020u, 0x00000033u, 0x0000003au, 0x0000002eu),
    vec4<u32>(0x00000040u, 0x00000055u, 0x00000071u, 0x00000045u),
    vec4<u32>(0x00000080u, 0x000000ffu, 0x000000a3u, 0x000000c9u),
    vec4<u32>(0x00000100u, 0x00000101u, 0x00000116u, 0x0000011bu),
    vec4<u32>(0x00000200u, 0x00000303u, 0x00000339u, 0x000002a4u),
    vec4<u32>(0x00000400u, 0x00000505u, 0x00000677u, 0x0000079au),
    vec4<u32>(0x00000800u, 0x00000f0fu, 0x000009aau, 0x00000b67u),
    vec4<u32>(0x00001000u, 0x00001111u, 0x00001601u, 0x0000101eu),
    vec4<u32>(0x00002000u, 0x00003333u, 0x00003903u, 0x0000302du),
    vec4<u32>(0x00004000u, 0x00005555u, 0x00007706u, 0x00004041u),
    vec4<u32>(0x00008000u, 0x0000ffffu, 0x0000aa09u, 0x0000a0c3u)
);

fn rd_sobol_hash(x: vec4<u32>) -> vec4<u32> {
    var n = x ^ vec4<u32>(0xe6fe3bebu);
    n ^= n >> vec4<u32>(16u);
    n *= vec4<u32>(0x7feb352du);
    n ^= n >> vec4<u32>(15u);
    n *= vec4<u32>(0x846ca68bu);
    n ^= n >> vec4<u32>(16u);
    return n;
}

fn rd_owen_rev(x: vec4<u32>, scramble: vec4<u32>) -> vec4<u32> {
    var n = x;
    n ^= n * vec4<u32>(0x3d20adeau);
    n += scramble;
    n *= (scramble >> vec4<u32>(16u)) | vec4<u32>(1u);
    n ^= n * vec4<u32>(0x05526c56u);
    n ^= n * vec4<u32>(0x53a22864u);
    return n;
}

/// sample_4d(index, 0, seed): point `index` (below 2^16) of the sequence `seed`, in [0, 1).
fn rd_sobol4(index: u32, seed: u32) -> vec4<f32> {
    let shuffled =
        rd_owen_rev(vec4<u32>(reverseBits(index)), rd_sobol_hash(vec4<u32>(seed ^ 0x79c68e4au))).x;
    var sobol = vec4<u32>(0u);
    var idx = shuffled & 0xffff0000u;
    var i = 0u;
    while idx != 0u {
        let j = countLeadingZeros(idx);
        sobol ^= RD_SOBOL_REV[i + j];
        i += j + 1u;
        idx = (idx << j) << 1u;
    }
    let scramble = vec4<u32>(seed * 0x9c8f2d3bu)
        ^ vec4<u32>(0x912f69bau, 0x174f18abu, 0x691e72cau, 0xb40cc1b8u);
    let r = reverseBits(rd_owen_rev(sobol, rd_sobol_hash(scramble)));
    return bitcast<vec4<f32>>((r >> vec4<u32>(9u)) | vec4<u32>(0x3f800000u)) - vec4<f32>(1.0);
}

struct RdUniforms {
    /// The map's pair (the rest's, where the map has a bright part), then the cosine pair.
    a: vec4<f32>,
    /// The BRDF's pair (here the GGX lobe's).
    b: vec2<f32>,
    /// The bright texels' pair.
    c: vec2<f32>,
}

/// The eight uniform numbers of sample `id` in pass `p` (environment.rs, `uniforms`).
fn rd_env_uniforms(id: u32, p: u32) -> RdUniforms {
    if env.options.x == 0u {
        // Pass k takes point k (mod 2^16) of the sequence seeded by the sample (and k / 2^16),
        // the BRDF's pair the first two dimensions of a second seed, the bright texels' its
        // last two.
        let seed = rd_pcg(id ^ rd_pcg(p >> 16u));
        let k = p & 0xffffu;
        let second = rd_sobol4(k, rd_pcg(seed ^ 0x68bc21ebu));
        return RdUniforms(rd_sobol4(k, seed), second.xy, second.zw);
    }
    var rng = rd_rng(id, p);
    let u1 = rd_uniform(&rng);
    let u2 = rd_uniform(&rng);
    let u3 = rd_uniform(&rng);
    let u4 = rd_uniform(&rng);
    let u5 = rd_uniform(&rng);
    let u6 = rd_uniform(&rng);
    let u7 = rd_uniform(&rng);
    let u8 = rd_uniform(&rng);
    return RdUniforms(vec4<f32>(u1, u2, u3, u4), vec2<f32>(u5, u6), vec2<f32>(u7, u8));
}

/// The CPU's sample id of the fragment at `pos` (environment.rs, `env_pass`).
fn rd_sample_id(pos: vec2<f32>) -> u32 {
    let gx = frame.tile.x + u32(pos.x);
    let gy = frame.tile.y + u32(pos.y);
    let n = frame.size.z;
    return ((gy / n) * frame.size.x + gx / n) * (n * n) + (gy % n) * n + gx % n;
}

// ---- the map (twins: env.rs) ----------------------------------------------------------------

struct RdBin {
    i: u32,
    frac: f32,
}

/// sample_cdf on the table of `n` bins at `env_cdf[off ..= off + n]`: the bin holding `u`
/// (scaled by the table's last entry) and where in it.
fn rd_env_bin(off: u32, n: u32, u_in: f32) -> RdBin {
    return rd_env_bin_at(off, n, clamp(u_in, 0.0, 0.99999988) * env_cdf[off + n]);
}

/// bin_of at the partition point of `u` (already scaled) in the table at `env_cdf[off ..=
/// off + n]`.
fn rd_env_bin_at(off: u32, n: u32, u: f32) -> RdBin {
    // The partition point: the first entry above u.
    var lo = 0u;
    var hi = n + 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if env_cdf[off + mid] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = min(max(lo, 1u) - 1u, n - 1u);
    let width = env_cdf[off + i + 1u] - env_cdf[off + i];
    var frac = 0.5;
    if width > 0.0 {
        frac = clamp((u - env_cdf[off + i]) / width, 0.0, 0.99999988);
    }
    return RdBin(i, frac);
}

struct RdEnvSample {
    d: vec3<f32>,
    le: vec3<f32>,
    pdf: f32,
}

/// EnvMap::sample: (unit direction, radiance, solid-angle density under the light
/// strategies; 0 at the poles).
fn rd_env_sample(u1: f32, u2: f32) -> RdEnvSample {
    let w = env.size.x;
    let h = env.size.y;
    let r = rd_env_bin(0u, h, u1);
    let c = rd_env_bin(h + 1u + r.i * (w + 1u), w, u2);
    return rd_env_drawn(r.i, r.frac, c.i, c.frac);
}

/// EnvMap::drawn: the direction at (`fc`, `fr`) within texel (column `c`, row `r`), its
/// radiance and density (the texel's A: the light strategies' mass).
fn rd_env_drawn(r: u32, fr: f32, c: u32, fc: f32) -> RdEnvSample {
    let u = (f32(c) + fc) / f32(env.size.x);
    let v = (f32(r) + fr) / f32(env.size.y);
    let phi = (u - 0.5) * 2.0 * RD_PI;
    let theta = v * RD_PI;
    let st = sin(theta);
    let d = vec3<f32>(st * sin(phi), cos(theta), -st * cos(phi));
    let t = textureLoad(env_map, vec2<i32>(i32(c), i32(r)), 0);
    if st <= 0.0 {
        return RdEnvSample(d, t.xyz, 0.0);
    }
    return RdEnvSample(d, t.xyz, t.w / (2.0 * RD_PI * RD_PI * st));
}

// ---- a sun apart (twins: env/bright.rs; EnvData::tables' sun section, env.rs `sun_section`)

/// Where the sun section starts in env_cdf (after the map's marginal and rows).
fn rd_sun_off() -> u32 {
    return env.size.y + 1u + env.size.y * (env.size.x + 1u);
}

/// How many bright texels the map has as a strategy of their own (0: none).
fn rd_sun_count() -> u32 {
    return u32(env_cdf[rd_sun_off()]);
}

/// EnvMap::bright_faces: whether a surface of shading normal `n` may see a bright texel.
fn rd_sun_faces(n: vec3<f32>) -> bool {
    let b = rd_sun_off();
    let axis = vec3<f32>(env_cdf[b + 2u], env_cdf[b + 3u], env_cdf[b + 4u]);
    return rd_sun_count() > 0u && rd_dot(n, axis) > env_cdf[b + 5u];
}

/// EnvMap::sample_bright: a direction drawn from the bright texels in proportion to their
/// weight (needs rd_sun_count() > 0).
fn rd_env_sample_bright(u1: f32, u2: f32) -> RdEnvSample {
    let b = rd_sun_off();
    let nb = rd_sun_count();
    let k = rd_env_bin_at(b + 8u, nb, clamp(u1, 0.0, 0.99999988));
    let texel = b + 9u + nb + k.i;
    let r = u32(env_cdf[texel]);
    let c = u32(env_cdf[texel + nb]);
    return rd_env_drawn(r, k.frac, c, clamp(u2, 0.0, 0.99999988));
}

/// EnvMap::sample_rest: a direction drawn from the map without its bright texels (the whole
/// map where it has none).
fn rd_env_sample_rest(u1: f32, u2: f32) -> RdEnvSample {
    let nb = rd_sun_count();
    if nb == 0u {
        return rd_env_sample(u1, u2);
    }
    let w = env.size.x;
    let h = env.size.y;
    let marginal = rd_sun_off() + 9u + 3u * nb;
    let rows = marginal + h + 1u;
    let r = rd_env_bin(marginal, h, u1);
    let t = u32(env_cdf[rows + r.i]);
    var off = h + 1u + t * (w + 1u);
    if t >= h {
        off = rows + h + (t - h) * (w + 1u);
    }
    let c = rd_env_bin(off, w, u2);
    return rd_env_drawn(r.i, r.frac, c.i, c.frac);
}

/// EnvMap::lookup: the radiance from unit direction `d` (xyz) and the map's density there (w).
fn rd_env_lookup(d: vec3<f32>) -> vec4<f32> {
    let w = env.size.x;
    let h = env.size.y;
    let y = clamp(d.y, -1.0, 1.0);
    let u = rd_atan2(d.x, -d.z) / RD_TAU + 0.5;
    let v = rd_atan2(sqrt((1.0 - y) * (1.0 + y)), y) / RD_PI;
    let c = min(u32(max(u * f32(w), 0.0)), w - 1u);
    let r = min(u32(max(v * f32(h), 0.0)), h - 1u);
    let t = textureLoad(env_map, vec2<i32>(i32(c), i32(r)), 0);
    let st = sqrt(max(1.0 - d.y * d.y, 0.0));
    if st <= 0.0 {
        return vec4<f32>(t.xyz, 0.0);
    }
    return vec4<f32>(t.xyz, t.w / (2.0 * RD_PI * RD_PI * st));
}

/// env::cosine_sample: a cosine-weighted direction about unit normal `n`.
fn rd_cosine_sample(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let f = rd_orthonormal_pair(n);
    let r = sqrt(u1);
    let a = RD_TAU * u2;
    return rd_normalize(f.t * (r * cos(a)) + f.b * (r * sin(a)) + n * sqrt(max(1.0 - u1, 0.0)));
}

// ---- shading ---------------------------------------------------------------------------------

/// environment.rs's `visible`: light from `l` reaches the hit (no shadow ray where only the
/// bumped normal faces `l`).
fn rd_env_visible(s: RdSurface, l: vec3<f32>) -> bool {
    return !RD_USE_SHADOWS || frame.shadow.x == 0.0 || rd_dot(s.g, l) <= 0.0
        || !rd_shadowed(s.p, s.g, l, 0.0, true);
}

/// The integrand without the radiance: base cos / pi + ks f(wi, wo) cos (R, G, B; a tinted
/// term mixed by its texel, `rd_specular`).
fn rd_env_f(s: RdSurface, l: vec3<f32>, cos_i: f32) -> vec3<f32> {
    var f = s.base * (cos_i / RD_PI);
    let ks = object.mat.x;
    if ks > 0.0 {
        let wi = vec3<f32>(rd_dot(l, s.t), rd_dot(l, s.b), cos_i);
        let wo = vec3<f32>(rd_dot(s.v, s.t), rd_dot(s.v, s.b), rd_dot(s.v, s.n));
        f += rd_specular(s, vec3<f32>(1.0), wi, wo);
    }
    return f;
}

// ---- the GGX lobe strategy ----------------------------------------------------------------

/// A hit's local frame and view direction, and the lobe's roughness (0: no lobe strategy).
struct RdLobe {
    t: vec3<f32>,
    b: vec3<f32>,
    wo: vec3<f32>,
    alpha: f32,
}

fn rd_lobe(s: RdSurface) -> RdLobe {
    let wo = vec3<f32>(rd_dot(s.v, s.t), rd_dot(s.v, s.b), rd_dot(s.v, s.n));
    var alpha = 0.0;
    if object.mat.x > 0.0 && wo.z > 0.0 {
        alpha = env.weights.z;
    }
    return RdLobe(s.t, s.b, wo, alpha);
}

/// The density of `rd_lobe_sample` at unit local direction `wi` (0 below the surface):
/// the GGX visible-normal density over 4 wo.h, `G1(wo) D(h) / (4 wo.z)` (Heitz 2018).
fn rd_lobe_pdf(lobe: RdLobe, wi: vec3<f32>) -> f32 {
    if lobe.alpha <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let h = rd_normalize(wi + lobe.wo);
    if rd_dot(lobe.wo, h) <= 0.0 || h.z <= 0.0 {
        return 0.0;
    }
    let a2 = lobe.alpha * lobe.alpha;
    let q = h.z * h.z * (a2 - 1.0) + 1.0;
    let d = a2 / (RD_PI * q * q);
    let wo = lobe.wo;
    let g1 = 2.0 * wo.z / (wo.z + sqrt(a2 * (wo.x * wo.x + wo.y * wo.y) + wo.z * wo.z));
    return g1 * d / (4.0 * wo.z);
}

/// A direction drawn from GGX's visible normals of roughness `lobe.alpha` (Heitz 2018), local.
fn rd_lobe_sample(lobe: RdLobe, u1: f32, u2: f32) -> vec3<f32> {
    let a = lobe.alpha;
    let vh = rd_normalize(vec3<f32>(a * lobe.wo.x, a * lobe.wo.y, lobe.wo.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if lensq > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
    }
    let t2 = rd_cross(vh, t1);
    let r = sqrt(u1);
    let phi = RD_TAU * u2;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    let h = rd_normalize(vec3<f32>(a * nh.x, a * nh.y, max(nh.z, 0.0)));
    return h * (2.0 * rd_dot(lobe.wo, h)) - lobe.wo;
}

/// A light direction's share: `m` drawn by a light strategy, its density theirs together.
fn rd_env_light(s: RdSurface, lobe: RdLobe, m: RdEnvSample) -> vec3<f32> {
    let cos_m = rd_dot(s.n, m.d);
    if m.pdf > 0.0 && cos_m > 0.0 && any(m.le != vec3<f32>(0.0)) && rd_env_visible(s, m.d) {
        let wi = vec3<f32>(rd_dot(m.d, lobe.t), rd_dot(m.d, lobe.b), cos_m);
        let p = m.pdf + cos_m / RD_PI + rd_lobe_pdf(lobe, wi);
        return m.le * s.ao * rd_env_f(s, m.d, cos_m) / p;
    }
    return vec3<f32>(0.0);
}

/// One pass's estimate at a hit: a map direction (where the map has a bright part, one from
/// the rest and, where the hit may see them, one from the bright texels: together one light
/// strategy, their densities disjoint, as the CPU's), a cosine direction and, with a
/// specular term and a lobe roughness given (`env.weights.z`), a direction from a GGX lobe of
/// that roughness about the view's mirror; the balance heuristic over the strategies taken.
fn rd_env_pass(s: RdSurface, id: u32, pass_index: u32) -> vec3<f32> {
    let u = rd_env_uniforms(id, pass_index);
    let lobe = rd_lobe(s);
    var sum = rd_env_light(s, lobe, rd_env_sample_rest(u.a.x, u.a.y));
    if rd_sun_faces(s.n) {
        sum += rd_env_light(s, lobe, rd_env_sample_bright(u.c.x, u.c.y));
    }
    let l = rd_cosine_sample(s.n, u.a.z, u.a.w);
    let cos_c = rd_dot(s.n, l);
    if cos_c > 0.0 {
        let e = rd_env_lookup(l);
        if any(e.xyz != vec3<f32>(0.0)) && rd_env_visible(s, l) {
            let wi = vec3<f32>(rd_dot(l, lobe.t), rd_dot(l, lobe.b), cos_c);
            let p = e.w + cos_c / RD_PI + rd_lobe_pdf(lobe, wi);
            sum += e.xyz * s.ao * rd_env_f(s, l, cos_c) / p;
        }
    }
    if lobe.alpha > 0.0 {
        let wi = rd_lobe_sample(lobe, u.b.x, u.b.y);
        let pl = rd_lobe_pdf(lobe, wi);
        if pl > 0.0 {
            let d = rd_normalize(lobe.t * wi.x + lobe.b * wi.y + s.n * wi.z);
            let cos_l = rd_dot(s.n, d);
            if cos_l > 0.0 {
                let e = rd_env_lookup(d);
                if any(e.xyz != vec3<f32>(0.0)) && rd_env_visible(s, d) {
                    sum += e.xyz * s.ao * rd_env_f(s, d, cos_l) / (e.w + cos_l / RD_PI + pl);
                }
            }
        }
    }
    return sum;
}

// ---- the split-sum shortcut (render/split_sum.rs) -------------------------------------

/// Texel (c, r) of prefiltered level `level`, wrapping in longitude.
fn rd_pre_texel(level: u32, c: i32, r: i32) -> vec3<f32> {
    let w = i32(env.options.z);
    let h = i32(env.options.w);
    let x = ((c % w) + w) % w;
    let y = clamp(r, 0, h - 1);
    return textureLoad(env_pre, vec2<i32>(x, i32(level) * h + y), 0).xyz;
}

/// Prefiltered level `level` towards unit direction `d`, bilinear between texel centres.
fn rd_pre_dir(level: u32, d: vec3<f32>) -> vec3<f32> {
    let y = clamp(d.y, -1.0, 1.0);
    let u = rd_atan2(d.x, -d.z) / RD_TAU + 0.5;
    let v = rd_atan2(sqrt((1.0 - y) * (1.0 + y)), y) / RD_PI;
    let x = u * f32(env.options.z) - 0.5;
    let yy = v * f32(env.options.w) - 0.5;
    let x0 = floor(x);
    let y0 = floor(yy);
    let fx = x - x0;
    let fy = yy - y0;
    let c = i32(x0);
    let r = i32(y0);
    let top = mix(rd_pre_texel(level, c, r), rd_pre_texel(level, c + 1, r), fx);
    let bottom = mix(rd_pre_texel(level, c, r + 1), rd_pre_texel(level, c + 1, r + 1), fx);
    return mix(top, bottom, fy);
}

/// The GGX-prefiltered radiance towards `d` at roughness `alpha`: linear between the two
/// levels around sqrt(alpha) (levels 1 .. 1 + K hold sqrt(alpha) = 0, 1 / (K - 1), ..., 1).
fn rd_prefiltered(d: vec3<f32>, alpha: f32) -> vec3<f32> {
    let k = textureDimensions(env_pre).y / env.options.w - 1u;
    let f = clamp(sqrt(max(alpha, 0.0)), 0.0, 1.0) * f32(k - 1u);
    let i0 = min(u32(f), k - 1u);
    let i1 = min(i0 + 1u, k - 1u);
    let t = f - f32(i0);
    return mix(rd_pre_dir(1u + i0, d), rd_pre_dir(1u + i1, d), t);
}

/// The split-sum shading of a hit: base E(n) / pi + ks L_pre(r, alpha) (f0 scale + bias).
fn rd_env_split(s: RdSurface) -> vec3<f32> {
    var out = s.base * rd_pre_dir(0u, s.n);
    let ks = object.mat.x;
    let nov = rd_dot(s.n, s.v);
    if ks > 0.0 && nov > 0.0 {
        let refl = s.n * (2.0 * nov) - s.v;
        let alpha = env.weights.z;
        let dfg = rd_dfg(nov, alpha);
        out += ks * rd_prefiltered(refl, alpha) * (env.weights.w * dfg.x + dfg.y);
    }
    return out;
}

// ---- the shading pass ------------------------------------------------------------------

/// The radiance of a hit under the environment: the direct light (rd_shade) times its
/// weight, plus this draw's passes times theirs (or, in the split-sum mode, the split-sum
/// shading times the direct light's weight).
fn rd_env_shade(pos: vec2<f32>, r: RdRay, hit: RdHit) -> vec3<f32> {
    var out = vec3<f32>(0.0);
    if env.weights.y != 0.0 {
        out = rd_shade(r, hit) * env.weights.y;
    }
    let s = rd_surface(r, hit);
    if env.options.y == 1u {
        return out + rd_env_split(s) * env.weights.y;
    }
    let id = rd_sample_id(pos);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < env.size.w; k++) {
        sum += rd_env_pass(s, id, env.size.z + k);
    }
    return out + sum * env.weights.x;
}

// ---- entry points (the shading pass under an environment) ---------------------------------

/// Spheres and planes, shading pass (rd_fs_analytic with the environment).
@fragment
fn rd_fs_analytic_env(@builtin(position) pos: vec4<f32>) -> RdOut {
    if !rd_visible(pos.xy, 0u) {
        discard;
    }
    let r = rd_primary_ray(pos.xy);
    let hit = rd_analytic_hit(r);
    if !hit.ok {
        discard;
    }
    return RdOut(vec4<f32>(rd_env_shade(pos.xy, r, hit), 1.0), rd_depth(hit.t));
}

/// Meshes, shading pass (rd_fs_mesh with the environment).
@fragment
fn rd_fs_mesh_env(@builtin(position) pos: vec4<f32>, @location(0) @interpolate(flat) tri: u32)
    -> RdOut {
    if !rd_visible(pos.xy, tri) {
        discard;
    }
    let r = rd_primary_ray(pos.xy);
    let hit = rd_triangle(r, tri);
    if !hit.ok {
        discard;
    }
    return RdOut(vec4<f32>(rd_env_shade(pos.xy, r, hit), 1.0), rd_depth(hit.t));
}

/// The background under an environment (render.rs, `initial`): the map's radiance along the
/// primary ray where the visibility pass found no object, times the direct weight. Drawn
/// with `rd_vs_full` before the objects; group 1 is not read (an empty group).
@fragment
fn rd_fs_env_background(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    if textureLoad(rd_ids, vec2<i32>(pos.xy), 0).x != 0u {
        discard;
    }
    let r = rd_primary_ray(pos.xy);
    return vec4<f32>(rd_env_lookup(r.d).xyz * env.weights.y, 1.0);
}
