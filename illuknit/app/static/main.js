// illuknit design app: wiring the controls, then starting the session.
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

// ---------------------------------------------------------------------------------------------
// wiring

function wire() {
  wireDrop("a");
  wireDrop("b");
  $("#saved-box").addEventListener("toggle", () => { if ($("#saved-box").open) loadSaved(); });
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
  $("#distance").addEventListener("change", () => updateFar());
  $("#measure-here").addEventListener("click", () => measureHere());
  $("#order").addEventListener("change", () => {
    clearError("order");
    if (state.candidates.length) loadCandidates().catch((err) => report(err, "order"));
  });
  num("width_cm", Number);
  num("gauge", Number);
  $("#n_colors").addEventListener("change", () => saveSettings({ n_colors: Number($("#n_colors").value) }));
  $("#candidates").addEventListener("change", () => saveSettings({ candidates: Math.round(Number($("#candidates").value)) }));
  $("#split_bumps").addEventListener("change", () => saveSettings({ split_bumps: $("#split_bumps").checked }));
  $("#made_for").addEventListener("change", () => saveSettings({ made_for: $("#made_for").value }));
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
  $("#find-widths").addEventListener("click", runWidths);
  $("#undo-edit").addEventListener("click", () => stepHistory("undo"));
  $("#redo-edit").addEventListener("click", () => stepHistory("redo"));
  for (const b of $$("[data-cancel]")) b.addEventListener("click", () => cancelJob(b.dataset.cancel));
  const angle = $("#angle");
  angle.addEventListener("input", () => onAngle(false));
  angle.addEventListener("change", () => onAngle(true));
  $("#make-knit").addEventListener("click", makeKnit);
  for (const b of $$("[data-dl]")) b.addEventListener("click", () => download(b.dataset.dl, b));
  $("#banner-close").addEventListener("click", () => { $("#banner").hidden = true; });
  document.addEventListener("keydown", onKey);
  // a file dropped outside a drop zone must not replace the page
  window.addEventListener("dragover", (e) => e.preventDefault());
  window.addEventListener("drop", (e) => e.preventDefault());
}

// Keyboard: Ctrl+Z / Ctrl+Shift+Z (or Ctrl+Y) undo and redo any change (outside a text field,
// where they edit the text); arrow keys move between candidates, Enter picks the focused one.
function onKey(e) {
  const t = e.target;
  const typing = t && (t.tagName === "TEXTAREA" || (t.tagName === "INPUT" && !["checkbox", "radio", "range", "color", "button", "file"].includes(t.type)) || t.isContentEditable);
  const mod = e.ctrlKey || e.metaKey;
  if (mod && !e.altKey && !typing) {
    const k = e.key.toLowerCase();
    if (k === "z" || k === "y") {
      const which = k === "y" || e.shiftKey ? "redo" : "undo";
      if (!$(`#${which}-edit`).disabled) stepHistory(which);
      e.preventDefault();
      return;
    }
  }
  if (mod || e.altKey || typing || (t && (t.tagName === "SELECT" || t.type === "range"))) return;
  const cards = $$(".cand");
  if (!cards.length || !["ArrowLeft", "ArrowRight", "ArrowUp", "ArrowDown"].includes(e.key)) return;
  const inCands = t && t.closest && t.closest("#cands");
  if (!inCands && t !== document.body) return;
  const at = inCands ? cards.indexOf(t.closest(".cand")) : cards.findIndex((c) => c.classList.contains("sel"));
  const step = e.key === "ArrowLeft" || e.key === "ArrowUp" ? -1 : 1;
  const next = cards[Math.min(cards.length - 1, Math.max(0, (at < 0 ? 0 : at) + (inCands ? step : 0)))];
  next.focus();
  e.preventDefault();
}

wire();
updateKnitButtons();
startSession()
  .then(() => { document.body.dataset.ready = "1"; })
  .catch((err) => report(err));
