"""Design methods compared by the benchmark, each behind one small adapter.

A method is one function ``run(instance, time_limit) -> (LogicalPattern, info)``: it draws the
instance's targets (:func:`illuknit.bench.instances.instance_targets`), designs a pattern with some
part of illuknit, and returns it with an ``info`` dict of what only the method knows:

=============  ==============================================================================
key            meaning
=============  ==============================================================================
status         ``optimal`` / ``feasible`` / ``timeout`` / ``infeasible`` (solvers) or ``ok``
objective      the method's own objective value (solvers), else absent
bound          lower bound on the objective where the solver proves one
gap            ``(objective - bound) / max(objective, 1)`` where both are known
solve_s        seconds spent searching (model building excluded where the method separates it)
compile_s      seconds spent building models / compiling the result into a pattern
note           free text shown in the summary
=============  ==============================================================================

A method whose optional third-party library is missing raises :class:`MethodUnavailable`
(a :class:`~illuknit.core.errors.BackendUnavailableError`); the runner records the cell as
``skipped`` with that reason instead of failing. Register more methods with
:func:`register_method`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from illuknit.bench.instances import Instance, instance_targets
from illuknit.core.errors import BackendUnavailableError, UnknownNameError
from illuknit.core.pattern import LogicalPattern

__all__ = [
    "DEFAULT_METHODS",
    "METHODS",
    "Method",
    "MethodUnavailable",
    "NoPattern",
    "get_method",
    "method_names",
    "register_method",
]

RunFn = Callable[[Instance, float], tuple[LogicalPattern, dict[str, Any]]]


class MethodUnavailable(BackendUnavailableError):
    """The method cannot run in this install; the message says why (and what to install)."""


class NoPattern(Exception):
    """The method ran but found no pattern (e.g. a solver timed out before its first solution).

    The runner records the cell with ``status`` (e.g. ``timeout``) and the message as reason.
    """

    def __init__(self, message: str, *, status: str = "timeout") -> None:
        self.status = status
        super().__init__(message)


@dataclass(frozen=True)
class Method:
    """A benchmark method: a name, the instance kinds it applies to, and its adapter."""

    name: str
    run: RunFn
    description: str = ""
    kinds: tuple[str, ...] = ("double", "single")


METHODS: dict[str, Method] = {}

#: Methods run when ``--methods`` is not given (the paper's comparison plus ours).
DEFAULT_METHODS = ("tiles", "single", "dp", "rc2", "cpsat", "knit-aware", "gradient")


def register_method(method: Method, *, replace: bool = False) -> Method:
    """Add ``method`` to :data:`METHODS` (``replace=True`` to overwrite an existing name)."""
    if method.name in METHODS and not replace:
        raise ValueError(f"method {method.name!r} is already registered")
    METHODS[method.name] = method
    return method


def method_names() -> list[str]:
    return list(METHODS)


def get_method(name: str) -> Method:
    """The method called ``name``; unknown names raise an error listing the valid ones."""
    try:
        return METHODS[name]
    except KeyError:
        raise UnknownNameError("method", name, method_names()) from None


def _solution_info(sol: Any, compile_s: float) -> dict[str, Any]:
    status = getattr(sol.status, "value", str(sol.status))
    gap = sol.gap() if callable(getattr(sol, "gap", None)) else getattr(sol, "gap", None)
    return {
        "status": status,
        "objective": sol.objective,
        "bound": sol.bound,
        "gap": gap,
        "solve_s": sol.wall_time,
        "compile_s": compile_s,
        "note": "; ".join(
            f"{k}={v}"
            for k, v in (getattr(sol, "stats", {}) or {}).items()
            if k in ("message", "infeasible_families")
        ),
    }


# --- single-view push-button compiler ---------------------------------------------------------


def run_single(instance: Instance, time_limit: float) -> tuple[LogicalPattern, dict[str, Any]]:
    """Paper section 5: alternating stripe rows, raised where the picture has the row's colour."""
    from illuknit.design.single_view import compile_single_view

    t = instance_targets(instance)
    t0 = time.perf_counter()
    pattern = compile_single_view(t.a, yarns=instance.yarns)
    return pattern, {"status": "ok", "compile_s": time.perf_counter() - t0}


register_method(
    Method("single", run_single, "push-button single-view compiler (paper section 5)", ("single",))
)


# --- the paper's MaxSAT baseline and its exact / CP-SAT counterparts ----------------------------


def _solve_model(
    instance: Instance,
    time_limit: float,
    *,
    solver: str,
    model: str,
    warm_start: str,
    split_bumps: bool = False,
) -> tuple[LogicalPattern, dict[str, Any]]:
    """The pipeline's :func:`~illuknit.pipeline.stages.solve_design` on the instance's targets
    (:func:`~illuknit.bench.instances.stage_arguments`), as ``illuknit solve`` runs it."""
    from illuknit import solvers
    from illuknit.bench.instances import stage_arguments
    from illuknit.core.errors import SolverError
    from illuknit.design.options import ModelKind, SolveOptions, WarmStart
    from illuknit.pipeline.stages import solve_design

    if solver not in solvers.available_backends():
        raise MethodUnavailable(f"solver backend {solver!r} is not available in this install")
    kind = model if instance.kind == "double" else "single"
    a, b, kw = stage_arguments(instance)
    options = SolveOptions(
        model=ModelKind(kind),
        solver=solver,
        warm_start=WarmStart(warm_start),
        split_bumps=split_bumps,
        time_limit=time_limit,
    )
    t0 = time.perf_counter()
    try:
        res = solve_design(a, b, options=options, **kw)
    except SolverError as e:
        if "found no pattern" in str(e):
            raise NoPattern(f"no pattern within {time_limit:g} s ({e})") from None
        raise
    total = time.perf_counter() - t0
    sol = res.solution
    info = _solution_info(sol, compile_s=max(0.0, total - sol.wall_time))
    info["note"] = (f"model {kind}; warm start {warm_start}; " + info["note"]).rstrip("; ")
    ws = sol.stats.get("warm_start", {})
    if ws.get("method", "none") != "none":
        info["note"] += f"; {ws['method']} warm start {ws['objective']} in {ws['seconds']:.0f} s"
    info["note"] += f"; found by {sol.found_by}"
    return res.pattern, info


def _solver_method(
    name: str,
    solver: str,
    model: str,
    description: str,
    *,
    warm_start: str = "none",
    split_bumps: bool = False,
) -> Method:
    def run(instance: Instance, time_limit: float) -> tuple[LogicalPattern, dict[str, Any]]:
        return _solve_model(
            instance,
            time_limit,
            solver=solver,
            model=model,
            warm_start=warm_start,
            split_bumps=split_bumps,
        )

    run.__name__ = f"run_{name.replace('-', '_')}"
    kinds = ("double",) if split_bumps else ("double", "single")
    return Method(name, run, description, kinds)


register_method(
    _solver_method("dp", "dp", "logical", "exact per-wale dynamic programming, model (a)")
)
register_method(
    _solver_method("rc2", "rc2", "logical", "pysat RC2 MaxSAT, model (a): the paper's baseline")
)
register_method(_solver_method("cpsat", "cpsat", "logical", "OR-Tools CP-SAT, model (a)"))
register_method(
    _solver_method(
        "dp-split",
        "dp",
        "logical",
        "exact per-wale DP, model (a) with split bumps (docs/split-bumps.md)",
        split_bumps=True,
    )
)
register_method(
    _solver_method(
        "knit-aware",
        "cpsat",
        "knit-aware",
        "CP-SAT on the knit-time-aware model (b), warm-started by exact-block descent",
        warm_start="descent",
    )
)


# --- tiles (paper section 6) --------------------------------------------------------------------


def run_tiles(
    instance: Instance,
    time_limit: float,
    *,
    split_bumps: bool = False,
    split_share: float | None = None,
) -> tuple[LogicalPattern, dict[str, Any]]:
    """The tile design that reads best (paper section 6): the double-view stage
    (:func:`illuknit.pipeline.stages.design_tiles`) with the search ``illuknit double`` makes by
    default (each solve within ``time_limit``; with split bumps in the bank when asked), its
    first-ranked design compiled."""
    from illuknit.core.views import DEFAULT_SPLIT_SHARE
    from illuknit.design.options import SearchOptions
    from illuknit.pictures.images import QuantisedImage
    from illuknit.pipeline.stages import design_tiles

    t = instance_targets(instance)
    qa, qb = (QuantisedImage(idx, t.yarns, t.palette) for idx in (t.a, t.b))
    design = design_tiles(
        qa,
        qb,
        yarns=instance.yarns,
        search=SearchOptions(
            time_limit=time_limit,
            split_bumps=split_bumps,
            split_share=DEFAULT_SPLIT_SHARE if split_share is None else split_share,
        ),
    )
    best = design.best
    score = getattr(best.assignment, "score", None)
    return best.pattern, {
        "status": "ok",
        "objective": score if isinstance(score, int | float) else None,
        "solve_s": design.seconds["search"],
        "compile_s": design.seconds["rank"],
        "note": f"best-reading of {design.searched} candidates (score rank {best.score_rank})",
    }


register_method(Method("tiles", run_tiles, "tile assignment + compile (paper section 6)"))


def run_tiles_split(instance: Instance, time_limit: float) -> tuple[LogicalPattern, dict[str, Any]]:
    """:func:`run_tiles` with split bumps in the canonical bank."""
    return run_tiles(instance, time_limit, split_bumps=True)


register_method(
    Method(
        "tiles-split",
        run_tiles_split,
        "tile design whose bank holds split bumps (docs/split-bumps.md)",
        ("double",),
    )
)


# --- gradient descent through the differentiable renderer (paper section 8.3) ------------------

#: Adam steps of the gradient method (stopped early by the time limit).
GRADIENT_STEPS = 200


def run_gradient(instance: Instance, time_limit: float) -> tuple[LogicalPattern, dict[str, Any]]:
    """MSE between renders at ±30° and the targets, annealed and binarised (paper Fig. 19 b)."""
    from illuknit.design.render.optimise import optimise_design

    t = instance_targets(instance)
    t0 = time.perf_counter()
    res = optimise_design(t.a, t.b, instance.yarns, steps=GRADIENT_STEPS, time_limit=time_limit)
    wall = time.perf_counter() - t0
    rep = dict(res.report)
    steps = rep.get("steps", len(res.history))
    return res.pattern, {
        "status": "ok" if steps >= GRADIENT_STEPS else "timeout",
        "objective": float(res.history[-1]) if len(res.history) else None,
        "solve_s": wall,
        "note": f"{steps} Adam steps",
    }


register_method(
    Method("gradient", run_gradient, "gradient descent through the renderer (paper 8.3)")
)
