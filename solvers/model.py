"""A solver-neutral constraint model: boolean variables, hard and weighted soft constraints.

Encoders (the illusion models of :mod:`illuknit.design.models.illusion_models`, the tile assignment) build a
:class:`Model` incrementally; every backend in :mod:`illuknit.solvers` then treats it as immutable
data, translates it into its own form, solves, and maps the answer back to variable ids.

Contract
--------
* **Variables** are positive integers (1-based, DIMACS style) handed out by one :class:`VarPool`
  from readable keys: ``m.var(("raised", r, c))``. Large regular families are allocated at once as
  numpy *blocks* (``m.pool.block("raised", (N, M))`` returns an int array of ids), and the tuple
  key ``("raised", r, c)`` then resolves into the block, so both styles agree.
* A **literal** is ``+id`` (true) or ``-id`` (false).
* **Hard clauses** must hold; each carries a *family* name ("one yarn per unit",
  "colour-change cap", ...) so an infeasible model can say which families conflict
  (:meth:`Model.infeasible_families`).
* **Soft clauses** carry a positive integer weight; the objective is the total weight of violated
  soft clauses, to be minimised.
* **Native constraints** (exactly-one, at-most-k, at-least-k, linear <=) are kept as such so a
  backend that understands them (CP-SAT) uses them directly; clause backends call
  :meth:`Model.to_clauses`, which encodes them with pysat's ``CardEnc`` (or a sequential weight
  counter for non-unit coefficients) into auxiliary variables numbered above ``pool.top``.
* ``problem`` holds an optional :class:`DomainPayload`: the structured data a domain built the
  model from, opaque to this package. A domain that has its own algorithms registers them as
  backends (:func:`illuknit.solvers.register_backend`) that recognise their payload with
  ``isinstance`` -- as design does for its illusion models (``illuknit.design.models.backends``).
* :meth:`Model.to_wcnf` writes the MaxSAT Evaluation format (2022+: hard clauses prefixed ``h``,
  soft clauses by their weight, no ``p`` line); ``style="old"`` writes the pre-2022
  ``p wcnf NV NC TOP`` format. pysat's ``WCNF`` reader accepts both.

The pool lives in :mod:`illuknit.solvers.var_pool`, the CNF encodings of native constraints in
:mod:`illuknit.solvers.cnf_encodings`. Clause blocks are stored as numpy arrays of shape (n, width) padded with 0 so that models with
~10^5 variables (330 x 200 units) are built in milliseconds; ``0`` is never a literal.

Naming: in illuknit a *constraint model* is this module's :class:`Model` (solver-neutral
variables and constraints); an *illusion model* is one of the three ways of asking for an illusion
whose data (an ``IllusionProblem``, a :class:`DomainPayload`) design encodes into a constraint
model.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import ModelError, OptionError
from illuknit.solvers.cnf_encodings import encode_card, encode_linear
from illuknit.solvers.var_pool import VarPool

__all__ = [
    "CardConstraint",
    "ClauseSet",
    "DomainPayload",
    "LinearConstraint",
    "Model",
]


class DomainPayload:
    """Base class of the structured data a domain builds a :class:`Model` from.

    Opaque to the solver layer: the generic backends never read it, and the backends a domain
    registers recognise their own payload with ``isinstance``. A payload may say what the
    generic backends can use without knowing the domain (:attr:`separable`).
    """

    __slots__ = ()

    @property
    def separable(self) -> bool:
        """True when the model falls apart into many small independent parts (a portfolio of
        search strategies then does not pay for itself: CP-SAT runs one worker)."""
        return False


@dataclass(frozen=True)
class CardConstraint:
    """``sum(lits) <op> k`` with op one of "<=", ">=", "==" (all coefficients 1)."""

    lits: tuple[int, ...]
    op: str
    k: int
    family: str


@dataclass(frozen=True)
class LinearConstraint:
    """``sum(coeffs[i] * lits[i]) <= bound`` with integer coefficients (a literal counts 0/1)."""

    lits: tuple[int, ...]
    coeffs: tuple[int, ...]
    bound: int
    family: str


@dataclass(frozen=True)
class ClauseSet:
    """Flat clause lists produced by :meth:`Model.to_clauses` (natives encoded to CNF).

    ``nv`` is the largest variable id used, including auxiliaries above the pool's ``top``.
    ``hard_families[i]`` names the family of ``hard[i]``.
    """

    hard: list[list[int]]
    hard_families: list[str]
    soft: list[list[int]]
    weights: list[int]
    nv: int


def _as_block(clauses: ArrayLike) -> NDArray[np.int64]:
    a = np.asarray(clauses, dtype=np.int64)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2:
        raise ModelError(f"clause block must be 2-D (n, width), got shape {a.shape}")
    return a


class Model:
    """A weighted partial MaxSAT model with native cardinality / linear constraints.

    Parameters
    ----------
    name : str
        Shown in reports and WCNF comments.
    problem : DomainPayload, optional
        The data the model was built from, which the backends a domain registers recognise.
    """

    def __init__(self, name: str = "model", *, problem: DomainPayload | None = None) -> None:
        if not isinstance(name, str):
            raise ModelError(f"`name` must be a string, got {type(name).__name__}")
        if problem is not None and not isinstance(problem, DomainPayload):
            raise ModelError(
                f"`problem` must be a DomainPayload or None, got {type(problem).__name__}"
            )
        self.name = name
        self.problem = problem
        self.pool = VarPool()
        # (block (n, w) padded with 0, family)
        self._hard: list[tuple[NDArray[np.int64], str]] = []
        # (block (n, w), weights (n,))
        self._soft: list[tuple[NDArray[np.int64], NDArray[np.int64]]] = []
        self.cards: list[CardConstraint] = []
        self.linears: list[LinearConstraint] = []
        #: constant added to every objective value (e.g. cost already decided while encoding)
        self.offset = 0
        #: optional warm start: bool array indexed by variable id (length pool.top + 1), used by
        #: backends that accept hints (CP-SAT) and as the timeout fallback of exact ones
        self.hint: NDArray[np.bool_] | None = None

    # -- variables ------------------------------------------------------------------------
    def var(self, key: Hashable) -> int:
        """Id of the variable named ``key`` (allocated on first use)."""
        return self.pool.var(key)

    def lit(self, key: Hashable, positive: bool = True) -> int:
        """Literal of ``key``: its id, negated when ``positive`` is False."""
        v = self.pool.var(key)
        return v if positive else -v

    # -- constraints ----------------------------------------------------------------------
    def _check_lits(self, a: NDArray[np.int64]) -> None:
        if a.size and (int(np.abs(a).max()) > self.pool.top):
            raise ModelError(
                f"literal {int(np.abs(a).max())} refers to no variable (pool top is {self.pool.top})"
            )

    def add_hard(self, clause: Sequence[int], *, family: str = "hard") -> None:
        """Add one hard clause (a disjunction of literals)."""
        self.add_hard_block(
            np.asarray([list(clause)], dtype=np.int64).reshape(1, -1), family=family
        )

    def add_hard_block(self, clauses: ArrayLike, *, family: str = "hard") -> None:
        """Add many hard clauses at once: array of shape (n, width), rows padded with 0."""
        a = _as_block(clauses)
        self._check_lits(a)
        if a.shape[0]:
            self._hard.append((a, family))

    def add_soft(self, clause: Sequence[int], weight: int = 1) -> None:
        """Add one soft clause with a positive integer weight."""
        self.add_soft_block(np.asarray([list(clause)], dtype=np.int64).reshape(1, -1), weight)

    def add_soft_block(self, clauses: ArrayLike, weights: int | ArrayLike = 1) -> None:
        """Add many soft clauses: array (n, width) padded with 0, weights scalar or (n,)."""
        a = _as_block(clauses)
        w = np.broadcast_to(np.asarray(weights, dtype=np.int64), (a.shape[0],)).copy()
        if w.size and int(w.min()) <= 0:
            raise ModelError("soft clause weights must be positive integers")
        self._check_lits(a)
        if a.shape[0]:
            self._soft.append((a, w))

    def add_exactly_one(self, lits: Sequence[int], *, family: str = "exactly-one") -> None:
        """Exactly one of ``lits`` is true."""
        self.add_card(lits, "==", 1, family=family)

    def add_at_most_k(self, lits: Sequence[int], k: int, *, family: str = "at-most-k") -> None:
        """At most ``k`` of ``lits`` are true."""
        self.add_card(lits, "<=", k, family=family)

    def add_at_least_k(self, lits: Sequence[int], k: int, *, family: str = "at-least-k") -> None:
        """At least ``k`` of ``lits`` are true."""
        self.add_card(lits, ">=", k, family=family)

    def add_card(
        self, lits: Sequence[int], op: str, k: int, *, family: str = "cardinality"
    ) -> None:
        """``sum(lits) op k`` for op in {"<=", ">=", "=="}."""
        if op not in ("<=", ">=", "=="):
            raise OptionError(f"`op` must be '<=', '>=' or '==', got {op!r}")
        t = tuple(int(x) for x in lits)
        self._check_lits(np.asarray(t, dtype=np.int64))
        self.cards.append(CardConstraint(t, op, int(k), family))

    def add_linear_le(
        self, lits: Sequence[int], coeffs: Sequence[int], bound: int, *, family: str = "linear"
    ) -> None:
        """``sum(coeffs[i] * lits[i]) <= bound`` (integer coefficients, literals count as 0/1)."""
        t = tuple(int(x) for x in lits)
        c = tuple(int(x) for x in coeffs)
        if len(t) != len(c):
            raise ModelError(f"`coeffs` must have {len(t)} entries, got {len(c)}")
        self._check_lits(np.asarray(t, dtype=np.int64))
        self.linears.append(LinearConstraint(t, c, int(bound), family))

    # -- reading --------------------------------------------------------------------------
    @property
    def num_vars(self) -> int:
        return self.pool.top

    @property
    def num_hard(self) -> int:
        return sum(a.shape[0] for a, _ in self._hard)

    @property
    def num_soft(self) -> int:
        return sum(a.shape[0] for a, _ in self._soft)

    def hard_blocks(self) -> Iterator[tuple[NDArray[np.int64], str]]:
        """The hard clause blocks: (array (n, width) padded with 0, family)."""
        yield from self._hard

    def soft_blocks(self) -> Iterator[tuple[NDArray[np.int64], NDArray[np.int64]]]:
        """The soft clause blocks: (array (n, width) padded with 0, weights (n,))."""
        yield from self._soft

    def total_soft_weight(self) -> int:
        return int(sum(int(w.sum()) for _, w in self._soft))

    def to_clauses(self) -> ClauseSet:
        """All constraints as CNF (native constraints encoded with auxiliary variables)."""
        hard: list[list[int]] = []
        fam: list[str] = []
        for a, f in self._hard:
            rows = _rows(a)
            hard.extend(rows)
            fam.extend([f] * len(rows))
        nv = self.pool.top
        for c in self.cards:
            cls, nv = encode_card(c.lits, c.op, c.k, nv)
            hard.extend(cls)
            fam.extend([c.family] * len(cls))
        for lc in self.linears:
            cls, nv = encode_linear(lc.lits, lc.coeffs, lc.bound, nv)
            hard.extend(cls)
            fam.extend([lc.family] * len(cls))
        soft: list[list[int]] = []
        weights: list[int] = []
        for a, w in self._soft:
            soft.extend(_rows(a))
            weights.extend(int(x) for x in w)
        return ClauseSet(hard, fam, soft, weights, nv)

    def to_wcnf(self, *, style: str = "new") -> str:
        """The model as WCNF text (MaxSAT Evaluation format).

        Parameters
        ----------
        style : {"new", "old"}
            ``"new"`` (MaxSAT Evaluation 2022+): ``h <lits> 0`` for hard clauses and
            ``<weight> <lits> 0`` for soft ones. ``"old"``: a ``p wcnf NV NC TOP`` header with
            hard clauses weighted ``TOP`` (sum of soft weights + 1).
        """
        if style not in ("new", "old"):
            raise OptionError(f"`style` must be 'new' or 'old', got {style!r}")
        cs = self.to_clauses()
        out = [f"c illuknit model {self.name}: {self.pool.top} named variables, {cs.nv} in all"]
        if self.offset:
            out.append(f"c objective offset {self.offset} (not included in the WCNF cost)")
        if style == "old":
            top = sum(cs.weights) + 1
            out.append(f"p wcnf {cs.nv} {len(cs.hard) + len(cs.soft)} {top}")
            hp = f"{top} "
        else:
            hp = "h "
        out.extend(hp + " ".join(map(str, c)) + " 0" for c in cs.hard)
        out.extend(
            f"{w} " + " ".join(map(str, c)) + " 0" for c, w in zip(cs.soft, cs.weights, strict=True)
        )
        return "\n".join(out) + "\n"

    def evaluate(self, values: ArrayLike) -> tuple[bool, int]:
        """(all hard constraints hold, objective) of a full assignment.

        ``values`` is a bool array indexed by variable id (index 0 unused), at least
        ``pool.top + 1`` long. Native constraints are checked directly (no auxiliaries needed).
        """
        v = np.asarray(values, dtype=bool)
        if v.shape[0] < self.pool.top + 1:
            raise ModelError(f"`values` must have at least {self.pool.top + 1} entries")
        ok = True
        for a, _ in self._hard:
            ok &= bool(_block_sat(a, v).all())
        for c in self.cards:
            s = int(_lit_vals(np.asarray(c.lits, dtype=np.int64), v).sum())
            ok &= (s <= c.k) if c.op == "<=" else (s >= c.k) if c.op == ">=" else (s == c.k)
        for lc in self.linears:
            s = int(
                (_lit_vals(np.asarray(lc.lits, dtype=np.int64), v) * np.asarray(lc.coeffs)).sum()
            )
            ok &= s <= lc.bound
        cost = self.offset
        for a, w in self._soft:
            cost += int(w[~_block_sat(a, v)].sum())
        return bool(ok), int(cost)

    def infeasible_families(self, *, max_seconds: float = 30.0) -> list[str]:
        """Names of hard-constraint families that together cannot hold (an unsat core).

        Returns an empty list when the hard constraints are satisfiable. Uses one selector
        literal per family and a SAT call with assumptions (pysat).
        """
        from threading import Timer

        from pysat.solvers import Solver

        cs = self.to_clauses()
        names = list(dict.fromkeys(cs.hard_families))
        sel = {f: cs.nv + 1 + i for i, f in enumerate(names)}
        with Solver(name="g4") as s:
            for c, f in zip(cs.hard, cs.hard_families, strict=True):
                s.add_clause([*c, -sel[f]])
            timer = Timer(max_seconds, s.interrupt)
            timer.start()
            try:
                res = s.solve_limited(assumptions=list(sel.values()), expect_interrupt=True)
            finally:
                timer.cancel()
            if res is None:
                return names
            if res:
                return []
            core = set(s.get_core() or [])
        return [f for f in names if sel[f] in core]

    def __repr__(self) -> str:
        return (
            f"Model({self.name!r}, vars={self.num_vars}, hard={self.num_hard}, soft={self.num_soft}, "
            f"cards={len(self.cards)}, linears={len(self.linears)})"
        )


def _rows(a: NDArray[np.int64]) -> list[list[int]]:
    if not (a == 0).any():
        return a.tolist()
    return [[x for x in row if x] for row in a.tolist()]


def _lit_vals(lits: NDArray[np.int64], v: NDArray[np.bool_]) -> NDArray[np.bool_]:
    return np.where(lits > 0, v[np.abs(lits)], ~v[np.abs(lits)])


def _block_sat(a: NDArray[np.int64], v: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Per clause: is it satisfied (0 padding counts as false)."""
    lv = _lit_vals(a, v) & (a != 0)
    return lv.any(axis=1)
