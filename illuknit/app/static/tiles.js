// illuknit design app: the tile table (tiles per overlap pair, grouped, the rare ones folded).
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

// ---------------------------------------------------------------------------------------------
// tiles per overlap pair

async function loadPairs() {
  const box = $("#pairs");
  // the folded line stays open over reloads (a pick, the measures arriving) if it was open
  const rareOpen = !!$("#pairs details.rare[open]");
  box.textContent = "";
  clearError("tiles");
  if (!state.selected) return;
  let p;
  try { p = await sapi("GET", "/pairs"); } catch (err) { report(err, "tiles"); return; }
  $("#tiles-hint").textContent = p.editable
    ? "Each row is a place where a colour of A lies over a colour of B, grouped by the fill side A (head-on, in a head-on design) shows there; overlaps too rare to matter much are folded into one line. Choose another tile from the bank to change how it looks; the preview updates."
    : (p.reason || "This candidate has no tiles to edit.");
  renderPairs(p, rareOpen);
}

// The tile table: a heading per group of overlaps that show one fill from A, their rows, and
// the rare overlaps folded into one line that opens.
function renderPairs(p, rareOpen = !!$("#pairs details.rare[open]")) {
  const box = $("#pairs");
  box.textContent = "";
  showEditMeasures(p);
  const byKey = new Map((p.pairs || []).map((pair) => [`${pair.a}/${pair.b}`, pair]));
  if (!p.groups) { for (const pair of p.pairs || []) box.appendChild(pairRow(pair)); return; }
  const pct = (x) => `${(100 * x).toFixed(1)}%`;
  // groups follow the fill seen from the design's first view: side A, or head-on
  const seenFrom = p.views && p.views[0] === "headon" ? "Head-on" : (p.views ? p.views[0] : "A");
  for (const g of p.groups) {
    const head = document.createElement("div");
    head.className = "group-head";
    head.innerHTML = `<span class="sw"></span><b></b><span class="muted"></span>`;
    if (g.fill_color) $(".sw", head).style.background = g.fill_color;
    else $(".sw", head).remove();
    $("b", head).textContent = `${seenFrom} shows ${g.fill}`;
    $(".muted", head).textContent = ` · ${g.pairs.length} overlap${g.pairs.length > 1 ? "s" : ""} · ${pct(g.share)} of units`;
    box.appendChild(head);
    for (const key of g.pairs) box.appendChild(pairRow(byKey.get(key)));
  }
  if (p.rare && p.rare.pairs.length) {
    const det = document.createElement("details");
    det.className = "rare";
    det.open = rareOpen;
    const sum = document.createElement("summary");
    const n = p.rare.pairs.length;
    sum.textContent = `${n} rare overlap${n > 1 ? "s" : ""} (each under ${pct(p.rare.below)} of units) · ${pct(p.rare.share)} together`;
    const rows = document.createElement("div");
    rows.className = "pairs";
    for (const key of p.rare.pairs) rows.appendChild(pairRow(byKey.get(key)));
    det.append(sum, rows);
    box.appendChild(det);
  }
}

function pairRow(pair) {
  const row = document.createElement("div");
  row.className = "pair" + (pair.overridden ? " edited" : "");
  const img = document.createElement("img");
  img.src = `/api/sessions/${state.sid}/${pair.tile_picture}`;
  img.alt = `tile ${pair.tile}`;
  const right = document.createElement("div");
  const over = document.createElement("div");
  over.className = "over";
  over.innerHTML = `<span class="sw"></span> A over <span class="sw"></span> B <span class="muted"></span>`;
  const sws = $$(".sw", over);
  sws[0].style.background = pair.a_color;
  sws[1].style.background = pair.b_color;
  $(".muted", over).textContent = `· ${(100 * pair.share).toFixed(1)}% of units`;
  const sel = document.createElement("select");
  sel.setAttribute("aria-label", `tile for A colour ${pair.a} over B colour ${pair.b}`);
  for (const opt of pair.options) {
    const o = document.createElement("option");
    o.value = opt.id;
    o.textContent = opt.label;
    if (opt.id === pair.tile) o.selected = true;
    sel.appendChild(o);
  }
  const apply = async (tile) => {
    try {
      const res = await sapi("PUT", `/pairs/${pair.a}/${pair.b}`, { tile });
      state.editTick = (state.editTick || 0) + 1;
      clearError("tiles");
      renderPairs(res);
      updatePreview();
      refreshHistory();
      await refreshKnit();
    } catch (err) { report(err, "tiles"); sel.value = pair.tile; }
  };
  sel.addEventListener("change", () => apply(sel.value === pair.default ? null : sel.value));
  // power users: any tile written as rows, top row first, ^ marking a raised unit (e.g. 0/1^)
  const rows = document.createElement("input");
  rows.type = "text";
  rows.className = "rows";
  rows.placeholder = "or type rows, e.g. 0/1^";
  rows.setAttribute("aria-label", `custom tile rows for A colour ${pair.a} over B colour ${pair.b}`);
  rows.addEventListener("keydown", (e) => { if (e.key === "Enter" && rows.value.trim()) apply(rows.value.trim()); });
  right.append(over, sel, rows);
  const meta = document.createElement("div");
  meta.className = "meta";
  meta.textContent = pair.fills || "";
  row.append(img, right, meta);
  return row;
}

// How the picked design reads with the tile edits, measured by the server at each edit, next to
// how the candidate read without them.
function showEditMeasures(p) {
  const line = $("#edit-measures");
  if (!p.edited) { line.hidden = true; line.textContent = ""; return; }
  line.hidden = false;
  const now = measuresText(p.edited);
  const was = p.measures ? measuresText({ ...p.measures, knit_minutes: null, knit_note: "" }) : "";
  const a = p.edited.perceptual_score, b = p.measures && p.measures.perceptual_score;
  let verdict = "";
  // the perceptual score (correlation-based), not a reader's verdict: "scores", never "reads"
  if (a != null && b != null) verdict = a > b + 1e-4 ? "scores higher" : a < b - 1e-4 ? "scores lower" : "scores the same";
  line.className = "edit-measures " + (verdict === "scores higher" ? "better" : verdict === "scores lower" ? "worse" : "");
  line.textContent = `With your tile edits${verdict ? ` it ${verdict}` : ""} ${viewpointText(p.measured_at)}: ${now}` + (was ? ` (without them: ${was})` : "");
}
