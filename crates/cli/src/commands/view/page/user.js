// user.js: "Your model": a .brdf, .wgsl or .glsl file dropped onto the page, or pasted into
// the box with a name, is compiled (WGSL first in the browser when it has WebGPU: its messages
// with line numbers at once), then sent to the server (POST /api/user: naga compiles every
// form and the server's line:column are the ones `fastbrdf eval --model file:...` prints),
// listed beside the built-ins (MODELS, state.models) and checked by conform (/api/conform:
// `fastbrdf conform file:... --json`'s record). Every message goes in as text.
const USER_EXT = /\.(brdf|wgsl|glsl)$/i, USER_MAX_BYTES = 256 * 1024; // api::MAX_UPLOAD
let userConformCtl = null, userLast = null, userDevice = null;

HOOKS.start.push(() => {
  const drop = el("div", { id: "user-drop", style: "border:2px dashed #b0bec5;border-radius:4px;padding:8px;text-align:center;color:#607d8b;margin-bottom:6px" },
    "Drop a .brdf, .wgsl or .glsl file here (or anywhere on the page)");
  const name = el("input", { type: "text", id: "user-name", value: "my_model.wgsl", style: "flex:1", title: "the file's name: its extension says the language" });
  const text = el("textarea", { id: "user-text", rows: 10, spellcheck: "false", style: "width:100%;box-sizing:border-box;font:11px monospace",
    placeholder: "// param alpha 0.01 1 0.3\nfn brdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 { ... }" });
  const compile = el("button", { id: "user-compile" }, "compile");
  const recheck = el("button", { id: "user-reconform", title: "conform again, with the current parameter values", disabled: true }, "conform");
  $("left").appendChild(el("section", { id: "user" }, el("h2", {}, "Your model"), drop,
    el("div", { class: "row" }, el("label", { for: "user-name" }, "name"), name), text,
    el("div", { class: "row" }, compile, recheck, el("span", { id: "user-status" })),
    el("pre", { id: "user-errors", hidden: true, style: "color:#c62828;white-space:pre-wrap" }),
    el("div", { id: "user-conform" })));
  compile.onclick = () => task(() => userSubmit(name.value.trim(), text.value));
  recheck.onclick = () => { if (userLast) task(() => userConform(userLast)); };
  // A file dragged anywhere onto the page: its name and text fill the box, then it compiles.
  const over = ev => { if ([...(ev.dataTransfer ? ev.dataTransfer.types : [])].includes("Files")) { ev.preventDefault(); drop.style.borderColor = "#1e88e5"; } };
  document.addEventListener("dragover", over);
  document.addEventListener("dragleave", () => { drop.style.borderColor = "#b0bec5"; });
  document.addEventListener("drop", ev => {
    const f = ev.dataTransfer && ev.dataTransfer.files[0];
    if (!f) return;
    ev.preventDefault(); drop.style.borderColor = "#b0bec5";
    task(async () => {
      if (f.size > USER_MAX_BYTES) { userStatus(`${f.name}: ${f.size} bytes; an upload is at most ${USER_MAX_BYTES} bytes`, true); return; }
      name.value = f.name; text.value = await f.text();
      await userSubmit(f.name, text.value);
    });
  });
});

function userStatus(t, bad) { const s = $("user-status"); s.textContent = t; s.className = bad ? "verdict-bad" : ""; }
function userErrors(lines) { const e = $("user-errors"); e.textContent = lines.join("\n"); e.hidden = lines.length === 0; }

// WGSL compiled by the browser's WebGPU (none: null): the parameters (`// param` lines) are
// declared after the user's text, so that the line numbers are the file's.
async function userBrowserMessages(name, text) {
  if (!navigator.gpu) return null;
  try {
    if (!userDevice) { const a = await navigator.gpu.requestAdapter(); if (!a) return null; userDevice = await a.requestDevice(); }
    const decl = [];
    for (const line of text.split("\n")) {
      const m = /^\s*\/\/\s*param\s+(?:(float|bool|color)\s+)?([A-Za-z_][A-Za-z0-9_]*)\b/.exec(line);
      if (m) decl.push(`var<private> ${m[2]}: ${m[1] === "bool" ? "bool" : m[1] === "color" ? "vec3<f32>" : "f32"};`);
    }
    const mod = userDevice.createShaderModule({ code: text + "\n" + decl.join("\n") + "\n" });
    const info = await mod.getCompilationInfo();
    const n = text.split("\n").length;
    return info.messages.filter(m => m.type === "error").map(m =>
      m.lineNum > 0 && m.lineNum <= n ? `${name}:${m.lineNum}:${m.linePos}: ${m.message}` : `${name}: ${m.message}`);
  } catch (e) { return null; }
}

async function userSubmit(name, text) {
  userErrors([]); $("user-conform").replaceChildren();
  if (!USER_EXT.test(name)) { userStatus(`name ${name || "(empty)"}: must end in .brdf, .wgsl or .glsl`, true); return; }
  if (!text.trim()) { userStatus(`${name}: nothing to compile`, true); return; }
  const browser = /\.wgsl$/i.test(name) ? await userBrowserMessages(name, text) : null;
  if (browser && browser.length) userErrors(browser.map(m => "browser: " + m));
  userStatus("compiling on the server...");
  const t = performance.now();
  const r = await fetch("/api/user?" + new URLSearchParams({ name }), { method: "POST", body: text, headers: { "content-type": "text/plain; charset=utf-8" } });
  const d = await r.json().catch(() => ({ error: "HTTP " + r.status }));
  if (!r.ok) {
    const at = d.line ? ` (line ${d.line}${d.column ? ", column " + d.column : ""})` : "";
    userStatus(`compile error${at}`, true);
    userErrors([...(browser || []).map(m => "browser: " + m), d.error || ("HTTP " + r.status)]);
    return;
  }
  MODELS[d.id] = d;
  if (!INFO.models.some(m => m.id === d.id)) INFO.models.push(d); else INFO.models = INFO.models.map(m => m.id === d.id ? d : m);
  const add = $("add");
  if (![...add.options].some(o => o.value === d.id)) add.appendChild(new Option(d.id, d.id));
  // A new upload of a name replaces the model: its parameters may differ.
  for (const p of d.params) delete state.params[p.name];
  if (!state.models.includes(d.id)) {
    if (state.models.length >= INFO.limits.models) state.models.pop();
    state.models.push(d.id);
  }
  userLast = d.id; $("user-reconform").disabled = false;
  userStatus(`${d.id}: compiled (${d.language}, ${d.channels} channel${d.channels === 1 ? "" : "s"}${d.samples ? ", samples" : ""}) in ${(performance.now() - t).toFixed(0)} ms`);
  changed(true);
  await userConform(d.id);
}

// conform's verdicts for model `id` at the page's values of the parameters it declares.
async function userConform(id) {
  if (userConformCtl) userConformCtl.abort(); userConformCtl = new AbortController();
  const q = new URLSearchParams({ model: id });
  for (const p of (MODELS[id] ? MODELS[id].params : [])) if (state.params[p.name] !== undefined) q.set(p.name, state.params[p.name]);
  const box = $("user-conform");
  box.replaceChildren(el("div", {}, `conform ${id}: running...`));
  const t = performance.now();
  let d;
  try { d = await getJSON("/api/conform?" + q, userConformCtl.signal); }
  catch (e) { if (e.name !== "AbortError") box.replaceChildren(el("div", { class: "verdict-bad" }, `conform ${id}: ${e.message}`)); return; }
  const num = v => v === null || v === undefined ? "-" : Number(v).toPrecision(4);
  const rows = d.checks.map(c => el("tr", { "data-check": c.check, "data-status": c.status, title: c.summary },
    el("td", {}, c.check), el("td", { class: c.status === "fail" ? "verdict-bad" : c.status === "pass" ? "verdict-ok" : "" }, c.status.toUpperCase()),
    el("td", {}, num(c.value)), el("td", {}, num(c.limit))));
  box.replaceChildren(
    el("div", { id: "user-verdict", class: d.passed ? "verdict-ok" : "verdict-bad" },
      `conform ${d.model} (${d.mode}): ${d.passed ? "PASS" : "FAIL"} (${(performance.now() - t).toFixed(0)} ms)`),
    el("table", { id: "user-checks" }, el("tr", {}, el("th", {}, "check"), el("th", {}, "verdict"), el("th", {}, "value"), el("th", {}, "limit")), rows));
}
