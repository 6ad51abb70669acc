// illuknit design app. Plain JavaScript, no build step, no network beyond this server.
// This file: state, the API helpers, errors next to their controls, the session, settings,
// uploads, quantised inputs and background jobs. The rest of the page is in candidates.js,
// tiles.js, suggestions.js and knit.js; main.js wires the controls and starts (index.html loads
// them in that order: classic scripts share one global scope).
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

const FIELD_ALIASES = { slot: "image_a", session: null, job: null, candidate: "candidates", view: "angle", view_angle: "measures", view_distance: "measures" };

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
  // who knits it: the menu is the declared option's (words, title and help from the server)
  const madeFor = state.info.controls.made_for;
  $("#made_for").title = `${madeFor.title}: ${madeFor.description}`;
  for (const word of madeFor.choices) {
    const o = document.createElement("option");
    o.value = word;
    o.textContent = word === "hands" ? "hand knitting" : word;
    $("#made_for").appendChild(o);
  }
  for (const m of state.info.machines) {
    const o = document.createElement("option");
    o.value = m.name;
    // a generic bed's label says its needles; a real machine's gets them after its name
    o.textContent = m.label.includes(`${m.needles}-needle`) ? m.label : `${m.label} · ${m.needles} needles`;
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
  $("#storage-note").textContent = state.info.storage.text;
  loadSaved();
  for (const [kind, job] of Object.entries(s.jobs || {})) {
    if (job.status === "interrupted") showInterrupted(kind, job);
  }
  if (!caps[s.settings.mode]) await saveSettings({ mode: "single" });
  await refreshInputs({ autorun: false });
  if (s.candidates) await loadCandidates();
  // a reloaded tab shows the suggested edits it had (and Undo / Redo, from the state)
  if (s.settings.mode === "double") await loadSuggestions();
  if (s.settings.mode === "double") await loadWidths(); // and how wide it must be, if found
}

// ---------------------------------------------------------------------------------------------
// saved designs: every session with a picture is saved; any tab can reopen one

const MODE_WORDS = { single: "single view", double: "double view", headon: "head-on" };

function ago(seconds) {
  const s = Math.max(0, Date.now() / 1000 - seconds);
  if (s < 90) return "just now";
  if (s < 5400) return `${Math.round(s / 60)} min ago`;
  if (s < 129600) return `${Math.round(s / 3600)} h ago`;
  return `${Math.round(s / 86400)} days ago`;
}

async function loadSaved() {
  let found;
  try {
    found = (await api("GET", "/api/sessions")).sessions;
  } catch (err) { return; } // the list is a convenience: the design itself is unaffected
  const list = $("#saved-list");
  list.textContent = "";
  for (const d of found) {
    const li = document.createElement("li");
    const b = document.createElement("button");
    b.type = "button";
    b.dataset.sid = d.id;
    const names = Object.entries(d.pictures).map(([slot, name]) => `${slot.toUpperCase()}: ${name}`).join(" · ");
    b.textContent = `${names} — ${MODE_WORDS[d.mode] || d.mode}`;
    const when = document.createElement("span");
    when.className = "when";
    const here = d.id === state.sid;
    when.textContent = here ? `open in this tab · ${ago(d.last_seen)}` : ago(d.last_seen);
    b.appendChild(when);
    if (here) b.setAttribute("aria-current", "true");
    else b.addEventListener("click", () => { sessionStorage.setItem("illuknit.sid", d.id); location.reload(); });
    li.appendChild(b);
    list.appendChild(li);
  }
  $("#saved-empty").hidden = found.length > 0;
  $("#saved-box summary").textContent = `Saved designs (${found.length})`;
}

function applyState(s) {
  // answers can arrive out of order (two pictures dropped at once): an older state of this
  // session never replaces a newer one (it would blank the newer picture's thumbnail)
  if (s.id === state.sid && s.revision < state.revision) return;
  state.settings = s.settings;
  state.revision = s.revision;
  state.knitReady = s.knit_ready;
  state.width_units = s.width_units; // the piece's width in units now (sized from the picture too)
  const st = s.settings;
  for (const b of $$("#modes button")) b.setAttribute("aria-checked", String(b.dataset.mode === st.mode));
  for (const b of $$("#size-mode button")) b.setAttribute("aria-checked", String(b.dataset.size === st.size_mode));
  $("#row-units").hidden = st.size_mode === "physical";
  $("#row-physical").hidden = st.size_mode !== "physical";
  $("#size-picture-note").hidden = st.size_mode !== "picture";
  // sized from the picture: the width it gives (typing one sizes by units from then on)
  setValue("#width_units", st.size_mode === "picture" ? (s.width_units ?? "") : st.width_units);
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
  $("#split_bumps").checked = st.split_bumps;
  setValue("#made_for", st.made_for);
  $("#made_for").hidden = $("#made-for-label").hidden = st.mode === "single"; // no tiles to choose
  $("#measured-at").textContent = `Measured ${viewpointText({ angle: st.view_angle, distance: st.view_distance })}`;
  $("#split-row").hidden = st.mode === "single"; // one picture: nothing to split
  $("#resize").checked = st.resize;
  if (st.resize) $("#resize-row").hidden = false;
  if (st.mode === "single") $("#resize-row").hidden = true;
  renderYarns(st.yarns);
  const single = st.mode === "single";
  $("#suggest-card").hidden = st.mode !== "double"; // edits of two pictures that share a design
  $("#widths-card").hidden = $("#widths-link").hidden = st.mode !== "double"; // two pictures, read
  if (st.mode === "double") refreshWidthsSoon(); // does the answer still hold for these?
  showHistory(s.history);
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
    // a change the server could not save (a full disk) is not kept: show what the session has
    if (err.status >= 500) {
      const s = await sapi("GET", "").catch(() => null);
      if (s) applyState(s);
    }
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

// Uploads run one at a time, in the order the pictures were given: each answer is the state
// after its own upload, and the next starts from it.
let uploads = Promise.resolve();

function upload(slot, file) {
  $(`#meta-${slot}`).textContent = `waiting to upload ${file.name}…`;
  uploads = uploads.then(() => uploadNow(slot, file)).catch((err) => report(err, `image_${slot}`));
  return uploads;
}

async function uploadNow(slot, file) {
  clearError(`image_${slot}`);
  const limit = state.info.limits.max_upload_bytes;
  if (file.size > limit) {
    showError(`image_${slot}`, `${file.name}: ${state.info.limits.too_large}`);
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
      // colours set through the style object, not a style attribute: the page's
      // Content-Security-Policy allows no inline style
      li.innerHTML = `<span class="sw"></span><span class="arrow">→</span>` +
        `<span class="sw"></span><span></span><span class="pct">${(100 * e.share).toFixed(0)}%</span>`;
      li.children[0].style.background = e.image_color;
      li.children[2].style.background = e.yarn_color;
      li.children[3].textContent = e.yarn;
      li.title = `picture colour ${e.image_color} becomes yarn ${e.yarn} (${e.yarn_color})`;
      ul.appendChild(li);
    }
    fig.append(img, cap, ul);
    quant.appendChild(fig);
  }
  $("#notes").textContent = inp.notes.join(" ");
  const w = inp.cols, h = inp.rows;
  const size = inp.finished_size;
  $("#grid-info").textContent = `${w} × ${h} units = ${2 * w} stitches × ${2 * h} rows. 1 unit = 2 stitches × 2 rows.` +
    (size ? ` Finished size${size.by_hand ? " by hand" : ""} about ${size.text} at ${size.gauge}` +
      `${size.estimate ? " (an estimate until your swatch says otherwise)" : ""}.` : "");
  if (autorun) runCandidates();
}

// ---------------------------------------------------------------------------------------------
// jobs with progress and cancel

// the page control a job's problems are shown next to
const jobField = (kind) => (["knit", "suggestions", "measures", "widths"].includes(kind) ? kind : "candidates");

async function startJob(kind, options = {}) {
  clearError(jobField(kind));
  const job = await sapi("POST", "/jobs", { kind, ...options });
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
  // where the work can be counted, an estimate of what is left (from the pace so far)
  let left = "";
  if (!box.hidden && job.progress >= 0.15 && job.progress < 1 && job.elapsed > 2 && !/s so far/.test(job.message)) {
    const secs = Math.round((job.elapsed * (1 - job.progress)) / job.progress);
    left = ` · about ${secs < 60 ? `${Math.max(1, secs)} s` : `${Math.round(secs / 60)} min`} left`;
  }
  $(".job-msg", box).textContent = job.message + left;
  if (kind === "candidates") $("#run").disabled = !box.hidden;
  if (kind === "knit") $("#make-knit").disabled = !box.hidden;
  if (kind === "suggestions") $("#suggest").disabled = !box.hidden;
  if (kind === "widths") $("#find-widths").disabled = !box.hidden;
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
    if (job.status === "interrupted") { showInterrupted(kind, job); return null; }
    await new Promise((r) => setTimeout(r, 200));
  }
}

// A job that was running when the server stopped comes back "interrupted" (its session was read
// back from disk): say so next to its control, with one click to run it again.
const RERUN = {
  candidates: () => runCandidates(),
  measures: () => measureCandidates(),
  suggestions: () => runSuggestions(),
  widths: () => runWidths(),
  knit: () => makeKnit(),
};

function showInterrupted(kind, job) {
  showJob(kind, job);
  const again = document.createElement("button");
  again.type = "button";
  again.className = "rerun";
  again.dataset.rerun = kind;
  again.textContent = "Run again";
  again.addEventListener("click", () => { clearError(jobField(kind)); RERUN[kind](); });
  showError(jobField(kind), `${job.message} `, again);
}

async function cancelJob(kind) {
  const id = state.jobs[kind];
  if (!id) return;
  state.jobs[kind] = null;
  const box = $(`#job-${kind}`);
  $(".job-msg", box).textContent = "cancelling…";
  try {
    const job = await sapi("DELETE", `/jobs/${id}`);
    showJob(kind, job);
    if (job.status === "cancelled") saidCancelled(kind);
  } catch (err) { report(err); }
}

// what the page says once work is cancelled: it is no longer searching, and how to start again
function saidCancelled(kind) {
  if (kind === "candidates") {
    clearCandidates("Search cancelled: press Find candidates (or change an input) to search again.");
  } else if (kind === "suggestions") {
    $("#suggs").textContent = "";
    showError("suggestions", "Cancelled: press Suggest edits to try again.");
  } else if (kind === "knit") {
    $("#knit-summary").textContent = "Cancelled: press Make knitout to make it again.";
  } else if (kind === "widths") {
    showError("widths", "Cancelled: press Find the smallest width that reads to try again.");
  } else if (kind === "measures") {
    const again = document.createElement("button");
    again.type = "button";
    again.className = "rerun";
    again.dataset.rerun = kind;
    again.textContent = "Measure them";
    again.addEventListener("click", () => { clearError("measures"); measureCandidates(); });
    showError("measures", "Measuring cancelled: the candidates are not measured. ", again);
  }
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
