// fastbrdf GPU renderer: the CPU renderer's per-sample work (crates/render/src/render.rs) as
// vertex and fragment shaders. See crates/gpu/src/render/mod.rs for the design.
//
// Every function here is the twin of the CPU code named in its comment, with the same
// arrangement of f32 operations (left-to-right sums, glam's formulas for dot, cross, normalize,
// lerp and any_orthonormal_pair), so that the two renders differ only by what WGSL allows a
// GPU to do differently (fused multiply-adds, looser division, sqrt, atan2, asin) and by the
// model functions' own CPU-GPU differences (tests/parity.rs).
//
// The module is completed at run time by the model library and a function
// `rd_brdf(wi, wo, h) -> RdSpec` (render/models.rs: the object's model per colour channel, and
// with a tint its zero model, from the block of coefficients at fb_k[h]), or by a user's shader (`user::UserShader::wgsl_at`, its
// parameters at group 1 binding 5) and `rd_brdf` calling its `fb_user_brdf` (R, G, B: the
// whole BRDF).

/// Per-frame (per-tile) data. Vectors are vec4 to keep the uniform layout obvious.
struct Frame {
    /// Camera: eye; forward f, right r, up u (Camera::ray's frame, computed by glam on the CPU).
    eye: vec4<f32>,
    fwd: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    /// tan(fov_y / 2), aspect w / h, w as f32, h as f32.
    cam: vec4<f32>,
    /// Ambient radiance (rgb).
    ambient: vec4<f32>,
    /// Image width, height (pixels), samples per pixel along each axis N, number of lights.
    size: vec4<u32>,
    /// The tile: first sample column and row (in the (W N) x (H N) sample grid).
    tile: vec4<u32>,
    /// World point -> clip position of the tile (meshes), rows of a 4x4 matrix.
    clip_x: vec4<f32>,
    clip_y: vec4<f32>,
    clip_z: vec4<f32>,
    clip_w: vec4<f32>,
    /// Shadow rays: on (1) or off (0), SHADOW_EPS, 1 - 1e-5 and f32::MAX (the CPU's f32
    /// values, so that no WGSL literal rounds differently).
    shadow: vec4<f32>,
}

/// A light (twin: scene::Light). kind_pos.w: 0 directional (xyz: unit direction to the
/// light), 1 point (xyz: position). color.w: intensity.
struct Light {
    kind_pos: vec4<f32>,
    color: vec4<f32>,
}

/// One object: shape and material (twin: scene::Object).
struct Object {
    /// Sphere: centre, radius. Plane: point.
    a: vec4<f32>,
    /// Plane: normal; and its tangent pair (glam's any_orthonormal_pair, from the CPU).
    normal: vec4<f32>,
    tu: vec4<f32>,
    tv: vec4<f32>,
    /// Albedo (rgb) and kd.
    albedo: vec4<f32>,
    /// ks, bump scale, bump depth, 0.
    mat: vec4<f32>,
    /// Texture width and height as f32, 0, 0.
    tex: vec4<f32>,
    /// Shape (0 sphere, 1 plane, 2 mesh), has a texture, has a bump, mesh has uvs.
    flags: vec4<u32>,
    /// Texture width and height, the object's index in the scene plus one (its id in the
    /// visibility pass), and 1 when the mesh has tangents (`mesh_v` then holds 12 floats per
    /// vertex, the tangent last).
    tex_size: vec4<u32>,
    /// The specular tint's texture (Specular::tint): width, height, its first row in the
    /// object's texture (below the albedo texture's rows), and 1 when there is one.
    tint: vec4<u32>,
    /// A glTF material's normal, occlusion, emissive and metallic-roughness textures
    /// (maps.rs), likewise.
    normal_map: vec4<u32>,
    occlusion: vec4<u32>,
    emissive: vec4<u32>,
    mr_tex: vec4<u32>,
    /// The normal texture's scale, the occlusion's strength, 0, 0.
    maps: vec4<f32>,
    /// The emission (emissiveFactor x strength; zero without one), 0.
    emission: vec4<f32>,
    /// A metallic-roughness texture's level table (render/models.rs): its first entry in
    /// fb_k, the lowest and highest level in it, and 1 when there is one.
    mr: vec4<u32>,
    /// Its metallicFactor, roughnessFactor, the levels per unit of roughness (maps::LEVELS), 0.
    mr_factors: vec4<f32>,
}

/// `rd_brdf`'s value: the model per channel, and its tint's zero model (Specular::tint).
struct RdSpec {
    f: vec3<f32>,
    zero: vec3<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> lights: array<Light>;

/// An occluder for the shadow rays (twin: scene::Shape). kind.x: 0 sphere (a: centre,
/// radius), 1 plane (a: point, b: normal), 2 mesh (kind.y: its root in `sh_nodes`).
struct Occluder {
    a: vec4<f32>,
    b: vec4<f32>,
    kind: vec4<u32>,
}

/// A BVH node (twin: geometry::Node): leaf (count > 0): first triangle in `sh_tris` and
/// count; inner: left child index in `sh_nodes` (right = left + 1).
struct BvhNode {
    lo: vec3<f32>,
    start: u32,
    hi: vec3<f32>,
    count: u32,
}

/// Every object of the scene, in scene order.
@group(0) @binding(2) var<storage, read> sh_objects: array<Occluder>;
/// Every mesh's BVH, one after the other (indices rebased).
@group(0) @binding(3) var<storage, read> sh_nodes: array<BvhNode>;
/// Every mesh's triangles in its BVH's leaf order: 9 floats each (corners a, b, c).
@group(0) @binding(4) var<storage, read> sh_tris: array<f32>;

@group(1) @binding(0) var<uniform> object: Object;
/// Linear albedo texels (rgb), then the specular tint's rows, read with textureLoad: the
/// bilinear filter is texture.rs's.
@group(1) @binding(1) var albedo_tex: texture_2d<f32>;
/// Mesh vertices: 8 floats each (position, normal, uv), 12 with tangents (xyz, w the
/// bitangent's sign).
@group(1) @binding(2) var<storage, read> mesh_v: array<f32>;
/// Mesh triangles: 4 u32 each, the vertex indices a, b, c and a mask of the triangle's
/// boundary edges (edges no other triangle shares): 1 for a-b, 2 for b-c, 4 for c-a.
@group(1) @binding(3) var<storage, read> mesh_t: array<u32>;
/// The model instance's coefficients (spec::Emit::storage).
@group(1) @binding(4) var<storage, read> fb_k: array<f32>;
// Binding 5 of group 1: a user's parameters (`fb_user_params`), declared by its module.
/// The visibility pass's result, read by the shading pass only: per sample, the object
/// nearest along the primary ray (its index plus one; 0: none) and, for a mesh, its triangle.
@group(2) @binding(0) var rd_ids: texture_2d<u32>;

const RD_PI: f32 = 3.14159265358979323846;
const RD_TAU: f32 = 6.28318530717958647692;
/// Ray parameters at or below this are no hit (twin: Scene::intersect's 1e-4).
const RD_T_MIN: f32 = 1e-4;
/// The largest f32 below 1: depth values stay inside the depth attachment's range.
const RD_DEPTH_MAX: f32 = 0.99999994;

// ---- the scene's features ---------------------------------------------------------------
// What the scene uses (render/features.rs sets false those no object needs): the code behind
// a false constant is dead and compilers drop it. Adapters that run both sides of a branch as
// masked SIMD code (lavapipe) would otherwise pay for every part in every
// fragment. Each guards a test of the object's (or the frame's) own flag, so the constants
// change no value.
const RD_USE_TEXTURE: bool = true;
const RD_USE_BUMP: bool = true;
const RD_USE_UVS: bool = true;
const RD_USE_TANGENTS: bool = true;
const RD_USE_TINT: bool = true;
const RD_USE_NORMAL_MAP: bool = true;
const RD_USE_OCCLUSION: bool = true;
const RD_USE_EMISSIVE: bool = true;
const RD_USE_MR: bool = true;
/// Shadow rays: off where no object can be shadowed (a lone sphere or plane).
const RD_USE_SHADOWS: bool = true;
/// The occluder kinds the shadow rays test.
const RD_OCC_SPHERES: bool = true;
const RD_OCC_PLANES: bool = true;
const RD_OCC_MESHES: bool = true;

// ---- glam twins ------------------------------------------------------------------------

/// glam Vec3::dot: (x x') + (y y') + (z z').
fn rd_dot(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// glam Vec3::cross.
fn rd_cross(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

/// glam Vec3::length_recip: 1 / sqrt(dot).
fn rd_length_recip(a: vec3<f32>) -> f32 {
    return 1.0 / sqrt(rd_dot(a, a));
}

/// glam Vec3::normalize: a * length_recip.
fn rd_normalize(a: vec3<f32>) -> vec3<f32> {
    return a * rd_length_recip(a);
}

/// glam Vec3::normalize_or: the fallback when 1 / length is not finite and positive.
fn rd_normalize_or(a: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let rcp = rd_length_recip(a);
    // Finite and positive: below the largest f32 (this also rejects NaN).
    if rcp > 0.0 && rcp <= 0x1.fffffep+127f {
        return a * rcp;
    }
    return fallback;
}

/// glam Vec3::lerp: a (1 - s) + b s.
fn rd_lerp3(a: vec3<f32>, b: vec3<f32>, s: f32) -> vec3<f32> {
    return a * (1.0 - s) + b * s;
}

/// Rust's f32::signum for non-NaN x: copysign(1, x), so -0.0 gives -1.
fn rd_signum(x: f32) -> f32 {
    return select(1.0, -1.0, (bitcast<u32>(x) & 0x80000000u) != 0u);
}

struct RdPair {
    t: vec3<f32>,
    b: vec3<f32>,
}

/// glam Vec3::any_orthonormal_pair (Duff et al., "Building an orthonormal basis, revisited").
fn rd_orthonormal_pair(n: vec3<f32>) -> RdPair {
    let sign = rd_signum(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return RdPair(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// ---- inverse trigonometry --------------------------------------------------------------

/// atan(a) for a in [0, 1], within 2 ulp: Cephes' atanf (range reduction at tan(pi/8), a
/// degree-9 odd polynomial). WGSL's built-in atan2 and asin may err by much more (lavapipe's
/// put sphere uvs off by 1e-4 of a texel row), which a texture turns into visible differences.
fn rd_atan01(a: f32) -> f32 {
    var x = a;
    var y = 0.0;
    if a > 0.41421356 {
        x = (a - 1.0) / (a + 1.0);
        y = 0.78539816;
    }
    let z = x * x;
    return y + (((0.0805374449538 * z - 0.138776856032) * z + 0.199777106478) * z
        - 0.333329491539) * z * x + x;
}

/// Rust's f32::atan2 (for finite inputs; the sign of a zero y is kept, as in libm).
fn rd_atan2(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let hi = max(ax, ay);
    if hi == 0.0 {
        return select(0.0, RD_PI, x < 0.0 || (bitcast<u32>(x) & 0x80000000u) != 0u)
            * rd_signum(y);
    }
    var r = rd_atan01(min(ax, ay) / hi);
    if ay > ax {
        r = 1.57079633 - r;
    }
    if x < 0.0 {
        r = RD_PI - r;
    }
    return r * rd_signum(y);
}

/// Rust's f32::asin for x in [-1, 1]: atan2(x, sqrt((1 - x)(1 + x))).
fn rd_asin(x: f32) -> f32 {
    return rd_atan2(x, sqrt((1.0 - x) * (1.0 + x)));
}

// ---- camera and geometry (twins: scene.rs, geometry.rs) -------------------------------------

struct RdRay {
    o: vec3<f32>,
    d: vec3<f32>,
}

/// The primary ray of the sample at fragment position `pos` (twins: render_tile's stratified
/// sample position and Camera::ray).
fn rd_primary_ray(pos: vec2<f32>) -> RdRay {
    let gx = frame.tile.x + u32(pos.x);
    let gy = frame.tile.y + u32(pos.y);
    let n = frame.size.z;
    let x = f32(gx / n) + (f32(gx % n) + 0.5) / f32(n);
    let y = f32(gy / n) + (f32(gy % n) + 0.5) / f32(n);
    let th = frame.cam.x;
    let aspect = frame.cam.y;
    let sx = (2.0 * x / frame.cam.z - 1.0) * th * aspect;
    let sy = (1.0 - 2.0 * y / frame.cam.w) * th;
    let d = frame.fwd.xyz + sx * frame.right.xyz + sy * frame.up.xyz;
    return RdRay(frame.eye.xyz, rd_normalize(d));
}

struct RdHit {
    ok: bool,
    t: f32,
    n: vec3<f32>,
    uv: vec2<f32>,
    /// The interpolated tangent of a mesh with tangents (TriMesh::hit_tangent), else zero.
    tangent: vec4<f32>,
}

fn rd_miss() -> RdHit {
    return RdHit(false, 0.0, vec3<f32>(0.0, 0.0, 1.0), vec2<f32>(0.0, 0.0), vec4<f32>(0.0));
}

/// Sphere::intersect with t in (RD_T_MIN, inf).
fn rd_sphere(r: RdRay) -> RdHit {
    let center = object.a.xyz;
    let radius = object.a.w;
    let oc = r.o - center;
    let b = rd_dot(oc, r.d);
    let c = rd_dot(oc, oc) - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return rd_miss();
    }
    let s = sqrt(disc);
    let t = select(-b + s, -b - s, -b - s > RD_T_MIN);
    if !(t > RD_T_MIN) {
        return rd_miss();
    }
    let p = r.o + t * r.d;
    let n = (p - center) / radius;
    let uv = vec2<f32>(
        0.5 + rd_atan2(n.z, n.x) / RD_TAU,
        0.5 - rd_asin(clamp(n.y, -1.0, 1.0)) / RD_PI,
    );
    return RdHit(true, t, n, uv, vec4<f32>(0.0));
}

/// Plane::intersect with t in (RD_T_MIN, inf).
fn rd_plane(r: RdRay) -> RdHit {
    let point = object.a.xyz;
    let normal = object.normal.xyz;
    let denom = rd_dot(normal, r.d);
    if abs(denom) < 1e-8 {
        return rd_miss();
    }
    let t = rd_dot(point - r.o, normal) / denom;
    if !(t > RD_T_MIN) {
        return rd_miss();
    }
    let p = r.o + t * r.d;
    let uv = vec2<f32>(rd_dot(p - point, object.tu.xyz), rd_dot(p - point, object.tv.xyz));
    return RdHit(true, t, normal, uv, vec4<f32>(0.0));
}

/// The first float of vertex `i` in `mesh_v`.
fn rd_vertex(i: u32) -> u32 {
    return select(8u, 12u, object.tex_size.w != 0u) * i;
}

fn rd_vertex_p(i: u32) -> vec3<f32> {
    let k = rd_vertex(i);
    return vec3<f32>(mesh_v[k], mesh_v[k + 1u], mesh_v[k + 2u]);
}

fn rd_vertex_n(i: u32) -> vec3<f32> {
    let k = rd_vertex(i);
    return vec3<f32>(mesh_v[k + 3u], mesh_v[k + 4u], mesh_v[k + 5u]);
}

fn rd_vertex_uv(i: u32) -> vec2<f32> {
    let k = rd_vertex(i);
    return vec2<f32>(mesh_v[k + 6u], mesh_v[k + 7u]);
}

fn rd_vertex_tangent(i: u32) -> vec4<f32> {
    let k = rd_vertex(i);
    return vec4<f32>(mesh_v[k + 8u], mesh_v[k + 9u], mesh_v[k + 10u], mesh_v[k + 11u]);
}

/// TriMesh::hit_triangle (Moller-Trumbore) and TriMesh::intersect's interpolation, for the
/// triangle the rasteriser chose. Where the rasteriser and the ray test disagree about a
/// sample within rounding of an edge: across a boundary edge (a silhouette of an open mesh)
/// the sample is discarded, as the CPU's ray misses; across a shared edge it is shaded with
/// its barycentrics as they are (the neighbour, which the CPU's ray hits, did not get the
/// sample from the rasteriser, and shading is continuous across the edge).
fn rd_triangle(r: RdRay, tri: u32) -> RdHit {
    let ia = mesh_t[4u * tri];
    let ib = mesh_t[4u * tri + 1u];
    let ic = mesh_t[4u * tri + 2u];
    let boundary = mesh_t[4u * tri + 3u];
    let a = rd_vertex_p(ia);
    let b = rd_vertex_p(ib);
    let c = rd_vertex_p(ic);
    let e1 = b - a;
    let e2 = c - a;
    let p = rd_cross(r.d, e2);
    let det = rd_dot(e1, p);
    if abs(det) < 1e-12 {
        return rd_miss();
    }
    let inv = 1.0 / det;
    let s = r.o - a;
    let u = rd_dot(s, p) * inv;
    let q = rd_cross(s, e1);
    let v = rd_dot(r.d, q) * inv;
    let t = rd_dot(e2, q) * inv;
    if !(t > RD_T_MIN) {
        return rd_miss();
    }
    // Outside edge c-a (u < 0), a-b (v < 0), b-c (u > 1 or u + v > 1): the CPU's tests.
    var outside = 0u;
    if !(u >= 0.0) {
        outside |= 4u;
    }
    if !(v >= 0.0) {
        outside |= 1u;
    }
    if u > 1.0 || u + v > 1.0 {
        outside |= 2u;
    }
    if (outside & boundary) != 0u {
        return rd_miss();
    }
    let w = 1.0 - u - v;
    var n = rd_normalize_or(
        rd_vertex_n(ia) * w + rd_vertex_n(ib) * u + rd_vertex_n(ic) * v,
        vec3<f32>(0.0),
    );
    if all(n == vec3<f32>(0.0)) {
        n = rd_normalize_or(rd_cross(e1, e2), vec3<f32>(0.0));
    }
    var uv = vec2<f32>(u, v);
    if RD_USE_UVS && object.flags.w != 0u {
        uv = rd_vertex_uv(ia) * w + rd_vertex_uv(ib) * u + rd_vertex_uv(ic) * v;
    }
    // TriMesh::hit_tangent: interpolated, the sign the first corner's.
    var tangent = vec4<f32>(0.0);
    if RD_USE_TANGENTS && object.tex_size.w != 0u {
        let ta = rd_vertex_tangent(ia);
        let ts = ta * w + rd_vertex_tangent(ib) * u + rd_vertex_tangent(ic) * v;
        tangent = vec4<f32>(ts.xyz, ta.w);
    }
    return RdHit(true, t, n, uv, tangent);
}

// ---- texture (twin: texture.rs) -------------------------------------------------------------

/// f32::rem_euclid(1.0): x - trunc(x) is Rust's exact fmod for a divisor of 1.
fn rd_rem1(x: f32) -> f32 {
    let r = x - trunc(x);
    return select(r, r + 1.0, r < 0.0);
}

/// Texel (xi, yi) of the w x h texture whose rows start at `row0`, wrapping.
fn rd_texel(xi: f32, yi: f32, size: vec2<u32>, row0: u32) -> vec3<f32> {
    let w = i32(size.x);
    let h = i32(size.y);
    let x = ((i32(xi) % w) + w) % w;
    let y = ((i32(yi) % h) + h) % h;
    return textureLoad(albedo_tex, vec2<i32>(x, y + i32(row0)), 0).xyz;
}

/// Texture::sample of the texture of `size` texels (`sf` as f32) at rows `row0..`: bilinear,
/// wrapping, v = 0 at the bottom.
fn rd_texture(uv: vec2<f32>, sf: vec2<f32>, size: vec2<u32>, row0: u32) -> vec3<f32> {
    let x = rd_rem1(uv.x) * sf.x - 0.5;
    let y = (1.0 - rd_rem1(uv.y)) * sf.y - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let top = rd_lerp3(rd_texel(x0, y0, size, row0), rd_texel(x0 + 1.0, y0, size, row0), fx);
    let bottom = rd_lerp3(rd_texel(x0, y0 + 1.0, size, row0),
        rd_texel(x0 + 1.0, y0 + 1.0, size, row0), fx);
    return rd_lerp3(top, bottom, fy);
}

// ---- micro-relief (twin: bump.rs) -----------------------------------------------------------

fn rd_hash(i: i32, j: i32, k: i32) -> f32 {
    var h = (bitcast<u32>(i) * 0x8da6b343u) ^ (bitcast<u32>(j) * 0xd8163841u)
        ^ (bitcast<u32>(k) * 0xcb1ab31fu);
    h ^= h >> 13u;
    h = h * 0x5bd1e995u;
    h ^= h >> 15u;
    return f32(h & 0x00ffffffu) / 16777215.0;
}

fn rd_smooth(t: f32) -> f32 {
    return t * t * (3.0 - 2.0 * t);
}

fn rd_lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + (b - a) * t;
}

/// bump::noise: value noise in [0, 1].
fn rd_noise(p: vec3<f32>) -> f32 {
    let f = floor(p);
    let i = i32(f.x);
    let j = i32(f.y);
    let k = i32(f.z);
    let t = p - f;
    let u = rd_smooth(t.x);
    let v = rd_smooth(t.y);
    let w = rd_smooth(t.z);
    let x00 = rd_lerp(rd_hash(i, j, k), rd_hash(i + 1, j, k), u);
    let x10 = rd_lerp(rd_hash(i, j + 1, k), rd_hash(i + 1, j + 1, k), u);
    let x01 = rd_lerp(rd_hash(i, j, k + 1), rd_hash(i + 1, j, k + 1), u);
    let x11 = rd_lerp(rd_hash(i, j + 1, k + 1), rd_hash(i + 1, j + 1, k + 1), u);
    return rd_lerp(rd_lerp(x00, x10, v), rd_lerp(x01, x11, v), w);
}

/// Bump::height.
fn rd_height(p: vec3<f32>) -> f32 {
    let scale = object.mat.y;
    let depth = object.mat.z;
    let q = p * scale;
    return (rd_noise(q) + 0.5 * rd_noise(q * 2.03 + 17.0) + 0.25 * rd_noise(q * 4.07 + 31.0))
        / 1.75 * depth / scale;
}

/// Bump::perturb.
fn rd_perturb(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let f = rd_orthonormal_pair(n);
    let eps = 0.25 / object.mat.y;
    let dt = (rd_height(p + eps * f.t) - rd_height(p - eps * f.t)) / (2.0 * eps);
    let db = (rd_height(p + eps * f.b) - rd_height(p - eps * f.b)) / (2.0 * eps);
    return rd_normalize_or(n - dt * f.t - db * f.b, n);
}

// ---- shadow rays (twins: Scene::shadowed, Scene::occluded, the shapes' hit) -------------

/// Sphere::hit with t in (t_min, t_max).
fn rd_occ_sphere(r: RdRay, center: vec3<f32>, radius: f32, t_min: f32, t_max: f32) -> bool {
    let oc = r.o - center;
    let b = rd_dot(oc, r.d);
    let c = rd_dot(oc, oc) - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return false;
    }
    let s = sqrt(disc);
    let t = select(-b + s, -b - s, -b - s > t_min);
    return t > t_min && t < t_max;
}

/// Plane::hit with t in (t_min, t_max).
fn rd_occ_plane(r: RdRay, point: vec3<f32>, normal: vec3<f32>, t_min: f32, t_max: f32) -> bool {
    let denom = rd_dot(normal, r.d);
    if abs(denom) < 1e-8 {
        return false;
    }
    let t = rd_dot(point - r.o, normal) / denom;
    return t > t_min && t < t_max;
}

fn rd_sh_corner(tri: u32, k: u32) -> vec3<f32> {
    let i = 9u * tri + 3u * k;
    return vec3<f32>(sh_tris[i], sh_tris[i + 1u], sh_tris[i + 2u]);
}

/// TriMesh::hit_triangle (Moller-Trumbore, the CPU's inclusive tests in its order).
fn rd_occ_triangle(r: RdRay, tri: u32, t_min: f32, t_max: f32) -> bool {
    let a = rd_sh_corner(tri, 0u);
    let b = rd_sh_corner(tri, 1u);
    let c = rd_sh_corner(tri, 2u);
    let e1 = b - a;
    let e2 = c - a;
    let p = rd_cross(r.d, e2);
    let det = rd_dot(e1, p);
    if abs(det) < 1e-12 {
        return false;
    }
    let inv = 1.0 / det;
    let s = r.o - a;
    let u = rd_dot(s, p) * inv;
    if !(u >= 0.0 && u <= 1.0) {
        return false;
    }
    let q = rd_cross(s, e1);
    let v = rd_dot(r.d, q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = rd_dot(e2, q) * inv;
    return t > t_min && t < t_max;
}

/// One axis of geometry.rs's `slab`, its comparisons as written (NaN-exact): the entry and
/// the widened exit along the axis, clipped to (near, far).
fn rd_slab_axis(lo: f32, hi: f32, o: f32, inv: f32, near: f32, far: f32) -> vec2<f32> {
    let a0 = (lo - o) * inv;
    let b0 = (hi - o) * inv;
    let lt = a0 < b0;
    let a = select(b0, a0, lt);
    let b = select(a0, b0, lt);
    // geometry::SLAB_WIDEN's bits (1 + 2 gamma(3)).
    let bw = b * bitcast<f32>(0x3f800003u);
    return vec2<f32>(select(near, a, a > near), select(far, bw, bw < far));
}

/// geometry.rs's `slab` of `node`: whether the ray may hit inside it between t_min and t_max.
fn rd_occ_slab(node: BvhNode, r: RdRay, inv: vec3<f32>, t_min: f32, t_max: f32) -> bool {
    let x = rd_slab_axis(node.lo.x, node.hi.x, r.o.x, inv.x, t_min, t_max);
    let y = rd_slab_axis(node.lo.y, node.hi.y, r.o.y, inv.y, x.x, x.y);
    let z = rd_slab_axis(node.lo.z, node.hi.z, r.o.z, inv.z, y.x, y.y);
    return z.x <= z.y;
}

/// TriMesh::occluded_binary: the same slab test and walk (both children tested at their
/// parent, the left taken first, the right kept on the stack when both pass: 64 entries as
/// on the CPU, or the scene's deepest BVH's depth + 1, which this walk never fills,
/// render/features.rs), ending at the first triangle hit. Whatever the order, a hit is found
/// exactly where some leaf whose slab tests pass holds one: the CPU's answer.
fn rd_occ_mesh(r: RdRay, root: u32, t_min: f32, t_max: f32) -> bool {
    let inv = vec3<f32>(1.0 / r.d.x, 1.0 / r.d.y, 1.0 / r.d.z);
    if !rd_occ_slab(sh_nodes[root], r, inv, t_min, t_max) {
        return false;
    }
    var stack: array<u32, 64>;
    var sp = 0u;
    var at = root;
    loop {
        let node = sh_nodes[at];
        if node.count > 0u {
            for (var k = 0u; k < node.count; k++) {
                if rd_occ_triangle(r, node.start + k, t_min, t_max) {
                    return true;
                }
            }
        } else {
            let l = node.start;
            let hl = rd_occ_slab(sh_nodes[l], r, inv, t_min, t_max);
            let hr = rd_occ_slab(sh_nodes[l + 1u], r, inv, t_min, t_max);
            if hl || hr {
                if hl && hr && sp < 64u {
                    stack[sp] = l + 1u;
                    sp += 1u;
                }
                at = select(l + 1u, l, hl);
                continue;
            }
        }
        if sp == 0u {
            return false;
        }
        sp -= 1u;
        at = stack[sp];
    }
    // Not reached (the loop returns); WGSL's validation asks for a return here.
    return false;
}

/// Scene::occluded: whether any object lies along `r` strictly between t_min and t_max.
fn rd_occluded(r: RdRay, t_min: f32, t_max: f32) -> bool {
    for (var i = 0u; i < arrayLength(&sh_objects); i++) {
        let o = sh_objects[i];
        var hit = false;
        if RD_OCC_SPHERES && o.kind.x == 0u {
            hit = rd_occ_sphere(r, o.a.xyz, o.a.w, t_min, t_max);
        } else if RD_OCC_PLANES && o.kind.x == 1u {
            hit = rd_occ_plane(r, o.a.xyz, o.b.xyz, t_min, t_max);
        } else if RD_OCC_MESHES && o.kind.x == 2u {
            hit = rd_occ_mesh(r, o.kind.y, t_min, t_max);
        }
        if hit {
            return true;
        }
    }
    return false;
}

/// Scene::shadowed: light from `l` blocked at `p` (normal `n`, facing `l`) up to `dist`
/// along `l` (`directional`: no limit; f32::MAX stands for the CPU's infinity, the same
/// decisions for the strict `t < t_max` and the slab test).
fn rd_shadowed(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, dist: f32, directional: bool) -> bool {
    let ap = abs(p);
    let eps = frame.shadow.y * (1.0 + max(ap.x, max(ap.y, ap.z)));
    let o = p + n * eps;
    var t_max = frame.shadow.w;
    if !directional {
        t_max = dist * frame.shadow.z - eps;
    }
    return rd_occluded(RdRay(o, l), eps, t_max);
}

// ---- shading (twin: render_tile) ------------------------------------------------------------

/// Light::at: (unit direction to the light, radiance scale).
fn rd_light_at(l: Light, p: vec3<f32>) -> RdPair {
    if l.kind_pos.w == 0.0 {
        return RdPair(l.kind_pos.xyz, l.color.xyz * l.color.w);
    }
    let d = l.kind_pos.xyz - p;
    let d2 = max(rd_dot(d, d), 1e-12);
    return RdPair(d / sqrt(d2), l.color.xyz * (l.color.w / d2));
}

/// A hit as shading sees it: point, view direction, shading normal (two-sided, bumped),
/// unbumped normal (shadow rays leave along it), kd x albedo (textured), the specular tint's
/// texel (one without a tint), the specular term's local frame (t, b) about n.
struct RdSurface {
    p: vec3<f32>,
    v: vec3<f32>,
    n: vec3<f32>,
    g: vec3<f32>,
    base: vec3<f32>,
    tint: vec3<f32>,
    t: vec3<f32>,
    b: vec3<f32>,
    /// The occlusion of the light that is not punctual (ambient, environment); emission.
    ao: f32,
    emit: vec3<f32>,
    /// The specular term's blocks in fb_k (render/models.rs): one (`h0`), or with a
    /// metallic-roughness texture two, the models at metallic 0 and 1 of the hit's roughness
    /// level, mixed by `metal`.
    corners: u32,
    h0: u32,
    h1: u32,
    metal: f32,
}

/// Rust's f32::round for x >= 0 (halves away from zero; WGSL's round goes to even).
fn rd_round(x: f32) -> f32 {
    let t = trunc(x);
    return select(t, t + 1.0, x - t >= 0.5);
}

/// maps::frame: the shading normal and local frame (t, b) about it from the smooth normal `n`
/// (facing the viewer `v`; `back`: the hit's normal reversed), the mesh's interpolated
/// `tangent` and the normal texture at `uv`; n and any_orthonormal_pair without a usable
/// tangent.
struct RdFrame {
    n: vec3<f32>,
    t: vec3<f32>,
    b: vec3<f32>,
}

fn rd_tangent_frame(n: vec3<f32>, tangent: vec4<f32>, back: bool, v: vec3<f32>, uv: vec2<f32>)
    -> RdFrame {
    let sign = select(1.0, -1.0, back);
    var t = sign * tangent.xyz;
    t = rd_normalize_or(t - n * rd_dot(n, t), vec3<f32>(0.0));
    if all(t == vec3<f32>(0.0)) {
        let f = rd_orthonormal_pair(n);
        return RdFrame(n, f.t, f.b);
    }
    let w = select(1.0, -1.0, tangent.w < 0.0);
    let b = rd_cross(n, t) * w;
    var shading = n;
    if RD_USE_NORMAL_MAP && object.normal_map.w != 0u {
        let x = rd_part(uv, object.normal_map) * 2.0 - vec3<f32>(1.0);
        let sc = object.maps.x;
        let p = rd_normalize_or(t * (x.x * sc) + b * (x.y * sc) + n * x.z, vec3<f32>(0.0));
        if rd_dot(p, v) > 0.0 {
            shading = p;
        }
    }
    let t2 = rd_normalize_or(t - shading * rd_dot(shading, t), vec3<f32>(0.0));
    if all(t2 == vec3<f32>(0.0)) {
        let f = rd_orthonormal_pair(shading);
        return RdFrame(shading, f.t, f.b);
    }
    let b2 = rd_cross(shading, t2);
    return RdFrame(shading, t2, select(b2, -b2, rd_dot(b2, b) < 0.0));
}

/// The shading prologue of render_tile (and of the environment's passes, env.wgsl).
fn rd_surface(r: RdRay, hit: RdHit) -> RdSurface {
    let p = r.o + hit.t * r.d;
    let v = -r.d;
    var n = hit.n;
    if rd_dot(hit.n, v) < 0.0 {
        n = -hit.n;
    }
    let g = n;
    // The frame: a bumped normal's any_orthonormal_pair, else the mesh's tangent frame (and
    // its normal texture).
    var f: RdPair;
    if RD_USE_BUMP && object.flags.z != 0u {
        let pn = rd_perturb(p, n);
        if rd_dot(pn, v) > 0.0 {
            n = pn;
        }
        f = rd_orthonormal_pair(n);
    } else {
        let tf = rd_tangent_frame(n, hit.tangent, rd_dot(hit.n, v) < 0.0, v, hit.uv);
        n = tf.n;
        f = RdPair(tf.t, tf.b);
    }
    var albedo = object.albedo.xyz;
    if RD_USE_TEXTURE && object.flags.y != 0u {
        albedo = albedo * rd_texture(hit.uv, object.tex.xy, object.tex_size.xy, 0u);
    }
    var tint = vec3<f32>(1.0);
    if RD_USE_TINT && object.tint.w != 0u {
        tint = rd_part(hit.uv, object.tint);
    }
    // maps::texels: occlusion and emission.
    var ao = 1.0;
    if RD_USE_OCCLUSION && object.occlusion.w != 0u {
        ao = 1.0 + object.maps.y * (clamp(rd_part(hit.uv, object.occlusion).x, 0.0, 1.0) - 1.0);
    }
    var emit = object.emission.xyz;
    if RD_USE_EMISSIVE && object.emissive.w != 0u {
        emit = emit * rd_part(hit.uv, object.emissive);
    }
    // MetallicRoughness::at: metallic (B) and the roughness level (G), and their blocks.
    var corners = 1u;
    var h0 = 0u;
    var h1 = 0u;
    var metal = 0.0;
    if RD_USE_MR && object.mr.w != 0u {
        let t = rd_part(hit.uv, object.mr_tex);
        metal = clamp(object.mr_factors.x * t.z, 0.0, 1.0);
        let r = clamp(object.mr_factors.y * t.y, 0.0, 1.0);
        let level = clamp(u32(rd_round(r * object.mr_factors.z)), object.mr.y, object.mr.z);
        let e = object.mr.x + 2u * (level - object.mr.y);
        corners = 2u;
        h0 = u32(fb_k[e]);
        h1 = u32(fb_k[e + 1u]);
    }
    return RdSurface(p, v, n, g, albedo * object.albedo.w, tint, f.t, f.b, ao, emit, corners,
        h0, h1, metal);
}

/// Texture::sample of the part `k` of the object's texture (width, height, first row, present).
fn rd_part(uv: vec2<f32>, k: vec4<u32>) -> vec3<f32> {
    return rd_texture(uv, vec2<f32>(k.xy), k.xy, k.z);
}

/// The specular term `li ks f cos` per channel (render.rs, `add_specular`): with a tint,
/// `f_zero + t (f - f_zero)` of the two terms so weighted, t the texel.
fn rd_specular(s: RdSurface, li: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let ks = object.mat.x;
    // One block, or two mixed by metallic (mapped.rs, `add_specular_mapped`): a loop, so that
    // the model's code is compiled once.
    var v = array<vec3<f32>, 2>();
    for (var c = 0u; c < s.corners; c++) {
        let f = rd_brdf(wi, wo, select(s.h0, s.h1, c == 1u));
        let f1 = li * (ks * f.f * wi.z);
        if !RD_USE_TINT || object.tint.w == 0u {
            v[c] = f1;
        } else {
            let f0 = li * (ks * f.zero * wi.z);
            v[c] = f0 + s.tint * (f1 - f0);
        }
    }
    if s.corners == 1u {
        return v[0];
    }
    return v[0] * (1.0 - s.metal) + v[1] * s.metal;
}

/// The radiance of a hit: two-sided normal, micro-relief, texture, ambient, then per light
/// the diffuse and the specular term, accumulated in the CPU's order.
fn rd_shade(r: RdRay, hit: RdHit) -> vec3<f32> {
    let s = rd_surface(r, hit);
    let p = s.p;
    let v = s.v;
    let n = s.n;
    let g = s.g;
    let base = s.base;
    let ks = object.mat.x;
    var radiance = frame.ambient.xyz * base * s.ao + s.emit;
    for (var i = 0u; i < frame.size.w; i++) {
        let la = rd_light_at(lights[i], p);
        let l = la.t;
        let li = la.b;
        let cos_i = rd_dot(n, l);
        if cos_i <= 0.0 {
            continue;
        }
        // The CPU's shadow rule (render.rs, `direct`): no shadow ray where only the bumped
        // normal faces the light.
        if RD_USE_SHADOWS && frame.shadow.x != 0.0 && rd_dot(g, l) > 0.0 {
            let directional = lights[i].kind_pos.w == 0.0;
            var dist = 0.0;
            if !directional {
                let d = lights[i].kind_pos.xyz - p;
                dist = sqrt(max(rd_dot(d, d), 1e-12));
            }
            if rd_shadowed(p, g, l, dist, directional) {
                continue;
            }
        }
        radiance += li * base * (cos_i / RD_PI);
        if ks > 0.0 {
            let wi = vec3<f32>(rd_dot(l, s.t), rd_dot(l, s.b), cos_i);
            let wo = vec3<f32>(rd_dot(v, s.t), rd_dot(v, s.b), rd_dot(v, n));
            // Per channel the CPU's `li * (ks * f * cos)`, grey, coloured or RGB.
            radiance += rd_specular(s, li, wi, wo);
        }
    }
    return radiance;
}

/// t as a depth value: scaling by 2^-40 is exact, so the depth test orders hits exactly as
/// the CPU's t comparisons do (strictly nearer wins; draws go in scene order).
fn rd_depth(t: f32) -> f32 {
    return min(ldexp(t, -40), RD_DEPTH_MAX);
}

struct RdOut {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

/// The visibility pass's output: the hit's object and triangle, and its depth.
struct RdIdOut {
    @location(0) id: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

/// Whether the visibility pass found this object's triangle `tri` nearest at this sample:
/// only that fragment is shaded (overlapping and coincident surfaces, however many, cost one
/// shading per sample; the exact tie rule is the visibility pass's `Less` in scene order).
fn rd_visible(pos: vec2<f32>, tri: u32) -> bool {
    let id = textureLoad(rd_ids, vec2<i32>(pos), 0).xy;
    return id.x == object.tex_size.z && id.y == tri;
}

// ---- entry points ---------------------------------------------------------------------------

/// Spheres and planes: one triangle covering the tile.
@vertex
fn rd_vs_full(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = select(-1.0, 3.0, i == 1u);
    let y = select(-1.0, 3.0, i == 2u);
    return vec4<f32>(x, y, 0.5, 1.0);
}

/// Spheres and planes: the analytic intersection of the sample's primary ray.
fn rd_analytic_hit(r: RdRay) -> RdHit {
    if object.flags.x == 0u {
        return rd_sphere(r);
    }
    return rd_plane(r);
}

/// Spheres and planes, visibility pass: the hit's depth and id.
@fragment
fn rd_fs_analytic_id(@builtin(position) pos: vec4<f32>) -> RdIdOut {
    let hit = rd_analytic_hit(rd_primary_ray(pos.xy));
    if !hit.ok {
        discard;
    }
    return RdIdOut(vec2<u32>(object.tex_size.z, 0u), rd_depth(hit.t));
}

/// Spheres and planes, shading pass: the visible sample's radiance.
@fragment
fn rd_fs_analytic(@builtin(position) pos: vec4<f32>) -> RdOut {
    if !rd_visible(pos.xy, 0u) {
        discard;
    }
    let r = rd_primary_ray(pos.xy);
    let hit = rd_analytic_hit(r);
    if !hit.ok {
        discard;
    }
    return RdOut(vec4<f32>(rd_shade(r, hit), 1.0), rd_depth(hit.t));
}

struct RdMeshVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) tri: u32,
}

/// Meshes: triangle corners (three per triangle, in triangle order) to clip space.
@vertex
fn rd_vs_mesh(@builtin(vertex_index) i: u32, @location(0) p: vec3<f32>) -> RdMeshVertex {
    let q = vec4<f32>(p, 1.0);
    let clip = vec4<f32>(dot(frame.clip_x, q), dot(frame.clip_y, q), dot(frame.clip_z, q),
        dot(frame.clip_w, q));
    return RdMeshVertex(clip, i / 3u);
}

/// Meshes, visibility pass: the ray-triangle intersection of the sample's primary ray with
/// the covering triangle, its depth and id.
@fragment
fn rd_fs_mesh_id(@builtin(position) pos: vec4<f32>, @location(0) @interpolate(flat) tri: u32)
    -> RdIdOut {
    let hit = rd_triangle(rd_primary_ray(pos.xy), tri);
    if !hit.ok {
        discard;
    }
    return RdIdOut(vec2<u32>(object.tex_size.z, tri), rd_depth(hit.t));
}

/// Meshes, shading pass: the ray-triangle intersection of the sample's primary ray with the
/// visible triangle (the CPU's barycentrics, t and interpolation), shaded.
@fragment
fn rd_fs_mesh(@builtin(position) pos: vec4<f32>, @location(0) @interpolate(flat) tri: u32)
    -> RdOut {
    if !rd_visible(pos.xy, tri) {
        discard;
    }
    let r = rd_primary_ray(pos.xy);
    let hit = rd_triangle(r, tri);
    if !hit.ok {
        discard;
    }
    return RdOut(vec4<f32>(rd_shade(r, hit), 1.0), rd_depth(hit.t));
}
