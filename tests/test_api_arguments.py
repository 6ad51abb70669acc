"""Every public function of ``illuknit`` (``illuknit._API``), given an argument of a wrong type or
value, raises an :class:`~illuknit.IlluknitError` subclass -- never a bare ``TypeError``,
``AttributeError`` or ``ValueError`` from deep inside -- and the message names the argument.

Each function gets one small valid call (``VALID``); then each of its parameters in turn is
replaced by every value of ``BAD`` (and, in a hypothesis test, by arbitrary garbage). A call
may also succeed (``None`` is a fine ``time_limit``); what it may not do is fail with anything
but an ``IlluknitError``. Machine arguments (a name or a ``MachineSpec``) are checked by their
own tests and skipped here.
"""

from __future__ import annotations

import inspect
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import illuknit
from illuknit import IlluknitError

warnings.filterwarnings("ignore", category=UserWarning)


def _pattern() -> illuknit.LogicalPattern:
    rng = np.random.default_rng(3)
    return illuknit.LogicalPattern(
        rng.integers(0, 2, (4, 4)),
        rng.random((4, 4)) < 0.5,
        illuknit.parse_yarns("black=#1b1b1b,white=#f4f0e8"),
    )


def _valid_calls(tmp: Path) -> dict[str, tuple[tuple[Any, ...], dict[str, Any]]]:
    p = _pattern()
    yarns = p.yarns
    pattern_file = tmp / "p.json"
    illuknit.save_pattern(p, pattern_file)
    rgb = np.random.default_rng(0).random((6, 6, 3))
    picture = tmp / "pic.png"
    from PIL import Image

    Image.fromarray((rgb * 255).astype(np.uint8)).save(picture)
    target = (np.arange(16).reshape(4, 4) % 2).astype(np.int16)
    q = illuknit.quantise_image(rgb, yarns=yarns)
    bank = illuknit.canonical_bank(yarns)
    problem = illuknit.build_model.__globals__["make_problem"](target, target, n_yarns=2)
    params_file = tmp / "params.json"
    from illuknit.design.render.params import save_params

    save_params(illuknit.RenderParams(), params_file)
    bank_file = tmp / "bank.json"
    from illuknit.design.tiles.bank import save_bank

    save_bank(bank, bank_file)
    from illuknit.design.render.calibrate import Measurement

    ms = [Measurement(2, 40.0, 1, "A", "", 1), Measurement(3, 30.0, 1, "A", "", 2)]
    qa = illuknit.quantise_image(np.tile(rgb[:, :1], (1, 6, 1)), yarns=yarns)
    knitout = ";!knitout-2\n;;Carriers: 1 2 3\n"
    tiled = illuknit.design_tiles(qa, qa, search=illuknit.SearchOptions(candidates=1, pool=1)).best
    return {
        "parse_yarns": (("black,white",), {}),
        "save_pattern": ((p, tmp / "out.json"), {}),
        "load_pattern": ((pattern_file,), {}),
        "can_see": ((p, "A"), {}),
        "view_a": ((p,), {}),
        "view_b": ((p,), {}),
        "view_headon": ((p,), {}),
        "logical_error": ((target, target), {}),
        "load_image": ((picture,), {}),
        "resize_to_units": ((rgb,), {"width": 3}),
        "quantise_image": ((rgb,), {"n_colors": 2}),
        "draw_text": (("AB",), {"shape": (10, 20)}),
        "draw_shape": (("circle", (8, 8)), {}),
        "skimage_image": (("camera", (8, 8)), {}),
        "compile_single_view": ((q,), {}),
        "write_previews": ((p, tmp / "previews"), {}),
        "written_instructions": ((p,), {}),
        "knit_pattern": ((p,), {}),
        "check_knitout": ((knitout,), {}),
        "canonical_bank": ((yarns,), {}),
        "load_bank": ((bank_file,), {}),
        "assign_tiles": ((qa, qa), {"candidates": 1, "time_limit": 5}),
        "compile_tiles": (
            (illuknit.assign_tiles(qa, qa, candidates=1, time_limit=5)[0],),
            {},
        ),
        "assign_headon": ((qa,), {"candidates": 1, "time_limit": 5}),
        "load_params": ((params_file,), {}),
        "render_views": ((p,), {}),
        "render_pattern": ((p,), {}),
        "render_at": ((p, 30.0), {}),
        "optimise_design": ((rgb, rgb, yarns), {"steps": 2}),
        "calibration_swatch": ((), {}),
        # the design stages (docs/library.md); one small search each
        "design_single": ((picture,), {}),
        "design_double": (
            (picture, picture),
            {"search": illuknit.SearchOptions(candidates=1, pool=1)},
        ),
        "design_headon": ((picture,), {"search": illuknit.SearchOptions(candidates=1, pool=1)}),
        "design_tiles": ((q, q), {"search": illuknit.SearchOptions(candidates=1, pool=1)}),
        "measure_design": ((tiled.pattern, "double", qa, qa), {}),
        "retile_design": ((tiled.assignment, {tiled.assignment.pairs[0]: "0/1"}), {}),
        "solve_design": ((picture, picture), {"options": illuknit.SolveOptions(solver="dp")}),
        "illusion_model": ((picture, picture), {}),
        "quantise_targets": ((picture, picture), {}),
        "resolve_machine": (("swg091n2",), {}),
        "fit_bump_height": ((ms,), {}),
        "build_model": ((problem,), {}),
        "solve_illusion": ((target, target), {"solver": "dp", "time_limit": 5}),
        "pattern_from_solution": (
            (problem, illuknit.solve_illusion(target, target, solver="dp").solution),
            {},
        ),
        "report_pattern": ((p, problem), {}),
        # the IR classes people construct themselves
        "LogicalPattern": ((p.yarn, p.raised, yarns), {}),
        "Yarn": (("navy", (0, 0, 128)), {}),
        "RenderParams": ((), {}),
        "KnitWeights": ((), {}),
        "Tile": ((np.zeros((2, 1), int), np.array([[True], [False]])), {}),
        "IllusionProblem": ((target, target, 2), {}),
    }


#: Arguments of a wrong type or value, for any parameter.
BAD: list[Any] = [None, "nonsense", -1, 0, 2.5, math.nan, math.inf, True, object(), [1, 2], b"\x00"]
#: Parameters checked elsewhere or taking any value by design.
SKIP = {"machine", "callback", "progress", "meta", "title", "name", "options"}


def _params(fn: Any) -> list[inspect.Parameter]:
    return [
        p
        for p in inspect.signature(fn).parameters.values()
        if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL) and p.name not in SKIP
    ]


def _call_with(
    fn: Any, args: tuple[Any, ...], kwargs: dict[str, Any], param: inspect.Parameter, value: Any
):
    names = [p.name for p in inspect.signature(fn).parameters.values()]
    args = list(args)
    i = names.index(param.name)
    if param.kind is param.KEYWORD_ONLY or i >= len(args):
        kwargs = {**kwargs, param.name: value}
    else:
        args[i] = value
    return fn(*args, **kwargs)


def _plain_errors(fn_name: str, fn: Any, args, kwargs, values, params=None) -> list[str]:
    bad = []
    for param in _params(fn) if params is None else params:
        for value in values:
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    _call_with(fn, args, kwargs, param, value)
            except IlluknitError as exc:
                # A required argument given as None: the message names it.
                required = value is None and param.default is inspect.Parameter.empty
                if required and f"`{param.name}`" not in str(exc):
                    bad.append(
                        f"{fn_name}({param.name}=None): message {str(exc)!r} does not name it"
                    )
            except Exception as exc:  # the point of the test
                bad.append(f"{fn_name}({param.name}={value!r}): {type(exc).__name__}: {exc}"[:300])
    return bad


@pytest.fixture(scope="module", autouse=True)
def _inside_a_scratch_folder(tmp_path_factory):
    """Bad values are also used as paths (``save_pattern(p, "nonsense")`` is a valid call that
    writes a file): run every call inside a scratch folder so none lands in the checkout."""
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(tmp_path_factory.mktemp("cwd"))
        yield


@pytest.fixture(scope="module")
def valid(tmp_path_factory):
    return _valid_calls(tmp_path_factory.mktemp("api"))


def test_every_public_function_has_a_valid_call_here(valid):
    """(``schedule_mixed`` takes a lowered ``StitchPattern`` and is checked in tests/knit.)"""
    functions = {
        name
        for name in illuknit._API
        if inspect.isfunction(getattr(illuknit, name)) and name not in ("schedule_mixed",)
    }
    assert functions <= set(valid), sorted(functions - set(valid))


def test_valid_calls_succeed(valid):
    for name, (args, kwargs) in valid.items():
        getattr(illuknit, name)(*args, **kwargs)


def test_bad_arguments_raise_illuknit_errors(valid):
    problems = []
    for name, (args, kwargs) in sorted(valid.items()):
        problems += _plain_errors(name, getattr(illuknit, name), args, kwargs, BAD)
    assert not problems, "\n".join(problems)


garbage = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=5),
    st.binary(max_size=5),
    st.lists(st.integers(-3, 3), max_size=3),
    st.dictionaries(st.text(max_size=2), st.integers(), max_size=2),
)

CHEAP = [
    "parse_yarns",
    "can_see",
    "view_a",
    "view_b",
    "view_headon",
    "logical_error",
    "resize_to_units",
    "quantise_image",
    "draw_text",
    "draw_shape",
    "compile_single_view",
    "written_instructions",
    "canonical_bank",
    "calibration_swatch",
    "fit_bump_height",
    "build_model",
    "report_pattern",
    "load_pattern",
    "load_params",
    "load_bank",
]


@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.data())
def test_garbage_arguments_raise_illuknit_errors(valid, data):
    name = data.draw(st.sampled_from(CHEAP))
    fn = getattr(illuknit, name)
    args, kwargs = valid[name]
    param = data.draw(st.sampled_from(_params(fn)))
    value = data.draw(garbage)
    assert not _plain_errors(name, fn, args, kwargs, [value], [param])
