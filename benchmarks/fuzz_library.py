"""Every public callable of the library, called with wrong types and values, argument by argument.

The callables are enumerated from the public exports (``illuknit._API`` and ``illuknit.solvers.
__all__``, the subpackage docs/library.md documents), not from a hand list: each needs one valid
call in ``valid_calls`` or a reason in ``EXEMPT``, and ``tests/test_api_arguments.py`` fails when
a new export has neither. Each argument of each valid call is then replaced, in turn, by each value
of ``BAD`` (None, a string, NaN, infinity, 10**30, -7, 2.5, True, an object, a 4-D array, an array
of strings; a callable taking ``**options`` also gets one it does not know), and the outcome
counted:

- **raw**: the call raised something other than an ``IlluknitError`` (a bare TypeError, ...);
- **blame**: it raised an ``IlluknitError`` whose message does not name the argument;
- **absurd**: it returned, with a value no caller can mean (NaN, 10**30, a string where a number
  goes, None where no default is None, ...; ``absurd`` says which, ``ALLOWED`` lists the few an
  argument takes by design, with why).

Target: 0 / 0 / 0. Run: ``python benchmarks/fuzz_library.py [names...]`` (from the checkout root;
every call runs in a scratch folder, as some bad values are valid file names).
"""

from __future__ import annotations

import enum
import inspect
import math
import os
import re
import signal
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

# the checkout this script is in, not whichever illuknit is installed
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import illuknit
import illuknit.solvers
from illuknit import IlluknitError

#: Wrong values, each with a label. ``object()`` and the arrays are made once.
BAD: list[tuple[str, Any]] = [
    ("None", None),
    ("str", "xyz"),
    ("nan", math.nan),
    ("inf", math.inf),
    ("huge", 10**30),
    ("negative", -7),
    ("fraction", 2.5),
    ("bool", True),
    ("object", object()),
    ("array4d", np.zeros((2, 2, 2, 2))),
    ("array_str", np.array([["a", "b"], ["c", "d"]])),
]

#: Public callables not fuzzed, with why. Results are made by the library and handed back, not
#: made by callers; enums are looked up by Python's own ``Enum(value)``.
EXEMPT: dict[str, str] = {
    "IlluknitError": "the error class itself",
    "RankedDesign": "a result: made by the design stages, read by callers",
    "SingleDesign": "a result of design_single",
    "TileDesign": "a result of design_double / design_headon / design_tiles",
    "SolvedDesign": "a result of solve_design",
    "KnitResult": "a result of knit_pattern",
    "CheckReport": "a result of check_knitout",
    "Finding": "a line of a CheckReport",
    "TileAssignment": "a result of assign_tiles / assign_headon",
    "solvers.Backend": "a Protocol that backends implement, not called",
    "solvers.BackendBase": "a base class that backends subclass",
    "solvers.Solution": "a result of a backend's solve",
    "solvers.ProgressEvent": "what a backend reports to a progress callback",
    "solvers.SolverName": "a result of parse_solver_name",
    "solvers.register_backend": "changes the process-wide registry (tests/solvers cover it)",
    "solvers.SolveStats": "a result: the statistics solve records in Solution.stats",
    "solvers.WarmStartInfo": "a result: what a warm start did (SolveStats.warm_start)",
}

#: (callable, argument) -> labels of BAD the argument takes by design, and why.
ALLOWED: dict[tuple[str, str], tuple[set[str], str]] = {
    ("schedule_mixed", "machine"): ({"None"}, "None is the default machine, as everywhere"),
    ("render_at", "angle"): ({"negative"}, "a signed elevation: -7 is view B at 7 degrees"),
    ("Model", "problem"): (
        {label for label, _ in BAD},
        "an opaque payload that backends may recognise (an IllusionProblem); any object",
    ),
}

#: Overrides of machine parameters: like MachineSpec's numeric fields, their ranges are the
#: machine parameter table's (branch ``machine``); only their types are tried here.
MACHINE_OVERRIDES = {
    ("check_knitout", "float_limit"),
    ("check_knitout", "max_racking"),
    ("check_knitout", "bed_width"),
}

#: MachineSpec's numeric fields: their ranges are the machine parameter table's (branch
#: ``machine``, issue 34 item 3); here only None, str and bool are tried on them.
MACHINE_NUMERIC = {
    "needles",
    "gauge",
    "max_racking",
    "float_limit",
    "park_distance",
    "stitch_number",
    "cast_on_stitch_number",
    "speed_number",
    "seconds_per_needle",
    "seconds_per_turn",
    "course_aspect",
}
MACHINE_TYPE_ONLY = {"None", "str", "bool", "object", "array_str"}

#: Seconds a call may take before it counts as hung (an absurd value accepted).
TIMEOUT_S = 20


def public_callables() -> dict[str, Callable[..., Any]]:
    """Every callable the public exports name (``solvers.`` before a name of illuknit.solvers),
    enums left out (Python's ``Enum(value)``)."""
    found: dict[str, Callable[..., Any]] = {}
    for prefix, module, names in (
        ("", illuknit, list(illuknit._API)),
        ("solvers.", illuknit.solvers, list(illuknit.solvers.__all__)),
    ):
        for name in names:
            obj = getattr(module, name)
            if not callable(obj) or (isinstance(obj, type) and issubclass(obj, enum.Enum)):
                continue
            found[prefix + name] = obj
    return found


def _pattern() -> illuknit.LogicalPattern:
    rng = np.random.default_rng(3)
    return illuknit.LogicalPattern(
        rng.integers(0, 2, (4, 4)),
        rng.random((4, 4)) < 0.5,
        illuknit.parse_yarns("black=#1b1b1b,white=#f4f0e8"),
    )


Calls = dict[str, tuple[tuple[Any, ...], dict[str, Any]]]


def valid_calls(tmp: Path) -> Calls:
    """One small valid call of each fuzzed callable (files it reads are made in ``tmp``)."""
    from PIL import Image

    from illuknit.design.render.calibrate import Measurement
    from illuknit.design.render.params import save_params
    from illuknit.design.tiles.bank import save_bank
    from illuknit.knit.stitches import lower_to_stitches

    p = _pattern()
    yarns = p.yarns
    pattern_file = tmp / "p.json"
    illuknit.save_pattern(p, pattern_file)
    rgb = np.random.default_rng(0).random((6, 6, 3))
    picture = tmp / "pic.png"
    Image.fromarray((rgb * 255).astype(np.uint8)).save(picture)
    target = (np.arange(16).reshape(4, 4) % 2).astype(np.int16)
    q = illuknit.quantise_image(rgb, yarns=yarns)
    bank = illuknit.canonical_bank(yarns)
    problem = illuknit.IllusionProblem(target, target, 2)
    model = illuknit.build_model(problem)
    params_file = tmp / "params.json"
    save_params(illuknit.RenderParams(), params_file)
    bank_file = tmp / "bank.json"
    save_bank(bank, bank_file)
    ms = [Measurement(2, 40.0, 1, "A", "", 1), Measurement(3, 30.0, 1, "A", "", 2)]
    qa = illuknit.quantise_image(np.tile(rgb[:, :1], (1, 6, 1)), yarns=yarns)
    knitout = ";!knitout-2\n;;Carriers: 1 2 3\n"
    one = illuknit.SearchOptions(candidates=1, pool=1)
    tiled = illuknit.design_tiles(qa, qa, search=one).best
    assignment = illuknit.assign_tiles(qa, qa, candidates=1, time_limit=5)[0]
    solution = illuknit.solve_illusion(target, target, solver="dp").solution
    tile = (np.zeros((2, 1), int), np.array([[True], [False]]))
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
        "schedule_mixed": ((lower_to_stitches(p),), {}),
        "check_knitout": ((knitout,), {}),
        "canonical_bank": ((yarns,), {}),
        "load_bank": ((bank_file,), {}),
        "assign_tiles": ((qa, qa), {"candidates": 1, "time_limit": 5}),
        "compile_tiles": ((assignment,), {}),
        "assign_headon": ((qa,), {"candidates": 1, "time_limit": 5}),
        "load_params": ((params_file,), {}),
        "render_views": ((p,), {}),
        "render_pattern": ((p,), {}),
        "render_at": ((p, 30.0), {}),
        "optimise_design": ((rgb, rgb, yarns), {"steps": 2}),
        "calibration_swatch": ((), {}),
        "design_single": ((picture,), {}),
        "design_double": ((picture, picture), {"search": one}),
        "design_headon": ((picture,), {"search": one}),
        "design_tiles": ((q, q), {"search": one}),
        "measure_design": ((tiled.pattern, "double", qa, qa), {}),
        "retile_design": ((tiled.assignment, {tiled.assignment.pairs[0]: "0/1"}), {}),
        "solve_design": ((picture, picture), {"options": illuknit.SolveOptions(solver="dp")}),
        "illusion_model": ((picture, picture), {}),
        "quantise_targets": ((picture, picture), {}),
        "resolve_machine": (("swg091n2",), {}),
        "fit_bump_height": ((ms,), {}),
        "build_model": ((problem,), {}),
        "solve_illusion": ((target, target), {"solver": "dp", "time_limit": 5}),
        "pattern_from_solution": ((problem, solution), {}),
        "report_pattern": ((p, problem), {}),
        # the IR and option classes callers make themselves
        "LogicalPattern": ((p.yarn, p.raised, yarns), {}),
        "Yarn": (("navy", (0, 0, 128)), {}),
        "QuantisedImage": ((q.indices, q.yarns, q.colors), {}),
        "PictureOptions": ((), {"width": 20}),
        "SearchOptions": ((), {}),
        "RankOptions": ((), {}),
        "RankChoice": (("legibility", "auto", "both pictures are words"), {"words": ("A", "B")}),
        "SolveOptions": ((), {}),
        "KnitOptions": ((), {}),
        "GradientOptions": ((), {}),
        "AssignOptions": ((), {}),
        "MachineSpec": ((), {}),
        "Tile": (tile, {}),
        "TileBank": ((yarns, bank.tiles), {}),
        "RenderParams": ((), {}),
        "KnitWeights": ((), {}),
        "IllusionProblem": ((target, target, 2), {}),
        "Model": (("m",), {}),
        # illuknit.solvers
        "solvers.available_backends": ((), {}),
        "solvers.backend_names": ((), {}),
        "solvers.describe_backends": ((), {}),
        "solvers.get_backend": (("dp",), {}),
        "solvers.parse_solver_name": (("dp",), {}),
        "solvers.resolve_backend": ((model, "dp"), {}),
        "solvers.solve": ((model,), {"solver": "dp"}),
    }


@dataclass(frozen=True)
class Outcome:
    """What one call with one wrong value did."""

    callable: str
    argument: str
    label: str | None
    kind: str  # "raw", "blame", "absurd", "refused" (an IlluknitError naming it) or "accepted"
    detail: str = ""

    def __str__(self) -> str:
        return f"{self.callable}({self.argument}=<{self.label}>): {self.kind} {self.detail}"[:300]


def absurd(annotation: str, default: Any, label: str) -> bool:
    """Whether no caller can mean the BAD value ``label`` for an argument so annotated."""
    if label == "None":
        return default is not None and "None" not in annotation
    if label == "str":
        return not re.search(r"\b(str|PathLike|Picture)\b", annotation)
    if label == "fraction":
        return not re.search(r"\bfloat\b", annotation)
    if label == "bool":
        return "bool" not in annotation
    return True


def label_of(value: Any) -> str | None:
    """The BAD label a value of another source (hypothesis) stands for, or None when it is
    not one no caller can mean (then only what it raises is judged)."""
    if value is None:
        return "None"
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, str):
        return "str"
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    if isinstance(value, float) and math.isinf(value):
        return "inf"
    if isinstance(value, int) and abs(value) >= 10**18:
        return "huge"
    if isinstance(value, np.ndarray) and (value.ndim > 3 or value.dtype.kind not in "biuf"):
        return "array4d" if value.ndim > 3 else "array_str"
    return None


def arguments(fn: Callable[..., Any]) -> list[inspect.Parameter]:
    """The named parameters of ``fn`` (not ``*args``, ``**kwargs``)."""
    return [
        p
        for p in inspect.signature(fn).parameters.values()
        if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)
    ]


class _Hung(Exception):
    pass


@contextmanager
def _time_limit(seconds: int) -> Iterator[None]:
    def stop(signum: int, frame: Any) -> None:
        raise _Hung

    if not hasattr(signal, "SIGALRM"):  # Windows: no limit
        yield
        return

    old = signal.signal(signal.SIGALRM, stop)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _call_with(
    fn: Callable[..., Any],
    args: tuple[Any, ...],
    kwargs: dict[str, Any],
    param: inspect.Parameter,
    value: Any,
) -> Any:
    names = [p.name for p in inspect.signature(fn).parameters.values()]
    i = names.index(param.name)
    if param.kind is param.KEYWORD_ONLY or i >= len(args):
        kwargs = {**kwargs, param.name: value}
    else:
        args = (*args[:i], value, *args[i + 1 :])
    return fn(*args, **kwargs)


def _names_it(message: str, name: str, value: Any) -> bool:
    if re.search(rf"(?<![\w.]){re.escape(name)}(?!\w)", message):
        return True
    # a file that is not there is named by its path, a wrong word of a text by that word
    if not isinstance(value, str):
        return False
    from illuknit.core.documents import shown_path

    # a file name is shown escaped (control characters as \xNN), as every message shows one
    if shown_path(value) in message:
        return True
    words = [value, *re.split(r"[\s,]+", value)]
    return repr(value) in message or any(w and (w in message or repr(w) in message) for w in words)


def try_one(name: str, fn: Callable[..., Any], call: Any, param: inspect.Parameter,
            label: str | None, value: Any) -> Outcome:  # fmt: skip
    """Call ``fn`` as ``call`` with ``param`` replaced by ``value`` and judge what happened."""
    args, kwargs = call
    try:
        with warnings.catch_warnings(), _time_limit(TIMEOUT_S):
            warnings.simplefilter("ignore")
            _call_with(fn, args, kwargs, param, value)
    except _Hung:
        return Outcome(name, param.name, label, "absurd", f"still running after {TIMEOUT_S} s")
    except IlluknitError as exc:
        if _names_it(str(exc), param.name, value):
            return Outcome(name, param.name, label, "refused")
        return Outcome(name, param.name, label, "blame", f"{type(exc).__name__}: {exc}")
    except Exception as exc:  # the point of the fuzz
        return Outcome(name, param.name, label, "raw", f"{type(exc).__name__}: {exc}")
    annotation = param.annotation if isinstance(param.annotation, str) else str(param.annotation)
    allowed = ALLOWED.get((name, param.name), (set(), ""))[0]
    if label is not None and label not in allowed and absurd(annotation, param.default, label):
        return Outcome(name, param.name, label, "absurd", f"accepted ({annotation})")
    return Outcome(name, param.name, label, "accepted")


def try_unknown_keyword(name: str, fn: Callable[..., Any], call: Any) -> Outcome:
    """A callable that takes ``**options`` given one it does not know: refused, naming it."""
    args, kwargs = call
    try:
        with warnings.catch_warnings(), _time_limit(TIMEOUT_S):
            warnings.simplefilter("ignore")
            fn(*args, **kwargs, bogus_option=1)
    except _Hung:
        return Outcome(name, "bogus_option", "keyword", "absurd", "still running")
    except IlluknitError as exc:
        if "bogus_option" in str(exc):
            return Outcome(name, "bogus_option", "keyword", "refused")
        return Outcome(name, "bogus_option", "keyword", "blame", f"{type(exc).__name__}: {exc}")
    except Exception as exc:  # the point of the fuzz
        return Outcome(name, "bogus_option", "keyword", "raw", f"{type(exc).__name__}: {exc}")
    return Outcome(name, "bogus_option", "keyword", "absurd", "an unknown keyword accepted")


def left_to_machine_table(name: str, argument: str, label: str | None) -> bool:
    """Whether the value ``label`` of ``argument`` is a machine parameter's number, whose range
    the machine parameter table checks (branch ``machine``), so not tried here."""
    spec = name == "MachineSpec" and argument in MACHINE_NUMERIC
    return (spec or (name, argument) in MACHINE_OVERRIDES) and label not in MACHINE_TYPE_ONLY


def fuzz(calls: Calls, names: list[str] | None = None) -> list[Outcome]:
    """Every argument of every call in ``calls`` (or of ``names``) with every value of BAD."""
    found = public_callables()
    outcomes = []
    for name in names or sorted(calls):
        fn = found[name]
        for param in arguments(fn):
            for label, value in BAD:
                if left_to_machine_table(name, param.name, label):
                    continue
                outcomes.append(try_one(name, fn, calls[name], param, label, value))
        kinds = {p.kind for p in inspect.signature(fn).parameters.values()}
        if inspect.Parameter.VAR_KEYWORD in kinds:
            outcomes.append(try_unknown_keyword(name, fn, calls[name]))
    return outcomes


def main(argv: list[str]) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)
        calls = valid_calls(Path(tmp))
        missing = sorted(set(public_callables()) - set(calls) - set(EXEMPT))
        outcomes = fuzz(calls, argv or None)
    kinds = {k: [o for o in outcomes if o.kind == k] for k in ("raw", "blame", "absurd")}
    for found in kinds.values():
        for o in found:
            print(o)
    print(f"public callables fuzzed: {len(argv) if argv else len(calls)} ({len(EXEMPT)} exempt)")
    print(f"calls: {len(outcomes)}")
    print(f"raw exceptions: {len(kinds['raw'])}")
    print(f"wrong-argument blames: {len(kinds['blame'])}")
    print(f"accepted absurd values: {len(kinds['absurd'])}")
    if missing:
        print(f"public callables with neither a valid call nor a reason: {missing}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
