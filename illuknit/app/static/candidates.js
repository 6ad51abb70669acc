// illuknit design app: candidates, picking one, the live preview and its diagnostic overlay.
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

// ---------------------------------------------------------------------------------------------
// candidates, picking, live preview

function clearCandidates(message) {
  state.candidates = [];
  state.selected = null;
  clearError("measures"); // a cancelled measuring of the old candidates says nothing of new ones
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

// "at 30° from 3 m": where the measures look from (the session's settings)
function viewpointText(at) {
  return `at ${+at.angle.toFixed(1)}° from ${+at.distance.toFixed(2)}\u00a0m`;
}

// The preview's angle and the far view's distance become the measuring viewpoint (an undoable
// setting); the candidates are measured again from there. Only on the button: a slider move
// re-renders the previews, it never re-measures.
async function measureHere() {
  const distance = Number($("#distance").value);
  if (!(distance > 0 && distance <= 1000)) { showError("measures", "Seen from must be a distance in metres, above 0 and at most 1000"); return; }
  clearError("measures");
  try {
    const s = await sapi("PUT", "/settings", { view_angle: state.angle, view_distance: distance });
    applyState(s);
  } catch (err) {
    report(err, "measures");
    return;
  }
  if (state.candidates.length) {
    await loadCandidates(); // the old numbers are gone: the cards say so while measuring
    await measureCandidates();
  }
}

function measuresText(m) {
  const f = (x) => (x == null ? "–" : x.toFixed(2));
  const parts = [];
  if (m.views.length) {
    // a correlation, not a legibility scale (docs/legibility.md); the weaker side first
    const order = m.views.map((v, i) => i).sort((i, j) => (m.readability[i] ?? -2) - (m.readability[j] ?? -2));
    parts.push(`correlation ${order.map((i) => `${m.views[i]} ${f(m.readability[i])}`).join(" · ")}`);
    parts.push(`contrast ${f(m.worse_contrast)}`);
    if (m.ghosting.some((g) => g != null)) parts.push(`ghosting ${f(m.worst_ghosting)} (shows ${f(m.worst_visible_ghosting)})`);
  }
  if (m.knit_minutes != null) parts.push(`${m.knit_minutes.toFixed(1)} min to knit`);
  else if (m.knit_note) parts.push(m.knit_note);
  // a correlation or gain below 0 is a picture seen in negative, not a score below nothing
  const negative = m.views.length && [...m.readability, m.worse_contrast].some((x) => x != null && x < 0);
  if (negative) parts.push(NEGATIVE_NOTE);
  return parts.join(" · ");
}

// Made for hands, or ordered by hand time: the hand knitter's figures (rows knittable by hand,
// longest float, the estimated hours).
function handFigures(cand, madeFor, order) {
  const h = (cand.measures && cand.measures.hand) || (cand.details && cand.details.hand);
  if ((madeFor !== "hands" && order !== "hand_time") || !h) return null;
  const d = document.createElement("div");
  d.className = "hand";
  const hours = h.hours == null ? "" : ` · about ${h.hours.toFixed(1)} h by hand`;
  d.textContent = `by hand: ${h.knittable_rows} of ${h.rows} rows knittable · longest float ${h.longest_float} sts${hours}`;
  d.title = "rows a hand knitter can work: stranded with 2 yarns and floats of at most 7 stitches, or intarsia with at most 6 blocks; " +
    "hours: estimated from the stitch counts and colour work at rules-of-thumb rates (the pattern's cover says which), not measured";
  if (h.knittable_rows < h.rows) d.classList.add("warn");
  return d;
}

// On the search's first design, the order the search ranked by and why ("ranked by the reader
// (legibility): both pictures are words (MILK, HAZE)"); null on the others or when not known.
function orderLine(cand) {
  const d = cand.details || {};
  return cand.rank === 1 && d.order ? d.order : null;
}

function orderText(cand) {
  const line = orderLine(cand);
  if (!line) return null;
  const div = document.createElement("div");
  div.className = "order muted";
  div.textContent = line;
  return div;
}

// On the search's first design, the candidates a designer may prefer to it and why (much less
// of the other picture showing, or much less knitting by hand, reading nearly as well).
function alternativesText(cand) {
  const found = cand.rank === 1 && cand.details && cand.details.alternatives;
  if (!Array.isArray(found) || !found.length) return null;
  const div = document.createElement("div");
  div.className = "alternatives";
  for (const a of found) {
    const p = document.createElement("p");
    p.textContent = `${a.text}: pick #${a.rank} to knit it instead`;
    div.appendChild(p);
  }
  return div;
}

// One side's verdict on a card: the reader's sentence, or a picture's estimate said as one.
function sideText(side) {
  if (side.judge !== "shapes") return `${side.reads ? "✓" : "✗"} ${side.sentence}`;
  const pct = side.shape_agreement == null ? "–" : `${Math.round(100 * side.shape_agreement)} %`;
  return `≈ side ${side.view} (a picture) ${side.reads ? "likely reads" : "may not read"}: shapes agree on ${pct}, an estimate`;
}

// Whether each side reads, by the reader (tesseract), the weaker side first as the server
// lists them; a picture side is judged by its shapes, an estimate, and says so.
function readsLine(v, at) {
  if (!v) return null;
  const d = document.createElement("div");
  d.className = "reads";
  if (!v.read) {
    d.classList.add("unread");
    d.textContent = v.sentence;
    d.title = "whether each side reads is asked of the tesseract OCR program (apt-get install tesseract-ocr); without it the cards show only the correlation, which is not a legibility scale";
    return d;
  }
  for (const side of v.sides) {
    const s = document.createElement("span");
    s.className = `side ${side.reads ? "ok" : "no"}${side.judge === "shapes" ? " estimate" : ""}`;
    s.textContent = sideText(side);
    s.title = side.sentence;
    d.appendChild(s);
  }
  // read from another viewpoint than the measures (the measures job reads them again)
  if (at && (v.angle !== at.angle || v.distance_m !== at.distance)) {
    const n = document.createElement("span");
    n.className = "muted";
    n.textContent = `read ${viewpointText({ angle: v.angle, distance: v.distance_m })}`;
    d.appendChild(n);
  }
  d.title = `read by ${v.reader} ${viewpointText({ angle: v.angle, distance: v.distance_m })}, the weaker side first: ${v.sentence}`;
  return d;
}

const NEGATIVE_NOTE = "below 0: that side shows its picture in negative (light and dark swapped)";

async function loadCandidates() {
  const c = await sapi("GET", `/candidates?order=${encodeURIComponent($("#order").value || "rank")}`);
  state.candidates = c.candidates;
  state.selected = c.selected;
  state.candRevision = c.revision;
  state.measuredAt = c.measured_at;
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
    // the search's own cost has no meaning to a designer: the card says how the design reads
    const ms = cand.measures;
    if (ms && ms.worse_readability != null) {
      $(".score", head).textContent = `corr ${ms.worse_readability.toFixed(2)}`;
      $(".score", head).title = "corr: the correlation (-1 to 1) of the worse side's light/dark pattern, as seen at an angle, " +
        "with its picture's (1: all of it is there). It is not a legibility scale: words at 0.92-0.95 can be " +
        "unreadable; `illuknit double` and `illuknit legible` ask a reader";
    }
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
      m.textContent = `${measuresText(cand.measures)} · ${viewpointText(c.measured_at)}`;
      m.title = "correlation: how much of each side's picture's light/dark pattern its render shows (1 is all; " +
        "not a legibility scale), the weaker side first; " +
        "contrast: how much of its light/dark difference survives (1 is all); " +
        "ghosting: how much of the other picture shows through (0 is best)";
      card.appendChild(m);
    }
    const reads = readsLine(cand.details && cand.details.legibility, c.measured_at);
    if (reads) card.appendChild(reads);
    const hand = handFigures(cand, c.made_for, c.order);
    if (hand) card.appendChild(hand);
    // on the search's first design: the order it ranked by and why (word pairs: the reader)
    const said = orderText(cand);
    if (said) card.appendChild(said);
    const instead = alternativesText(cand);
    if (instead) card.appendChild(instead);
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
  updateFar();
}

// The far view: the render as an eye resolves it from the chosen distance, above what each view
// should show (the quantised picture; nothing where a view should show a plain field or stripes).
function updateFar() {
  const d = Number($("#distance").value);
  const ok = d > 0 && d <= 1000;
  const mode = state.settings && state.settings.mode;
  const pics = (state.inputs && state.inputs.images) || {};
  const want = mode === "single" ? { A: pics.a, B: pics.a }
    : mode === "headon" ? { headon: pics.a, A: pics.b, B: pics.b }
    : { A: pics.a, B: pics.b };
  for (const view of ["A", "headon", "B"]) {
    const far = $(`#far-${view}`);
    if (ok && state.selected) {
      const url = new URL(renderUrl(view, null, state.angle), location.href);
      url.searchParams.set("distance", String(d));
      if (far.getAttribute("src") !== url.pathname + url.search) far.src = url.pathname + url.search;
    }
    $("figcaption", far.parentElement).textContent = `${view === "headon" ? "Head-on" : `Side ${view}`} from ${d} m`;
    const tg = $(`#tg-${view}`);
    tg.hidden = !want[view];
    if (want[view]) tg.src = want[view]; else tg.removeAttribute("src");
    $("figcaption", tg.parentElement).textContent = want[view]
      ? `${view === "headon" ? "Head-on" : `Side ${view}`} should show`
      : `${view === "headon" ? "Head-on" : `Side ${view}`}: ${view === "headon" ? HEADON_SHOWS[mode] || HEADON_SHOWS.double : "a plain field"}`;
  }
}

// What head-on shows when no picture is asked of it, as the library measures it
// (illuknit.outputs.captions): a single view's rows alternate, so head-on is stripes
// (correlation 0 with either side); a double view shows both pictures mixed (0.5-0.9).
const HEADON_SHOWS = {
  single: "stripes (no picture)",
  double: "no picture of its own: both pictures show, mixed",
};

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
