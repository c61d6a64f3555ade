// kinds.js: the terms that are not shaded (shadowing, Fresnel, split-sum env), as BRDF
// Explorer's panes show them: /api/plots' `terms`, each term's curves (the model solid, its
// reference dashed) and a table of its errors against the reference (`fastbrdf errors`'
// numbers). Shadowing: G1(theta_v) and G2(theta_v, theta_l = theta_i) in the plane of
// incidence; Fresnel: F(cos); env: the split-sum scale and bias against NoV at the slider's
// alpha and against alpha at the slider's cos_v. The section is hidden without a term.
const TERM_KINDS = ["shadowing", "fresnel", "env"];
const termIds = () => allIds().filter(id => MODELS[id] && TERM_KINDS.includes(MODELS[id].kind));

function termsShown(on) { const s = $("terms"); if (s) s.hidden = !on; }

HOOKS.start.push(() => {
  $("right").appendChild(el("section", { id: "terms", hidden: true },
    el("h2", {}, "Terms ", el("small", {}, "(shadowing, Fresnel, split-sum: model solid, reference dashed)")),
    el("div", { id: "terms-plots", style: "display:grid;grid-template-columns:repeat(3,1fr);gap:8px" }), el("table", { id: "terms-numbers" }), el("div", { id: "terms-notes" })));
});
HOOKS.controls.push(() => termsShown(termIds().length > 0));
HOOKS.plots.push(d => drawTerms(d.terms || []));

// Where an error lies, in the plot's words (the server's `max_*_where`).
function termWhere(w) {
  if (!w) return "-";
  if (w.theta_v_deg !== undefined) return `theta_v ${fmt(w.theta_v_deg)} deg`;
  if (w.term !== undefined) return `${w.term}, NoV ${fmt(w.cos_v)}`;
  return `cos ${fmt(w.cos)}`;
}

function drawTerms(terms) {
  termsShown(terms.length > 0);
  const box = $("terms-plots"); box.replaceChildren();
  const refColor = id => allIds().includes(id) ? colorOf(id) : "#777";
  // A term that is another's reference is drawn dashed in that one's plots, not again.
  const shownAsRef = new Set(terms.map(t => t.reference));
  for (const t of terms) for (const p of shownAsRef.has(t.id) ? [] : t.plots) {
    const cv = el("canvas", { class: "plot term-plot", width: 420, height: 260, "data-model": t.id, "data-plot": p.name });
    box.appendChild(cv);
    const ys = p.curves.flatMap(c => [c.model, c.reference || []]);
    const [lo, hi] = range(ys, false);
    const at = p.at ? " at " + Object.entries(p.at).map(([k, v]) => `${k} = ${short(v)}`).join(", ") : "";
    const f = frame(cv, `${t.id} vs ${t.reference || "(reference itself)"}${at}`, p.x_label, p.y_label,
      p.x[0], p.x[p.x.length - 1], Math.min(lo, 0), Math.max(hi, 1e-6), false);
    p.curves.forEach((c, k) => {
      // The second curve of a term (G2, the bias) lighter: dashes are the reference's.
      f.c.globalAlpha = k ? 0.55 : 1;
      curve(f, p.x, c.model, colorOf(t.id));
      if (c.reference) { f.c.setLineDash([6, 4]); curve(f, p.x, c.reference, refColor(t.reference)); f.c.setLineDash([]); }
      f.c.globalAlpha = 1;
      f.c.fillStyle = colorOf(t.id); f.c.font = "10px sans-serif";
      f.c.fillText(`${k ? "light" : "solid"}: ${c.label}`, f.rect[0] + 6, f.rect[1] + 0.55 * f.rect[3] + 12 * k);
    });
  }
  const heads = ["term", "reference", "at", "max abs", "where", "max rel", "where", "rms"];
  const rows = [el("tr", {}, heads.map(h => el("th", {}, h)))];
  const notes = [];
  for (const t of terms) {
    const e = t.error, cell = (cls, value, text) => el("td", { class: cls, "data-value": value }, text);
    rows.push(el("tr", { "data-model": t.id },
      el("td", {}, el("span", { class: "swatch", style: `background:${colorOf(t.id)}` }), ` ${t.id} `, el("small", {}, t.kind)),
      el("td", {}, t.reference ? `${t.reference} (${t.reference_rule})` : "-"),
      el("td", {}, e ? `${e.param} = ${short(e.value)}` : "-"),
      cell("max-abs", e ? e.max_abs : "", e ? fmt(e.max_abs) : "-"),
      cell("max-abs-at", e ? e.max_abs_at : "", e ? termWhere(e.max_abs_where) : "-"),
      cell("max-rel", e ? (e.max_rel === null ? "inf" : e.max_rel) : "", e ? (e.max_rel === null ? "inf" : fmt(e.max_rel)) : "-"),
      cell("max-rel-at", e ? e.max_rel_at : "", e ? termWhere(e.max_rel_where) : "-"),
      cell("rms", e ? e.rms : "", e ? fmt(e.rms) : "-")));
    if (t.why) notes.push(el("div", {}, `${t.id}: ${t.why}`));
    if (e && t.errors_ignore.length)
      notes.push(el("div", {}, `${t.id}: the errors are measured at ${e.param} = ${short(e.value)} with ${t.errors_ignore.join(", ")} at the default (as fastbrdf errors); the curves use the sliders' values`));
  }
  $("terms-numbers").replaceChildren(...rows);
  $("terms-notes").replaceChildren(...notes);
}
