"""When no tile assignment exists: a minimal conflicting set of overlap pairs and the fixes that
would make one exist (merge two colours, stripes on both sides, another yarn, a softer order)."""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from illuknit.core.colors import hex_color, lab_from_rgb
from illuknit.core.pattern import Yarn
from illuknit.design.tiles.assign_model import _build_problem, _encode, _Problem
from illuknit.design.tiles.assignment import Regions
from illuknit.design.tiles.bank import canonical_bank

__all__ = ["explain_infeasible"]


# -- when nothing fits -------------------------------------------------------------------------


def _restricted(prob: _Problem, pairs: Sequence[tuple[int, int]]) -> _Problem:
    keep = dict.fromkeys(pairs, 1)
    cols_a = sorted({a for a, _ in keep})
    cols_b = sorted({b for _, b in keep})
    return _Problem(**{**prob.__dict__, "pairs": keep, "cols_a": cols_a, "cols_b": cols_b})


def _name(side: str, k: int, colors: NDArray[np.uint8]) -> str:
    return f"{side}{k} ({hex_color(colors[k])})"


def explain_infeasible(prob: _Problem, *, solver: str = "cpsat") -> str:
    """Why no assignment exists, and which changes would make one exist (one paragraph).

    Finds a minimal set of overlap pairs that cannot be realised together (deletion-based core
    over the pairs), then tries: relaxing the brightness order, merging two colours of one input,
    allowing stripes on both sides (canonical bank), and adding a yarn of a picture colour.
    """
    lines = []
    if prob.brightness == "hard":
        soft = _Problem(**{**prob.__dict__, "brightness": "soft"})
        if _feasible_real(soft, solver):
            lines.append(
                "the fills that fit cannot keep the brightness order of the inputs; "
                "allow it to change (--brightness soft / brightness='soft') or merge colours"
            )
    core = list(prob.pairs)
    if not _feasible_real(_restricted(prob, core), solver):
        for pair in list(core):
            kept = [q for q in core if q != pair]
            if kept and not _feasible_real(_restricted(prob, kept), solver):
                core = kept
    names = ", ".join(
        f"{_name('A', a, prob.ra.colors)} over {_name('B', b, prob.rb.colors)}" for a, b in core
    )
    lines.insert(
        0, f"no tile assignment exists: the overlap pairs {names} cannot all be realised together"
    )
    fixes = []
    # merging two colours of one input
    for side in ("A", "B"):
        r = prob.ra if side == "A" else prob.rb
        cols = prob.cols_a if side == "A" else prob.cols_b
        for p, q in itertools.combinations(cols, 2):
            idx = np.where(r.indices == q, p, r.indices).astype(np.int16)
            merged = Regions(idx, r.colors)
            ra, rb = (merged, prob.rb) if side == "A" else (prob.ra, merged)
            trial = _build_problem(ra, rb, prob.bank, prob.views, prob.brightness, prob.weights)
            if _feasible_real(trial, solver):
                fixes.append(
                    f"merge colours {_name(side, p, r.colors)} and {_name(side, q, r.colors)} of input {side}"
                )
    # stripes on both sides
    full = canonical_bank(prob.bank.yarns, views=prob.views)
    if len(full) > len(prob.bank) or prob.bank.name != "canonical":
        trial = _build_problem(prob.ra, prob.rb, full, prob.views, prob.brightness, prob.weights)
        if _feasible_real(trial, solver):
            fixes.append("allow stripes on both sides (use the full canonical bank)")
    # one more yarn
    # (only for a canonical bank: a custom bank says nothing about tiles with another yarn)
    if len(prob.bank.yarns) < 8 and prob.bank.name == "canonical":
        tried: set[tuple[int, int, int]] = set()
        ylab = lab_from_rgb(np.array([y.rgb for y in prob.bank.yarns], dtype=np.float64))
        for side, k, colors in [("A", a, prob.ra.colors) for a, _ in core] + [
            ("B", b, prob.rb.colors) for _, b in core
        ]:
            rgb = tuple(int(v) for v in colors[k])
            lab = lab_from_rgb(np.array([rgb], dtype=np.float64))[0]
            if rgb in tried or np.sqrt(((ylab - lab) ** 2).sum(axis=1)).min() < 10:
                continue  # as good as a yarn we already have
            tried.add(rgb)  # type: ignore[arg-type]
            more = canonical_bank(
                (*prob.bank.yarns, Yarn("extra", (rgb[0], rgb[1], rgb[2]))), views=prob.views
            )
            trial = _build_problem(
                prob.ra, prob.rb, more, prob.views, prob.brightness, prob.weights
            )
            if _feasible_real(trial, solver):
                fixes.append(f"add a yarn of colour {hex_color(rgb)} (like {side}{k})")
                break
    text = "; ".join(lines)
    if fixes:
        text += ". Would fix it: " + "; or ".join(fixes)
    else:
        text += ". Try another yarn set, fewer colours, or editing the inputs so these regions do not overlap"
    return text


def _feasible_real(prob: _Problem, solver: str) -> bool:
    """Whether the hard constraints of ``prob`` can hold (objective ignored)."""
    from illuknit.solvers import solve

    if _check_levels(prob) is False:
        return False
    m, _, _ = _encode(_Problem(**{**prob.__dict__, "row_classes": []}))
    # soft clauses do not matter for feasibility, but the encoder adds them; they are cheap
    return solve(m, solver=solver, time_limit=10.0).has_values


def _check_levels(prob: _Problem) -> bool:
    if prob.brightness != "hard":
        return True
    la = {round(f.brightness, 9) for f in prob.fa}
    lb = {round(f.brightness, 9) for f in prob.fb}
    return len(prob.cols_a) <= len(la) and len(prob.cols_b) <= len(lb)
