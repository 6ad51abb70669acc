"""Smoke-test every solver backend on a tiny instance: does it answer, here, within a limit?

``available: yes`` only says a backend's library imports. :func:`smoke_test_backends` runs each
installed backend, like one benchmark row (:func:`illuknit.bench.solver_runs.run_solver_task`:
its own process, the time and memory limits enforced from outside, the answer verified), on the
logical model of a 8 x 8 two-yarn instance (192 variables) whose optimum the exact DP knows, and
says

* ``answers`` -- a verified assignment at the optimum (``answers (not optimal: C)`` when
  its cost is above it, ``answers, but its claim is false: ...`` when a claim was flagged);
* ``returns nothing`` -- no assignment within the limit (it timed out, exited or crashed
  without one; the reason follows);
* and, separately, whether the backend can be time-limited: ``cannot be time-limited`` marks
  the solvers that refuse a limit (only the benchmark's kill stops them; they are run under
  that external limit).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from illuknit.bench.instances import Instance
from illuknit.bench.solver_runs import SolverTask, run_solver_task
from illuknit.core.pattern import Yarn

__all__ = ["SMOKE_INSTANCE", "smoke_test_backends"]

#: The tiny instance every backend is tried on.
SMOKE_INSTANCE = Instance(
    "smoke-plus-circle",
    "double",
    (8, 8),
    (Yarn("dark", (20, 20, 20)), Yarn("cream", (240, 236, 230))),
    5.0,
    {"A": {"draw": "plus"}, "B": {"draw": "circle"}},
)


def _verdict(row: dict[str, Any]) -> str:
    cost, opt = row.get("verified_cost"), row.get("reference_optimum")
    if row.get("status") == "n/a":
        return f"n/a ({row.get('reason')})"
    if cost is None:
        why = row.get("reason") or row.get("status")
        return f"returns nothing in {row['time_limit']:g} s ({row.get('status')}: {why})"
    if row.get("flag"):
        return f"answers, but its claim is false: {row['flag']}"
    secs = row.get("wall_s") or 0.0
    if opt is not None and cost > opt:
        return f"answers (not optimal: {cost} > {opt}, {secs:.1f} s)"
    if row.get("status") != "optimal":
        return f"answers ({cost} in {secs:.1f} s, {row.get('status')}: not proven in time)"
    return f"answers ({cost} in {secs:.1f} s)"


def smoke_test_backends(
    names: Sequence[str] | None = None,
    *,
    time_limit: float = 5.0,
    memory_mb: float = 2048.0,
    on_result: Callable[[dict[str, str]], None] | None = None,
) -> list[dict[str, str]]:
    """One dict per backend: name, kind, version, available, ``smoke`` (see the module
    docstring) and ``limit`` ("yes" or "cannot be time-limited (...)")."""
    from illuknit.solvers import describe_backends, get_backend

    out = []
    for desc in describe_backends():
        if names is not None and desc["name"] not in names:
            continue
        entry = dict(desc)
        if desc["available"] != "yes":
            entry.update(smoke="-", limit="-")
        else:
            backend = get_backend(desc["name"])
            limited = backend.time_limited
            entry["limit"] = (
                "yes" if limited else "cannot be time-limited (runs under the external limit)"
            )
            task = SolverTask(
                SMOKE_INSTANCE, "logical", desc["name"], "none", time_limit, memory_mb
            )
            entry["smoke"] = _verdict(run_solver_task(task)["row"])
        out.append(entry)
        if on_result is not None:
            on_result(entry)
    return out
