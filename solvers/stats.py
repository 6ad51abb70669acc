"""What a solve records, typed: :class:`WarmStartInfo` and :class:`SolveStats`.

:func:`illuknit.solvers.solve` hands back ``Solution.stats`` as a :class:`SolveStats`: the
backend's own statistics as it reported them (``backend``: each backend names its own, e.g.
``message``, ``interrupted``, ``claimed_cost``) and what the orchestration adds, as typed fields
(the warm start, whether its assignment was kept, the conflicting constraint families of an
infeasible model). It reads as the read-only mapping it always was, in the order report.json
writes it (:meth:`SolveStats.as_dict` is that one conversion at the edge), so
``solution.stats["warm_start"]["method"]`` and ``solution.stats.warm_start.method`` agree.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

__all__ = ["SolveStats", "WarmStartInfo"]


@dataclass(frozen=True)
class WarmStartInfo:
    """What a warm start did.

    Parameters
    ----------
    method : str
        The concrete policy that ran (``"none"`` when none did).
    objective : int, optional
        The objective of its assignment.
    seconds : float
        How long it took (rounded to the millisecond).
    bound : float, optional
        A proven lower bound of the objective it found, handed to backends that
        ``accepts_lower_bound``.
    proves_bound : bool
        True when the warm start looks for a bound at all (its statistics then name the
        ``bound``, found or not).
    """

    method: str
    objective: int | None = None
    seconds: float = 0.0
    bound: float | None = None
    proves_bound: bool = False

    def as_stats(self) -> dict[str, Any]:
        """The JSON form ``Solution.stats["warm_start"]`` and report.json carry."""
        out: dict[str, Any] = {"method": self.method}
        if self.proves_bound:
            out["bound"] = self.bound
        if self.objective is not None:
            out["objective"] = self.objective
            out["seconds"] = self.seconds
        return out


@dataclass(frozen=True)
class SolveStats(Mapping[str, Any]):
    """The statistics of one :func:`~illuknit.solvers.solve`, typed; read-only mapping too.

    Parameters
    ----------
    backend : mapping
        The backend's own statistics, as it reported them.
    warm_start : WarmStartInfo
        The warm start that ran before the backend (method ``"none"`` when none did).
    kept_warm_start : bool
        True when the answer is the warm start's (the backend did no better).
    infeasible_families : tuple of str, optional
        For an infeasible model, the hard-constraint families that conflict.

    Examples
    --------
    >>> s = SolveStats({"message": "ok"}, WarmStartInfo("dp", 3, 0.5))
    >>> dict(s)
    {'message': 'ok', 'warm_start': {'method': 'dp', 'objective': 3, 'seconds': 0.5}}
    >>> s.warm_start.objective == s["warm_start"]["objective"]
    True
    """

    backend: Mapping[str, Any] = field(default_factory=dict)
    warm_start: WarmStartInfo = WarmStartInfo("none")
    kept_warm_start: bool = False
    infeasible_families: tuple[str, ...] | None = None
    _items: Mapping[str, Any] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "backend", MappingProxyType(dict(self.backend)))
        object.__setattr__(self, "_items", MappingProxyType(self.as_dict()))

    def as_dict(self) -> dict[str, Any]:
        """The statistics as one plain dict, in report order: the backend's, then the warm
        start, whether it was kept, the conflicting families (a key the backend reported keeps
        its place)."""
        out = {**self.backend, "warm_start": self.warm_start.as_stats()}
        if self.kept_warm_start:
            out["kept_warm_start"] = True
        if self.infeasible_families is not None:
            out["infeasible_families"] = list(self.infeasible_families)
        return out

    def __getitem__(self, key: str) -> Any:
        return self._items[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)
