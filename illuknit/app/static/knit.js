// illuknit design app: downloads, knitout and the machine summary.
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

// ---------------------------------------------------------------------------------------------
// downloads and knitout

function updateKnitButtons() {
  for (const b of $$("[data-needs-knit]")) {
    const format = b.dataset.format;
    b.disabled = !state.knitReady || (format && !(state.knitFormats || []).includes(format));
  }
  const none = !state.selected;
  for (const b of $$(".downloads button[data-dl]")) if (!b.hasAttribute("data-needs-knit") && !b.classList.contains("unavail")) b.disabled = none;
  $("#make-knit").disabled = none || !(state.info && state.info.capabilities.knit) || !$("#job-knit").hidden;
  if (state.info && !state.info.capabilities.knit) $("#make-knit").title = "the knitout compiler is not in this install";
}

async function refreshKnit() {
  state.knitReady = false;
  $("#knit-summary").textContent = "";
  if (state.selected) {
    try {
      const k = await sapi("GET", "/knit");
      state.knitReady = k.ready;
      state.knitFormats = k.ready ? k.formats : [];
      if (k.ready) showKnitSummary(k);
    } catch (err) { report(err, "knit"); }
  }
  updateKnitButtons();
}

function showKnitSummary(k) {
  const box = $("#knit-summary");
  box.textContent = "";
  const st = k.stats || {};
  const parts = [];
  if (st.wales != null) parts.push(`${st.wales} wales × ${st.courses} courses`);
  if (st.width_cm != null) parts.push(`${st.width_cm} × ${st.height_cm} cm`);
  if (st.passes != null) parts.push(`${st.passes} carriage passes`);
  else if (st.knit_passes != null) parts.push(`${st.knit_passes} knit + ${st.transfer_passes || 0} transfer passes`);
  // the estimate's range (the documented carriage speeds) and the bind-off's part, as the CLI says
  if (st.time) parts.push(`about ${st.time} to knit` + (st.time_range ? ` (${st.time_range}; bind-off ${st.bind_off_time})` : ""));
  parts.push(`${k.lines} lines`);
  const line = document.createElement("div");
  line.textContent = `Knitout ready · ${parts.join(" · ")}`;
  box.appendChild(line);
  if (st.long_floats) {
    // kept on request ("allow long floats"): say how long and where, as the CLI's warning does
    const warn = document.createElement("div");
    warn.className = "err";
    warn.id = "knit-long-floats";
    warn.textContent = `${st.long_floats} long float(s) kept; the longest, ${st.longest_float} needles: ${st.longest_float_at}`;
    box.appendChild(warn);
  }
  const machine = (state.info.machines || []).find((m) => m.name === k.machine);
  if (k.needle_range) {
    const bed = document.createElement("div");
    bed.id = "knit-needles";
    bed.textContent = `On the ${machine ? machine.label : k.machine}: needles ${k.needle_range[0]}–${k.needle_range[1]} of ${st.needles}` +
      (st.time ? ` · estimated machine time ${st.time}` : "");
    box.appendChild(bed);
  }
  if (k.carriers && k.carriers.length) {
    // which cone goes on which carrier
    const table = document.createElement("table");
    table.className = "carriers";
    table.id = "carrier-table";
    const head = table.createTHead().insertRow();
    for (const h of ["Carrier", "Yarn"]) head.appendChild(document.createElement("th")).textContent = h;
    const body = table.createTBody();
    for (const row of k.carriers) {
      const tr = body.insertRow();
      tr.insertCell().textContent = row.carriers.join(", ");
      const cell = tr.insertCell();
      if (row.rgb) {
        const sw = document.createElement("span");
        sw.className = "sw";
        sw.style.background = row.rgb;
        cell.append(sw, document.createTextNode(` ${row.yarn} (${row.rgb})`));
      } else {
        cell.textContent = row.yarn; // the waste yarn and draw thread: any cone of their kind
      }
    }
    box.appendChild(table);
  }
  if (k.report) {
    const r = k.report;
    const verdict = document.createElement("div");
    verdict.className = r.ok ? "ok" : "bad";
    verdict.textContent = r.ok
      ? `Checker: nothing blocking · ${r.warnings} warning(s) · ${r.pieces} piece(s)`
      : `Checker: ${r.blocking} blocking problem(s) — see the check report`;
    box.appendChild(verdict);
  }
}

async function makeKnit() {
  try {
    const job = await startJob("knit", { allow_long_floats: $("#allow-long-floats").checked });
    if (job) await refreshKnit();
  } catch (err) { report(err, "knit"); }
}

async function download(name, button) {
  const field = button.hasAttribute("data-needs-knit") ? "knit" : "downloads";
  clearError("downloads", "knit");
  button.disabled = true;
  try {
    const res = await sapi("GET", `/download/${name}?angle=${state.angle}`, undefined, { raw: true });
    const blob = await res.blob();
    const cd = res.headers.get("content-disposition") || "";
    const m = /filename="([^"]+)"/.exec(cd);
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = m ? m[1] : name;
    document.body.appendChild(a);
    a.click();
    setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
  } catch (err) {
    report(err, field);
  } finally {
    button.disabled = false;
    updateKnitButtons();
  }
}
