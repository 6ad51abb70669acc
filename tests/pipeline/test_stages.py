"""The design stages: typed results, ranks that explain themselves, inputs left as they were,
and a machine given by name or by spec everywhere."""

from __future__ import annotations

import copy
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit import (
    IlluknitError,
    KnitOptions,
    MachineSpec,
    RankBy,
    RankOptions,
    SearchOptions,
    SolveOptions,
    check_knitout,
    design_double,
    design_headon,
    design_single,
    design_tiles,
    illusion_model,
    knit_pattern,
    quantise_image,
    resolve_machine,
    schedule_mixed,
    solve_design,
)
from illuknit.core.errors import OptionError, SchedulingError, UnknownNameError
from illuknit.core.machine import MACHINES
from illuknit.core.pattern import pattern_to_json


def _pictures(rows: int = 8, cols: int = 10) -> tuple[np.ndarray, np.ndarray]:
    yy, xx = np.mgrid[0:rows, 0:cols]
    a = np.where(((xx + yy) % 5 < 2)[..., None], 25, 235).astype(np.uint8).repeat(3, axis=2)
    b = np.where((((xx - 5) ** 2 + (yy - 4) ** 2) < 10)[..., None], 25, 235)
    return a, b.astype(np.uint8).repeat(3, axis=2)


def _snapshot(obj):
    """A deep copy to compare against after a call."""
    return copy.deepcopy(obj)


def _same(before, after) -> bool:
    if isinstance(before, np.ndarray):
        return before.dtype == after.dtype and np.array_equal(before, after)
    if hasattr(before, "indices"):  # QuantisedImage
        return (
            np.array_equal(before.indices, after.indices)
            and np.array_equal(before.colors, after.colors)
            and before.yarns == after.yarns
        )
    return before == after


# -- results --------------------------------------------------------------------------------


def test_double_view_designs_are_ranked_with_their_keys():
    a, b = _pictures()
    d = design_double(a, b, search=SearchOptions(candidates=3, pool=4))
    assert d.mode == "double" and d.views == ("A", "B")
    assert [x.rank for x in d.designs] == list(range(1, len(d.designs) + 1))
    assert 1 <= len(d.designs) <= 3 and d.searched >= len(d.designs)
    keys = [x.rank_key for x in d.designs]
    assert keys == sorted(keys)  # the rank key is what the ranking sorted by
    assert d.best.rank_fields == RankBy.PERCEPTION.key_fields
    assert d.best.rank_key[0] == -d.best.measures.perceptual_score
    assert d.best.why().startswith("rank 1 by -perceptual score")
    assert "knitting minutes not measured" in d.best.why()  # not "inf" (no knitting asked)
    by_score = design_double(
        a, b, search=SearchOptions(candidates=3, pool=4), ranking=RankOptions(rank_by="score")
    )
    scores = [x.assignment.score for x in by_score.designs]
    assert scores == sorted(scores)


def test_single_view_ranks_by_the_worse_mismatch():
    a, _ = _pictures()
    d = design_single(a)
    assert {x.measures["first"] for x in d.designs} == {"dark", "light"}
    worse = [max(x.measures["mismatch_A"], x.measures["mismatch_B"]) for x in d.designs]
    assert worse == sorted(worse)
    assert d.first("light").pattern.shape == d.first("dark").pattern.shape


def test_solve_design_reports_the_solver_and_the_sources():
    a, b = _pictures()
    d = solve_design(a, b, options=SolveOptions(solver="dp"))
    assert d.solution.status.value == "optimal"
    assert d.report["solver"]["objective"] == d.solution.objective
    assert d.report["sources"] == {"A": None, "B": None}  # arrays have no path
    model = illusion_model(a, b, options=SolveOptions(solver="dp"))
    assert model.num_vars > 0


def test_options_are_validated_where_they_are_made():
    with pytest.raises(OptionError, match="rank_by"):
        RankOptions(rank_by="beauty")
    with pytest.raises(OptionError, match="candidates"):
        SearchOptions(candidates=0)
    with pytest.raises(OptionError, match="pool_seconds"):
        SearchOptions(pool_seconds=float("nan"))
    with pytest.raises(OptionError, match="alternate_rows"):
        SolveOptions(model="logical", alternate_rows=True)
    with pytest.raises(OptionError, match="catching"):
        KnitOptions(catching="glue")
    with pytest.raises(OptionError, match="overrides"):
        RankOptions(overrides={(0, -1): "0/1"})
    with pytest.raises(OptionError, match="search"):
        design_tiles(*(quantise_image(p, n_colors=2) for p in _pictures()), search={"pool": 3})  # type: ignore[arg-type]


# -- stages never change their inputs ---------------------------------------------------------


def test_tile_stages_leave_their_inputs_as_they_were():
    a, b = _pictures()
    qa, qb = quantise_image(a, n_colors=2), quantise_image(b, n_colors=2)
    search = SearchOptions(candidates=2, pool=2, edits="suggest")
    ranking = RankOptions(overrides=(((0, 1), "0/1"),))
    inputs = (a, b, qa, qb, search, ranking)
    before = [_snapshot(x) for x in inputs]
    design_double(a, b, search=search, ranking=ranking)
    design_headon(a, b, search=SearchOptions(candidates=2, pool=2))
    design_tiles(qa, qb, search=SearchOptions(candidates=2, pool=2), ranking=ranking)
    assert all(_same(x, y) for x, y in zip(before, inputs, strict=True))


def test_solve_leaves_the_model_it_was_given_as_it_was():
    from illuknit.solvers import solve

    a, b = _pictures()
    model = illusion_model(a, b)
    assert model.hint is None
    clauses = model.num_hard, model.num_soft
    sol = solve(model, solver="rc2", warm_start="dp", time_limit=30)
    assert sol.stats["warm_start"]["method"] == "dp"  # the warm start did run
    assert model.hint is None and (model.num_hard, model.num_soft) == clauses


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    rows=st.integers(3, 6),
    cols=st.integers(3, 6),
    seed=st.integers(0, 2**16),
)
def test_single_and_solve_stages_leave_random_pictures_as_they_were(rows, cols, seed):
    rng = np.random.default_rng(seed)
    a = rng.choice([20, 230], size=(rows, cols, 1)).astype(np.uint8).repeat(3, axis=2)
    b = rng.choice([20, 230], size=(rows, cols, 1)).astype(np.uint8).repeat(3, axis=2)
    before = (a.copy(), b.copy())
    options = SolveOptions(solver="dp")
    design_single(a)
    d = solve_design(a, b, options=options)
    yarn, raised = d.pattern.yarn.copy(), d.pattern.raised.copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # long floats are not this test's business
        knit_pattern(d.pattern, options=KnitOptions(allow_long_floats=True))
    assert np.array_equal(a, before[0]) and np.array_equal(b, before[1])
    assert options == SolveOptions(solver="dp")
    assert np.array_equal(yarn, d.pattern.yarn) and np.array_equal(raised, d.pattern.raised)


# -- a machine is a name or a MachineSpec everywhere --------------------------------------------


def _mixed_pattern():
    a, b = _pictures()
    return solve_design(a, b, options=SolveOptions(solver="dp")).pattern


def _knit(machine):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return knit_pattern(_mixed_pattern(), machine=machine, allow_long_floats=True).program


def _schedule(machine):
    from illuknit.knit.stitches import lower_to_stitches

    stitches = lower_to_stitches(_mixed_pattern(), machine=resolve_machine(machine))
    options = KnitOptions(allow_long_floats=True)
    return schedule_mixed(stitches, machine=machine, options=options).stats.as_dict()


def _check(machine):
    program = _knit("swg091n2")
    return check_knitout(program, machine=machine).to_text(name="p.k")


def _single(machine):
    a, _ = _pictures()
    return pattern_to_json(design_single(a, knit_on=machine).best.pattern)


def _solve(machine):
    a, b = _pictures()
    return pattern_to_json(
        solve_design(a, b, options=SolveOptions(solver="dp"), knit_on=machine).pattern
    )


def _model(machine):
    a, b = _pictures()
    return illusion_model(a, b, knit_on=machine).to_wcnf()


def _tiles(machine):
    a, b = _pictures()
    design = design_double(
        a,
        b,
        search=SearchOptions(candidates=1, pool=1),
        ranking=RankOptions(knit_time=True, machine=machine),
        knit_on=machine,
    )
    return design.best.measures.to_json()


def _headon(machine):
    a, _ = _pictures()
    return design_headon(
        a, search=SearchOptions(candidates=1, pool=1), knit_on=machine
    ).best.rank_key


#: every public call that takes a machine -> a function of the machine that returns its result
CALLS = {
    "knit_pattern": _knit,
    "schedule_mixed": _schedule,
    "check_knitout": _check,
    "design_single": _single,
    "design_double": _tiles,
    "RankOptions": _tiles,
    "design_headon": _headon,
    "solve_design": _solve,
    "illusion_model": _model,
    "resolve_machine": resolve_machine,
}


def test_every_public_call_taking_a_machine_is_tested_here():
    import inspect

    import illuknit

    taking = set()
    for name in illuknit.__all__:
        obj = getattr(illuknit, name)
        if not callable(obj) or name in ("KnitResult", "CheckReport"):  # results, not calls
            continue
        try:
            params = inspect.signature(obj).parameters
        except (TypeError, ValueError):
            continue
        if "machine" in params or "knit_on" in params:
            taking.add(name)
    assert taking == set(CALLS)


@pytest.mark.parametrize("call", sorted(CALLS))
def test_a_machine_name_and_its_spec_give_the_same_result(call):
    name = "kniterate" if call != "check_knitout" else "swg091n2"
    assert CALLS[call](name) == CALLS[call](MACHINES[name])


@pytest.mark.parametrize("call", sorted(CALLS))
def test_an_unknown_machine_name_is_refused_with_the_valid_ones(call):
    with pytest.raises(UnknownNameError, match=r"unknown machine 'swg09'; valid: .*kniterate") as e:
        CALLS[call]("swg09")
    assert isinstance(e.value, IlluknitError) and "swg091n2" in e.value.valid


@pytest.mark.parametrize("machine", ["swg091n2", MACHINES["swg091n2"]])
def test_a_pattern_too_wide_for_the_bed_is_refused_before_design_work(machine):
    a, b = _pictures(rows=4, cols=8)
    for call in (
        lambda: design_double(a, b, width=130, knit_on=machine),
        lambda: design_headon(a, width=130, knit_on=machine),
        lambda: solve_design(a, b, width=130, knit_on=machine),
        lambda: design_single(a, width=130, knit_on=machine),
    ):
        with pytest.raises(SchedulingError, match="holds at most 123 units"):
            call()


def test_a_machine_of_another_type_is_refused_naming_the_argument():
    with pytest.raises(OptionError, match="`machine` must be a machine name"):
        knit_pattern(_mixed_pattern(), machine=252)  # type: ignore[arg-type]
    assert isinstance(resolve_machine(None), MachineSpec)


# -- bad arguments: one specific library error naming what is wrong ------------------------------

_A = _pictures()[0]
BAD_CALLS = {
    "search": lambda: design_double(_A, _A, search="x"),
    "ranking": lambda: design_double(_A, _A, ranking={}),
    "yarns": lambda: design_double(_A, _A, yarns=0),
    "picture_b": lambda: design_double(_A, None),
    "first": lambda: design_single(_A, first="mid"),
    "qa": lambda: design_tiles("x"),
    "mode": lambda: design_tiles(quantise_image(_A, n_colors=2), mode="x"),
    "options": lambda: solve_design(_A, _A, options="x"),
    "one picture": lambda: solve_design(_A, _A, options=SolveOptions(model="single")),
    "KnitOptions": lambda: knit_pattern(design_single(_A).best.pattern, options="x"),
    "knitting option": lambda: knit_pattern(design_single(_A).best.pattern, catchy=1),
    "machine": lambda: RankOptions(machine=5),
    "pool": lambda: SearchOptions(pool="3"),
    "seed": lambda: SolveOptions(seed=-1),
    "weights": lambda: SolveOptions(weights={}),
    "cast_on_courses": lambda: KnitOptions(cast_on_courses=-1),
    "float_avoidance": lambda: KnitOptions(float_avoidance="yes"),
}


@pytest.mark.parametrize("what", sorted(BAD_CALLS))
def test_a_bad_argument_raises_a_library_error_that_names_it(what):
    with pytest.raises(IlluknitError, match=what):
        BAD_CALLS[what]()
