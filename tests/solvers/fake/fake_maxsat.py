#!/usr/bin/env python3
"""A tiny stand-in for a MaxSAT Evaluation solver binary, used by the external-backend tests.

Usage: fake_maxsat.py [--old-v] [--sleep S] [--lie] [--garbage] FILE.wcnf

Parses WCNF itself (2022+ ``h`` format and the old ``p wcnf`` header, independently of
illuknit's writer), brute-forces the optimum when there are at most 16 variables and otherwise
asks pysat's RC2, then prints ``o``/``s``/``v`` lines. ``--old-v`` prints literal-list ``v`` lines
instead of the binary string; ``--sleep`` waits first (printing an incumbent ``o``/``v`` and
``s SATISFIABLE`` if terminated meanwhile); ``--lie`` prints an all-false assignment claimed
optimal; ``--lie-feasible`` prints the first model of the hard clauses alone (feasible, rarely
optimal) with a false ``o 0`` and ``s OPTIMUM FOUND``; ``--garbage`` prints an unparseable ``v``
line.

Liars and misbehaviours for the benchmark's tests: ``--lie-unsat`` claims ``s UNSATISFIABLE``
of a satisfiable instance; ``--lie-optimum`` prints the worst assignment it can find quickly
(the first model of the hard clauses with every soft variable set against its clause where the
hard clauses allow), with its true cost, as ``s OPTIMUM FOUND``; ``--hog`` allocates (and
touches) about 1 GB/s until stopped; ``--late S`` ignores its time limit and prints the optimum
S seconds in, or as soon as it gets SIGTERM.
"""

from __future__ import annotations

import itertools
import signal
import sys
import time


def read_wcnf(path: str) -> tuple[int, list[list[int]], list[tuple[int, list[int]]]]:
    hard: list[list[int]] = []
    soft: list[tuple[int, list[int]]] = []
    top = None
    nv = 0
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t or t[0] == "c":
                continue
            if t[0] == "p":
                top = int(t[4])
                continue
            lits = [int(x) for x in t[1:-1]]
            assert t[-1] == "0", line
            nv = max([nv, *(abs(x) for x in lits)])
            if t[0] == "h" or (top is not None and int(t[0]) >= top):
                hard.append(lits)
            else:
                soft.append((int(t[0]), lits))
    return nv, hard, soft


def cost_of(assign: dict[int, bool], soft: list[tuple[int, list[int]]]) -> int:
    return sum(w for w, c in soft if not any(assign[abs(x)] == (x > 0) for x in c))


def sat(assign: dict[int, bool], hard: list[list[int]]) -> bool:
    return all(any(assign[abs(x)] == (x > 0) for x in c) for c in hard)


def solve(nv: int, hard: list[list[int]], soft: list[tuple[int, list[int]]]):
    if nv <= 16:
        best = None
        for bits in itertools.product((False, True), repeat=nv):
            a = {i + 1: b for i, b in enumerate(bits)}
            if sat(a, hard):
                c = cost_of(a, soft)
                if best is None or c < best[0]:
                    best = (c, a)
        return best
    from pysat.examples.rc2 import RC2
    from pysat.formula import WCNF

    w = WCNF()
    for c in hard:
        w.append(c)
    for wt, c in soft:
        w.append(c, weight=wt)
    with RC2(w) as rc2:
        m = rc2.compute()
        if m is None:
            return None
        a = {i: False for i in range(1, nv + 1)}
        for x in m:
            if abs(x) <= nv:
                a[abs(x)] = x > 0
        return rc2.cost, a


def _worst_feasible(nv: int, hard: list[list[int]], soft: list[tuple[int, list[int]]]):
    """A feasible assignment violating as much soft weight as a SAT call that prefers so finds."""
    from pysat.solvers import Solver

    against = {}
    for _w, c in soft:
        for x in c:
            against.setdefault(abs(x), x < 0)  # the polarity that falsifies this literal
    with Solver(name="m22", bootstrap_with=hard) as s:
        s.set_phases([v if against.get(v, False) else -v for v in range(1, nv + 1)])
        s.solve()
        m = s.get_model() or []
    a = {i: False for i in range(1, nv + 1)}
    for x in m:
        if abs(x) <= nv:
            a[abs(x)] = x > 0
    return cost_of(a, soft), a


def emit(assign: dict[int, bool], nv: int, old: bool) -> None:
    if old:
        print("v " + " ".join(str(i if assign[i] else -i) for i in range(1, nv + 1)) + " 0")
    else:
        print("v " + "".join("1" if assign[i] else "0" for i in range(1, nv + 1)))


def main(argv: list[str]) -> int:
    old = "--old-v" in argv
    path = argv[-1]
    nv, hard, soft = read_wcnf(path)
    if "--lie-unsat" in argv:
        print("s UNSATISFIABLE")
        return 20
    if "--lie-optimum" in argv:
        worst = _worst_feasible(nv, hard, soft)
        print(f"o {worst[0]}")
        print("s OPTIMUM FOUND")
        emit(worst[1], nv, old)
        return 30
    if "--hog" in argv:
        chunks = []
        while True:  # about 1 GB/s, every page touched
            chunks.append(b"x" * (50 * 2**20))
            time.sleep(0.05)
    if "--late" in argv:
        delay = float(argv[argv.index("--late") + 1])
        best = solve(nv, hard, soft)

        def prove(signum=None, frame=None):
            print(f"o {best[0]}")
            print("s OPTIMUM FOUND")
            emit(best[1], nv, old)
            sys.stdout.flush()
            sys.exit(0)

        signal.signal(signal.SIGTERM, prove)
        time.sleep(delay)
        prove()
    if "--garbage" in argv:
        print("s OPTIMUM FOUND")
        print("v x y z")
        return 30
    if "--lie" in argv:
        print("o 0")
        print("s OPTIMUM FOUND")
        emit({i: False for i in range(1, nv + 1)}, nv, old)
        return 30
    if "--lie-feasible" in argv:
        from pysat.solvers import Solver

        with Solver(name="m22", bootstrap_with=hard) as s:
            s.solve()
            m = s.get_model() or []
        a = {i: False for i in range(1, nv + 1)}
        for x in m:
            if abs(x) <= nv:
                a[abs(x)] = x > 0
        print("o 0")
        print("s OPTIMUM FOUND")
        emit(a, nv, old)
        return 30
    if "--sleep" in argv:
        delay = float(argv[argv.index("--sleep") + 1])
        first = solve(nv, hard, soft)

        def on_term(signum, frame):  # a real solver prints its incumbent when terminated
            if first is not None:
                print(f"o {first[0]}")
                print("s SATISFIABLE")
                emit(first[1], nv, old)
            else:
                print("s UNKNOWN")
            sys.stdout.flush()
            sys.exit(0)

        signal.signal(signal.SIGTERM, on_term)
        time.sleep(delay)
    best = solve(nv, hard, soft)
    if best is None:
        print("s UNSATISFIABLE")
        return 20
    print(f"c fake solver: {nv} variables, {len(hard)} hard, {len(soft)} soft")
    print(f"o {best[0]}")
    print("s OPTIMUM FOUND")
    emit(best[1], nv, old)
    return 30


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
