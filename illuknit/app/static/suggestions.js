// illuknit design app: suggested edits of the pictures (double view), accepted or refused.
// (plain scripts sharing one global scope, loaded in order by index.html; no build step)
"use strict";

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
  // the server lists the most helpful first; edits that make the design worse are folded away
  const harmful = got.suggestions.filter((s) => s.verdict === "worse");
  for (const s of got.suggestions) if (s.verdict !== "worse") box.appendChild(suggestionCard(s));
  if (harmful.length) {
    const fold = document.createElement("details");
    fold.className = "harmful";
    const sum = document.createElement("summary");
    sum.textContent = `${harmful.length} edit${harmful.length > 1 ? "s" : ""} that would make the design worse`;
    const inner = document.createElement("div");
    inner.className = "suggs";
    for (const s of harmful) inner.appendChild(suggestionCard(s));
    fold.append(sum, inner);
    box.appendChild(fold);
  }
}

const VERDICT_WORDS = {
  better: "helps",
  same: "changes nothing measurable",
  mixed: "helps one measure, harms the other",
  worse: "makes it worse",
};

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
  // coloured by what the edit does: green only when it helps and harms nothing
  const effect = document.createElement("div");
  effect.className = `effect ${s.verdict}`;
  card.classList.add(s.verdict);
  const words = document.createElement("b");
  words.textContent = `${VERDICT_WORDS[s.verdict] || s.verdict}: `;
  const detail = document.createElement("span");
  const negative = [s.readability_before, s.readability_after].some((x) => x != null && x < 0);
  detail.textContent = `${s.effect} (worse side's correlation ${f(s.readability_before)} → ${f(s.readability_after)}, ghosting ${f(s.ghosting_before)} → ${f(s.ghosting_after)})` + (negative ? ` · ${NEGATIVE_NOTE}` : "");
  effect.append(words, detail);
  effect.title = "correlation: how much of the worse side's picture's light/dark pattern its render shows (1 is all; not a legibility scale: the cards say whether a reader reads it); ghosting: how much of the other picture shows through (0 is best)";
  const acts = document.createElement("div");
  acts.className = "acts";
  const yes = Object.assign(document.createElement("button"), {
    type: "button", className: s.verdict === "better" ? "primary small" : "ghost small", textContent: "Accept",
  });
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
// undo and redo of every change (uploads, settings, tile edits, accepted suggestions): the server
// keeps the design before each change, whole

function showHistory(h) {
  const undo = $("#undo-edit");
  const redo = $("#redo-edit");
  const steps = h || { undo: [], redo: [] };
  state.history = steps;
  undo.disabled = !steps.undo.length;
  undo.title = steps.undo.length ? `Undo the ${steps.undo[0]} (Ctrl+Z)` : "Nothing to undo yet (Ctrl+Z)";
  redo.disabled = !steps.redo.length;
  redo.title = steps.redo.length ? `Redo the ${steps.redo[0]} (Ctrl+Shift+Z)` : "Nothing to redo (Ctrl+Shift+Z)";
  $("#history-list summary").textContent = `History (${steps.undo.length})`;
  $("#history-empty").hidden = steps.undo.length + steps.redo.length > 0;
  const fill = (list, labels, verb) => {
    list.textContent = "";
    labels.forEach((label, k) => {
      const li = document.createElement("li");
      li.textContent = `${k === 0 ? `${verb}: ` : ""}${label.replaceAll(" -> ", " → ")}`;
      list.appendChild(li);
    });
  };
  fill($("#undo-list"), steps.undo, "Undo takes back");
  fill($("#redo-list"), steps.redo, "Redo brings back");
}

async function refreshHistory() {
  try { showHistory((await sapi("GET", "/history"))); } catch (err) { /* the next state shows it */ }
}

async function stepHistory(which) {
  clearError("suggestions");
  let answer;
  try {
    answer = await sapi("POST", `/history/${which}`);
  } catch (err) {
    report(err, "suggestions");
    const s = await sapi("GET", "").catch(() => null);
    if (s) applyState(s);
    return;
  }
  // the pictures, settings and design of that step are the session's again
  applyState(answer.state);
  await refreshInputs({ autorun: false });
  if (answer.job) {
    // that step had no candidates yet: the server is finding them
    clearCandidates("Designing again…");
    state.jobs.candidates = answer.job.id;
    showJob("candidates", answer.job);
    if (!(await pollJob("candidates", answer.job.id))) return;
  }
  await loadCandidates();
  await loadSuggestions();
  if (state.candidates.some((c) => !c.measures)) measureCandidates();
}
