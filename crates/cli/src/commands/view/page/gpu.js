// ---- pictures drawn by WebGPU (issue 32) ---------------------------------------------
// The page draws the lit object of every model, the reference and the difference maps
// itself, with the GPU renderer's own module (crates/gpu/src/shaders/render.wgsl and the
// model's runtime-parameter WGSL, from /api/gpu/shader, once per model and choice set) on the
// scene's buffers (/api/gpu/scene, once per object and size). A slider move writes the
// parameter blocks and redraws: no request. The passes are the native renderer's
// (crates/gpu/src/render/: visibility, then shading, in scene order), then per model a
// resolve (the N x N samples averaged, sRGB 8-bit as Film::to_srgb8), the difference maps
// (compare::difference, scaled by their common maximum, magma as compare::heat_map) with RMSE
// and PSNR (compare::pixel_metrics), and one draw per canvas. Without WebGPU (or for what it
// cannot draw: a measured reference, R,G,B parameters) the server's pictures are shown and
// the page says why. document.body.dataset.renderer is "webgpu" or "server"; each redraw a
// control causes is a performance measure "fastbrdf:frame", from the control's input event
// to the GPU having finished every picture of that state.
const GPU = {
  on: false, why: "", device: null, L: null, tools: null,
  size: 512, spp: 1, scene: null,
  mods: new Map(), scenes: new Map(), pass: 0, maxPasses: 64, restart: false, preview: 128, budget: 100, fullMs: 0, settle: null, drawn: [], busy: false, again: false, since: null, bypass: false,
  stats: null, readback: null, metricsBusy: false,
};
const WEBGPU_TOOLS = `
struct Dims { w: u32, h: u32, n: u32, k: u32 }
@group(0) @binding(0) var<uniform> dims: Dims;
@group(0) @binding(1) var img: texture_2d<f32>;
@group(0) @binding(2) var<storage, read_write> px: array<u32>;
// Per sample, the sum of the passes drawn so far (environment light: one pass per frame).
@group(0) @binding(3) var<storage, read_write> acc: array<vec4<f32>>;
// texture.rs linear_to_srgb, then Film::to_srgb8's (x 255 + 0.5) as u8.
fn srgb8(c: f32) -> u32 {
  let x = clamp(c, 0.0, 1.0);
  var s = 12.92 * x;
  if x > 0.0031308 { s = 1.055 * pow(x, 1.0 / 2.4) - 0.055; }
  return u32(s * 255.0 + 0.5);
}
// dims.k: the pass just drawn (0: the sum restarts with it).
@compute @workgroup_size(8, 8) fn accumulate(@builtin(global_invocation_id) g: vec3<u32>) {
  let W = dims.w * dims.n;
  if g.x >= W || g.y >= dims.h * dims.n { return; }
  let c = textureLoad(img, vec2<u32>(g.x, g.y), 0);
  let i = g.y * W + g.x;
  if dims.k == 0u { acc[i] = c; } else { acc[i] = acc[i] + c; }
}
// The CPU's order: samples row by row within the pixel, summed, then scaled by 1 / N^2.
@compute @workgroup_size(8, 8) fn resolve(@builtin(global_invocation_id) g: vec3<u32>) {
  if g.x >= dims.w || g.y >= dims.h { return; }
  var sum = vec3<f32>(0.0);
  for (var sy = 0u; sy < dims.n; sy++) {
    for (var sx = 0u; sx < dims.n; sx++) {
      sum += textureLoad(img, vec2<u32>(g.x * dims.n + sx, g.y * dims.n + sy), 0).xyz;
    }
  }
  sum = sum * (1.0 / f32(dims.n * dims.n));
  px[g.y * dims.w + g.x] = srgb8(sum.x) | (srgb8(sum.y) << 8u) | (srgb8(sum.z) << 16u);
}
// The same from the passes' sums (environment light), also scaled by 1 / passes.
@compute @workgroup_size(8, 8) fn resolve_passes(@builtin(global_invocation_id) g: vec3<u32>) {
  if g.x >= dims.w || g.y >= dims.h { return; }
  var sum = vec3<f32>(0.0);
  for (var sy = 0u; sy < dims.n; sy++) {
    for (var sx = 0u; sx < dims.n; sx++) {
      sum += acc[(g.y * dims.n + sy) * dims.w * dims.n + g.x * dims.n + sx].xyz;
    }
  }
  sum = sum * (1.0 / f32(dims.n * dims.n)) * (1.0 / f32(dims.k + 1u));
  px[g.y * dims.w + g.x] = srgb8(sum.x) | (srgb8(sum.y) << 8u) | (srgb8(sum.z) << 16u);
}
`;
const WEBGPU_DIFF = `
struct Dims { w: u32, h: u32, n: u32, k: u32 }
@group(0) @binding(0) var<uniform> dims: Dims;
@group(0) @binding(1) var<storage, read> ref_px: array<u32>;
@group(0) @binding(2) var<storage, read> px: array<u32>;
@group(0) @binding(3) var<storage, read_write> diff: array<f32>;
// [0]: the largest difference of all maps (f32 bits: non-negative floats order as u32);
// then 256 partial sums of squared 8-bit differences per model (k).
@group(0) @binding(4) var<storage, read_write> stats: array<atomic<u32>>;
fn ch(p: u32, s: u32) -> f32 { return f32((p >> s) & 255u); }
@compute @workgroup_size(8, 8) fn diff_main(@builtin(global_invocation_id) g: vec3<u32>,
    @builtin(workgroup_id) wg: vec3<u32>) {
  if g.x >= dims.w || g.y >= dims.h { return; }
  let i = g.y * dims.w + g.x;
  let a = ref_px[i];
  let b = px[i];
  // compare::difference: (|dr| + |dg| + |db|) / (3 x 255), summed in f32 in that order.
  let d = (abs(ch(a, 0u) - ch(b, 0u)) + abs(ch(a, 8u) - ch(b, 8u)) + abs(ch(a, 16u) - ch(b, 16u))) / (3.0 * 255.0);
  diff[i] = d;
  atomicMax(&stats[0], bitcast<u32>(d));
  var se = 0u;
  for (var s = 0u; s < 24u; s += 8u) {
    let e = i32((a >> s) & 255u) - i32((b >> s) & 255u);
    se += u32(e * e);
  }
  atomicAdd(&stats[1u + dims.k * 256u + (wg.x + wg.y * 64u) % 256u], se);
}
`;
const WEBGPU_SHOW = `
struct Dims { w: u32, h: u32, n: u32, k: u32 }
@group(0) @binding(0) var<uniform> dims: Dims;
@group(0) @binding(1) var<storage, read> px: array<u32>;
@group(0) @binding(2) var<storage, read> diff: array<f32>;
@group(0) @binding(3) var<storage, read> stats: array<u32>;
@group(0) @binding(4) var<storage, read> magma: array<u32>;
@group(0) @binding(5) var<storage, read_write> rgba: array<u32>;
// dims.n: 0 the picture, 1 its difference map (compare::heat_map with the common scale, at
// least 1/255, as /api/render); written as RGBA bytes at picture dims.k of rgba.
@compute @workgroup_size(8, 8) fn show(@builtin(global_invocation_id) g: vec3<u32>) {
  if g.x >= dims.w || g.y >= dims.h { return; }
  let i = g.y * dims.w + g.x;
  var c = px[i];
  if dims.n == 1u {
    let scale = max(bitcast<f32>(stats[0]), 1.0 / 255.0);
    let t = clamp(diff[i] / scale, 0.0, 1.0) * 255.0;
    c = magma[u32(floor(t + 0.5))];
  }
  rgba[dims.k * dims.w * dims.h + i] = (c & 0xffffffu) | 0xff000000u;
}
`;

// A rejected promise's message prefixed with what was being done.
async function labelled(what, p) { try { return await p; } catch (e) { throw new Error(`${what}: ${e.message}`); } }
function b64bytes(s) { const b = atob(s), u = new Uint8Array(b.length); for (let i = 0; i < b.length; i++) u[i] = b.charCodeAt(i); return u; }
function gpuBuffer(usage, data, size) {
  const d = GPU.device, n = Math.max(256, Math.ceil((data ? data.byteLength : size) / 4) * 4);
  const buf = d.createBuffer({ size: n, usage: usage | GPUBufferUsage.COPY_DST });
  if (data && data.byteLength) d.queue.writeBuffer(buf, 0, data.buffer, data.byteOffset, data.byteLength);
  return buf;
}
const STORAGE = () => GPUBufferUsage.STORAGE, UNIFORM = () => GPUBufferUsage.UNIFORM;

async function gpuInit() {
  if (!navigator.gpu) throw new Error("this browser has no WebGPU");
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) throw new Error("no WebGPU adapter");
  GPU.adapter = adapter; // kept: Chromium loses async pipeline creation when the adapter is collected
  const d = GPU.device = await adapter.requestDevice();
  d.lost.then(info => { GPU.on = false; GPU.why = "the WebGPU device was lost: " + info.message; document.body.dataset.renderer = "server"; renderAll(paramQuery()); });
  // A validation error is a bug of this page: shown, and the server draws from then on.
  d.onuncapturederror = ev => {
    const m = "WebGPU: " + ev.error.message;
    document.body.dataset.gpuError = m; setStatus(m, true);
    GPU.on = false; GPU.why = m; document.body.dataset.renderer = "server";
  };
  const F = GPUShaderStage.FRAGMENT, ro = { buffer: { type: "read-only-storage" } }, un = { buffer: { type: "uniform" } };
  const e = (binding, visibility, rest) => Object.assign({ binding, visibility }, rest);
  // layouts.rs, binding for binding.
  const frame = d.createBindGroupLayout({ entries: [e(0, GPUShaderStage.VERTEX | F, un), e(1, F, ro), e(2, F, ro), e(3, F, ro), e(4, F, ro)] });
  const object = d.createBindGroupLayout({ entries: [e(0, F, un), e(1, F, { texture: { sampleType: "unfilterable-float" } }), e(2, F, ro), e(3, F, ro), e(4, F, ro), e(5, F, un)] });
  const ids = d.createBindGroupLayout({ entries: [e(0, F, { texture: { sampleType: "uint" } })] });
  GPU.L = {
    frame, object, ids,
    shading: d.createPipelineLayout({ bindGroupLayouts: [frame, object, ids] }),
    visibility: d.createPipelineLayout({ bindGroupLayouts: [frame, object] }),
  };
  const C = GPUShaderStage.COMPUTE;
  const resolveL = d.createBindGroupLayout({ entries: [e(0, C, un), e(1, C, { texture: { sampleType: "unfilterable-float" } }), e(2, C, { buffer: { type: "storage" } }), e(3, C, { buffer: { type: "storage" } })] });
  // Group 3 under an environment light (crates/gpu/src/render/env.rs, "Bind group 3").
  const envL = d.createBindGroupLayout({ entries: [e(0, F, un), e(1, F, { texture: { sampleType: "unfilterable-float" } }), e(2, F, ro), e(3, F, { texture: { sampleType: "unfilterable-float" } })] });
  const emptyL = d.createBindGroupLayout({ entries: [] });
  Object.assign(GPU.L, {
    env: envL,
    shadingEnv: d.createPipelineLayout({ bindGroupLayouts: [frame, object, ids, envL] }),
    background: d.createPipelineLayout({ bindGroupLayouts: [frame, emptyL, ids, envL] }),
    empty: d.createBindGroup({ layout: emptyL, entries: [] }),
  });
  const diffL = d.createBindGroupLayout({ entries: [e(0, C, un), e(1, C, ro), e(2, C, ro), e(3, C, { buffer: { type: "storage" } }), e(4, C, { buffer: { type: "storage" } })] });
  const showL = d.createBindGroupLayout({ entries: [e(0, C, un), e(1, C, ro), e(2, C, ro), e(3, C, ro), e(4, C, ro), e(5, C, { buffer: { type: "storage" } })] });
  const mod = code => d.createShaderModule({ code });
  GPU.tools = await labelled("the page's own pipelines", (async () => ({
    resolveL, diffL, showL,
    resolve: await d.createComputePipelineAsync({ layout: d.createPipelineLayout({ bindGroupLayouts: [resolveL] }), compute: { module: mod(WEBGPU_TOOLS), entryPoint: "resolve" } }),
    resolvePasses: await d.createComputePipelineAsync({ layout: d.createPipelineLayout({ bindGroupLayouts: [resolveL] }), compute: { module: mod(WEBGPU_TOOLS), entryPoint: "resolve_passes" } }),
    accumulate: await d.createComputePipelineAsync({ layout: d.createPipelineLayout({ bindGroupLayouts: [resolveL] }), compute: { module: mod(WEBGPU_TOOLS), entryPoint: "accumulate" } }),
    diff: await d.createComputePipelineAsync({ layout: d.createPipelineLayout({ bindGroupLayouts: [diffL] }), compute: { module: mod(WEBGPU_DIFF), entryPoint: "diff_main" } }),
    show: await d.createComputePipelineAsync({ layout: d.createPipelineLayout({ bindGroupLayouts: [showL] }), compute: { module: mod(WEBGPU_SHOW), entryPoint: "show" } }),
  }))());
  GPU.dummy = gpuBuffer(STORAGE(), null, 16);
  GPU.on = true;
}

// ---- what is drawn -------------------------------------------------------------------
function gpuDrawable() {
  // What the page cannot draw itself: the measured reference (CPU data), coloured values.
  if (state.ref && state.ref === MEAS) return "a measured reference is drawn by the server";
  for (const v of Object.values(state.params)) if (String(v).includes(",") && !allIds().some(id => MODELS[id] && MODELS[id].kind === "user")) return "R,G,B parameters are drawn by the server";
  return "";
}
// Models with a picture: the reference first (as /api/render), only kinds the renderer shades.
function gpuModels() { return allIds().filter(id => MODELS[id] && !["shadowing", "fresnel", "env"].includes(MODELS[id].kind)); }
function choiceKey(id) {
  const q = new URLSearchParams({ model: id, mesh: state.mesh });
  if (state.env !== "none") { q.set("env", state.env); q.set("dfg", state.dfg || "env-brdf"); }
  for (const p of MODELS[id].params) if (p.type === "choice" && MODELS[id].kind !== "user") q.set(p.name, state.params[p.name] ?? choiceDefault(p));
  return q.toString();
}

async function gpuScene(size) {
  const key = `${state.mesh}|${size}|${GPU.spp}|${state.env}`;
  if (GPU.scenes.has(key)) return GPU.scenes.get(key);
  if (![...GPU.scenes.keys()].every(k => k.startsWith(state.mesh + "|") && k.endsWith("|" + state.env))) GPU.scenes.clear();
  const q = new URLSearchParams({ mesh: state.mesh, light: state.light, size, spp: GPU.spp, env: state.env });
  const s = await getJSON("/api/gpu/scene?" + q);
  const d = GPU.device, u32 = t => new Uint32Array(b64bytes(t).buffer), f32 = t => new Float32Array(b64bytes(t).buffer);
  const W = s.width * s.spp, H = s.height * s.spp, tex = (format, usage) => d.createTexture({ size: [W, H], format, usage });
  const RA = GPUTextureUsage.RENDER_ATTACHMENT;
  const sc = {
    key, s, W, H, lightsData: f32(s.lights), light: state.light, lightNow: state.light,
    frame: gpuBuffer(UNIFORM(), u32(s.frame)), lights: null,
    occ: gpuBuffer(STORAGE(), u32(s.occluders)), nodes: gpuBuffer(STORAGE(), u32(s.nodes)), tris: gpuBuffer(STORAGE(), f32(s.shadow_triangles)),
    depth: tex("depth32float", RA), ids: tex("rg32uint", RA | GPUTextureUsage.TEXTURE_BINDING),
    magma: gpuBuffer(STORAGE(), new Uint32Array(Array.from({ length: 256 }, (_, i) => { const m = b64bytes(s.magma); return m[3 * i] | (m[3 * i + 1] << 8) | (m[3 * i + 2] << 16); }))),
    dims: gpuBuffer(UNIFORM(), new Uint32Array([s.width, s.height, s.spp, 0])),
    objects: s.objects.map(o => {
      const t = d.createTexture({ size: [o.texture.width, o.texture.height], format: "rgba32float", usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
      d.queue.writeTexture({ texture: t }, f32(o.texture.texels), { bytesPerRow: 16 * o.texture.width }, [o.texture.width, o.texture.height]);
      return {
        uniform: gpuBuffer(UNIFORM(), u32(o.uniform)), whole: gpuBuffer(UNIFORM(), u32(o.whole)), view: t.createView(),
        vertices: gpuBuffer(STORAGE(), f32(o.vertices)), triangles: gpuBuffer(STORAGE(), u32(o.triangles)),
        corners: o.corners ? gpuBuffer(GPUBufferUsage.VERTEX, f32(o.corners)) : null, count: o.count,
      };
    }),
  };
  sc.lights = gpuBuffer(STORAGE(), sc.lightsData);
  if (s.env) {
    const E = s.env, P = E.prefiltered, T = GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST;
    const texture = (w, h, data) => { const t = d.createTexture({ size: [w, h], format: "rgba32float", usage: T }); d.queue.writeTexture({ texture: t }, data, { bytesPerRow: 16 * w }, [w, h]); return t.createView(); };
    sc.env = { E, map: texture(E.width, E.height, f32(E.texels)), tables: gpuBuffer(STORAGE(), f32(E.tables)), pre: texture(P.width, P.height * P.levels, f32(P.texels)) };
  }
  sc.frameBind = d.createBindGroup({ layout: GPU.L.frame, entries: [sc.frame, sc.lights, sc.occ, sc.nodes, sc.tris].map((b, i) => ({ binding: i, resource: { buffer: b } })) });
  sc.idsBind = d.createBindGroup({ layout: GPU.L.ids, entries: [{ binding: 0, resource: sc.ids.createView() }] });
  sc.idsReady = false;
  GPU.scenes.set(key, sc);
  return sc;
}

// glam's Vec3::normalize in f32 (Light::parse's direction), for a light dragged in the page.
function lightRecord(text, base) {
  const f = Math.fround, v = text.split(",").map(x => f(Number(x)));
  const dot = f(f(f(v[0] * v[0]) + f(v[1] * v[1])) + f(v[2] * v[2])), r = f(1 / f(Math.sqrt(dot)));
  const out = base.slice(0, 8); out[0] = f(v[0] * r); out[1] = f(v[1] * r); out[2] = f(v[2] * r); out[3] = 0;
  return out;
}

async function gpuModule(id) {
  const key = choiceKey(id);
  let m = GPU.mods.get(key);
  if (m) return m.ready;
  m = { key, id };
  GPU.mods.set(key, m);
  m.ready = (async () => {
    const info = await getJSON("/api/gpu/shader?" + key);
    let code = info.wgsl;
    const d = GPU.device, module = d.createShaderModule({ code });
    const ci = await labelled(`${id}: compiling`, module.getCompilationInfo());
    const errs = ci.messages.filter(x => x.type === "error");
    if (errs.length) throw new Error(`${id}: WebGPU cannot compile its module: ${errs[0].lineNum}:${errs[0].linePos}: ${errs[0].message}`);
    const pipe = (vs, fs, vis, buffers, lit) => labelled(`${id}: the ${fs} pipeline`, d.createRenderPipelineAsync({
      layout: vis ? GPU.L.visibility : lit ? GPU.L.shadingEnv : GPU.L.shading,
      vertex: { module, entryPoint: vs, buffers },
      primitive: { topology: "triangle-list", cullMode: "none" },
      depthStencil: { format: "depth32float", depthWriteEnabled: true, depthCompare: "less" },
      fragment: { module, entryPoint: fs, targets: [{ format: vis ? "rg32uint" : "rgba32float" }] },
    }));
    const corners = [{ arrayStride: 12, attributes: [{ shaderLocation: 0, offset: 0, format: "float32x3" }] }];
    const mesh = state.mesh === "mesh";
    const lit = state.env !== "none", x = lit ? "_env" : "";
    Object.assign(m, {
      info, mesh, lit,
      shade: await (mesh ? pipe("rd_vs_mesh", "rd_fs_mesh" + x, false, corners, lit) : pipe("rd_vs_full", "rd_fs_analytic" + x, false, [], lit)),
      background: lit ? await labelled(`${id}: the background pipeline`, d.createRenderPipelineAsync({
        layout: GPU.L.background, vertex: { module, entryPoint: "rd_vs_full" },
        primitive: { topology: "triangle-list", cullMode: "none" },
        depthStencil: { format: "depth32float", depthWriteEnabled: false, depthCompare: "always" },
        fragment: { module, entryPoint: "rd_fs_env_background", targets: [{ format: "rgba32float" }] },
      })) : null,
      vis: await (mesh ? pipe("rd_vs_mesh", "rd_fs_mesh_id", true, corners) : pipe("rd_vs_full", "rd_fs_analytic_id", true, [])),
      block: new Float32Array(4 * Math.max(1, info.params.length)),
      per: new Map(),
    });
    m.params = gpuBuffer(UNIFORM(), m.block);
    return m;
  })();
  m.ready.catch(() => GPU.mods.delete(key));
  return m.ready;
}

// The block of parameter values (one vec4 each): the page's values, else the defaults.
function fillBlock(m) {
  const own = MODELS[m.id].params;
  m.info.params.forEach((p, k) => {
    const spec = own.find(q => q.name === p.name) || {}, text = state.params[p.name];
    let v = text !== undefined ? text : (p.default !== undefined ? p.default : spec.default);
    if (spec.type === "color") {
      const c = String(v).split(",").map(Number), rgb = c.length === 1 ? [c[0], c[0], c[0]] : c;
      m.block.set(rgb.slice(0, 3), 4 * k);
    } else m.block[4 * k] = Number(v);
  });
  for (const p of own) if (p.type === "number" && state.params[p.name] !== undefined) {
    const v = Number(state.params[p.name]);
    if (!(v >= p.min && v <= p.max)) return false; // the server's message says why
  }
  GPU.device.queue.writeBuffer(m.params, 0, m.block);
  return true;
}

function perScene(m, sc) {
  if (m.per.has(sc.key)) return m.per.get(sc.key);
  const d = GPU.device, whole = m.info.whole;
  const color = d.createTexture({ size: [sc.W, sc.H], format: "rgba32float", usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.TEXTURE_BINDING });
  const n = sc.s.width * sc.s.height;
  const px = gpuBuffer(STORAGE() | GPUBufferUsage.COPY_SRC, null, 4 * n), diff = gpuBuffer(STORAGE(), null, 4 * n);
  const binds = sc.objects.map(o => d.createBindGroup({ layout: GPU.L.object, entries: [
    { binding: 0, resource: { buffer: whole ? o.whole : o.uniform } }, { binding: 1, resource: o.view },
    { binding: 2, resource: { buffer: o.vertices } }, { binding: 3, resource: { buffer: o.triangles } },
    { binding: 4, resource: { buffer: GPU.dummy } }, { binding: 5, resource: { buffer: m.params } }] }));
  const acc = gpuBuffer(STORAGE(), null, sc.env ? 16 * sc.W * sc.H : 16), passDims = gpuBuffer(UNIFORM(), new Uint32Array([sc.s.width, sc.s.height, sc.s.spp, 0]));
  const resolve = d.createBindGroup({ layout: GPU.tools.resolveL, entries: [
    { binding: 0, resource: { buffer: passDims } }, { binding: 1, resource: color.createView() }, { binding: 2, resource: { buffer: px } }, { binding: 3, resource: { buffer: acc } }] });
  const out = { color, view: color.createView(), px, diff, binds, resolve, passDims };
  if (sc.env) {
    out.envParams = gpuBuffer(UNIFORM(), null, 48);
    out.envBind = d.createBindGroup({ layout: GPU.L.env, entries: [
      { binding: 0, resource: { buffer: out.envParams } }, { binding: 1, resource: sc.env.map },
      { binding: 2, resource: { buffer: sc.env.tables } }, { binding: 3, resource: sc.env.pre }] });
  }
  m.per.set(sc.key, out);
  return out;
}

// ---- one frame -----------------------------------------------------------------------
async function gpuFrame(size) {
  const t0 = performance.now();
  const ids = gpuModels();
  const sc = await gpuScene(size);
  const mods = [];
  for (const id of ids) mods.push(await gpuModule(id));
  if (!mods.length) return;
  for (const m of mods) if (!fillBlock(m)) return;
  const d = GPU.device;
  if (sc.lightNow !== state.light) {
    const rec = state.light === sc.light ? sc.lightsData : new Float32Array(lightRecord(state.light, sc.lightsData));
    d.queue.writeBuffer(sc.lights, 0, rec);
    sc.lightNow = state.light;
  }
  const ref = state.ref && ids[0] === state.ref ? mods[0] : null, tests = ref ? mods.slice(1) : mods;
  // The pass drawn: under an environment, frame k adds pass k (EnvData::params(k, 1, [1, 1]));
  // a changed view restarts at 0. The split-sum shortcut (state.dfg) draws the models, not
  // the reference, with its prefiltered maps and the model's alpha and f0.
  const k = sc.env ? GPU.pass : 0;
  if (sc.env) for (const m of mods) {
    const E = sc.env.E, P = sc.env.E.prefiltered, split = !!state.dfg && m !== ref;
    const num = (name, dflt) => { const v = Number(state.params[name] ?? ((MODELS[m.id].params.find(p => p.name === name) || {}).default ?? dflt)); return Number.isFinite(v) ? v : dflt; };
    const n = num("n", NaN), alpha = Math.min(1, Math.max(1e-3, num("alpha", Number.isFinite(n) ? Math.sqrt(2 / (n + 2)) : 0.3)));
    const w = new ArrayBuffer(48), u = new Uint32Array(w), f = new Float32Array(w);
    u.set([E.width, E.height, split ? 0 : k, split ? 0 : 1]);
    f.set([split ? 0 : 1, 1, alpha, split ? num("f0", 0.04) : 0], 4);
    u.set([0, split ? 1 : 0, split ? P.width : 0, split ? P.height : 0], 8);
    d.queue.writeBuffer(perScene(m, sc).envParams, 0, w);
  }
  for (const m of mods) d.queue.writeBuffer(perScene(m, sc).passDims, 12, new Uint32Array([k]));
  d.pushErrorScope("validation");
  const enc = d.createCommandEncoder();
  const bg = sc.s.background;
  const scenePass = (target, clear, m, pipeline, bind2) => {
    const p = enc.beginRenderPass({
      colorAttachments: [{ view: target, clearValue: clear, loadOp: "clear", storeOp: "store" }],
      depthStencilAttachment: { view: sc.depth.createView(), depthClearValue: 1, depthLoadOp: "clear", depthStoreOp: "discard" },
    });
    p.setBindGroup(0, sc.frameBind);
    if (bind2) p.setBindGroup(2, sc.idsBind);
    if (bind2 && m.lit) {
      // The environment's background where no object is, then the objects.
      p.setBindGroup(3, perScene(m, sc).envBind);
      p.setPipeline(m.background); p.setBindGroup(1, GPU.L.empty); p.draw(3);
    }
    p.setPipeline(pipeline);
    sc.objects.forEach((o, i) => {
      p.setBindGroup(1, perScene(m, sc).binds[i]);
      if (o.corners) { p.setVertexBuffer(0, o.corners); p.draw(o.count); } else p.draw(3);
    });
    p.end();
  };
  // Visibility: the same for every model (the scene's geometry), drawn once per scene.
  if (!sc.idsReady) { scenePass(sc.ids.createView(), { r: 0, g: 0, b: 0, a: 0 }, mods[0], mods[0].vis, false); sc.idsReady = true; }
  const clear = sc.env ? { r: 0, g: 0, b: 0, a: 1 } : { r: bg[0], g: bg[1], b: bg[2], a: 1 };
  for (const m of mods) scenePass(perScene(m, sc).view, clear, m, m.shade, true);
  const groups = [Math.ceil(sc.s.width / 8), Math.ceil(sc.s.height / 8)];
  let cp = enc.beginComputePass();
  if (sc.env) {
    cp.setPipeline(GPU.tools.accumulate);
    for (const m of mods) { cp.setBindGroup(0, perScene(m, sc).resolve); cp.dispatchWorkgroups(Math.ceil(sc.W / 8), Math.ceil(sc.H / 8)); }
    cp.end();
    cp = enc.beginComputePass();
  }
  cp.setPipeline(sc.env ? GPU.tools.resolvePasses : GPU.tools.resolve);
  for (const m of mods) { cp.setBindGroup(0, perScene(m, sc).resolve); cp.dispatchWorkgroups(...groups); }
  cp.end();
  const statsWords = 1 + 256 * Math.max(1, tests.length);
  if (!GPU.stats || GPU.stats.size < 4 * statsWords) {
    GPU.stats = gpuBuffer(STORAGE() | GPUBufferUsage.COPY_SRC, null, 4 * statsWords);
    GPU.readback = d.createBuffer({ size: GPU.stats.size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
  }
  enc.clearBuffer(GPU.stats);
  if (ref) {
    cp = enc.beginComputePass();
    cp.setPipeline(GPU.tools.diff);
    tests.forEach((m, k) => {
      const dims = dimsOf(sc, 0, k);
      cp.setBindGroup(0, d.createBindGroup({ layout: GPU.tools.diffL, entries: [dims, perScene(ref, sc).px, perScene(m, sc).px, perScene(m, sc).diff, GPU.stats].map((b, i) => ({ binding: i, resource: { buffer: b } })) }));
      cp.dispatchWorkgroups(...groups);
    });
    cp.end();
  }
  // The pictures (reference first), then the difference maps, as RGBA bytes in one buffer,
  // read back and put into 2D canvases. (Presenting through a "webgpu" canvas context loses
  // the device in headless Chromium 156 on SwiftShader; a read-back works on every adapter.)
  const shown = [...mods.map(m => [m, false]), ...(ref ? tests.map(m => [m, true]) : [])];
  const n = sc.s.width * sc.s.height, bytes = 4 * n * shown.length;
  if (!GPU.rgba || GPU.rgba.size < bytes) {
    GPU.rgba = gpuBuffer(STORAGE() | GPUBufferUsage.COPY_SRC, null, bytes);
    GPU.rgbaBack = d.createBuffer({ size: GPU.rgba.size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
  }
  cp = enc.beginComputePass();
  cp.setPipeline(GPU.tools.show);
  shown.forEach(([m, heat], k) => {
    cp.setBindGroup(0, d.createBindGroup({ layout: GPU.tools.showL, entries: [dimsOf(sc, heat ? 1 : 0, k), perScene(m, sc).px, perScene(m, sc).diff, GPU.stats, sc.magma, GPU.rgba].map((b, i) => ({ binding: i, resource: { buffer: b } })) }));
    cp.dispatchWorkgroups(...groups);
  });
  cp.end();
  enc.copyBufferToBuffer(GPU.rgba, 0, GPU.rgbaBack, 0, bytes);
  const readStats = ref && GPU.readback.mapState === "unmapped" && !GPU.metricsBusy;
  if (readStats) enc.copyBufferToBuffer(GPU.stats, 0, GPU.readback, 0, 4 * statsWords);
  const cmd = enc.finish();
  const bad = await d.popErrorScope();
  if (bad) throw new Error("WebGPU: " + bad.message);
  const t1 = performance.now();
  d.queue.submit([cmd]);
  await labelled("the frame", GPU.rgbaBack.mapAsync(GPUMapMode.READ, 0, bytes));
  const t2 = performance.now();
  const all = new Uint8ClampedArray(GPU.rgbaBack.getMappedRange(0, bytes).slice(0));
  GPU.rgbaBack.unmap();
  const canvases = gpuCanvases(ids, ref ? tests.map(m => m.id) : [], sc);
  const targets = [...canvases.pictures, ...canvases.diffs];
  shown.forEach((_, k) => targets[k].getContext("2d").putImageData(new ImageData(all.subarray(4 * n * k, 4 * n * (k + 1)), sc.s.width, sc.s.height), 0, 0));
  GPU.drawn = mods.map(m => m.id); GPU.scene = sc;
  // Where a frame's time goes: encoding, the GPU's work and read-back, the 2D canvases.
  GPU.phases = { encode: t1 - t0, gpu: t2 - t1, canvas: performance.now() - t2 };
  if (readStats) gpuMetrics(tests.map(m => m.id), statsWords, sc);
  else if (!ref) { lastRender = null; drawNumbers(); }
}

// RMSE and PSNR of each picture against the reference (compare::pixel_metrics, exact: the
// squared 8-bit differences are summed as integers), and the maps' scale, off the frame.
async function gpuMetrics(ids, words, sc) {
  GPU.metricsBusy = true;
  try {
    await GPU.readback.mapAsync(GPUMapMode.READ, 0, 4 * words);
    const w = new Uint32Array(GPU.readback.getMappedRange(0, 4 * words).slice(0));
    GPU.readback.unmap();
    const scale = Math.max(new Float32Array(new Uint32Array([w[0]]).buffer)[0], 1 / 255), n = 3 * sc.s.width * sc.s.height;
    const metrics = ids.map((id, k) => {
      let se = 0; for (let j = 0; j < 256; j++) se += w[1 + 256 * k + j];
      const rmse = Math.sqrt(se / (255 * 255) / n);
      return { model: id, rmse, psnr: rmse === 0 ? null : 20 * Math.log10(1 / rmse), flip: null };
    });
    lastRender = { metrics, reference: state.ref, webgpu: true };
    flipPending = false; drawNumbers();
    for (const c of $("pictures").querySelectorAll("canvas.diff")) c.nextSibling.textContent = `|${c.dataset.model} - ${state.ref}| (scale ${scale.toFixed(3)})`;
  } catch (e) { /* a newer frame owns the buffer */ } finally { GPU.metricsBusy = false; }
}

// The small uniforms of the passes after the scene's (w, h, n, k), made once per scene.
function dimsOf(sc, n, k) {
  sc.dimsCache = sc.dimsCache || new Map();
  const key = n + "," + k;
  if (!sc.dimsCache.has(key)) sc.dimsCache.set(key, gpuBuffer(UNIFORM(), new Uint32Array([sc.s.width, sc.s.height, n, k])));
  return sc.dimsCache.get(key);
}

// One canvas per picture and per difference map, kept while the models stay the same.
function gpuCanvases(ids, diffIds, sc) {
  const box = $("pictures"), key = ids.join(",") + "|" + diffIds.join(",");
  if (box.dataset.key !== key || box.querySelector("img")) {
    box.replaceChildren(); box.dataset.key = key;
    const fig = (id, cls, caption, color) => {
      const c = el("canvas", { class: cls, "data-model": id, width: sc.s.width, height: sc.s.height });
      box.appendChild(el("figure", {}, c, el("figcaption", { style: color ? `color:${color}` : undefined }, caption)));
      if (cls === "render") gpuLightDrag(c);
      return c;
    };
    ids.forEach(id => fig(id, "render", `${id}${id === state.ref ? " (reference)" : ""}`, colorOf(id)));
    diffIds.forEach(id => fig(id, "diff", `|${id} - ${state.ref}|`));
  }
  for (const c of box.querySelectorAll("canvas")) if (c.width !== sc.s.width) { c.width = sc.s.width; c.height = sc.s.height; }
  return { pictures: [...box.querySelectorAll("canvas.render")], diffs: [...box.querySelectorAll("canvas.diff")] };
}

// Dragging on a picture moves the light, redrawn as it moves (no request).
function gpuLightDrag(c) {
  c.onpointerdown = ev => {
    const move = e => {
      const r = c.getBoundingClientRect(), x = 2 * (e.clientX - r.left) / r.width - 1, y = 1 - 2 * (e.clientY - r.top) / r.height;
      const z = Math.sqrt(Math.max(0.05, 1 - Math.min(1, x * x + y * y)));
      state.light = [x, y, z].map(v => v.toFixed(3)).join(",");
      $("light-text").textContent = state.light;
      gpuRequest(e.timeStamp);
    };
    move(ev);
    const up = () => { window.removeEventListener("pointermove", move); window.removeEventListener("pointerup", up); writeHash(); };
    window.addEventListener("pointermove", move); window.addEventListener("pointerup", up);
  };
}

// Frames: at most one in flight; inputs meanwhile are served by the next one, whose
// measure starts at the earliest of them. Where a full-size frame takes longer than
// GPU.budget ms (a software adapter), a control's frames are drawn at GPU.preview pixels per
// side and the full size follows once the control has rested 300 ms ("fastbrdf:settle").
let gpuInput = null;
function gpuRequest(since, full, more) {
  if (since !== undefined && since !== null && GPU.since === null) GPU.since = since;
  if (full) GPU.wantFull = true;
  // Any request but a progressive one restarts the environment's passes at 0.
  if (!more) GPU.restart = true;
  if (GPU.busy) { GPU.again = true; return; }
  GPU.busy = true;
  let last = 0;
  const run = async () => {
    try {
      do {
        GPU.again = false;
        const since = GPU.since; GPU.since = null;
        const preview = since !== null && !GPU.wantFull && GPU.fullMs > GPU.budget;
        const size = preview ? GPU.preview : GPU.size;
        GPU.wantFull = false;
        if (GPU.restart) { GPU.pass = 0; GPU.restart = false; }
        const t = performance.now();
        await gpuFrame(size);
        const end = performance.now();
        if (!preview && GPU.pass === 0) GPU.fullMs = end - t;
        last = size;
        const detail = Object.assign({ models: GPU.drawn.length, size, pass: GPU.pass }, GPU.phases);
        if (since !== null) performance.measure("fastbrdf:frame", { start: since, end, detail });
        else if (GPU.settleSince) performance.measure("fastbrdf:settle", { start: GPU.settleSince, end, detail });
        GPU.settleSince = null;
        if (GPU.scene.env) GPU.pass++;
        clearTimeout(GPU.settle);
        if (preview) GPU.settle = setTimeout(() => { GPU.settleSince = performance.now(); gpuRequest(null, true); }, 300);
      } while (GPU.again);
      const env = GPU.scene.env ? `, environment: ${GPU.pass} pass${GPU.pass === 1 ? "" : "es"}${state.dfg ? ", models split-sum (" + state.dfg + ")" : ""}` : "";
      $("render-info").textContent = `(drawn by WebGPU in this browser: ${GPU.scene.s.width}x${GPU.scene.s.height}, ${GPU.spp * GPU.spp} spp${env}; control to frame ${gpuMedian()})`;
    } catch (e) {
      // What WebGPU cannot draw goes to the server, which says why if it cannot either.
      GPU.bypass = e.message; setStatus(e.message, true);
      document.body.dataset.gpuError = String(e.stack || e.message);
      renderAll(paramQuery());
    } finally { GPU.busy = false; }
    // Under an environment, the picture improves by one pass per frame while nothing moves
    // (not counted in document.body.dataset.ready), up to GPU.maxPasses at the full size.
    if (GPU.on && GPU.scene && GPU.scene.env && last === GPU.size && GPU.pass < GPU.maxPasses && !GPU.again)
      setTimeout(() => { if (!GPU.busy) gpuRequest(null, true, true); }, 0);
  };
  if (more) run(); else task(run);
}
function gpuMedian() {
  const t = performance.getEntriesByName("fastbrdf:frame").map(e => e.duration).sort((a, b) => a - b);
  return t.length ? `median ${t[t.length >> 1].toFixed(1)} ms over ${t.length}` : "not yet measured";
}

// A control's input event: when the frame it causes starts to count.
for (const type of ["input", "change"]) document.addEventListener(type, e => { gpuInput = e.timeStamp; }, true);

HOOKS.start.push(async info => {
  try { await gpuInit(); } catch (e) { GPU.why = e.message; }
  document.body.dataset.renderer = GPU.on ? "webgpu" : "server";
  // Environment light and the split-sum toggle, in the Scene section (WebGPU only).
  const box = $("mesh").closest("section"), env = el("select", { id: "env" }), dfg = el("select", { id: "dfg" });
  env.add(new Option("key light only", "none")); env.add(new Option("sky + key light", "sky"));
  if (info.env) env.add(new Option(`${info.env} + key light`, "file"));
  dfg.add(new Option("sampled", ""));
  for (const m of info.models) if (m.kind === "env") dfg.add(new Option(`split-sum: ${m.id}`, m.id));
  const note = GPU.on ? "" : " (WebGPU only: " + GPU.why + ")";
  for (const [label, sel] of [["env", env], ["IBL", dfg]]) {
    sel.disabled = !GPU.on; sel.title = "the pictures' light" + note;
    box.insertBefore(el("div", { class: "row" }, el("label", { for: sel.id }, label), sel), box.lastElementChild);
  }
  env.onchange = () => { state.env = env.value; writeHash(); renderAll(paramQuery()); };
  dfg.onchange = () => { state.dfg = dfg.value; writeHash(); renderAll(paramQuery()); };
});
HOOKS.controls.push(() => {
  if ($("env")) { $("env").value = state.env; $("dfg").value = state.dfg; }
});
HOOKS.render.push(() => {
  if (!GPU.on) { $("render-info").dataset.why = GPU.why; return false; }
  const why = GPU.bypass || gpuDrawable();
  if (why) { document.body.dataset.renderer = "server"; $("render-info").dataset.why = why; GPU.bypass = ""; return false; }
  document.body.dataset.renderer = "webgpu";
  const since = gpuInput; gpuInput = null;
  gpuRequest(since);
  return true;
});
// For tests and users: the last picture of `id` as drawn, 8-bit RGB, base64.
window.fastbrdfPixels = async id => {
  const m = GPU.scene && [...GPU.mods.values()].find(x => x.id === id && x.per.has(GPU.scene.key));
  if (!m) throw new Error(`${id}: no picture drawn`);
  const px = perScene(m, GPU.scene).px;
  const b = GPU.device.createBuffer({ size: px.size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
  const enc = GPU.device.createCommandEncoder(); enc.copyBufferToBuffer(px, 0, b, 0, b.size); GPU.device.queue.submit([enc.finish()]);
  await b.mapAsync(GPUMapMode.READ);
  const w = new Uint32Array(b.getMappedRange().slice(0)); b.unmap(); b.destroy();
  const n = GPU.scene.s.width * GPU.scene.s.height; let s = "";
  for (let i = 0; i < n; i++) s += String.fromCharCode(w[i] & 255, (w[i] >> 8) & 255, (w[i] >> 16) & 255);
  return btoa(s);
};
// For `fastbrdf view --measure-frames`: `k` frames of the current state at `size` pixels per
// side, drawn back to back with no control involved (the GPU's share of a frame), in ms.
window.fastbrdfFramesAlone = async (size, k) => {
  const out = [];
  for (let i = 0; i < k; i++) { const t = performance.now(); await gpuFrame(size); out.push(performance.now() - t); }
  return out;
};
window.fastbrdfAdapter = () => {
  const i = GPU.adapter && GPU.adapter.info;
  return i ? { vendor: i.vendor, architecture: i.architecture, device: i.device, description: i.description } : null;
};
