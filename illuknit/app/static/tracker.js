// illuknit design app: the row tracker, for the knitter at the needles (GET / PUT /tracker).
// The current row is highlighted on the chart and in the written rows; Next / Previous move it
// (large buttons, or the keys N / P, and the arrow keys while the tracker has the focus). The row
// is stored with the session, per pattern, so a reload or a restart of the app finds it again.
"use strict";

// asked: the number of the latest refresh (an older one's answer is dropped); loading: the row
// shown may be another pattern's until that answer lands, so Next / Previous wait for it
const tracker = { data: null, busy: false, pending: null, asked: 0, loading: false };

// the chart's cell and the room for row numbers, in CSS pixels (drawn at the screen's resolution)
const TRACK_CELL = 10;
const TRACK_MARGIN = 24;

async function trackerRefresh() {
  const card = $("#tracker-card");
  const asked = ++tracker.asked;
  if (!state.selected) {
    card.hidden = true;
    tracker.data = null;
    trackerLoading(false);
    return;
  }
  trackerLoading(true);
  try {
    const data = await sapi("GET", "/tracker");
    if (asked !== tracker.asked) return; // a newer refresh is on its way
    const old = tracker.data;
    // the same pattern while this tab's own move is on its way: this tab's row stands
    if (old && old.key === data.key && (tracker.busy || tracker.pending !== null)) data.row = old.row;
    const same = old && old.key === data.key && old.row === data.row;
    tracker.data = data;
    if (same) { card.hidden = false; return; }
    card.hidden = false;
    clearError("tracker");
    trackerDrawRows();
    trackerShow(false);
  } catch (err) {
    if (asked !== tracker.asked) return;
    if (err.code === "no_candidates") { card.hidden = true; return; }
    report(err, "tracker");
  } finally {
    if (asked === tracker.asked) trackerLoading(false);
  }
}

// While the picked pattern's rows are on their way, Next / Previous are off (a click would move
// the row of the pattern shown before); then they follow the row.
function trackerLoading(on) {
  tracker.loading = on;
  $("#tracker-card").setAttribute("aria-busy", on ? "true" : "false");
  const d = tracker.data;
  $("#row-prev").disabled = on || !d || d.row <= 1;
  $("#row-next").disabled = on || !d || d.row >= d.rows;
}

function trackerDrawRows() {
  const d = tracker.data;
  const list = $("#tracker-rows");
  list.textContent = "";
  for (const w of d.written) {
    const li = document.createElement("li");
    li.dataset.row = String(w.number);
    li.textContent = `Row ${w.number} (${w.side}): ${w.text}`;
    li.addEventListener("click", () => trackerGo(w.number));
    list.appendChild(li);
  }
}

// The chart as knitted: row 1 (the cast-on edge) at the bottom, stitches as seen on the right
// side, row numbers as on the printed chart (RS rows at the right, WS rows at the left), bold
// lines every 10; the rows done are shaded and the current row is outlined.
function trackerDrawChart() {
  const d = tracker.data;
  const canvas = $("#tracker-chart");
  const c = TRACK_CELL, m = TRACK_MARGIN;
  const dpr = window.devicePixelRatio || 1;
  const w = d.stitches * c, h = d.rows * c;
  canvas.style.width = `${w + 2 * m}px`;
  canvas.style.height = `${h}px`;
  canvas.width = Math.round((w + 2 * m) * dpr);
  canvas.height = Math.round(h * dpr);
  const g = canvas.getContext("2d");
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.fillStyle = "#fff";
  g.fillRect(0, 0, w + 2 * m, h);
  g.translate(m, 0);
  for (let r = 0; r < d.rows; r++) {
    const y = (d.rows - 1 - r) * c;
    const row = d.chart[r], purl = d.purl[r];
    for (let s = 0; s < d.stitches; s++) {
      g.fillStyle = d.yarns[row[s]].hex;
      g.fillRect(s * c, y, c, c);
      if (purl[s]) {
        g.fillStyle = trackerDark(d.yarns[row[s]].hex) ? "#eee" : "#222";
        g.beginPath();
        g.arc(s * c + c / 2, y + c / 2, c * 0.18, 0, 2 * Math.PI);
        g.fill();
      }
    }
  }
  const cur = d.row;
  g.fillStyle = "rgba(255,255,255,0.5)"; // the rows done
  g.fillRect(0, (d.rows - cur + 1) * c, w, (cur - 1) * c);
  for (let k = 0; k <= d.stitches; k++) trackerLine(g, k * c, 0, k * c, h, (d.stitches - k) % 10 === 0);
  for (let k = 0; k <= d.rows; k++) trackerLine(g, 0, k * c, w, k * c, (d.rows - k) % 10 === 0);
  g.font = `${Math.min(10, c)}px sans-serif`;
  g.textBaseline = "middle";
  for (let r = 1; r <= d.rows; r++) {
    const y = (d.rows - r) * c + c / 2;
    g.fillStyle = r === cur ? "#e11d48" : "#555";
    g.font = `${r === cur ? "bold " : ""}${Math.min(10, c)}px sans-serif`;
    if (r % 2) { g.textAlign = "left"; g.fillText(String(r), w + 3, y); }
    else { g.textAlign = "right"; g.fillText(String(r), -3, y); }
  }
  const y = (d.rows - cur) * c;
  g.lineWidth = 3;
  g.strokeStyle = "#e11d48";
  g.strokeRect(-1.5, y - 1.5, w + 3, c + 3);
}

function trackerLine(g, x0, y0, x1, y1, bold) {
  g.strokeStyle = bold ? "rgba(0,0,0,0.7)" : "rgba(0,0,0,0.15)";
  g.lineWidth = bold ? 1.2 : 0.5;
  g.beginPath();
  g.moveTo(x0, y0);
  g.lineTo(x1, y1);
  g.stroke();
}

function trackerDark(hex) {
  const n = parseInt(hex.slice(1), 16);
  const r = (n >> 16) & 255, gg = (n >> 8) & 255, b = n & 255;
  return 0.2126 * r + 0.7152 * gg + 0.0722 * b < 100;
}

// Everything that shows the current row, then scroll it into view (inside its own boxes only).
function trackerShow(scroll = true) {
  const d = tracker.data;
  if (!d) return;
  const w = d.written[d.row - 1];
  $("#row-now").textContent = `Row ${d.row} of ${d.rows}`;
  $("#row-side").textContent = w.side === "RS" ? "right side: read the chart right to left" : "wrong side: read the chart left to right";
  $("#row-text").textContent = w.text;
  $("#row-prev").disabled = tracker.loading || d.row <= 1;
  $("#row-next").disabled = tracker.loading || d.row >= d.rows;
  for (const li of $$("#tracker-rows li")) {
    const on = Number(li.dataset.row) === d.row;
    li.classList.toggle("now", on);
    if (on) li.setAttribute("aria-current", "step"); else li.removeAttribute("aria-current");
  }
  trackerDrawChart();
  const list = $("#tracker-rows"), li = $(`#tracker-rows li[data-row="${d.row}"]`);
  if (li) list.scrollTop = li.offsetTop - list.offsetTop - list.clientHeight / 2 + li.clientHeight / 2;
  const box = $("#tracker-chart-box");
  const y = (d.rows - d.row) * TRACK_CELL;
  if (scroll || box.scrollTop === 0) box.scrollTop = y - box.clientHeight / 2;
  // where the row starts: RS rows are read from the right edge, WS rows from the left
  box.scrollLeft = w.side === "RS" ? box.scrollWidth : 0;
}

async function trackerGo(row) {
  const d = tracker.data;
  if (!d || tracker.loading) return;
  row = Math.min(d.rows, Math.max(1, row));
  if (row === d.row) return;
  d.row = row;
  trackerShow();
  // saves are sent one at a time, the latest row last
  tracker.pending = row;
  if (tracker.busy) return;
  tracker.busy = true;
  try {
    while (tracker.pending !== null) {
      const next = tracker.pending;
      tracker.pending = null;
      await sapi("PUT", "/tracker", { row: next, key: d.key });
    }
    clearError("tracker");
  } catch (err) {
    if (err.code === "stale") trackerRefresh();
    else report(err, "tracker");
  } finally {
    tracker.busy = false;
  }
}

function trackerKey(e) {
  if (!tracker.data || tracker.loading || $("#tracker-card").hidden) return;
  const t = e.target;
  const typing = t && (t.tagName === "TEXTAREA" || t.tagName === "SELECT" || (t.tagName === "INPUT" && !["checkbox", "radio", "button"].includes(t.type)) || t.isContentEditable);
  if (typing || e.ctrlKey || e.metaKey || e.altKey) return;
  const inside = t && t.closest && t.closest("#tracker-card");
  let step = 0;
  if (e.key === "n" || e.key === "N") step = 1;
  else if (e.key === "p" || e.key === "P") step = -1;
  else if (inside && (e.key === "ArrowUp" || e.key === "ArrowRight" || e.key === "PageUp")) step = 1;
  else if (inside && (e.key === "ArrowDown" || e.key === "ArrowLeft" || e.key === "PageDown")) step = -1;
  if (!step) return;
  e.preventDefault();
  e.stopPropagation();
  trackerGo(tracker.data.row + step);
}

function wireTracker() {
  $("#row-next").addEventListener("click", () => tracker.data && trackerGo(tracker.data.row + 1));
  $("#row-prev").addEventListener("click", () => tracker.data && trackerGo(tracker.data.row - 1));
  // before the page's own keys (the arrow keys move between candidates elsewhere)
  document.addEventListener("keydown", trackerKey, true);
  // The picked pattern changes with the pick or a tile edit (each redraws the preview) and with
  // new inputs (a new state): the tracker follows them, and only them (the preview is also
  // redrawn at every step of the angle slider). Wrapping the two functions keeps this file
  // apart from the rest of the page.
  let seen = "";
  const follow = () => {
    const now = `${state.revision}:${state.candRevision}:${state.selected}:${state.editTick || 0}`;
    if (now !== seen) { seen = now; trackerRefresh(); }
  };
  const preview = updatePreview;
  updatePreview = function (...args) { const r = preview(...args); follow(); return r; };
  const apply = applyState;
  applyState = function (s, ...rest) {
    const r = apply(s, ...rest);
    if (s && s.settings) $("#square_units").checked = !!s.settings.square_units;
    // nothing picked on the server (a change of settings cleared the candidates): no tracker to
    // ask for, though this tab's candidates are still on screen until the new ones come
    if (s && s.selected === null) {
      $("#tracker-card").hidden = true;
      tracker.data = null;
      tracker.asked++; // a refresh on its way is for the pattern gone
      trackerLoading(false);
      seen = "";
      return r;
    }
    follow();
    return r;
  };
  $("#square_units").addEventListener("change", () => saveSettings({ square_units: $("#square_units").checked }));
}

wireTracker();
