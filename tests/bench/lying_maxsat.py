#!/usr/bin/env python3
"""A zoo of lying MaxSAT solvers: each prints MaxSAT Evaluation output (``o``/``s``/``v``
lines) and fails in one way a real solver can (issue 35). Used by tests/bench/test_lying_solvers.py
and benchmarks/lying_solvers.py.

Usage: lying_maxsat.py MODE FILE.wcnf

Modes:
  honest          the optimum (pysat RC2), proved
  wale-first, wale-middle, wale-last
                  the optimum everywhere but one component of the formula (its own union-find),
                  where a feasible costlier assignment stands; honest ``o`` cost, false
                  ``s OPTIMUM FOUND``
  early-o         ``o 1`` at once with no assignment, then the honest optimum after 3 s
  escape          double-forks a helper (its own session, parent gone) holding 600 MB for 60 s,
                  then answers honestly
  big-alloc       one 3 GB allocation (refused under an address-space limit)
  v-long, v-short, v-both, v-twice, v-range
                  malformed v-lines (5 too long, 40 too short, a literal in both polarities,
                  two v-lines, a literal out of range)
  false-unsat     ``s UNSATISFIABLE`` of a satisfiable formula
"""

from __future__ import annotations

import os
import sys
import time


def read_wcnf(path: str) -> tuple[int, list[list[int]], list[tuple[int, list[int]]]]:
    hard: list[list[int]] = []
    soft: list[tuple[int, list[int]]] = []
    nv = 0
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t or t[0] == "c":
                continue
            lits = [int(x) for x in t[1:-1]]
            nv = max([nv, *(abs(x) for x in lits)])
            (hard.append(lits) if t[0] == "h" else soft.append((int(t[0]), lits)))
    return nv, hard, soft


def optimum(nv, hard, soft):
    from pysat.examples.rc2 import RC2
    from pysat.formula import WCNF

    w = WCNF()
    for c in hard:
        w.append(c)
    for wt, c in soft:
        w.append(c, weight=wt)
    with RC2(w) as rc2:
        m = rc2.compute()
    a = [False] * (nv + 1)
    for x in m or []:
        if abs(x) <= nv:
            a[abs(x)] = x > 0
    return a


def cost(a, soft) -> int:
    return sum(w for w, c in soft if not any(a[abs(x)] == (x > 0) for x in c))


def components(nv, hard, soft) -> list[set[int]]:
    parent = list(range(nv + 1))

    def find(v):
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for c in [*hard, *(c for _, c in soft)]:
        for x in c[1:]:
            parent[find(abs(x))] = find(abs(c[0]))
    groups: dict[int, set[int]] = {}
    for c in [*hard, *(c for _, c in soft)]:
        for x in c:
            groups.setdefault(find(abs(x)), set()).add(abs(x))
    costly = [g for g in groups.values() if len(g) > 1]
    return sorted(costly, key=min)


def worse_in(a, nv, hard, soft, which: str):
    """``a`` with one component (by position) set by a SAT call preferring violated softs."""
    from pysat.solvers import Solver

    comps = components(nv, hard, soft)
    for k in {"first": [0], "middle": [len(comps) // 2], "last": [len(comps) - 1]}[which]:
        vs = comps[k]
        against = {abs(x): x < 0 for _, c in soft for x in c if abs(x) in vs}
        with Solver(name="m22", bootstrap_with=[c for c in hard if abs(c[0]) in vs]) as s:
            s.set_phases([v if against.get(v, False) else -v for v in sorted(vs)])
            s.solve()
            for x in s.get_model() or []:
                if abs(x) in vs:
                    a[abs(x)] = x > 0
    return a


def bits(a, nv) -> str:
    return "".join("1" if a[i] else "0" for i in range(1, nv + 1))


def answer(a, nv, soft, status="OPTIMUM FOUND") -> None:
    print(f"o {cost(a, soft)}")
    print(f"s {status}")
    print("v " + bits(a, nv), flush=True)


def escape() -> None:
    """Fork, the child forks again in a session of its own and exits: the grandchild, holding
    600 MB, is an orphan nobody waits for."""
    if os.fork() == 0:
        os.setsid()
        if os.fork() == 0:
            pidfile = os.environ.get("LYING_HELPER_PIDFILE")
            if pidfile:
                with open(pidfile, "w") as f:
                    f.write(str(os.getpid()))
            hold = bytearray(600 * 2**20)
            for i in range(0, len(hold), 4096):
                hold[i] = 1
            time.sleep(60)
        os._exit(0)
    os.wait()
    time.sleep(1.5)  # the helper is up and holding its memory while we "solve"


def main(mode: str, path: str) -> int:
    nv, hard, soft = read_wcnf(path)
    if mode == "false-unsat":
        print("s UNSATISFIABLE")
        return 20
    if mode == "big-alloc":
        block = bytearray(3 * 2**30)
        print(len(block))
    if mode == "early-o":
        print("o 1", flush=True)
        time.sleep(3)
    if mode == "escape":
        escape()
    a = optimum(nv, hard, soft)
    if mode.startswith("wale-"):
        a = worse_in(a, nv, hard, soft, mode.removeprefix("wale-"))
    if mode.startswith("v-"):
        print(f"o {cost(a, soft)}\ns OPTIMUM FOUND")
        line = "v " + bits(a, nv)
        lits = " ".join(str(i if a[i] else -i) for i in range(1, nv + 1))
        print(
            {
                "v-long": line + "01011",
                "v-short": line[:-40],
                "v-both": f"v {lits} {-1 if a[1] else 1} 0",
                "v-twice": line + "\n" + line,
                "v-range": f"v {lits} {nv + 3} 0",
            }[mode]
        )
        return 30
    answer(a, nv, soft)
    return 30


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
