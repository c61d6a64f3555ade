// ---- panes.js: BRDF Explorer's panes (issue 32) --------------------------------------
// The "Lobe and angles" section: the 3D lobe of each model for the incident direction
// (theta_i = the page's theta, phi_i here), draggable; f against theta_h, theta_d (at phi_d)
// and theta_v (in the plane of phi_v); the theta_h x theta_d slice at phi_d. Numbers from
// /api/panes (docs/book/src/explorer-panes.md). phi_i and the pane angles live here, not in
// the link: an unknown key of the link would be sent to the server as a model parameter.
const PANES = {
  phi_i: 0, phi_h: 0, phi_d: 90, phi_v: null, theta_h: 0, theta_d: 30, log: true,
  yaw: -0.6, pitch: 0.45, ctl: null, last: null, tiles: [], drag: null,
};
const PANE_SLIDERS = [
  ["phi_i", "phi_i", 0, 360, "azimuth of the incident direction (theta_i is the page's theta); drag the lobe to move both"],
  ["phi_v", "phi_v", 0, 360, "the plane of the theta_v plot (default: phi_i + 180, the mirror side)"],
  ["theta_d", "theta_d", 0, 90, "theta_d of the theta_h plot"],
  ["theta_h", "theta_h", 0, 90, "theta_h of the theta_d plot"],
  ["phi_d", "phi_d", 0, 360, "phi_d of the theta_h and theta_d plots and of the slice"],
  ["phi_h", "phi_h", 0, 360, "phi_h of the theta_h and theta_d plots and of the slice (isotropic models: no effect)"],
];
const PANE_CANVASES = [["panes-lobe", 420, 360], ["panes-theta-h", 420, 260], ["panes-theta-d", 420, 260], ["panes-theta-v", 420, 260], ["panes-slice", 420, 260]];
const PANES_DEG = Math.PI / 180;

function panesQuery() {
  const q = paramQuery();
  q.set("theta_i", String(state.theta));
  for (const k of ["phi_i", "phi_h", "phi_d", "theta_h", "theta_d"]) q.set(k, String(PANES[k]));
  if (PANES.phi_v !== null) q.set("phi_v", String(PANES.phi_v));
  return q;
}
function panesFetch() {
  if (PANES.ctl) PANES.ctl.abort(); PANES.ctl = new AbortController(); const sig = PANES.ctl.signal;
  const q = panesQuery();
  task(async () => {
    const d = await getJSON("/api/panes?" + q, sig);
    PANES.last = d; panesDraw(d);
  }, "panes");
}
function panesShowSliders() {
  for (const [k] of PANE_SLIDERS) {
    const v = k === "phi_v" && PANES.phi_v === null && PANES.last ? PANES.last.phi_v_deg : PANES[k];
    if (v === null) continue;
    $(`panes-${k}`).value = v; $(`panes-${k}-text`).value = v;
  }
}

// ---- the 3D lobe ------------------------------------------------------------------------
// A fixed oblique orthographic view: world z (the normal) up, turned by yaw about z and seen
// from pitch above the surface.
function panesView() {
  const cy = Math.cos(PANES.yaw), sy = Math.sin(PANES.yaw), cp = Math.cos(PANES.pitch), sp = Math.sin(PANES.pitch);
  return {
    to: p => { const qx = cy * p[0] - sy * p[1], qy = sy * p[0] + cy * p[1]; return [qx, qy * sp + p[2] * cp, -qy * cp + p[2] * sp]; },
    from: v => { const qx = v[0], qy = v[1] * sp - v[2] * cp, qz = v[1] * cp + v[2] * sp; return [cy * qx + sy * qy, -sy * qx + cy * qy, qz]; },
  };
}
function panesGeom(cv) { return { cx: cv.width / 2, cy: cv.height * 0.66, S: Math.min(cv.width, cv.height) * 0.48 }; }
const panesDir = (t, p) => [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];

function panesDrawLobe(d) {
  const cv = $("panes-lobe"), c = cv.getContext("2d"), W = cv.width, H = cv.height, g = panesGeom(cv), V = panesView();
  const scr = p => { const v = V.to(p); return [g.cx + g.S * v[0], g.cy - g.S * v[1]]; };
  const line = (pts, close) => { c.beginPath(); pts.forEach((p, i) => { const s = scr(p); i ? c.lineTo(s[0], s[1]) : c.moveTo(s[0], s[1]); }); if (close) c.closePath(); c.stroke(); };
  c.clearRect(0, 0, W, H); c.fillStyle = "#fff"; c.fillRect(0, 0, W, H);
  c.fillStyle = "#222"; c.font = "12px sans-serif";
  const own = d.reference_kind === "measured";
  c.fillText(`3D lobe: f cos theta_o / ${own ? "own max" : "max"}, theta_i = ${d.theta_i_deg}, phi_i = ${d.phi_i_deg} deg`, 8, 14);
  c.fillStyle = "#777"; c.font = "10px sans-serif";
  c.fillText("drag: incident direction; right or shift drag: turn the view", 8, 28);
  // The surface: the unit circle, the x and y axes, the normal.
  c.strokeStyle = "#ccc"; c.lineWidth = 1;
  line(Array.from({ length: 65 }, (_, k) => [Math.cos(k * Math.PI / 32), Math.sin(k * Math.PI / 32), 0]), true);
  line([[-1, 0, 0], [1, 0, 0]]); line([[0, -1, 0], [0, 1, 0]]); line([[0, 0, 0], [0, 0, 1]]);
  c.fillStyle = "#999"; for (const [p, t] of [[[1.06, 0, 0], "x"], [[0, 1.06, 0], "y"], [[0, 0, 1.06], "n"]]) { const s = scr(p); c.fillText(t, s[0] - 3, s[1] + 3); }
  const th = d.lobe_theta_deg.map(t => t * PANES_DEG), ph = d.lobe_phi_deg.map(p => p * PANES_DEG), nt = th.length, np = ph.length;
  const peak = Math.max(0, ...d.models.map(m => m.lobe_max)) || 1;
  for (const m of d.models) {
    const sc = own ? (m.lobe_max || 1) : peak;
    const P = (i, j) => { const v = m.lobe[i * np + j], r = v === null ? 0 : v / sc; return panesDir(th[i], ph[j]).map(x => r * x); };
    c.strokeStyle = colorOf(m.id); c.lineWidth = 1; c.globalAlpha = 0.75;
    for (let i = 1; i < nt; i++) line(Array.from({ length: np }, (_, j) => P(i, j)), true);
    for (let j = 0; j < np; j += 2) line(Array.from({ length: nt }, (_, i) => P(i, j)));
    c.globalAlpha = 1;
  }
  // The incident direction (its handle) and the mirror direction (dashed).
  const wi = d.wi, o = scr([0, 0, 0]), a = scr(wi), mr = scr([-wi[0], -wi[1], wi[2]]);
  c.strokeStyle = "#f9a825"; c.lineWidth = 2; c.beginPath(); c.moveTo(o[0], o[1]); c.lineTo(a[0], a[1]); c.stroke();
  c.setLineDash([4, 3]); c.lineWidth = 1; c.beginPath(); c.moveTo(o[0], o[1]); c.lineTo(mr[0], mr[1]); c.stroke(); c.setLineDash([]);
  c.fillStyle = "#f9a825"; c.beginPath(); c.arc(a[0], a[1], 5, 0, 2 * Math.PI); c.fill(); c.fillText("wi", a[0] + 7, a[1] - 4);
  d.models.forEach((m, k) => { c.fillStyle = colorOf(m.id); c.fillText(m.id, W - 130, 44 + 12 * k); });
  cv.dataset.thetaI = d.theta_i_deg; cv.dataset.phiI = d.phi_i_deg;
}

// The direction under the cursor on the unit hemisphere (the front of the sphere, else its
// back, else the horizon).
function panesPick(ev) {
  const cv = $("panes-lobe"), r = cv.getBoundingClientRect(), g = panesGeom(cv), V = panesView();
  let vx = ((ev.clientX - r.left) * cv.width / r.width - g.cx) / g.S, vy = (g.cy - (ev.clientY - r.top) * cv.height / r.height) / g.S;
  const len = Math.hypot(vx, vy); if (len > 1) { vx /= len; vy /= len; }
  const vz = Math.sqrt(Math.max(0, 1 - vx * vx - vy * vy));
  let p = V.from([vx, vy, vz]);
  if (p[2] < 0) { const b = V.from([vx, vy, -vz]); p = b[2] >= 0 ? b : [p[0], p[1], 0]; }
  const n = Math.hypot(...p) || 1;
  const theta = Math.min(89, Math.acos(Math.min(1, Math.max(0, p[2] / n))) / PANES_DEG);
  const phi = (Math.atan2(p[1], p[0]) / PANES_DEG + 360) % 360;
  state.theta = Math.round(theta * 10) / 10; PANES.phi_i = Math.round(phi * 10) / 10;
  $("theta").value = state.theta; $("theta-text").value = state.theta;
  panesShowSliders(); panesFetch();
}
function panesMouse(cv) {
  cv.addEventListener("contextmenu", ev => ev.preventDefault());
  cv.addEventListener("mousedown", ev => {
    ev.preventDefault();
    const turn = ev.button === 2 || ev.shiftKey;
    if (!turn && ev.button !== 0) return;
    let x0 = ev.clientX, y0 = ev.clientY;
    if (!turn) panesPick(ev);
    const move = e => {
      if (turn) {
        PANES.yaw += (e.clientX - x0) * 0.01; PANES.pitch = Math.max(-0.2, Math.min(Math.PI / 2, PANES.pitch + (e.clientY - y0) * 0.01));
        x0 = e.clientX; y0 = e.clientY;
        if (PANES.last) panesDrawLobe(PANES.last);
      } else panesPick(e);
    };
    const up = () => {
      window.removeEventListener("mousemove", move); window.removeEventListener("mouseup", up);
      // theta_i is the page's theta: the other plots and the pictures follow on release.
      if (!turn) changed(false);
    };
    window.addEventListener("mousemove", move); window.addEventListener("mouseup", up);
  });
}

// ---- angle plots and the slice ------------------------------------------------------------
function panesPlot(id, d, key, xs, title, xlabel, x0, x1) {
  const ms = d.models, log = PANES.log;
  const [lo, hi] = range(ms.map(m => m[key]), log);
  const f = frame($(id), title + (log ? " (log)" : ""), xlabel, "f", x0, x1, log ? lo : Math.min(lo, 0), hi, log);
  for (const m of ms) curve(f, xs, m[key], colorOf(m.id));
}
function panesDrawSlice(d) {
  const cv = $("panes-slice"), c = cv.getContext("2d"), n = d.slice_size, ms = d.models;
  c.fillStyle = "#fff"; c.fillRect(0, 0, cv.width, cv.height);
  c.fillStyle = "#222"; c.font = "12px sans-serif";
  c.fillText(`theta_h (x) x theta_d (y), phi_d = ${d.phi_d_deg} deg, log (click: set them)`, 8, 14);
  const tile = Math.min(160, Math.floor((cv.width - 10) / Math.max(ms.length, 1)) - 6);
  PANES.tiles = [];
  ms.forEach((m, k) => {
    const img = c.createImageData(n, n); let mx = 0; for (const v of m.slice) if (v !== null) mx = Math.max(mx, v);
    for (let j = 0; j < n; j++) for (let i = 0; i < n; i++) {
      const v = m.slice[j * n + i], o = 4 * ((n - 1 - j) * n + i);
      if (v === null) { img.data.set([90, 90, 90, 255], o); continue; }
      const t = v > 0 && mx > 0 ? Math.max(0, 1 + Math.log10(v / mx) / 4) : 0;
      img.data.set([255 * Math.min(1, 2 * t), 255 * Math.max(0, 2 * t - 1), 80 * (1 - t) + 40, 255], o);
    }
    const tmp = document.createElement("canvas"); tmp.width = n; tmp.height = n; tmp.getContext("2d").putImageData(img, 0, 0);
    const x = 8 + k * (tile + 6), y = 30; c.imageSmoothingEnabled = false; c.drawImage(tmp, x, y, tile, tile);
    // The theta_h and theta_d of the plots.
    c.strokeStyle = "#fff"; c.setLineDash([2, 2]); c.beginPath();
    const hx = x + tile * d.theta_h_deg / 90, dy = y + tile * (1 - d.theta_d_deg / 90);
    c.moveTo(hx, y); c.lineTo(hx, y + tile); c.moveTo(x, dy); c.lineTo(x + tile, dy); c.stroke(); c.setLineDash([]);
    c.fillStyle = colorOf(m.id); c.fillText(m.id, x, y + tile + 14);
    PANES.tiles.push([x, y, tile]);
  });
}
function panesDraw(d) {
  panesDrawLobe(d);
  panesPlot("panes-theta-h", d, "theta_h", d.curve_theta_deg, `f vs theta_h (theta_d = ${d.theta_d_deg}, phi_d = ${d.phi_d_deg}, phi_h = ${d.phi_h_deg})`, "theta_h (deg)", 0, 90);
  panesPlot("panes-theta-d", d, "theta_d", d.curve_theta_deg, `f vs theta_d (theta_h = ${d.theta_h_deg}, phi_d = ${d.phi_d_deg}, phi_h = ${d.phi_h_deg})`, "theta_d (deg)", 0, 90);
  panesPlot("panes-theta-v", d, "theta_v", d.theta_v_deg, `f vs theta_v (wi at ${d.theta_i_deg}, ${d.phi_i_deg}; plane phi_v = ${d.phi_v_deg})`, "theta_v (deg)", -90, 90);
  panesDrawSlice(d);
  panesShowSliders();
  $("panes-note").textContent = (d.skipped || []).map(t => `${t.id}: ${t.why}`).join("; ");
}

// ---- the section ----------------------------------------------------------------------------
HOOKS.start.push(() => {
  const rows = PANE_SLIDERS.map(([k, label, lo, hi, doc]) => {
    const sl = el("input", { type: "range", id: `panes-${k}`, min: lo, max: hi, step: 0.5 });
    const tx = el("input", { type: "text", id: `panes-${k}-text` });
    const set = v => { if (!isFinite(v) || v < lo || v > hi) return; PANES[k] = v; panesShowSliders(); panesFetch(); };
    sl.oninput = () => set(Number(sl.value));
    tx.onchange = () => set(Number(tx.value));
    return el("div", { class: "row", style: "width:260px" }, el("label", { title: doc }, label), sl, tx);
  });
  const log = el("input", { type: "checkbox", id: "panes-log", checked: PANES.log });
  log.onchange = () => { PANES.log = log.checked; if (PANES.last) panesDraw(PANES.last); };
  const canvases = PANE_CANVASES.map(([id, w, h]) => el("canvas", { class: "plot", id, width: w, height: h }));
  $("right").append(el("section", { id: "panes" }, el("h2", {}, "Lobe and angles"),
    el("div", { style: "display:flex;flex-wrap:wrap;gap:0 16px" }, rows, el("div", { class: "row" }, el("label", { for: "panes-log" }, "log f"), log)),
    el("div", { style: "display:grid;grid-template-columns:repeat(3, 1fr);gap:8px" }, canvases),
    el("div", { id: "panes-note" })));
  panesMouse($("panes-lobe"));
  $("panes-slice").addEventListener("click", ev => {
    const cv = $("panes-slice"), r = cv.getBoundingClientRect(), x = (ev.clientX - r.left) * cv.width / r.width, y = (ev.clientY - r.top) * cv.height / r.height;
    for (const [tx, ty, s] of PANES.tiles) if (x >= tx && x < tx + s && y >= ty && y < ty + s) {
      PANES.theta_h = Math.round((x - tx) / s * 900) / 10; PANES.theta_d = Math.round((1 - (y - ty) / s) * 900) / 10;
      panesShowSliders(); panesFetch(); return;
    }
  });
  panesShowSliders();
});
HOOKS.update.push(() => panesFetch());
