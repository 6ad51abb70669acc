"""The solver layer knows no knitting: domain backends register, capabilities are flags, old
import paths of what moved still work for a release with a DeprecationWarning."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np
import pytest

from illuknit.core.errors import ModelError
from illuknit.design.models.illusion_models import build_model, make_problem
from illuknit.pictures.drawings import draw_ecg, draw_heart
from illuknit.solvers import REGISTRY, BackendKind, backend_names, get_backend, solve
from illuknit.solvers.model import DomainPayload, Model
from illuknit.solvers.warm_start import WarmStartInfo, warm_start_policies

#: (old module, a name it held, the module that holds it now)
MOVED = [
    ("illuknit.design.models.model", "Model", "illuknit.solvers.model"),
    ("illuknit.design.models.var_pool", "VarPool", "illuknit.solvers.var_pool"),
    ("illuknit.design.models.cnf_encodings", "encode_card", "illuknit.solvers.cnf_encodings"),
    ("illuknit.solvers.dp", "solve_dp", "illuknit.design.models.backends.dp"),
    ("illuknit.solvers.descent", "optimise_descent", "illuknit.design.models.backends.descent"),
    (
        "illuknit.solvers.descent_blocks",
        "pattern_cost",
        "illuknit.design.models.backends.descent_blocks",
    ),
    ("illuknit.solvers.gradient", "GradientBackend", "illuknit.design.models.backends.gradient"),
    (
        "illuknit.solvers.lagrangian",
        "lagrangian_bound",
        "illuknit.design.models.backends.lagrangian",
    ),
    ("illuknit.solvers.warm_start", "WARM_STARTS", "illuknit.design.models.backends.warm_start"),
]


@pytest.mark.parametrize(("old", "name", "new"), MOVED)
def test_an_old_import_path_warns_and_gives_the_same_object(old, name, new):
    module = importlib.import_module(old)
    with pytest.warns(DeprecationWarning, match=f"{old}.{name} moved to {new}.{name}"):
        value = getattr(module, name)
    assert value is getattr(importlib.import_module(new), name)


def test_an_unknown_name_on_an_old_path_is_an_attribute_error():
    module = importlib.import_module("illuknit.solvers.dp")
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        module.no_such_name  # noqa: B018


def test_the_solver_layer_loads_without_design():
    code = (
        "import sys, illuknit.solvers, illuknit.solvers.model, illuknit.solvers.warm_start\n"
        "print(sorted(m for m in sys.modules if m.startswith('illuknit.design')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_design_registers_its_backends_in_preference_order():
    names = backend_names()
    assert names[:7] == ["dp", "cpsat", "rc2", "lsu", "fm", "gradient", "descent"]
    assert REGISTRY["dp"] == "illuknit.design.models.backends.dp:DPBackend"
    assert warm_start_policies() == ("none", "dp", "descent", "hand", "auto")


def test_capabilities_are_declared_flags():
    dp, descent, gradient = (get_backend(n) for n in ("dp", "descent", "gradient"))
    cpsat, rc2 = get_backend("cpsat"), get_backend("rc2")
    assert {b.kind for b in (dp, descent, gradient)} == {BackendKind.DOMAIN}
    assert (cpsat.kind, rc2.kind) == (BackendKind.CP, BackendKind.MAXSAT)
    assert not dp.accepts_warm_start and not descent.accepts_warm_start
    assert gradient.accepts_warm_start and rc2.accepts_warm_start
    assert cpsat.accepts_lower_bound and not rc2.accepts_lower_bound
    assert dp.exact and dp.proves_bound and not gradient.exact and not gradient.proves_bound


def test_dp_solves_a_built_model_by_name_and_refuses_a_plain_one():
    a = draw_heart((8, 6)).astype(np.int16)
    b = draw_ecg((8, 6)).astype(np.int16)
    sol = solve(build_model(make_problem(a, b)), solver="dp")
    assert sol.backend == "dp" and sol.status.value == "optimal"
    assert get_backend("dp").why_not(Model("plain")) is not None


def test_the_payload_is_typed():
    with pytest.raises(ModelError, match="DomainPayload"):
        Model("m", problem={"target": 1})  # type: ignore[arg-type]
    assert not DomainPayload().separable


def test_warm_start_info_keeps_the_report_keys_in_order():
    assert WarmStartInfo("dp", 3, 0.25).as_stats() == {
        "method": "dp",
        "objective": 3,
        "seconds": 0.25,
    }
    descent = WarmStartInfo("descent", 3, 0.5, None, proves_bound=True).as_stats()
    assert list(descent) == ["method", "bound", "objective", "seconds"]
    assert WarmStartInfo("none").as_stats() == {"method": "none"}


def test_solve_statistics_are_typed_and_read_as_the_report_mapping():
    a = draw_heart((8, 6)).astype(np.int16)
    b = draw_ecg((8, 6)).astype(np.int16)
    sol = solve(build_model(make_problem(a, b)), solver="rc2", warm_start="dp")
    typed = sol.solve_stats
    assert typed is not None and typed.warm_start.method == "dp"
    assert sol.stats["warm_start"] == typed.warm_start.as_stats()
    assert list(sol.summary()["stats"])[-2:] == ["warm_start", "kept_warm_start"] or (
        list(sol.summary()["stats"])[-1] == "warm_start"
    )
    assert get_backend("rc2").solve(build_model(make_problem(a, b))).solve_stats is None
