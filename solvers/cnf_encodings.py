"""Cardinality and linear constraints as CNF, for the clause backends.

:meth:`Model.to_clauses <illuknit.solvers.model.Model.to_clauses>` encodes each native constraint with
these: :func:`encode_card` (pysat's ``CardEnc``: pairwise or sequential counter) and
:func:`encode_linear` (a sequential weight counter for integer coefficients). Like ``CardEnc``
they return clauses and the new top variable id instead of touching a solver.
"""

from __future__ import annotations

__all__ = ["encode_card", "encode_linear"]


def encode_card(lits: tuple[int, ...], op: str, k: int, nv: int) -> tuple[list[list[int]], int]:
    """Clauses for ``sum(lits) <op> k`` (op "<=", ">=" or "=="), auxiliaries above ``nv``.

    Returns the clauses and the new largest variable id; an impossible bound gives one empty
    clause.
    """
    from pysat.card import CardEnc, EncType

    n = len(lits)
    ls = list(lits)
    out: list[list[int]] = []
    if op in ("<=", "=="):
        if k < 0:
            return [[]], nv
        if k < n:
            enc = EncType.pairwise if k == 1 and n <= 6 else EncType.seqcounter
            cnf = CardEnc.atmost(ls, bound=k, top_id=nv, encoding=enc)
            out.extend(cnf.clauses)
            nv = max(nv, cnf.nv)
    if op in (">=", "=="):
        if k > n:
            return [[]], nv
        if k == 1:
            out.append(ls)
        elif k > 0:
            cnf = CardEnc.atleast(ls, bound=k, top_id=nv, encoding=EncType.seqcounter)
            out.extend(cnf.clauses)
            nv = max(nv, cnf.nv)
    return out, nv


def encode_linear(
    lits: tuple[int, ...], coeffs: tuple[int, ...], bound: int, nv: int
) -> tuple[list[list[int]], int]:
    """Sequential weight counter for ``sum c_i l_i <= bound`` (Hölldobler et al. 2012)."""
    # Normalise negative coefficients: c*l = c - c*(-l) (with -c > 0).
    ls: list[int] = []
    cs: list[int] = []
    for lit, c in zip(lits, coeffs, strict=True):
        if c < 0:
            ls.append(-lit)
            cs.append(-c)
            bound -= c
        elif c > 0:
            ls.append(lit)
            cs.append(c)
    if bound < 0:
        return [[]], nv
    if sum(cs) <= bound:
        return [], nv
    if all(c == 1 for c in cs):
        return encode_card(tuple(ls), "<=", bound, nv)
    out: list[list[int]] = []
    # lits whose coefficient alone exceeds the bound are false
    keep = [(lit, c) for lit, c in zip(ls, cs, strict=True) if c <= bound]
    out.extend([-lit] for lit, c in zip(ls, cs, strict=True) if c > bound)
    k = bound
    prev: list[int] | None = None  # prev[j] <-> partial sum >= j+1
    for lit, c in keep:
        cur = list(range(nv + 1, nv + k + 1))
        nv += k
        for j in range(c):  # x_i -> s_i,j for j < c
            out.append([-lit, cur[j]])
        if prev is not None:
            for j in range(k):
                out.append([-prev[j], cur[j]])
                if j + c < k:
                    out.append([-lit, -prev[j], cur[j + c]])
            # overflow: prev >= k+1-c and x_i true exceeds the bound
            out.append([-lit, -prev[k - c]])
        prev = cur
    return out, nv
