"""Each option is declared once, on its frozen option class (illuknit.core.declared), and the
class refuses exactly what its declaration's range leaves out."""

from __future__ import annotations

import math
from dataclasses import dataclass

import pytest

from illuknit.core.declared import Declared, declared_options, option
from illuknit.core.errors import OptionError
from illuknit.design.options import RankOptions, SearchOptions, SolveOptions
from illuknit.knit.options import KnitOptions

CLASSES = (KnitOptions, SearchOptions, RankOptions, SolveOptions)


def _edges(opt):
    """(values the declaration takes, values it refuses) at the ends of its range."""
    low, high, low_open, high_open = opt.declared.bounds
    step = 1 if opt.base_type is int else 1e-9
    inside, outside = [], []
    for bound, is_open, sign in ((low, low_open, 1), (high, high_open, -1)):
        if bound is None:
            continue
        if opt.base_type is int:
            bound = int(bound)
        inside.append(bound + sign * step if is_open else bound)
        outside.append(bound if is_open else bound - sign * step)
    return inside, outside


NUMERIC = [
    (cls, opt)
    for cls in CLASSES
    for opt in declared_options(cls).values()
    if opt.base_type in (int, float)
]


@pytest.mark.parametrize(
    ("cls", "opt"), NUMERIC, ids=[f"{c.__name__}.{o.name}" for c, o in NUMERIC]
)
def test_the_class_refuses_what_the_declared_range_leaves_out(cls, opt):
    low, high, _, _ = opt.declared.bounds
    assert low is not None and high is not None, f"{opt.name} declares no finite range"
    inside, outside = _edges(opt)
    for value in inside:
        assert opt.declared.contains(value)
        assert getattr(cls(**{opt.name: value}), opt.name) == pytest.approx(value)
    for value in outside:
        assert not opt.declared.contains(value)
        with pytest.raises(OptionError, match=opt.name):
            cls(**{opt.name: value})


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_every_declared_default_is_the_class_default(cls):
    made = cls()
    opts = declared_options(cls)
    assert opts, f"{cls.__name__} declares no option"
    for name, opt in opts.items():
        assert getattr(made, name) == opt.default
        assert opt.declared.help.strip(), name
        if opt.choices is not None:  # an enum's words are what the CLI and the app take
            assert opt.cli_default in opt.choices


def test_a_declaration_reads_its_range():
    d = Declared(help="h", gt=0, le=90)
    assert d.bounds == (0, 90, True, False)
    assert not d.contains(0) and d.contains(90) and not d.contains(math.nextafter(90, 100))


def test_fields_made_without_option_are_not_declared():
    @dataclass(frozen=True)
    class Opts:
        seed: int = option(0, help="Random seed.", ge=0, le=9)
        note: str = ""
        limit: float | None = option(None, help="Seconds.", gt=0, le=60, title="Limit (s)")

    opts = declared_options(Opts)
    assert list(opts) == ["seed", "limit"]
    assert opts["limit"].base_type is float and opts["limit"].title == "Limit (s)"
    assert opts["seed"].flag == "--seed" and opts["seed"].title == "Seed"


def test_search_options_take_solve_seconds_for_one_release():
    from dataclasses import replace

    with pytest.warns(DeprecationWarning, match="`solve_seconds` is deprecated.*`time_limit`"):
        old = SearchOptions(solve_seconds=4.0, candidates=2)
    assert old == SearchOptions(time_limit=4.0, candidates=2)
    with pytest.warns(DeprecationWarning, match=r"solve_seconds.*time_limit"):
        assert old.solve_seconds == 4.0  # still read, with a warning
    assert replace(old, pool=3).time_limit == 4.0
    with pytest.raises(TypeError, match="not both"):
        SearchOptions(solve_seconds=1.0, time_limit=2.0)
    with pytest.raises(OptionError, match="time_limit"), pytest.warns(DeprecationWarning):
        SearchOptions(solve_seconds=-1.0)
