"""Every public callable of ``illuknit`` (the exports of ``illuknit`` and ``illuknit.solvers``,
enumerated, not listed by hand), given an argument of a wrong type or value, raises an
:class:`~illuknit.IlluknitError` subclass whose message names that argument -- never a bare
``TypeError``, ``AttributeError``, ``OverflowError`` or ``ValueError`` from deep inside -- and
never accepts a value no caller can mean (NaN, 10**30, a string for a number, None where no
default is None, ...).

The engine is ``benchmarks/fuzz_library.py`` (which prints the same counts): one small valid call
of each callable, then each argument replaced in turn by each wrong value of ``BAD``, and, in a
hypothesis test, by arbitrary garbage. The numeric ranges of machine parameters are the machine
parameter table's, tested with it; here they are tried with wrong types only.
"""

from __future__ import annotations

import importlib.util
import inspect
import math
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import illuknit

warnings.filterwarnings("ignore", category=UserWarning)

_PATH = Path(__file__).resolve().parents[1] / "benchmarks" / "fuzz_library.py"
_spec = importlib.util.spec_from_file_location("fuzz_library", _PATH)
assert _spec is not None and _spec.loader is not None
fuzz = importlib.util.module_from_spec(_spec)
sys.modules["fuzz_library"] = fuzz  # dataclasses look their module up by name
_spec.loader.exec_module(fuzz)

PUBLIC = fuzz.public_callables()


@pytest.fixture(scope="module", autouse=True)
def _inside_a_scratch_folder(tmp_path_factory):
    """Bad values are also used as paths (``save_pattern(p, "xyz")`` is a valid call that
    writes a file): run every call inside a scratch folder so none lands in the checkout."""
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(tmp_path_factory.mktemp("cwd"))
        yield


@pytest.fixture(scope="module")
def valid(tmp_path_factory):
    return fuzz.valid_calls(tmp_path_factory.mktemp("api"))


def test_the_public_callables_are_enumerated_from_the_exports():
    """Every export of ``illuknit`` and ``illuknit.solvers`` that can be called is here (enums
    aside), so a new export is fuzzed or given a reason: the list cannot go stale."""
    exported = {n for n in illuknit._API if callable(getattr(illuknit, n))}
    assert {n for n in PUBLIC if "." not in n} <= exported
    assert {"solve_design", "MachineSpec", "TileBank", "solvers.solve"} <= set(PUBLIC)


def test_every_public_callable_has_a_valid_call_or_a_reason(valid):
    missing = set(PUBLIC) - set(valid) - set(fuzz.EXEMPT)
    assert not missing, f"give these a valid call in benchmarks/fuzz_library.py: {sorted(missing)}"
    assert not set(valid) & set(fuzz.EXEMPT)
    assert set(valid) <= set(PUBLIC)


def test_valid_calls_succeed(valid):
    for name, (args, kwargs) in valid.items():
        PUBLIC[name](*args, **kwargs)


@pytest.mark.parametrize("name", sorted(set(PUBLIC) - set(fuzz.EXEMPT)))
def test_wrong_arguments_are_refused_naming_them(valid, name):
    """Each argument of ``name`` replaced by each value of ``BAD``: 0 raw exceptions, 0 errors
    that blame another argument, 0 absurd values accepted."""
    problems = [o for o in fuzz.fuzz(valid, [name]) if o.kind in ("raw", "blame", "absurd")]
    assert not problems, "\n".join(map(str, problems))


@pytest.mark.parametrize(
    ("name", "argument", "value"),
    [
        ("MachineSpec", "gauge", None),
        ("TileBank", "tiles", "xyz"),
        ("design_double", "progress", "xyz"),
        ("solve_illusion", "n_yarns", 10**30),
        ("TileBank", "split_share", math.nan),
        ("check_knitout", "simulate", None),
        ("solvers.solve", "seed", "xyz"),
        ("design_single", "knit_on", 3),
        ("view_a", "raised", object()),
        ("compile_tiles", "overrides", {"x": 0}),
        ("assign_headon", "side", "xyz"),
    ],
)
def test_the_cases_of_issue_34(valid, name, argument, value):
    """The calls the issue found (and hypothesis after it): each refused with a library error
    naming the argument."""
    fn = PUBLIC[name]
    param = inspect.signature(fn).parameters[argument]
    outcome = fuzz.try_one(name, fn, valid[name], param, fuzz.label_of(value), value)
    assert outcome.kind == "refused", outcome


def test_render_at_takes_a_signed_angle_and_nothing_beyond_90(valid):
    """-7 is view B at 7 degrees (documented), so it is allowed; -91 and 0 are not."""
    p = valid["render_at"][0][0]
    assert illuknit.render_at(p, -7).shape == illuknit.render_pattern(p, view="B", angle=7).shape
    for angle in (-91, 0, 91):
        with pytest.raises(illuknit.IlluknitError, match="`angle`"):
            illuknit.render_at(p, angle)


def test_the_absurd_judge():
    """What counts as absurd: None only where no default is None, text only where text goes,
    a fraction only where a float goes; NaN, infinity and 10**30 everywhere."""
    assert fuzz.absurd("int", 0, "None") and not fuzz.absurd("int | None", None, "None")
    assert fuzz.absurd("float", 1.0, "str") and not fuzz.absurd("str | os.PathLike[str]", 1, "str")
    assert fuzz.absurd("int", 1, "fraction") and not fuzz.absurd("float", 1.0, "fraction")
    assert fuzz.absurd("int", 1, "bool") and not fuzz.absurd("bool", True, "bool")
    assert all(fuzz.absurd("Any", None, label) for label in ("nan", "inf", "huge", "object"))
    assert fuzz.label_of(2.0) is None and fuzz.label_of(10**30) == "huge"


garbage = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=5),
    st.binary(max_size=5),
    st.lists(st.integers(-3, 3), max_size=3),
    st.dictionaries(st.text(max_size=2), st.integers(), max_size=2),
    hnp.arrays(
        st.sampled_from([np.float64, np.int64, np.bool_, np.dtype("U2"), np.complex128]),
        hnp.array_shapes(min_dims=0, max_dims=4, max_side=3),
    ),
)

#: Callables fast enough to call hundreds of times (the design stages run a search each).
CHEAP = sorted(
    {
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
        "compile_tiles",
        "retile_design",
        "written_instructions",
        "canonical_bank",
        "calibration_swatch",
        "fit_bump_height",
        "build_model",
        "report_pattern",
        "load_pattern",
        "load_params",
        "load_bank",
        "render_at",
        "LogicalPattern",
        "Yarn",
        "QuantisedImage",
        "SearchOptions",
        "RankOptions",
        "SolveOptions",
        "KnitOptions",
        "MachineSpec",
        "Tile",
        "TileBank",
        "RenderParams",
        "KnitWeights",
        "IllusionProblem",
        "Model",
        "solvers.parse_solver_name",
        "solvers.get_backend",
        "solvers.solve",
    }
)


@settings(
    max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.data())
def test_garbage_arguments_are_refused_naming_them(valid, data):
    name = data.draw(st.sampled_from(CHEAP))
    fn = PUBLIC[name]
    param = data.draw(st.sampled_from(fuzz.arguments(fn)))
    value: Any = data.draw(garbage)
    label = fuzz.label_of(value)
    if fuzz.left_to_machine_table(name, param.name, label):
        return
    outcome = fuzz.try_one(name, fn, valid[name], param, label, value)
    assert outcome.kind not in ("raw", "blame", "absurd"), outcome


@pytest.mark.parametrize(
    ("message", "value", "names"),
    [
        # a file name is shown escaped, as every message shows one (found: load_params("\x1f"))
        ("render parameters file not found: \\x1f", "\x1f", True),
        ("render parameters file not found: somewhere.json", "somewhere.json", True),
        ("something went wrong", "\x1f", False),
    ],
)
def test_a_name_shown_escaped_counts_as_named(message, value, names):
    assert fuzz._names_it(message, "path", value) is names


@pytest.mark.parametrize("spec", ["=", "navy=", "navy= ,#fff"])
def test_a_yarn_without_a_colour_names_the_spec(spec):
    # found by the fuzz: parse_yarns("=") said "empty yarn colour string", naming no argument
    from illuknit.core.errors import YarnSpecError
    from illuknit.core.yarns import parse_yarns

    with pytest.raises(YarnSpecError, match=r"`spec` names a yarn without a colour"):
        parse_yarns(spec)
