// illuknit design app. Plain JavaScript, no build step, no network beyond this server.
// One session per tab (sessionStorage is per tab), so tabs never share state.
"use strict";

const $ = (sel, root = document) => root.querySelector(sel);
const $$ = (sel, root = document) => Array.from(root.querySelectorAll(sel));

const state = {
  sid: null,
  info: null,
  settings: null,
  revision: 0,
  inputs: null, // last good /inputs answer
  candidates: [],
  selected: null,
  candRevision: -1,
  angle: 30,
  jobs: {}, // kind -> job id being polled
  knitReady: false,
};

// ---------------------------------------------------------------------------------------------
// API helpers: every error answers {"error": {"message", "field", "code"}}

class ApiError extends Error {
  constructor(status, body) {
    const e = (body && body.error) || {};
    super(e.message || `request failed (HTTP ${status})`);
    this.status = status;
    this.field = e.field || null;
    this.code = e.code || null;
  }
}

async function api(method, path, body, { raw = false } = {}) {
  const opts = { method, headers: {} };
  if (body instanceof FormData) opts.body = body;
  else if (body !== undefined) {
    opts.body = JSON.stringify(body);
    opts.headers["Content-Type"] = "application/json";
  }
  let res;
  try {
    res = await fetch(path, opts);
  } catch (err) {
    throw new ApiError(0, { error: { message: "the illuknit server is not answering; is `illuknit app` still running?" } });
  }
  if (!res.ok) {
    let payload = null;
    try { payload = await res.json(); } catch (_) { /* not JSON */ }
    throw new ApiError(res.status, payload);
  }
  if (raw) return res;
  const type = res.headers.get("content-type") || "";
  return type.includes("application/json") ? res.json() : res;
}

const sapi = (method, path, body, opts) => api(method, `/api/sessions/${state.sid}${path}`, body, opts);

// ---------------------------------------------------------------------------------------------
// errors next to the control that caused them

const FIELD_ALIASES = { slot: "image_a", session: null, job: null, candidate: "candidates", view: "angle" };

function showError(field, message, extra) {
  if (field in FIELD_ALIASES) field = FIELD_ALIASES[field];
  const box = field ? $(`[data-error-for="${field}"]`) : null;
  if (!box) {
    $("#banner-text").textContent = message;
    $("#banner").classList.remove("notice");
    $("#banner").hidden = false;
    return;
  }
  box.textContent = message;
  if (extra) box.appendChild(extra);
  const control = document.getElementById(field);
  if (control) control.setAttribute("aria-invalid", "true");
  const drop = field.startsWith("image_") ? document.getElementById(`drop-${field.slice(6)}`) : null;
  if (drop) drop.classList.add("invalid");
}

function showNotice(message) {
  $("#banner-text").textContent = message;
  $("#banner").classList.add("notice");
  $("#banner").hidden = false;
}

function clearError(...fields) {
  for (const field of fields) {
    const box = $(`[data-error-for="${field}"]`);
    if (box) box.textContent = "";
    const control = document.getElementById(field);
    if (control) control.removeAttribute("aria-invalid");
    if (field.startsWith("image_")) {
      const drop = document.getElementById(`drop-${field.slice(6)}`);
      if (drop) drop.classList.remove("invalid");
    }
  }
}

const INPUT_FIELDS = ["image_a", "image_b", "width_units", "width_cm", "gauge", "n_colors", "yarns", "mode", "machine"];

function report(err, fallbackField) {
  if (!(err instanceof ApiError)) {
    console.error(err);
    showError(null, String(err && err.message ? err.message : err));
    return;
  }
  if (err.code === "no_session") {
    sessionStorage.removeItem("illuknit.sid");
    showError(null, "This session expired; reload the page to start a new one.");
    return;
  }
  if (err.code === "evicted") {
    // the server closed this tab's session to free memory for newer work: say so, plainly
    sessionStorage.removeItem("illuknit.sid");
    showNotice(`${err.message}.`);
    return;
  }
  if (err.code === "size_mismatch") {
    const fix = document.createElement("button");
    fix.type = "button";
    fix.textContent = "Stretch B to A's size";
    fix.addEventListener("click", () => { $("#resize").checked = true; saveSettings({ resize: true }); });
    showError("image_b", err.message, fix);
    $("#resize-row").hidden = false;
    return;
  }
  showError(err.field || fallbackField || null, err.message);
}

// ---------------------------------------------------------------------------------------------
// session

async function startSession() {
  state.info = await api("GET", "/api/info");
  $("#version").textContent = `v${state.info.version}`;
  const caps = state.info.capabilities;
  for (const b of $$("#modes button")) {
    if (!caps[b.dataset.mode]) {
      b.disabled = true;
      b.title += " (not available in this install)";
    }
  }
  for (const m of state.info.machines) {
    const o = document.createElement("option");
    o.value = m.name;
    o.textContent = `${m.label} · ${m.needles} needles`;
    o.title = m.description;
    $("#machine").appendChild(o);
  }
  const preset = $("#preset");
  for (const name of Object.keys(state.info.presets)) {
    const o = document.createElement("option");
    o.value = name;
    o.textContent = name;
    preset.appendChild(o);
  }
  let s = null;
  const saved = sessionStorage.getItem("illuknit.sid");
  if (saved) {
    try {
      s = await api("GET", `/api/sessions/${saved}`);
    } catch (err) {
      s = null;
      if (err instanceof ApiError && err.code === "evicted") showNotice(`${err.message}. A new session has started.`);
    }
  }
  if (!s) s = await api("POST", "/api/sessions");
  state.sid = s.id;
  sessionStorage.setItem("illuknit.sid", s.id);
  document.body.dataset.session = s.id;
  applyState(s);
  if (!caps[s.settings.mode]) await saveSettings({ mode: "single" });
  await refreshInputs({ autorun: false });
  if (s.candidates) await loadCandidates();
}

function applyState(s) {
  state.settings = s.settings;
  state.revision = s.revision;
  state.knitReady = s.knit_ready;
  const st = s.settings;
  for (const b of $$("#modes button")) b.setAttribute("aria-checked", String(b.dataset.mode === st.mode));
  for (const b of $$("#size-mode button")) b.setAttribute("aria-checked", String(b.dataset.size === st.size_mode));
  $("#row-units").hidden = st.size_mode !== "units";
  $("#row-physical").hidden = st.size_mode !== "physical";
  setValue("#width_units", st.width_units);
  setValue("#machine", st.machine);
  const machine = state.info.machines.find((m) => m.name === st.machine);
  if (machine) {
    // the bed bounds the width control: a wider pattern is refused before any work
    $("#width_units").max = String(machine.max_units);
    $("#machine-info").textContent = `${machine.description}. Widest piece: ${machine.max_units} units (${2 * machine.max_units} stitches).`;
  }
  setValue("#width_cm", st.width_cm);
  setValue("#gauge", st.gauge);
  setValue("#n_colors", st.n_colors);
  setValue("#candidates", st.candidates);
  $("#resize").checked = st.resize;
  if (st.resize) $("#resize-row").hidden = false;
  if (st.mode === "single") $("#resize-row").hidden = true;
  renderYarns(st.yarns);
  const single = st.mode === "single";
  $("#suggest-card").hidden = st.mode !== "double"; // edits of two pictures that share a design
  $("#drop-b").hidden = single;
  $(".drops").classList.toggle("one", single);
  $("#title-a").textContent = single ? "Seen from both sides" : st.mode === "headon" ? "Seen head-on" : "Seen from above";
  $("#title-b").textContent = st.mode === "headon" ? "At an angle (optional)" : "Seen from below";
  for (const slot of ["a", "b"]) {
    const im = s.images[slot];
    const thumb = $(`#thumb-${slot}`);
    if (im) {
      thumb.src = `${im.url}`;
      thumb.hidden = false;
      $(`#hint-${slot}`).hidden = true;
      $(`#drop-${slot}`).classList.add("has");
      // what the reader did to it (a reduction, an animation's first frame) is said, not hidden
      const notes = (im.notes || []).join("; ");
      $(`#meta-${slot}`).textContent = `${im.filename} · ${im.width}×${im.height}px${notes ? ` · ${notes}` : ""}`;
      $(`#meta-${slot}`).title = notes ? `${im.filename}: ${notes}` : im.filename;
    } else {
      thumb.hidden = true;
      thumb.removeAttribute("src");
      $(`#hint-${slot}`).hidden = false;
      $(`#drop-${slot}`).classList.remove("has");
      $(`#meta-${slot}`).textContent = "";
    }
  }
  updateKnitButtons();
}

function setValue(sel, v) {
  const el = $(sel);
  if (document.activeElement !== el) el.value = v;
}

// ---------------------------------------------------------------------------------------------
// settings

let settingsTimer = null;
let pendingSettings = {};

function queueSettings(change, delay = 350) {
  Object.assign(pendingSettings, change);
  clearTimeout(settingsTimer);
  settingsTimer = setTimeout(() => { const c = pendingSettings; pendingSettings = {}; saveSettings(c); }, delay);
}

async function saveSettings(change) {
  const fields = Object.keys(change);
  try {
    const s = await sapi("PUT", "/settings", change);
    clearError(...fields, "mode");
    const changed = s.revision !== state.revision;
    applyState(s);
    if (changed) await refreshInputs({ autorun: true });
  } catch (err) {
    // a refused machine or width leaves the controls showing what the session still has
    if ("machine" in change) setValue("#machine", state.settings.machine);
    report(err, fields[0]);
  }
}

function renderYarns(yarns) {
  const box = $("#yarns");
  box.textContent = "";
  yarns.forEach((hex, i) => {
    const chip = document.createElement("div");
    chip.className = "yarn";
    const pick = document.createElement("input");
    pick.type = "color";
    pick.value = toHex(hex);
    pick.setAttribute("aria-label", `yarn ${i + 1} colour`);
    const code = document.createElement("code");
    code.textContent = pick.value;
    pick.addEventListener("input", () => { code.textContent = pick.value; });
    pick.addEventListener("change", () => {
      const ys = state.settings.yarns.slice();
      ys[i] = pick.value;
      $("#preset").value = "";
      saveSettings({ yarns: ys });
    });
    const rm = document.createElement("button");
    rm.type = "button";
    rm.textContent = "×";
    rm.title = "Remove this yarn";
    rm.disabled = yarns.length <= 2;
    rm.addEventListener("click", () => {
      const ys = state.settings.yarns.filter((_, k) => k !== i);
      $("#preset").value = "";
      saveSettings({ yarns: ys });
    });
    chip.append(pick, code, rm);
    box.appendChild(chip);
  });
  $("#add-yarn").disabled = yarns.length >= 6;
}

function toHex(c) {
  if (/^#[0-9a-f]{6}$/i.test(c)) return c.toLowerCase();
  const ctx = document.createElement("canvas").getContext("2d");
  ctx.fillStyle = c;
  return ctx.fillStyle;
}

// ---------------------------------------------------------------------------------------------
// uploads (file picker and drag and drop)

async function upload(slot, file) {
  clearError(`image_${slot}`);
  const limit = state.info.limits.max_upload_bytes;
  if (file.size > limit) {
    showError(`image_${slot}`, `${file.name} is ${(file.size / 1e6).toFixed(1)} MB; pictures are limited to ${(limit / 1e6).toFixed(0)} MB.`);
    return;
  }
  const form = new FormData();
  form.append("file", file, file.name);
  $(`#meta-${slot}`).textContent = `uploading ${file.name}…`;
  try {
    const s = await sapi("PUT", `/images/${slot}`, form);
    applyState(s);
    await refreshInputs({ autorun: true });
  } catch (err) {
    const s = await sapi("GET", "").catch(() => null);
    if (s) applyState(s);
    report(err, `image_${slot}`);
  }
}

function wireDrop(slot) {
  const drop = $(`#drop-${slot}`);
  const input = $(`#file-${slot}`);
  drop.addEventListener("click", () => input.click());
  drop.addEventListener("keydown", (e) => { if (e.key === "Enter" || e.key === " ") { e.preventDefault(); input.click(); } });
  input.addEventListener("change", () => {
    if (input.files && input.files[0]) upload(slot, input.files[0]);
    input.value = "";
  });
  drop.addEventListener("dragover", (e) => { e.preventDefault(); drop.classList.add("over"); });
  drop.addEventListener("dragleave", () => drop.classList.remove("over"));
  drop.addEventListener("drop", (e) => {
    e.preventDefault();
    drop.classList.remove("over");
    const f = e.dataTransfer && e.dataTransfer.files && e.dataTransfer.files[0];
    if (f) upload(slot, f);
  });
}

// ---------------------------------------------------------------------------------------------
// quantised inputs and legend

function slotsNeeded() { return state.settings.mode === "double" ? ["a", "b"] : ["a"]; }

async function refreshInputs({ autorun }) {
  const quant = $("#quant");
  const missing = slotsNeeded().filter((slot) => !$(`#drop-${slot}`).classList.contains("has"));
  clearError(...INPUT_FIELDS);
  if (missing.length) {
    state.inputs = null;
    quant.className = "quant one";
    quant.innerHTML = `<p class="empty">Upload ${missing.length === 2 ? "two pictures" : "picture " + missing[0].toUpperCase()} to see ${missing.length === 2 ? "them" : "it"} in yarn colours.</p>`;
    $("#notes").textContent = "";
    clearCandidates();
    return;
  }
  let inp;
  try {
    inp = await sapi("GET", "/inputs");
  } catch (err) {
    state.inputs = null;
    quant.className = "quant one";
    quant.innerHTML = `<p class="empty">Fix the problem marked in red to see the quantised pictures.</p>`;
    clearCandidates();
    report(err);
    return;
  }
  state.inputs = inp;
  quant.className = "quant" + (Object.keys(inp.images).length === 1 ? " one" : "");
  quant.textContent = "";
  for (const [slot, url] of Object.entries(inp.images)) {
    const fig = document.createElement("figure");
    const img = document.createElement("img");
    img.src = url;
    img.alt = `quantised picture ${slot.toUpperCase()}`;
    const cap = document.createElement("figcaption");
    cap.textContent = `${slot.toUpperCase()} · ${inp.cols}×${inp.rows} units`;
    const ul = document.createElement("ul");
    ul.className = "legend";
    for (const e of inp.legend[slot]) {
      const li = document.createElement("li");
      li.innerHTML = `<span class="sw" style="background:${e.image_color}"></span><span class="arrow">→</span>` +
        `<span class="sw" style="background:${e.yarn_color}"></span><span></span><span class="pct">${(100 * e.share).toFixed(0)}%</span>`;
      li.children[3].textContent = e.yarn;
      li.title = `picture colour ${e.image_color} becomes yarn ${e.yarn} (${e.yarn_color})`;
      ul.appendChild(li);
    }
    fig.append(img, cap, ul);
    quant.appendChild(fig);
  }
  $("#notes").textContent = inp.notes.join(" ");
  const w = inp.cols, h = inp.rows;
  $("#grid-info").textContent = `${w} × ${h} units = ${2 * w} stitches × ${2 * h} rows. 1 unit = 2 stitches × 2 rows.`;
  if (autorun) runCandidates();
}

// ---------------------------------------------------------------------------------------------
// jobs with progress and cancel

// the page control a job's problems are shown next to
const jobField = (kind) => (kind === "knit" || kind === "suggestions" ? kind : "candidates");

async function startJob(kind) {
  clearError(jobField(kind));
  const job = await sapi("POST", "/jobs", { kind });
  state.jobs[kind] = job.id;
  showJob(kind, job);
  return pollJob(kind, job.id);
}

function showJob(kind, job) {
  const box = $(`#job-${kind}`);
  box.hidden = !(job.status === "queued" || job.status === "running");
  // a stage with no finer progress of its own shows a moving bar, so the page never looks stuck
  box.classList.toggle("busy", !box.hidden && job.progress < 0.1 && job.elapsed > 0.5);
  $(".bar i", box).style.width = `${Math.round(100 * job.progress)}%`;
  $(".job-msg", box).textContent = job.message;
  if (kind === "candidates") $("#run").disabled = !box.hidden;
  if (kind === "knit") $("#make-knit").disabled = !box.hidden;
  if (kind === "suggestions") $("#suggest").disabled = !box.hidden;
}

async function pollJob(kind, id) {
  for (;;) {
    if (state.jobs[kind] !== id) return null; // superseded
    let job;
    try {
      job = await sapi("GET", `/jobs/${id}`);
    } catch (err) {
      if (state.jobs[kind] !== id) return null; // an edit started newer work meanwhile
      report(err, jobField(kind));
      showJob(kind, { status: "failed", progress: 0, message: "" });
      return null;
    }
    // A job replaced by newer work (an edit, a new upload) answers with its successor: this
    // loop stops quietly and the loop of the successor shows its progress.
    if (state.jobs[kind] !== id || job.superseded) return null;
    showJob(kind, job);
    if (job.status === "done") return job;
    if (job.status === "failed") {
      const e = job.error || {};
      showError(e.field || jobField(kind), e.message || "the job failed");
      return null;
    }
    if (job.status === "cancelled") return null;
    await new Promise((r) => setTimeout(r, 200));
  }
}

async function cancelJob(kind) {
  const id = state.jobs[kind];
  if (!id) return;
  state.jobs[kind] = null;
  try {
    const job = await sapi("DELETE", `/jobs/${id}`);
    showJob(kind, job);
  } catch (err) { report(err); }
}

async function runCandidates() {
  if (!state.inputs) return;
  clearCandidates("Finding candidates…");
  try {
    const job = await startJob("candidates");
    if (job) {
      await loadCandidates();
      measureCandidates(); // readability, ghosting, knitting time: filled in when measured
    }
  } catch (err) {
    report(err, "candidates");
  }
}

// ---------------------------------------------------------------------------------------------
// candidates, picking, live preview

function clearCandidates(message) {
  state.candidates = [];
  state.selected = null;
  $("#cands").innerHTML = `<p class="empty"></p>`;
  $("#cands .empty").textContent = message || "Candidates appear here: each is shown from side A, head-on and from side B.";
  for (const v of ["A", "headon", "B"]) $(`#pv-${v}`).removeAttribute("src");
  $("#preview-label").textContent = "";
  $("#pairs").textContent = "";
  $("#knit-summary").textContent = "";
  $("#suggs").textContent = ""; // suggestions belong to the design they were made for
  clearError("suggestions");
  state.knitReady = false;
  updateKnitButtons();
}

function renderUrl(view, rank, angle) {
  const q = new URLSearchParams({ view, angle: String(angle), r: `${state.candRevision}.${state.editTick || 0}` });
  if (rank) q.set("candidate", String(rank));
  return `/api/sessions/${state.sid}/render?${q}`;
}

function diagnosticUrl(view) {
  const q = new URLSearchParams({ view, angle: String(state.angle), r: `${state.candRevision}.${state.editTick || 0}` });
  return `/api/sessions/${state.sid}/diagnostic.png?${q}`;
}

async function measureCandidates() {
  try {
    const job = await startJob("measures");
    if (job) await loadCandidates();
  } catch (err) {
    report(err, "candidates");
  }
}

function measuresText(m) {
  const f = (x) => (x == null ? "–" : x.toFixed(2));
  const parts = [];
  if (m.views.length) {
    parts.push(`reads ${m.views.map((v, i) => `${v} ${f(m.readability[i])}`).join(" · ")}`);
    parts.push(`contrast ${f(m.worse_contrast)}`);
    if (m.ghosting.some((g) => g != null)) parts.push(`ghosting ${f(m.worst_ghosting)}`);
  }
  if (m.knit_minutes != null) parts.push(`${m.knit_minutes.toFixed(1)} min to knit`);
  else if (m.knit_note) parts.push(m.knit_note);
  return parts.join(" · ");
}

async function loadCandidates() {
  const c = await sapi("GET", `/candidates?order=${encodeURIComponent($("#order").value || "rank")}`);
  state.candidates = c.candidates;
  state.selected = c.selected;
  state.candRevision = c.revision;
  const box = $("#cands");
  box.textContent = "";
  box.dataset.order = c.order;
  if (!c.candidates.length) {
    box.innerHTML = `<p class="empty">No candidates.</p>`;
    return;
  }
  for (const cand of c.candidates) {
    const card = document.createElement("button");
    card.type = "button";
    card.className = "cand";
    card.dataset.rank = cand.rank;
    const head = document.createElement("div");
    head.className = "cand-head";
    head.innerHTML = `<span class="rank">#${cand.rank}</span>${cand.rank === 1 ? '<span class="badge">default</span>' : ""}<span class="cand-label"></span><span class="score"></span>`;
    $(".cand-label", head).textContent = cand.label;
    $(".score", head).textContent = cand.score == null ? "" : `score ${cand.score}`;
    const triple = document.createElement("div");
    triple.className = "triple";
    for (const [view, cap] of [["A", "side A"], ["headon", "head-on"], ["B", "side B"]]) {
      const fig = document.createElement("figure");
      const img = document.createElement("img");
      img.dataset.view = view;
      img.alt = `candidate ${cand.rank}, ${cap}`;
      img.src = renderUrl(view, cand.rank, state.angle);
      const fc = document.createElement("figcaption");
      fc.textContent = cap;
      fig.append(img, fc);
      triple.appendChild(fig);
    }
    card.append(head, triple);
    if (cand.measures) {
      const m = document.createElement("div");
      m.className = "measures";
      m.textContent = measuresText(cand.measures);
      m.title = "readability: how well each side's render matches its picture (1 is best); " +
        "contrast: how much of its light/dark difference survives (1 is all); " +
        "ghosting: how much of the other picture shows through (0 is best)";
      card.appendChild(m);
    }
    const fills = cand.details && cand.details.fills;
    if (Array.isArray(fills) && fills.length) {
      const f = document.createElement("div");
      f.className = "fills";
      for (const row of fills) {
        const chip = document.createElement("span");
        chip.className = "fill";
        chip.title = `${row.input} colour ${row.image_color} is shown as ${row.fill}`;
        chip.innerHTML = `<b></b><span class="sw"></span><span class="arrow">→</span><span class="sw"></span>`;
        chip.children[0].textContent = row.input;
        chip.children[1].style.background = row.image_color;
        chip.children[3].style.background = row.fill_color;
        if (row.kind !== "solid") chip.children[3].classList.add("striped");
        f.appendChild(chip);
      }
      card.appendChild(f);
    } else if (cand.details && cand.details.mismatch_A != null) {
      const f = document.createElement("div");
      f.className = "fills";
      f.textContent = `one-row shift; mismatch A ${(100 * cand.details.mismatch_A).toFixed(1)}%, B ${(100 * cand.details.mismatch_B).toFixed(1)}%`;
      card.appendChild(f);
    }
    card.addEventListener("click", () => pick(cand.rank));
    box.appendChild(card);
  }
  markSelected();
  updatePreview();
  await loadPairs();
  await refreshKnit();
}

function markSelected() {
  for (const card of $$(".cand")) card.classList.toggle("sel", Number(card.dataset.rank) === state.selected);
  const cand = state.candidates.find((c) => c.rank === state.selected);
  $("#preview-label").textContent = cand ? `· candidate #${cand.rank} · ${cand.cols}×${cand.rows} units` : "";
}

async function pick(rank) {
  if (rank === state.selected) return;
  try {
    await sapi("PUT", "/selection", { candidate: rank });
    state.selected = rank;
    state.knitReady = false;
    markSelected();
    updatePreview();
    await loadPairs();
    await refreshKnit();
  } catch (err) { report(err, "candidates"); }
}

// Live preview: at most one request per picture in flight; the latest angle wins.
const live = {};

function updatePreview() {
  if (!state.selected) return;
  for (const view of ["A", "headon", "B"]) loadLive(view);
}

function loadLive(view) {
  const img = $(`#pv-${view}`);
  // "where it fails": the side views as diagnostics (wrong shade red, ghosting blue)
  // (a head-on design is diagnosed in all three views: its point is what each one shows)
  const diagnose = $("#where-fails").checked && (view !== "headon" || state.settings.mode === "headon");
  const want = diagnose ? diagnosticUrl(view) : renderUrl(view, null, state.angle);
  const slot = live[view] || (live[view] = { busy: false, next: null });
  if (slot.busy) { slot.next = want; return; }
  slot.busy = true;
  const done = () => {
    slot.busy = false;
    if (slot.next && slot.next !== img.dataset.want) { const n = slot.next; slot.next = null; img.dataset.want = n; slot.busy = true; img.src = n; }
    else { slot.next = null; img.dataset.loadedAngle = String(state.angle); document.body.dataset.previewAngle = String(state.angle); }
  };
  img.onload = done;
  img.onerror = () => { done(); showError("angle", "the preview could not be rendered"); };
  img.dataset.want = want;
  img.src = want;
}

function onAngle(final) {
  state.angle = Number($("#angle").value);
  $("#angle-out").textContent = `${state.angle}°`;
  clearError("angle");
  updatePreview();
  if (final) {
    // candidate thumbnails follow once the slider rests (keyboard steps fire "change" each time)
    clearTimeout(thumbTimer);
    thumbTimer = setTimeout(() => {
      for (const img of $$(".cand img")) {
        if (img.dataset.view === "headon") continue;
        img.src = renderUrl(img.dataset.view, Number(img.closest(".cand").dataset.rank), state.angle);
      }
    }, 350);
  }
}
let thumbTimer = null;

// ---------------------------------------------------------------------------------------------
// tiles per overlap pair

async function loadPairs() {
  const box = $("#pairs");
  box.textContent = "";
  clearError("tiles");
  if (!state.selected) return;
  let p;
  try { p = await sapi("GET", "/pairs"); } catch (err) { report(err, "tiles"); return; }
  $("#tiles-hint").textContent = p.editable
    ? "Each row is a place where a colour of A lies over a colour of B. Choose another tile from the bank to change how it looks; the preview updates."
    : (p.reason || "This candidate has no tiles to edit.");
  for (const pair of p.pairs || []) box.appendChild(pairRow(pair));
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
      const box = $("#pairs");
      box.textContent = "";
      for (const p of res.pairs) box.appendChild(pairRow(p));
      updatePreview();
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

// ---------------------------------------------------------------------------------------------
// suggested edits of the pictures (double view)

async function runSuggestions() {
  clearError("suggestions");
  if (!state.inputs) { showError("suggestions", "upload both pictures first"); return; }
  $("#suggs").textContent = "";
  try {
    const job = await startJob("suggestions");
    if (job) await loadSuggestions();
  } catch (err) { report(err, "suggestions"); }
}

async function loadSuggestions() {
  const box = $("#suggs");
  let got;
  try { got = await sapi("GET", "/suggestions"); } catch (err) { report(err, "suggestions"); return; }
  box.textContent = "";
  box.dataset.set = got.set || "";
  if (!got.set) return;
  if (!got.suggestions.length) {
    const p = document.createElement("p");
    p.className = "empty";
    p.textContent = got.refused
      ? "Every suggestion was refused."
      : "No edits to suggest: the pictures have no specks, ragged outlines or overlaps too small to see.";
    box.appendChild(p);
    return;
  }
  for (const s of got.suggestions) box.appendChild(suggestionCard(s));
}

function suggestionCard(s) {
  const f = (x) => (x == null ? "–" : x.toFixed(3));
  const card = document.createElement("div");
  card.className = "sugg";
  card.dataset.id = s.id;
  const what = document.createElement("div");
  what.className = "what";
  const changed = s.slots.map((slot) => `${s.units_changed[slot.toUpperCase()]} units of ${slot.toUpperCase()}`);
  what.textContent = `${s.description} (${changed.join(", ")} changed)`;
  const pics = document.createElement("div");
  pics.className = "pairs-ba";
  for (const slot of s.slots) {
    for (const [which, cap] of [["before", "before"], ["after", "after"]]) {
      const fig = document.createElement("figure");
      const img = document.createElement("img");
      img.src = `/api/sessions/${state.sid}/${s.previews[slot][which]}`;
      img.alt = `picture ${slot.toUpperCase()} ${cap} the edit`;
      img.dataset.which = which;
      const fc = document.createElement("figcaption");
      fc.textContent = `${slot.toUpperCase()} ${cap}`;
      fig.append(img, fc);
      pics.appendChild(fig);
      if (which === "before") pics.appendChild(Object.assign(document.createElement("span"), { className: "arrow", textContent: "→" }));
    }
  }
  const effect = document.createElement("div");
  effect.className = "effect " + (s.improves ? "better" : s.readability_after < s.readability_before ? "worse" : "");
  effect.textContent = `worse side reads ${f(s.readability_before)} → ${f(s.readability_after)} · ghosting ${f(s.ghosting_before)} → ${f(s.ghosting_after)}`;
  effect.title = "readability: how well the worse side's render matches its picture (1 is best); ghosting: how much of the other picture shows through (0 is best)";
  const acts = document.createElement("div");
  acts.className = "acts";
  const yes = Object.assign(document.createElement("button"), { type: "button", className: "primary small", textContent: "Accept" });
  yes.dataset.accept = s.id;
  yes.addEventListener("click", () => acceptSuggestion(s.id));
  const no = Object.assign(document.createElement("button"), { type: "button", className: "ghost small", textContent: "Refuse" });
  no.dataset.refuse = s.id;
  no.addEventListener("click", () => refuseSuggestion(s.id));
  acts.append(yes, no);
  card.append(what, pics, effect, acts);
  return card;
}

async function acceptSuggestion(id) {
  clearError("suggestions");
  let answer;
  try {
    answer = await sapi("POST", `/suggestions/${id}/accept`);
  } catch (err) {
    report(err, "suggestions");
    await loadSuggestions(); // a superseded suggestion: show what is current
    return;
  }
  // the edited pictures replace the inputs; the server has started designing with them
  applyState(answer.state);
  clearCandidates("Designing with the edited pictures…");
  await refreshInputs({ autorun: false });
  const job = answer.job;
  state.jobs.candidates = job.id;
  showJob("candidates", job);
  const done = await pollJob("candidates", job.id);
  if (done) {
    await loadCandidates();
    measureCandidates();
  }
}

async function refuseSuggestion(id) {
  clearError("suggestions");
  try {
    await sapi("POST", `/suggestions/${id}/refuse`);
  } catch (err) { report(err, "suggestions"); }
  await loadSuggestions();
}

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
  if (st.time) parts.push(`about ${st.time} to knit`);
  parts.push(`${k.lines} lines`);
  const line = document.createElement("div");
  line.textContent = `Knitout ready · ${parts.join(" · ")}`;
  box.appendChild(line);
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
    const job = await startJob("knit");
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

// ---------------------------------------------------------------------------------------------
// wiring

function wire() {
  wireDrop("a");
  wireDrop("b");
  for (const b of $$("#modes button")) b.addEventListener("click", () => { if (!b.disabled) saveSettings({ mode: b.dataset.mode }); });
  for (const b of $$("#size-mode button")) b.addEventListener("click", () => saveSettings({ size_mode: b.dataset.size }));
  const num = (id, parse) => {
    const el = $(`#${id}`);
    el.addEventListener("input", () => {
      if (el.value === "") return;
      queueSettings({ [id]: parse(el.value) }, 600);
    });
  };
  num("width_units", (v) => Math.round(Number(v)));
  $("#machine").addEventListener("change", () => saveSettings({ machine: $("#machine").value }));
  $("#where-fails").addEventListener("change", () => updatePreview());
  $("#order").addEventListener("change", () => {
    clearError("order");
    if (state.candidates.length) loadCandidates().catch((err) => report(err, "order"));
  });
  num("width_cm", Number);
  num("gauge", Number);
  $("#n_colors").addEventListener("change", () => saveSettings({ n_colors: Number($("#n_colors").value) }));
  $("#candidates").addEventListener("change", () => saveSettings({ candidates: Math.round(Number($("#candidates").value)) }));
  $("#resize").addEventListener("change", () => saveSettings({ resize: $("#resize").checked }));
  $("#preset").addEventListener("change", () => {
    const name = $("#preset").value;
    if (!name) return;
    const yarns = state.info.presets[name];
    const change = { yarns };
    // a single view shows a third colour as a mix of two yarns; other modes need a yarn per colour
    if (state.settings.mode !== "single" && state.settings.n_colors > yarns.length) change.n_colors = yarns.length;
    saveSettings(change);
  });
  $("#add-yarn").addEventListener("click", () => {
    const spare = ["#8a8a8a", "#b3202a", "#1d2b53", "#d9a62e", "#1f4d3a", "#c97b84"];
    const ys = state.settings.yarns.slice();
    const next = spare.find((c) => !ys.includes(c)) || "#777777";
    ys.push(next);
    $("#preset").value = "";
    saveSettings({ yarns: ys });
  });
  $("#run").addEventListener("click", runCandidates);
  $("#suggest").addEventListener("click", runSuggestions);
  for (const b of $$("[data-cancel]")) b.addEventListener("click", () => cancelJob(b.dataset.cancel));
  const angle = $("#angle");
  angle.addEventListener("input", () => onAngle(false));
  angle.addEventListener("change", () => onAngle(true));
  $("#make-knit").addEventListener("click", makeKnit);
  for (const b of $$("[data-dl]")) b.addEventListener("click", () => download(b.dataset.dl, b));
  $("#banner-close").addEventListener("click", () => { $("#banner").hidden = true; });
  // a file dropped outside a drop zone must not replace the page
  window.addEventListener("dragover", (e) => e.preventDefault());
  window.addEventListener("drop", (e) => e.preventDefault());
}

wire();
updateKnitButtons();
startSession()
  .then(() => { document.body.dataset.ready = "1"; })
  .catch((err) => report(err));
