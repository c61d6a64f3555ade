// The page is main.js and the files after it (gpu.js, panes.js, kinds.js, user.js), one
// script (request.rs joins them). The later files add themselves through HOOKS, so each
// part lives in one file:
//   start(info)      after /api/models has arrived, before the first update (add controls);
//   controls()       after the controls were rebuilt (models or structure changed);
//   update(q)        on every change of state (q: the models' query, paramQuery());
//   plots(d)         after /api/plots' numbers were drawn (d: its JSON);
//   render(q, g)     replaces the server's pictures when it returns true (gpu.js: WebGPU).
const HOOKS = { start: [], controls: [], update: [], plots: [], render: [] };
const COLORS = ["#000000", "#e53935", "#1e88e5", "#43a047", "#fb8c00", "#8e24aa", "#00897b"];
let MODELS = {}, INFO = null, MEAS = null; // MEAS: the --measured file's name, a reference only; users' models (--model file:PATH) are in MODELS, kind "user"
// env: the pictures' environment light (none, sky, file; WebGPU only, gpu.js), dfg: the
// split-sum shortcut's environment model ("" for the sampled picture).
let state = { models: ["flog"], ref: "pow", theta: 30, params: {}, mesh: "sphere", light: "0.5,0.7,0.6", lang: "wgsl", exp: "", env: "none", dfg: "" };
let plotCtl = null, renderCtl = null, gen = 0, pending = 0, lastPlots = null, lastRender = null, flipPending = false;
const client = Math.random().toString(36).slice(2);
const $ = id => document.getElementById(id);
// Every string from the link, a file name or the server goes into the page as text: el()
// builds elements with setAttribute and text nodes; no string is ever parsed as HTML.
function el(tag, attrs, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {}))
    if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? "" : String(v));
  for (const c of kids.flat()) if (c !== undefined && c !== null && c !== false) e.append(c instanceof Node ? c : String(c));
  return e;
}

// The status line. `of`: the view (a count of update() calls) the message is about. An error
// stays until a later view's news replaces it: the plots of its own view, arriving after its
// pictures failed, do not hide it (they did, and a failure went unseen).
let view = 0, errView = -1;
function setStatus(t, err, of = view) {
  if (!err && of <= errView) return;
  const s = $("status"); s.textContent = t; s.className = err ? "err" : "";
  if (err) errView = Math.max(errView, of);
}
function ready() { document.body.dataset.ready = pending === 0 ? "1" : "0"; }
window.addEventListener("error", e => setStatus("script error: " + e.message, true));

// ---- state <-> URL -------------------------------------------------------------------
function readHash() {
  const q = new URLSearchParams(location.hash.slice(1));
  const s = { models: [], ref: "", theta: 30, params: {}, mesh: "sphere", light: state.light, lang: "wgsl", exp: "", env: "none", dfg: "" };
  for (const [k, v] of q) {
    if (k === "models") s.models = v.split(",").filter(x => x);
    else if (k === "ref") s.ref = v;
    else if (k === "theta") s.theta = Number(v);
    else if (k === "mesh") s.mesh = v;
    else if (k === "env") s.env = v;
    else if (k === "dfg") s.dfg = v;
    else if (k === "light") s.light = v;
    else if (k === "lang") s.lang = v;
    else if (k === "exp") s.exp = v;
    else s.params[k] = v;
  }
  if (s.models.length) state = s;
}
function allIds() { const ids = state.ref ? [state.ref] : []; for (const m of state.models) if (!ids.includes(m)) ids.push(m); return ids; }
function paramQuery() {
  const q = new URLSearchParams();
  q.set("models", state.models.join(","));
  if (state.ref) q.set("ref", state.ref);
  q.set("theta", String(state.theta));
  for (const [k, v] of Object.entries(state.params)) q.set(k, v);
  return q;
}
function writeHash() {
  const q = paramQuery();
  q.set("mesh", state.mesh); q.set("light", state.light); q.set("lang", state.lang);
  if (state.env !== "none") q.set("env", state.env);
  if (state.dfg) q.set("dfg", state.dfg);
  if (state.exp) q.set("exp", state.exp);
  history.replaceState(null, "", "#" + q.toString());
  $("link").href = location.href;
}

// ---- controls ------------------------------------------------------------------------
function paramSpecs() {
  const seen = {}, out = [];
  for (const id of allIds()) for (const p of (MODELS[id] ? MODELS[id].params : []))
    if (!seen[p.name]) { seen[p.name] = 1; out.push(p); }
  return out;
}
// A choice whose default follows another choice (cook-torrance's g follows d: ggx -> smith-ggx),
// as the server resolves it: the menu shows what the pictures and numbers use.
function choiceDefault(p, depth = 0) {
  const f = p.default_follows;
  if (!f || depth > 4) return p.default;
  const o = paramSpecs().find(q => q.name === f.param);
  const other = state.params[f.param] ?? (o ? (o.type === "choice" ? choiceDefault(o, depth + 1) : o.default) : undefined);
  return f.defaults[other] ?? p.default;
}
function pruneParams() {
  const names = paramSpecs().map(p => p.name);
  for (const k of Object.keys(state.params)) if (!names.includes(k)) delete state.params[k];
}
const toSlider = (p, v) => p.log ? Math.log(v / p.min) / Math.log(p.max / p.min) * 1000 : (v - p.min) / (p.max - p.min) * 1000;
const fromSlider = (p, s) => p.log ? p.min * Math.pow(p.max / p.min, s / 1000) : p.min + (p.max - p.min) * s / 1000;
const short = v => Number(v.toPrecision(4)).toString();

function buildControls() {
  const box = $("models"); box.replaceChildren();
  allIds().forEach((id, i) => {
    const radio = el("input", { type: "radio", name: "ref", checked: id === state.ref }), remove = el("button", { title: "remove" }, "x");
    const d = el("div", { class: "model" }, el("span", { class: "swatch", style: `background:${COLORS[i % COLORS.length]}` }),
      el("label", {}, radio, " ref"), " ", el("b", {}, id), " ",
      el("small", {}, MODELS[id] ? MODELS[id].kind : id === MEAS ? "measured" : "?"), " ", remove);
    radio.onchange = () => { if (id !== MEAS && !state.models.includes(id)) state.models.push(id); state.ref = id; changed(true); };
    remove.onclick = () => {
      state.models = state.models.filter(m => m !== id);
      if (state.ref === id) state.ref = "";
      if (!state.models.length) state.models = [state.ref || "flog"];
      changed(true);
    };
    box.appendChild(d);
  });
  if (MEAS && !allIds().includes(MEAS)) {
    // The measured file (--measured): offered as a reference only.
    const radio = el("input", { type: "radio", name: "ref", id: "ref-measured" });
    radio.onchange = () => { state.ref = MEAS; changed(true); };
    box.appendChild(el("div", { class: "model" }, el("span", { class: "swatch" }), el("label", {}, radio, " ref"), " ", el("b", {}, MEAS), " ", el("small", {}, "measured")));
  }
  const pbox = $("params"); pbox.replaceChildren();
  for (const p of paramSpecs()) {
    const row = document.createElement("div"); row.className = "row";
    const cur = state.params[p.name];
    if (p.type === "number") {
      const v = cur !== undefined ? Number(cur) : (p.default ?? p.min);
      const sl = el("input", { type: "range", min: 0, max: 1000, step: 1, id: `slider-${p.name}` });
      const tx = el("input", { type: "text", id: `text-${p.name}`, title: `${p.log ? "log " : ""}[${p.min}, ${p.max}]` });
      row.append(el("label", { title: p.doc }, p.name), sl, tx);
      sl.value = toSlider(p, v); tx.value = cur !== undefined ? cur : (p.default === null ? "" : String(v));
      sl.oninput = () => { const x = short(fromSlider(p, Number(sl.value))); tx.value = x; state.params[p.name] = x; changed(false); };
      tx.onchange = () => { if (tx.value === "") delete state.params[p.name]; else { state.params[p.name] = tx.value.trim(); sl.value = toSlider(p, Number(tx.value)); } changed(false); };
    } else if (p.type === "color") {
      // A user's model's colour parameter: R,G,B (or one grey number), as --param takes it.
      const tx = el("input", { type: "text", id: `text-${p.name}`, title: "R,G,B" });
      row.append(el("label", { title: p.doc }, p.name), tx);
      tx.value = cur !== undefined ? cur : p.default.map(short).join(",");
      tx.onchange = () => { if (tx.value === "") delete state.params[p.name]; else state.params[p.name] = tx.value.trim(); changed(false); };
    } else {
      const sel = el("select", { id: `choice-${p.name}` });
      row.append(el("label", { title: p.doc }, p.name), sel);
      for (const o of p.options) sel.add(new Option(o, o, false, o === (cur ?? choiceDefault(p))));
      // A choice another one's default follows redraws the controls, so that one's menu follows.
      const led = paramSpecs().some(q => q.default_follows && q.default_follows.param === p.name);
      sel.onchange = () => { state.params[p.name] = sel.value; changed(led); };
    }
    pbox.appendChild(row);
  }
  $("theta").value = state.theta; $("theta-text").value = state.theta;
  $("mesh").value = state.mesh; $("lang").value = state.lang;
  $("light-text").textContent = state.light;
  const em = $("export-model"); em.replaceChildren();
  for (const id of allIds()) if (id !== MEAS) em.add(new Option(id, id, false, id === (state.exp || state.models[0])));
  for (const h of HOOKS.controls) h();
}

function changed(structure) {
  if (structure) { pruneParams(); buildControls(); }
  writeHash(); update(structure);
}

// ---- plots ---------------------------------------------------------------------------
function frame(cv, title, xlabel, ylabel, x0, x1, y0, y1, logy) {
  const c = cv.getContext("2d"), W = cv.width, H = cv.height, L = 52, R = 10, T = 20, B = 32;
  c.clearRect(0, 0, W, H); c.fillStyle = "#fff"; c.fillRect(0, 0, W, H);
  c.fillStyle = "#222"; c.font = "12px sans-serif"; c.fillText(title, L, 14);
  const ty = v => logy ? Math.log10(Math.max(v, 1e-300)) : v;
  const Y0 = ty(y0), Y1 = ty(y1);
  const px = x => L + (x - x0) / (x1 - x0 || 1) * (W - L - R);
  const py = y => H - B - (ty(y) - Y0) / (Y1 - Y0 || 1) * (H - T - B);
  c.strokeStyle = "#999"; c.strokeRect(L, T, W - L - R, H - T - B);
  c.font = "10px sans-serif"; c.fillStyle = "#555";
  for (let k = 0; k <= 4; k++) {
    const xv = x0 + (x1 - x0) * k / 4; c.fillText(short(xv), px(xv) - 8, H - B + 12);
    const yv = logy ? Math.pow(10, Y0 + (Y1 - Y0) * k / 4) : y0 + (y1 - y0) * k / 4;
    c.fillText(Math.abs(yv) < 1e-3 && yv !== 0 || Math.abs(yv) >= 1e4 ? yv.toExponential(1) : short(yv), 14, py(yv) + 3);
  }
  c.fillText(xlabel, W / 2 - 20, H - 4);
  c.save(); c.translate(10, T + (H - T - B) / 2 + 20); c.rotate(-Math.PI / 2); c.fillText(ylabel, 0, 0); c.restore();
  return { c, px, py, rect: [L, T, W - L - R, H - T - B] };
}
function curve(f, xs, ys, color) {
  const { c, px, py } = f; c.save(); c.beginPath(); c.rect(...f.rect); c.clip();
  c.strokeStyle = color; c.lineWidth = 1.5; c.beginPath();
  let on = false;
  xs.forEach((x, i) => { const y = ys[i]; if (y === null || !isFinite(y)) { on = false; return; } if (on) c.lineTo(px(x), py(y)); else c.moveTo(px(x), py(y)); on = true; });
  c.stroke(); c.restore();
}
function range(arrays, logy) {
  let lo = Infinity, hi = -Infinity;
  for (const a of arrays) for (const v of a) if (v !== null && isFinite(v) && (!logy || v > 0)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!isFinite(lo)) { lo = logy ? 1e-3 : 0; hi = 1; }
  if (logy) lo = Math.max(lo, hi * 1e-8);
  if (lo === hi) hi = lo + (logy ? lo : 1);
  return [lo, hi];
}
function colorOf(id) { return COLORS[allIds().indexOf(id) % COLORS.length]; }

function drawPlots(d) {
  const ms = d.models;
  // Polar: radius = f / max over all models, theta_o in the plane of incidence.
  {
    const cv = $("polar"), c = cv.getContext("2d"), W = cv.width, H = cv.height, cx = W / 2, cy = H - 24, R = Math.min(W / 2 - 20, H - 44);
    c.clearRect(0, 0, W, H); c.fillStyle = "#fff"; c.fillRect(0, 0, W, H);
    c.fillStyle = "#222"; c.font = "12px sans-serif"; // Measured data carries its albedos (the models do not): then each curve is scaled to its own
    // maximum, so that the shapes compare.
    const own = d.reference_kind === "measured";
    c.fillText(`in-plane polar plot, theta_i = ${d.theta_i_deg} deg (${own ? "each / own max; measured: luminance" : "f / max"})`, 8, 14);
    c.strokeStyle = "#ccc"; c.beginPath(); c.arc(cx, cy, R, Math.PI, 2 * Math.PI); c.moveTo(cx - R, cy); c.lineTo(cx + R, cy); c.stroke();
    let mx = 0; for (const m of ms) for (const v of m.polar) mx = Math.max(mx, v);
    mx = mx || 1;
    for (const m of ms) {
      const mm = own ? (Math.max(...m.polar) || 1) : mx;
      c.strokeStyle = colorOf(m.id); c.lineWidth = 1.5; c.beginPath();
      d.polar_theta_deg.forEach((t, i) => { const r = R * m.polar[i] / mm, a = t * Math.PI / 180; const x = cx + r * Math.sin(a), y = cy - r * Math.cos(a); i ? c.lineTo(x, y) : c.moveTo(x, y); });
      c.stroke();
    }
    // The incident direction, on its side (wi at +theta_i: the reflection leaves on the other).
    const a = d.theta_i_deg * Math.PI / 180; c.strokeStyle = "#f9a825"; c.lineWidth = 2; c.beginPath();
    c.moveTo(cx, cy); c.lineTo(cx - R * Math.sin(a), cy - R * Math.cos(a)); c.stroke();
    c.fillStyle = "#f9a825"; c.fillText("wi", cx - R * Math.sin(a) - 14, cy - R * Math.cos(a));
  }
  const th = d.curve_theta_deg;
  const withLobe = ms.filter(m => m.lobe);
  {
    const [lo, hi] = range(withLobe.map(m => m.lobe), true);
    const f = frame($("lobe"), "lobe: lobe(cos) / D(theta_h) / BRDF at wi = wo (log)", "theta (deg)", "value", 0, 90, lo, hi, true);
    for (const m of withLobe) curve(f, th, m.lobe, colorOf(m.id));
  }
  const withErr = ms.filter(m => m.error);
  for (const [id, key, title, log] of [["err-abs", "abs", "signed error vs reference (abs; / peak for non-lobes)", false], ["err-rel", "rel", "relative error |f - ref| / ref (log)", true]]) {
    // Where the reference nears zero the relative error explodes: the plot shows up to 100.
    const clip = a => log ? a.map(v => v === null ? null : Math.min(v, 100)) : a;
    const arrays = withErr.map(m => clip(m.error[key]));
    const [lo, hi] = range(arrays, log);
    const f = frame($(id), title, "theta (deg)", key, 0, 90, log ? lo : Math.min(lo, 0), log ? hi : Math.max(hi, 0), log);
    for (const m of withErr) {
      curve(f, th, clip(m.error[key]), colorOf(m.id));
      // The located maximum (refined, as `fastbrdf errors`).
      const at = key === "abs" ? m.error.max_abs_at_deg : m.error.max_rel_at_deg;
      const c = f.c; c.strokeStyle = colorOf(m.id); c.setLineDash([3, 3]); c.beginPath(); c.moveTo(f.px(at), 20); c.lineTo(f.px(at), $(id).height - 32); c.stroke(); c.setLineDash([]);
    }
    if (!withErr.length) {
      const c = $(id).getContext("2d");
      if (d.reference_kind === "measured") {
        c.fillText("not drawn against measured data (colour, diffuse part,", 60, 120);
        c.fillText("no swept curve): see its residuals in Numbers", 60, 136);
      } else if (d.reference_kind === "user" || ms.some(m => m.kind === "user")) {
        c.fillText("a user's model has no swept curve: its errors on a grid", 60, 120);
        c.fillText("of direction pairs are in Numbers (max abs, max rel)", 60, 136);
      } else c.fillText("choose a reference of the same kind", 80, 130);
    }
  }
  {
    // theta_h x theta_d slices (phi_d = 90 deg), log colour, one tile per model.
    const cv = $("slice"), c = cv.getContext("2d"), n = d.slice_size; c.fillStyle = "#fff"; c.fillRect(0, 0, cv.width, cv.height);
    c.fillStyle = "#222"; c.font = "12px sans-serif"; c.fillText("theta_h (x) x theta_d (y) slice, log colour", 8, 14);
    const tile = Math.min(120, Math.floor((cv.width - 10) / Math.max(ms.length, 1)) - 6);
    ms.forEach((m, k) => {
      const img = c.createImageData(n, n); let mx = 0; for (const v of m.slice) mx = Math.max(mx, v);
      for (let j = 0; j < n; j++) for (let i = 0; i < n; i++) {
        const v = m.slice[j * n + i], t = v > 0 && mx > 0 ? Math.max(0, 1 + Math.log10(v / mx) / 4) : 0, o = 4 * ((n - 1 - j) * n + i);
        img.data[o] = 255 * Math.min(1, 2 * t); img.data[o + 1] = 255 * Math.max(0, 2 * t - 1); img.data[o + 2] = 80 * (1 - t) + 40; img.data[o + 3] = 255;
      }
      const tmp = document.createElement("canvas"); tmp.width = n; tmp.height = n; tmp.getContext("2d").putImageData(img, 0, 0);
      const x = 8 + k * (tile + 6); c.imageSmoothingEnabled = false; c.drawImage(tmp, x, 30, tile, tile);
      c.fillStyle = colorOf(m.id); c.fillText(m.id, x, 30 + tile + 14);
    });
  }
}

function drawAlbedo(d) {
  const ms = d.models.filter(m => m.albedo);
  const [, hi] = range(ms.map(m => m.albedo.albedo), false);
  const title = d.estimate ? "directional albedo: ESTIMATE (quick quadrature; precise curve coming)" : "directional albedo vs incidence (white furnace: <= 1)";
  const f = frame($("albedo"), title, "theta_i (deg)", "albedo", 0, 90, 0, Math.max(1.1, hi * 1.05), false);
  f.c.strokeStyle = "#bbb"; f.c.setLineDash([4, 4]); f.c.beginPath(); f.c.moveTo(f.px(0), f.py(1)); f.c.lineTo(f.px(90), f.py(1)); f.c.stroke(); f.c.setLineDash([]);
  if (d.estimate) f.c.setLineDash([6, 3]);
  for (const m of ms) curve(f, m.albedo.theta_deg, m.albedo.albedo, colorOf(m.id));
  f.c.setLineDash([]);
  $("albedo").dataset.estimate = d.estimate ? "1" : "0";
  // The verdict only ever comes from the precise computation.
  if (d.estimate) { $("verdicts").replaceChildren(el("div", { class: "estimate" }, "white furnace: computing (the albedo curve shown is an estimate)")); return; }
  const why = d.models.filter(m => m.why).map(m => el("div", {}, `${m.id}: albedo ${m.why}`));
  $("verdicts").replaceChildren(...why, ...ms.map(m => {
    const a = m.albedo, ok = a.conserves;
    const t = a.claims_energy ? (ok ? `white furnace: passes (max albedo ${a.worst_albedo.toFixed(6)} at ${a.worst_theta_deg} deg)` : `white furnace: FAILS (albedo ${a.worst_albedo.toFixed(6)} at ${a.worst_theta_deg} deg > 1)`) : `no energy claim; max albedo ${a.worst_albedo.toFixed(6)} at ${a.worst_theta_deg} deg`;
    return el("div", { class: !a.claims_energy || ok ? "verdict-ok" : "verdict-bad" }, `${m.id} (${a.brdf}): ${t}`);
  }));
}

// ---- numbers -------------------------------------------------------------------------
const fmt = v => v === null || v === undefined ? "-" : (typeof v === "number" ? v.toPrecision(4) : v);
function drawNumbers() {
  const d = lastPlots; if (!d) return;
  const metrics = {}; if (lastRender) for (const m of lastRender.metrics) metrics[m.model] = m;
  const meas = d.reference_kind === "measured";
  const heads = ["model", "max abs", "at (deg)", "max rel", "at (deg)", ...(meas ? ["ngan-l2", "low-log", "max"] : []),
    "PSNR (dB)", "FLIP", "documented bounds", "cost (evals/s, one core)", "shader instructions (transc./div-sqrt/branch)"];
  const rows = [el("tr", {}, heads.map(t => el("th", {}, t)))];
  for (const m of d.models) {
    // A user's model (or one against a user's reference): its errors on the server's grid of
    // direction pairs (m.against), in the same columns.
    const e = m.error || m.against, mt = metrics[m.id], info = MODELS[m.id] || { bounds: [], cost: null }, r = m.measured;
    const bounds = m.kind === "measured" ? "measured data (" + (INFO.measured ? INFO.measured.file : "") + ")" : m.kind === "user" ? "user's model (" + (info.file || "") + ")" : info.bounds.map(b => `${b.metric} ${b.bound} vs ${b.reference} (${b.param[0]} in [${b.param[1]}, ${b.param[2]}])`).join("; ") || "none (reference or exact)";
    const cell = (cls, value, text) => el("td", { class: cls, "data-value": value }, text);
    rows.push(el("tr", { "data-model": m.id },
      el("td", {}, el("span", { class: "swatch", style: `background:${colorOf(m.id)}` }), ` ${m.id}${m.id === d.reference ? " (ref)" : ""}`),
      cell("max-abs", e ? e.max_abs : "", e ? fmt(e.max_abs) : "-"), el("td", {}, e ? fmt(e.max_abs_at_deg) : "-"),
      cell("max-rel", e ? (e.max_rel === null ? "inf" : e.max_rel) : "", e ? (e.max_rel === null ? "inf" : fmt(e.max_rel)) : "-"), el("td", {}, e ? fmt(e.max_rel_at_deg) : "-"),
      meas ? [cell("ngan-l2", r ? r.ngan_l2 : "", r ? fmt(r.ngan_l2) : "-"), cell("low-log", r ? r.low_log : "", r ? fmt(r.low_log) : "-"), cell("res-max", r ? r.max : "", r ? fmt(r.max) : "-")] : [],
      el("td", { class: "psnr" }, mt ? (mt.psnr === null ? "inf" : fmt(mt.psnr)) : "-"), el("td", { class: "flip", "data-value": mt && mt.flip !== null ? mt.flip : "" }, mt && mt.flip !== null ? fmt(mt.flip) : flipPending && m.id !== d.reference ? "..." : "-"),
      el("td", { style: "text-align:left" }, bounds),
      el("td", { class: "cost" }, info.cost && info.cost.simd ? info.cost.simd.toExponential(3) + " (SIMD)" : info.cost && info.cost.scalar ? info.cost.scalar.toExponential(3) + " (scalar)" : "unavailable (no --bench run)"),
      // SPIR-V instructions after spirv-opt -O: the same on every machine (fastbrdf_gpu::cost).
      el("td", { class: "instructions", "data-value": info.instructions ? info.instructions.total : "" }, info.instructions ? `${info.instructions.total} (${info.instructions.transcendental}/${info.instructions.division_sqrt}/${info.instructions.branches})` : "-")));
  }
  $("numbers").replaceChildren(...rows);
}

// ---- requests ------------------------------------------------------------------------
// A request's answer, its body read whole: {ok, status, text, error}, `error` (when not ok)
// the server's JSON `error`, else "HTTP <status>" for a body that is not the server's JSON. A
// body cut short by an abort (the headers were in, then a newer request took over), or one
// that arrived after its request was replaced, is an AbortError: the page draws nothing of it.
async function fetchAnswer(url, signal) {
  const r = await fetch(url, { signal });
  const aborted = () => new DOMException("aborted while its answer arrived", "AbortError");
  const text = await r.text().catch(e => { throw (signal && signal.aborted) ? aborted() : e; });
  if (signal && signal.aborted) throw aborted();
  let error = null;
  if (!r.ok) {
    error = "HTTP " + r.status;
    try { error = JSON.parse(text).error || error; } catch (_) { /* not the server's JSON */ }
  }
  return { ok: r.ok, status: r.status, text, error };
}
// A request's JSON; a failed one throws its error (with `status`), and a successful answer
// whose body is not JSON throws too: both used to come back as the answer
// `{error: "HTTP 200"}`, which became lastPlots, so that the next drawNumbers() threw and the
// newest pictures' task ended before its full picture and FLIP (the flaky view_page test, #30).
async function getJSON(url, signal) {
  const a = await fetchAnswer(url, signal);
  if (!a.ok) throw Object.assign(new Error(a.error), { status: a.status });
  return JSON.parse(a.text);
}
// What task() ended without drawing, newest last, at most 40 (window.fastbrdfDropped, for
// the end-to-end tests' failure messages and a user's console): aborted or superseded (409)
// requests, which the page drops without a word, and errors, which the status line shows
// only until another one replaces them.
const DROPPED = window.fastbrdfDropped = [];
async function task(fn, what) {
  const born = view;
  pending++; ready();
  try { await fn(); } catch (e) {
    const quiet = e.name === "AbortError" || e.status === 409;
    if (!quiet) setStatus(e.message, true, born);
    DROPPED.push(`${typeof what === "function" ? what() : what || "?"} (view ${born}, now ${view}, render ${gen}): ${quiet ? (e.status === 409 ? "409 " + e.message : "aborted") : "error: " + e.message}`);
    if (DROPPED.length > 40) DROPPED.shift();
  }
  finally { pending--; ready(); }
}
// While a control moves and the browser draws the pictures (WebGPU), the server's numbers
// (plots, albedo, shader, the hooks' panes) follow once it has rested LAZY_MS: a frame is not
// kept waiting behind computations that the next move would replace. Pending, they keep
// document.body.dataset.ready at "0".
const LAZY_MS = 300;
let lazyTimer = null;
function update(structure) {
  view++;
  const q = paramQuery();
  if (lazyTimer !== null) { clearTimeout(lazyTimer); lazyTimer = null; pending--; }
  if (!structure && document.body.dataset.renderer === "webgpu") {
    renderAll(q);
    pending++; ready();
    lazyTimer = setTimeout(() => { lazyTimer = null; pending--; numbers(paramQuery(), false); }, LAZY_MS);
    return;
  }
  numbers(q, true);
}
// The server's numbers of the view `q` (and its pictures too when `pictures`).
function numbers(q, pictures) {
  if (plotCtl) plotCtl.abort(); plotCtl = new AbortController(); const ps = plotCtl.signal, v = view;
  task(async () => {
    const t = performance.now();
    const d = await getJSON("/api/plots?" + q, ps);
    lastPlots = d; drawPlots(d); drawNumbers();
    for (const h of HOOKS.plots) h(d);
    setStatus(`plots ${(performance.now() - t).toFixed(0)} ms (server ${d.ms.toFixed(0)} ms)`, false, v);
  }, "plots");
  if (albedoCtl) albedoCtl.abort(); albedoCtl = new AbortController(); const as = albedoCtl.signal;
  // A quick estimate first (looser quadrature, drawn dashed, no verdict), then the precise
  // curve and the white-furnace verdict replace it.
  task(async () => {
    const qq = new URLSearchParams(q); qq.set("quick", "1");
    drawAlbedo(await getJSON("/api/albedo?" + qq, as));
    drawAlbedo(await getJSON("/api/albedo?" + q, as));
  }, "albedo");
  if (pictures) renderAll(q);
  exportShader();
  for (const h of HOOKS.update) h(q);
  ready();
}
let albedoCtl = null;
function renderAll(q) {
  for (const h of HOOKS.render) if (h(q, gen + 1)) { gen++; return; }
  if (renderCtl) renderCtl.abort(); renderCtl = new AbortController(); const rs = renderCtl.signal;
  const g = ++gen;
  const rq = new URLSearchParams(q); rq.set("mesh", state.mesh); rq.set("light", state.light); rq.set("client", client); rq.set("gen", String(g));
  flipPending = true;
  let stage = "128 px";
  task(async () => {
    try {
      // A quick low-resolution preview first (no FLIP), then the full picture, shown as soon
      // as it is rendered, with RMSE and PSNR; its FLIP follows from the server's FLIP pool.
      let d = null;
      for (const [size, spp, flip] of [[128, 1, "none"], [512, 2, "later"]]) {
        rq.set("size", size); rq.set("spp", spp); rq.set("flip", flip); stage = `${size} px`;
        d = await getJSON("/api/render?" + rq, rs);
        if (g !== gen) return;
        lastRender = d; showPictures(d); drawNumbers();
        $("render-info").textContent = `(${serverWhy()}${d.width}x${d.height}, ${d.spp * d.spp} spp, ${d.ms.toFixed(0)} ms)`;
      }
      if (d.flip_job === null || d.flip_job === undefined) return;
      stage = `FLIP job ${d.flip_job}`;
      const f = await getJSON("/api/flip?" + new URLSearchParams({ job: d.flip_job }), rs);
      // Only onto the picture it was computed for: a newer request has replaced lastRender.
      if (g !== gen || lastRender !== d) return;
      lastRender = Object.assign({}, d, { metrics: f.metrics });
      flipPending = false; drawNumbers();
      $("render-info").textContent = `(${serverWhy()}${d.width}x${d.height}, ${d.spp * d.spp} spp, ${d.ms.toFixed(0)} ms; FLIP after, ${f.flip_ms.toFixed(0)} ms of work)`;
    } finally { if (g === gen) { flipPending = false; drawNumbers(); } }
  }, () => `render gen ${g}, ${stage}`);
}
// Who draws the server's pictures and why the browser does not (gpu.js leaves the reason).
function serverWhy() {
  const why = $("render-info").dataset.why;
  return `drawn by the server${why ? ": " + why : ""}; `;
}
function showPictures(d) {
  const box = $("pictures"); box.replaceChildren();
  const png = im => `data:image/png;base64,${im.png}`;
  for (const im of d.images)
    box.appendChild(el("figure", {}, el("img", { class: "render", "data-model": im.id, src: png(im), draggable: "false" }),
      el("figcaption", { style: `color:${colorOf(im.id)}` }, `${im.id}${im.id === d.reference ? " (reference)" : ""}`)));
  for (const im of d.diffs)
    box.appendChild(el("figure", {}, el("img", { class: "diff", "data-model": im.id, src: png(im), draggable: "false" }),
      el("figcaption", {}, `|${im.id} - ${d.reference}| (scale ${d.diff_scale.toFixed(3)})`)));
  for (const img of box.querySelectorAll("img")) {
    const move = ev => {
      const r = img.getBoundingClientRect(), x = 2 * (ev.clientX - r.left) / r.width - 1, y = 1 - 2 * (ev.clientY - r.top) / r.height;
      const z = Math.sqrt(Math.max(0.05, 1 - Math.min(1, x * x + y * y)));
      state.light = [x, y, z].map(v => v.toFixed(3)).join(",");
      $("light-text").textContent = state.light;
    };
    img.onmousedown = ev => {
      move(ev);
      const up = () => { window.removeEventListener("mousemove", move); window.removeEventListener("mouseup", up); writeHash(); renderAll(paramQuery()); };
      window.addEventListener("mousemove", move); window.addEventListener("mouseup", up);
    };
  }
}
let shaderCtl = null;
function exportShader() {
  if (shaderCtl) shaderCtl.abort(); shaderCtl = new AbortController(); const s = shaderCtl.signal;
  const id = $("export-model").value || state.models[0];
  const q = new URLSearchParams({ model: id, lang: state.lang });
  for (const p of (MODELS[id] ? MODELS[id].params : [])) if (state.params[p.name] !== undefined) q.set(p.name, state.params[p.name]);
  task(async () => {
    const a = await fetchAnswer("/api/shader?" + q, s);
    // The pane says why it holds no shader rather than keep the last view's.
    $("shader").textContent = a.ok ? a.text : a.error;
  }, "shader");
}

// ---- start ---------------------------------------------------------------------------
async function start() {
  INFO = await getJSON("/api/models");
  if (INFO.measured) MEAS = INFO.measured.name;
  for (const m of INFO.models) MODELS[m.id] = m;
  const add = $("add"); add.add(new Option("add a model...", ""));
  const kinds = {};
  for (const m of INFO.models) (kinds[m.kind] = kinds[m.kind] || []).push(m.id);
  for (const [k, ids] of Object.entries(kinds)) { const g = document.createElement("optgroup"); g.label = k; for (const id of ids) g.appendChild(new Option(id, id)); add.appendChild(g); }
  add.onchange = () => { if (add.value && !state.models.includes(add.value) && state.models.length < INFO.limits.models) state.models.push(add.value); add.value = ""; changed(true); };
  for (const n of INFO.materials) $("material").add(new Option(n, n));
  $("material").onchange = async () => {
    const name = $("material").value; if (!name) return;
    for (const id of allIds()) {
      try { const r = await getJSON("/api/material?" + new URLSearchParams({ name, model: id })); for (const [k, v] of Object.entries(r.params)) state.params[k] = String(v); } catch (e) { /* the model takes none of the fit's parameters */ }
    }
    changed(true);
  };
  if (INFO.mesh) $("mesh").add(new Option(INFO.mesh, "mesh"));
  $("mesh").onchange = () => { state.mesh = $("mesh").value; writeHash(); renderAll(paramQuery()); };
  for (const l of INFO.langs) $("lang").add(new Option(l, l));
  $("lang").onchange = () => { state.lang = $("lang").value; writeHash(); exportShader(); };
  $("export-model").onchange = () => { state.exp = $("export-model").value; writeHash(); exportShader(); };
  $("copy").onclick = () => navigator.clipboard.writeText($("shader").textContent);
  $("theta").oninput = () => { state.theta = Number($("theta").value); $("theta-text").value = state.theta; changed(false); };
  $("theta-text").onchange = () => { state.theta = Number($("theta-text").value); $("theta").value = state.theta; changed(false); };
  readHash();
  for (const h of HOOKS.start) await h(INFO);
  window.addEventListener("hashchange", () => { readHash(); changed(true); });
  changed(true);
}
