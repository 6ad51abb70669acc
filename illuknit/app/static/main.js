// illuknit design app: wiring the controls, then starting the session.
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

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
  $("#undo-edit").addEventListener("click", () => stepHistory("undo"));
  $("#redo-edit").addEventListener("click", () => stepHistory("redo"));
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
