// illuknit design app: how wide must it be? The smallest width at which both sides read.
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

// ---------------------------------------------------------------------------------------------
// the widths job: the session's two pictures designed at a few widths, narrowest first, each
// side asked of the reader (tesseract) from the measuring viewpoint

async function runWidths() {
  clearError("widths");
  $("#widths").textContent = "";
  try {
    const job = await startJob("widths");
    if (job) await loadWidths();
  } catch (err) { report(err, "widths"); }
}

let widthsTimer = null;

// after a change of settings or pictures: is the answer still the one for them?
function refreshWidthsSoon() {
  clearTimeout(widthsTimer);
  widthsTimer = setTimeout(() => { loadWidths().catch(() => {}); }, 300);
}

async function loadWidths() {
  if (!state.sid || (state.settings && state.settings.mode !== "double")) return;
  let got;
  try { got = await sapi("GET", "/widths"); } catch (err) { report(err, "widths"); return; }
  const button = $("#find-widths");
  // no reader: one clear line instead of a button that can only fail
  button.hidden = !got.reader;
  $("#widths-no-reader").hidden = got.reader;
  showWidths(got);
}

const YES = (b) => (b ? "✓ reads" : "✗ no");

function showWidths(got) {
  const box = $("#widths");
  box.textContent = "";
  const found = got.result;
  if (!found) return;
  const answer = document.createElement("p");
  answer.className = `widths-answer ${found.both != null ? "ok" : "no"}`;
  answer.textContent = found.both != null
    ? `Both sides read from ${found.both} units wide (${found.tried.find((v) => v.width === found.both).width_cm.toFixed(1)} cm).`
    : "Both sides read at none of the widths tried.";
  box.appendChild(answer);
  const said = found.words.map((w, i) => `side ${"AB"[i]} ${w == null ? "is a picture (judged by its shapes, an estimate)" : `says ${w}`}`);
  const how = document.createElement("p");
  how.className = "muted";
  how.textContent = `${said.join(", ")}; read ${viewpointText({ angle: found.angle, distance: found.distance_m })}, ${found.gauge}.`;
  box.appendChild(how);
  const wide = state.width_units;
  if (got.current && wide) {
    const here = document.createElement("p");
    here.className = "muted";
    const tried = found.tried.find((v) => v.width === wide);
    here.textContent = tried
      ? `The design is now ${wide} units wide; the best design this search found there: ${tried.sentence}.`
      : `The design is now ${wide} units wide (not one of the widths tried).`;
    box.appendChild(here);
  }
  if (!got.current) {
    const stale = document.createElement("p");
    stale.className = "err-note";
    stale.textContent = "Found for other pictures or settings (colours, viewpoint, machine): find it again for these.";
    box.appendChild(stale);
  }
  const table = document.createElement("table");
  table.className = "widths-table";
  table.innerHTML = "<thead><tr><th>width</th><th>side A</th><th>side B</th><th>both sides</th><th></th></tr></thead>";
  const body = document.createElement("tbody");
  const now = state.width_units;
  for (const v of found.tried) {
    const tr = document.createElement("tr");
    tr.dataset.width = v.width;
    if (v.width === found.both) tr.className = "smallest";
    const cells = [`${v.width} units`, YES(v.a_reads), YES(v.b_reads), YES(v.both_read)];
    for (const [i, text] of cells.entries()) {
      const td = document.createElement("td");
      td.textContent = text;
      if (i === 0) td.appendChild(Object.assign(document.createElement("small"), { textContent: `${v.width_cm.toFixed(1)} cm` }));
      if (i > 0) td.className = (i === 3 ? v.both_read : [v.a_reads, v.b_reads][i - 1]) ? "ok" : "no";
      if (i > 0) td.title = v.sentence;
      tr.appendChild(td);
    }
    const act = document.createElement("td");
    if (got.current && v.width === now) {
      act.textContent = "current width";
      act.className = "muted";
    } else if (got.current) {
      const b = document.createElement("button");
      b.type = "button";
      b.className = v.width === found.both ? "primary small" : "ghost small";
      b.textContent = "Use this width";
      b.title = `Set the width to ${v.width} units and find candidates there (the best design found here: ${v.sentence})`;
      b.addEventListener("click", () => applyWidth(v.width));
      act.appendChild(b);
    }
    tr.appendChild(act);
    body.appendChild(tr);
  }
  table.appendChild(body);
  const wrap = document.createElement("div");
  wrap.className = "widths-scroll";
  wrap.appendChild(table);
  box.appendChild(wrap);
  const note = document.createElement("p");
  note.className = "hint";
  note.textContent = "Each width is a small search of 8 designs ranked by the reader. The candidates found at a width are ranked by how they read (the correlation); each card says whether its sides read, and Rank by: sides that read puts first those that do.";
  box.appendChild(note);
}

async function applyWidth(width) {
  clearError("widths");
  await saveSettings({ size_mode: "units", width_units: width });
  await loadWidths();
}
