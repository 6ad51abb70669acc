"""Row descent for a model made for hands: every unit row knittable by hand, re-optimised
exactly one row at a time (the ``hand`` warm start; issue #37).

With every other row fixed, the cost a row's units add is separable per unit: unit ``j`` in yarn
``c`` and raised ``r`` decides view A of its own cell (unless the unit below is raised, which
hides it), view B of its own cell (unless the unit above is raised), and, through ``r``, view A
of the cell above and view B of the cell below (paper section 4.2). So the best raised bit of
each (unit, yarn) is local, and what couples the units of the row is only the hand knitter's row
rule (:class:`~illuknit.design.hand_cost.HandRow`): at most ``MAX_HAND_BLOCKS`` colour blocks
(intarsia), or at most two yarns with no float longer than ``MAX_FLOAT`` stitches (stranded).
Both are finite automata over the row's yarns, so the best knittable row is a shortest path
(:func:`best_row`), exact.

:func:`hand_row_descent` sweeps the rows from the cast-on edge until a sweep improves nothing or
the time is up. Its first sweep makes every row knittable (from any start, e.g. the per-wale DP
optimum, which ignores the rows); every later move is exact, so the view cost never rises after
it.

>>> import numpy as np
>>> from dataclasses import replace
>>> from illuknit.design.models.illusion_problem import make_problem
>>> a = np.array([[0, 1] * 6] * 3)
>>> p = replace(make_problem(a, a, n_yarns=2), for_hands=True)
>>> yarn, raised, cost = hand_row_descent(p, np.array(a), np.zeros(a.shape, bool))
>>> cost  # alternate every unit: floats of 2 stitches, stranded
0
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from functools import cache

import numpy as np
from numpy.typing import NDArray

from illuknit.design.hand_cost import MAX_FLOAT, MAX_HAND_BLOCKS
from illuknit.design.models.illusion_problem import IllusionProblem

__all__ = ["best_row", "hand_row_descent", "row_unit_costs", "view_cost"]

#: The shortest run of units (2 stitches each) too long for another yarn to float behind.
FLOAT_UNITS = MAX_FLOAT // 2 + 1


@dataclass(frozen=True)
class _Automaton:
    """The hand row rule over ``k`` yarns: state colours, start states, allowed moves."""

    colour: NDArray[np.int64]  # (S,)
    start: NDArray[np.bool_]  # (S,)
    moves: NDArray[np.float64]  # (S, S): 0 allowed, inf not


@cache
def _automaton(k: int) -> _Automaton:
    colour: list[int] = []
    start: list[bool] = []
    index: dict[tuple[object, ...], int] = {}

    def state(key: tuple[object, ...], c: int, first: bool) -> int:
        if key not in index:
            index[key] = len(colour)
            colour.append(c)
            start.append(first)
        return index[key]

    moves: list[tuple[int, int]] = []
    # intarsia: (yarn, changes so far); a change adds a block
    blocks = MAX_HAND_BLOCKS - 1
    for c in range(k):
        for t in range(blocks + 1):
            s = state(("i", c, t), c, t == 0)
            for d in range(k):
                if d == c:
                    moves.append((s, state(("i", c, t), c, t == 0)))
                elif t < blocks:
                    moves.append((s, state(("i", d, t + 1), d, False)))
    # stranded in a pair of yarns: (pair, yarn, run length capped, other yarn seen before)
    for pair in itertools.combinations(range(k), 2):
        for c in pair:
            other = pair[1] if c == pair[0] else pair[0]
            for run in range(1, FLOAT_UNITS + 1):
                for seen in (False, True):
                    s = state(("s", pair, c, run, seen), c, run == 1 and not seen)
                    moves.append(
                        (s, state(("s", pair, c, min(run + 1, FLOAT_UNITS), seen), c, False))
                    )
                    if not (seen and run >= FLOAT_UNITS):  # else ``other`` floated too far
                        moves.append((s, state(("s", pair, other, 1, True), other, False)))
    size = len(colour)
    allowed = np.full((size, size), np.inf)
    for a, b in moves:
        allowed[a, b] = 0.0
    return _Automaton(np.array(colour), np.array(start), allowed)


def best_row(costs: NDArray[np.float64]) -> tuple[NDArray[np.int64], float]:
    """The yarns of the cheapest knittable row, and its cost.

    ``costs[j, c]`` is what unit ``j`` costs in yarn ``c``; a knittable row is one the hand row
    rule admits (the module docstring). Exact: a shortest path through the rule's automaton.
    """
    m, k = costs.shape
    auto = _automaton(k)
    per_state = costs[:, auto.colour]  # (m, S)
    dist = np.where(auto.start, per_state[0], np.inf)
    back = np.zeros((m, dist.size), dtype=np.int64)
    for j in range(1, m):
        via = dist[:, None] + auto.moves
        back[j] = np.argmin(via, axis=0)
        dist = via[back[j], np.arange(dist.size)] + per_state[j]
    s = int(np.argmin(dist))
    total = float(dist[s])
    states = np.empty(m, dtype=np.int64)
    for j in range(m - 1, -1, -1):
        states[j] = s
        s = int(back[j, s])
    return auto.colour[states], total


def row_unit_costs(
    problem: IllusionProblem, yarn: NDArray[np.int64], raised: NDArray[np.bool_], i: int
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Per unit ``j`` and yarn ``c`` of row ``i``: the view cells it decides that miss their
    targets (the rest of the pattern fixed), at its best raised bit, and that bit."""
    n, m = yarn.shape
    k = problem.n_yarns
    ta, tb = problem.target_a, problem.target_b
    c = np.arange(k)[None, :]
    base = np.zeros((m, k))
    # view A of this cell: this unit's yarn unless the unit below is raised
    seen_a = np.ones(m, bool) if i == 0 else ~raised[i - 1]
    base += seen_a[:, None] * (c != ta[i][:, None])
    # view B of this cell: this unit's yarn unless the unit above is raised
    seen_b = np.ones(m, bool) if i == n - 1 else ~raised[i + 1]
    base += seen_b[:, None] * (c != tb[i][:, None])
    flat = np.zeros((m, k))
    up = np.zeros((m, k))
    if i + 1 < n:  # raised: view A of the cell above sees this unit
        up += c != ta[i + 1][:, None]
        flat += (yarn[i + 1] != ta[i + 1])[:, None]
    if i > 0:  # raised: view B of the cell below sees this unit
        up += c != tb[i - 1][:, None]
        flat += (yarn[i - 1] != tb[i - 1])[:, None]
    lift = up < flat
    return base + np.where(lift, up, flat), lift


def view_cost(problem: IllusionProblem, yarn: NDArray[np.int64], raised: NDArray[np.bool_]) -> int:
    """View cells that miss their targets (the logical model's objective, weight 1)."""
    va = yarn.copy()
    va[1:] = np.where(raised[:-1], yarn[:-1], yarn[1:])
    vb = yarn.copy()
    vb[:-1] = np.where(raised[1:], yarn[1:], yarn[:-1])
    return int((va != problem.target_a).sum() + (vb != problem.target_b).sum())


def hand_row_descent(
    problem: IllusionProblem,
    yarn: NDArray[np.integer],
    raised: NDArray[np.bool_],
    *,
    time_limit: float | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.bool_], int]:
    """Sweep the rows of a start pattern, replacing each by the best knittable row.

    Returns the yarns, the raised bits and the view cost (:func:`view_cost`). The first sweep
    always completes (it makes every row knittable); later sweeps stop at ``time_limit``
    seconds or when one improves nothing.
    """
    t0 = time.perf_counter()
    rows: NDArray[np.int64] = np.array(yarn, dtype=np.int64)
    lifted: NDArray[np.bool_] = np.array(raised, dtype=bool)
    n = rows.shape[0]
    best = None
    while True:
        for i in range(n):
            costs, lift = row_unit_costs(problem, rows, lifted, i)
            row, _ = best_row(costs)
            rows[i] = row
            lifted[i] = lift[np.arange(row.size), row]
        cost = view_cost(problem, rows, lifted)
        if best is not None and cost >= best:
            break
        best = cost
        if time_limit is not None and time.perf_counter() - t0 > time_limit:
            break
    return rows, lifted, cost
