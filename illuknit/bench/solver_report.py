"""Summaries of the solver rows: solved counts, PAR-2, the MaxSAT Evaluation anytime score, the
virtual best solver, and the cactus and cost-over-time plots.

* **solved** -- runs with status ``optimal`` whose claim survived verification (no ``flag``).
* **PAR-2** -- penalised average runtime: the mean over a solver's runs of its time to prove
  optimality, an unsolved run counted as twice its time limit.
* **anytime score at t** -- the MaxSAT Evaluation's incomplete-track score: per run
  ``(best known cost + 1) / (cost at t + 1)``, 0 without a verified solution by t (or with a
  flag), averaged over the solver's runs. The best known cost of an (instance, model) is the
  least verified cost of any run, or the DP optimum. **Only verified answers score**: the cost
  at t is the run's verified cost once an assignment backs it (``time_best``: the first time
  the run reported that very cost, its final assignment verifying it), never a cost it only
  claimed (an ``o`` line, a backend's progress report) -- those are drawn in the plots as
  claims and never scored. Scores are taken at the Evaluation's 60 and 300 s when every run
  had that long; when the runs' limit is shorter, at that limit instead, and the column says
  so (``score@10s (limit)``).
* **virtual best solver** -- per (instance, model) the fastest unflagged proof of any solver.
* **repetitions** -- with ``--repeat N`` each figure above is taken per repetition and the
  summary gives its median with the spread (min-max) over the repetitions.

Rows with status ``n/a`` (a solver that does not apply to the model: the DP on a plain WCNF)
are listed but stay out of every score.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = [
    "ANYTIME_TIMES",
    "cost_at",
    "environment_markdown",
    "score_times",
    "solver_summary",
    "summary_markdown",
    "write_plots",
]

#: Seconds at which the anytime score is taken, as in the MaxSAT Evaluation (a time above a
#: run's limit gives way to a column at the limit, see :func:`score_times`).
ANYTIME_TIMES = (60.0, 300.0)


def _label(r: dict[str, Any]) -> str:
    ws = r.get("warm_start") or "none"
    return r["solver"] if ws == "none" else f"{r['solver']} (+{ws})"


def _trace_key(r: dict[str, Any]) -> tuple[Any, ...]:
    return (r["instance"], r["model"], r["solver"], r.get("warm_start") or "none", r.get("run", 0))


def _median(xs: Sequence[float]) -> float:
    ys = sorted(xs)
    n = len(ys)
    return ys[n // 2] if n % 2 else 0.5 * (ys[n // 2 - 1] + ys[n // 2])


#: Certificates that make a claimed optimum count: the DP's exact optimum, or an independent
#: exact engine per component (:mod:`illuknit.bench.certify`).
CONFIRMED = ("reference (dp)", "certified")


def _solved(r: dict[str, Any]) -> bool:
    """A proven optimum that survived verification and was certified (never a bare claim)."""
    return (
        r.get("status") == "optimal"
        and not r.get("flag")
        and r.get("time_prove") is not None
        and r.get("certificate") in CONFIRMED
    )


def cost_at(r: dict[str, Any], trace: Sequence[tuple[float, Any, Any]], t: float) -> float | None:
    """The run's verified cost at ``t`` seconds (see the module docstring), or None. ``trace``
    is not consulted: its costs are claims until an assignment backs them."""
    del trace
    if r.get("flag") or r.get("verified_cost") is None or r.get("time_best") is None:
        return None
    return float(r["verified_cost"]) if float(r["time_best"]) <= t else None


def score_times(rows: Sequence[dict[str, Any]]) -> list[tuple[str, float]]:
    """(column name, seconds) of the anytime scores of ``rows``: each of :data:`ANYTIME_TIMES`
    every run had (its limit at least that long), then each shorter limit of the runs,
    labelled as such."""
    limits = sorted({float(r["time_limit"]) for r in rows if r.get("time_limit") is not None})
    if not limits:
        return [(f"score@{t:g}s", t) for t in ANYTIME_TIMES]
    out = [(f"score@{t:g}s", t) for t in ANYTIME_TIMES if t <= limits[0]]
    out += [(f"score@{lim:g}s (limit)", lim) for lim in limits if lim < ANYTIME_TIMES[-1]]
    return out


def _best_known(rows: Sequence[dict[str, Any]]) -> dict[tuple[str, str], float]:
    best: dict[tuple[str, str], float] = {}
    for r in rows:
        key = (r["instance"], r["model"])
        for v in (r.get("reference_optimum"), None if r.get("flag") else r.get("verified_cost")):
            if v is not None:
                best[key] = min(best.get(key, float(v)), float(v))
    return best


def solver_summary(
    rows: Sequence[dict[str, Any]], traces: dict[tuple[Any, ...], list[Any]]
) -> list[dict[str, Any]]:
    """One summary row per solver label plus the virtual best solver (see the module docstring).

    ``traces`` maps (instance, model, solver, warm_start, run) to that run's trace.
    """
    scored = [r for r in rows if r.get("status") != "n/a"]
    best = _best_known(scored)
    times = score_times(scored)
    groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        groups[_label(r)].append(r)
    out = []
    for label, all_rs in groups.items():
        rs = [r for r in all_rs if r.get("status") != "n/a"]
        reps: dict[int, list[dict[str, Any]]] = defaultdict(list)
        for r in rs:
            reps[int(r.get("run") or 0)].append(r)
        entry: dict[str, Any] = {"solver": label, "runs": len(rs)}
        per_rep = [_figures(rep, traces, best, times) for rep in reps.values()] or [
            _figures([], {}, {}, times)
        ]
        for k in per_rep[0]:
            vals = [f[k] for f in per_rep]
            entry[k] = round(_median(vals), 4) if len(vals) > 1 else vals[0]
        entry["flagged"] = sum(bool(r.get("flag")) for r in rs)
        entry["errors"] = sum(r.get("status") == "error" for r in rs)
        entry["memouts"] = sum(r.get("status") == "memout" for r in rs)
        entry["n/a"] = len(all_rs) - len(rs)
        if len(per_rep) > 1:
            entry["repeats"] = len(per_rep)
            par2 = [f["par2"] for f in per_rep]
            entry["par2_spread"] = f"{min(par2):g}-{max(par2):g}"
        out.append(entry)
    out.sort(key=lambda e: (-e["solved"], e["par2"]))
    out.append(_virtual_best(scored))
    return out


def _figures(
    rs: Sequence[dict[str, Any]],
    traces: dict[tuple[Any, ...], list[Any]],
    best: dict[tuple[str, str], float],
    times: Sequence[tuple[str, float]] = (),
) -> dict[str, Any]:
    """solved, certified, with_solution, PAR-2 and the anytime scores (at ``times``, see
    :func:`score_times`) of one repetition's runs."""
    par2 = [float(r["time_prove"]) if _solved(r) else 2 * float(r["time_limit"]) for r in rs]
    entry: dict[str, Any] = {
        "solved": sum(_solved(r) for r in rs),
        "certified": sum(r.get("certificate") in CONFIRMED for r in rs),
        "with_solution": sum(r.get("verified_cost") is not None for r in rs),
        "par2": round(sum(par2) / len(par2), 3) if par2 else 0.0,
    }
    for name, t in times:
        scores = []
        for r in rs:
            c = cost_at(r, traces.get(_trace_key(r), []), t)
            b = best.get((r["instance"], r["model"]))
            scores.append(0.0 if c is None or b is None else (b + 1) / (c + 1))
        entry[name] = round(sum(scores) / len(scores), 4) if scores else 0.0
    return entry


def _virtual_best(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    per: dict[tuple[str, str, int], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        per[(r["instance"], r["model"], int(r.get("run") or 0))].append(r)
    par2 = []
    solved = 0
    for rs in per.values():
        times = [float(r["time_prove"]) for r in rs if _solved(r)]
        limit = max(float(r["time_limit"]) for r in rs)
        if times:
            solved += 1
            par2.append(min(times))
        else:
            par2.append(2 * limit)
    return {
        "solver": "virtual best",
        "runs": len(per),
        "solved": solved,
        "par2": round(sum(par2) / max(1, len(par2)), 3),
    }


def _cell(v: Any) -> str:
    if v is None or v == "":
        return "-"
    if isinstance(v, float):
        return f"{v:.3g}" if abs(v) < 1000 else f"{v:.0f}"
    return str(v).replace("|", "\\|")


def environment_markdown(env: dict[str, Any]) -> list[str]:
    """The limits, the machine and the software, as the opening lines of solvers.md."""
    if not env:
        return []
    lim, mach, soft = env.get("limits", {}), env.get("machine", {}), env.get("software", {})
    secs = ", ".join(f"{t:g}" for t in lim.get("time_limit_s", []))
    mem = ", ".join(f"{m:g}" for m in lim.get("memory_mb", [])) or "none"
    lines = [
        f"- **Limits**: {secs} s per run (wall clock); memory {mem} MB. {lim.get('time', '')}.",
        f"  Memory: {lim.get('memory', '')}. Claims nothing else settles: "
        f"{lim.get('certifier', '')}, {lim.get('certify_time_s', 0):g} s each.",
        f"- **Machine**: {mach.get('cpu', '?')}, {mach.get('cores', '?')} cores, "
        f"{mach.get('memory_mb', '?')} MB memory, {mach.get('platform', '')}; load average "
        f"{mach.get('load_average_start')} at the start, {env.get('load_average_end')} at "
        "the end.",
        "- **Software**: " + ", ".join(f"{k} {v}" for k, v in soft.items()) + ".",
    ]
    versions = env.get("solver_versions") or {}
    if versions:
        lines.append(
            "- **Solvers**: " + ", ".join(f"`{k}` {v}" for k, v in sorted(versions.items())) + "."
        )
    return [*lines, ""]


def certificate_lines(rows: Sequence[dict[str, Any]]) -> list[str]:
    """What became of the claims (optimum or UNSATISFIABLE): how many were certified, and
    how; a claim neither certified nor refuted is said to be unchecked, never confirmed."""
    claims = [r for r in rows if r.get("status") in ("optimal", "infeasible")]
    if not claims:
        return ["No run claimed an optimum or UNSATISFIABLE."]
    by: dict[str, int] = defaultdict(int)
    for r in claims:
        by[str(r.get("certificate") or "not checked")] += 1
    certified = sum(by[c] for c in CONFIRMED)
    parts = ", ".join(f"{n} {c}" for c, n in sorted(by.items()))
    return [f"**Claims certified: {certified} of {len(claims)}** ({parts})."]


def summary_markdown(
    rows: Sequence[dict[str, Any]],
    summary: Sequence[dict[str, Any]],
    env: dict[str, Any] | None = None,
) -> str:
    """solvers.md: the limits, machine and software, the summary table, the flagged runs, then
    every row."""
    lines = ["# Solver benchmark", "", *environment_markdown(env or {})]
    keys = [k for k in summary[0] if k != "solver"] if summary else []
    all_keys = list(dict.fromkeys(k for s in summary for k in s if k != "solver"))
    keys = all_keys or keys
    lines.append("| solver | " + " | ".join(keys) + " |")
    lines.append("|---" * (len(keys) + 1) + "|")
    for s in summary:
        lines.append(f"| {s['solver']} | " + " | ".join(_cell(s.get(k)) for k in keys) + " |")
    flagged = [r for r in rows if r.get("flag")]
    lines += ["", f"## Flagged runs ({len(flagged)})", ""]
    lines += [f"- {r['instance']} / {r['model']} / {_label(r)}: {r['flag']}" for r in flagged]
    if not flagged:
        lines.append("none")
    lines += ["", *certificate_lines(rows)]
    cols = [
        "instance",
        "model",
        "run",
        "solver",
        "warm_start",
        "status",
        "verified_cost",
        "claimed_cost",
        "bound",
        "gap",
        "time_first",
        "time_best",
        "time_prove",
        "wall_s",
        "cpu_s",
        "peak_rss_mb",
        "certificate",
        "found_by",
        "reason",
    ]
    lines += ["", "## Runs", "", "| " + " | ".join(cols) + " |", "|---" * len(cols) + "|"]
    lines += ["| " + " | ".join(_cell(r.get(c)) for c in cols) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def _colour(i: int) -> str:
    """The ``i``-th solver's colour: 20 distinct ones (matplotlib's ``tab20``), so that a portfolio
    of more than the default cycle's 10 solvers never draws two runs alike."""
    from matplotlib import colormaps
    from matplotlib.colors import to_hex

    return str(to_hex(colormaps["tab20"](i % 20)))


def _cost_curve(ax: Any, r: dict[str, Any], trace: Sequence[Any], colour: str) -> None:
    """One run on a cost-over-time plot: every claimed cost as an ``x`` (never joined: no
    assignment backs it), the verified cost from when it is backed to the end of the run as a
    step line with its point drawn (a single point stays visible), and its lower bounds as a
    dotted step line."""
    label = _label(r)
    claims = [(float(t), float(o)) for t, o, _ in trace if o is not None]
    if claims:
        ax.scatter(*zip(*claims, strict=True), marker="x", s=14, color=colour, alpha=0.6)
    bounds = [(float(t), float(b)) for t, _, b in trace if b is not None]
    if r.get("bound") is not None:
        bounds.append((float(r.get("wall_s") or r["time_limit"]), float(r["bound"])))
    if bounds:
        bounds.sort()
        ax.step(*zip(*bounds, strict=True), where="post", ls=":", color=colour, lw=0.9)
    if r.get("verified_cost") is not None and r.get("time_best") is not None:
        t0, cost = float(r["time_best"]), float(r["verified_cost"])
        end = max(t0, float(r.get("wall_s") or t0))
        ax.step([t0, end], [cost, cost], where="post", color=colour, label=label)
        ax.plot([t0], [cost], "o", color=colour, ms=4)
    elif claims or bounds:
        ax.plot([], [], color=colour, label=f"{label} (nothing verified)")


def write_plots(
    rows: Sequence[dict[str, Any]], traces: dict[tuple[str, ...], list[Any]], outdir: Path
) -> list[str]:
    """cactus.png and cost_<instance>_<model>.png (needs matplotlib; [] without it)."""
    import importlib.util

    if importlib.util.find_spec("matplotlib") is None:
        return []
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    groups: dict[str, list[float]] = defaultdict(list)
    for r in rows:
        groups.setdefault(_label(r), [])
        if _solved(r):
            groups[_label(r)].append(float(r["time_prove"]))
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, (label, times) in enumerate(sorted(groups.items())):
        ts = sorted(times)
        ax.step(range(1, len(ts) + 1), ts, where="post", label=label, marker=".", color=_colour(i))
    ax.set_xlabel("instances solved (proven optimal, verified)")
    ax.set_ylabel("time to prove (s)")
    ax.set_yscale("log")
    ax.set_title("cactus plot")
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(outdir / "cactus.png", dpi=120)
    plt.close(fig)
    written.append("cactus.png")
    per: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        per[(r["instance"], r["model"])].append(r)
    best = _best_known([r for r in rows if r.get("status") != "n/a"])
    for (inst, model), rs in per.items():
        fig, ax = plt.subplots(figsize=(6, 4))
        for i, r in enumerate(rs):
            _cost_curve(ax, r, traces.get(_trace_key(r), []), _colour(i))
        if (inst, model) in best:
            ax.axhline(best[(inst, model)], color="k", ls="--", lw=0.8, label="best known")
        ax.set_xlabel("seconds")
        ax.set_ylabel("cost")
        ax.set_title(
            f"{inst} ({model}): cost over time\n"
            "line and dot: verified; x: claimed, no assignment; dotted: lower bound",
            fontsize=9,
        )
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6, ncol=2)
        fig.tight_layout()
        name = f"cost_{inst}_{model}.png".replace("/", "_")
        fig.savefig(outdir / name, dpi=120)
        plt.close(fig)
        written.append(name)
    return written
