"""The design stages take context objects: the pictures' size and colours travel as one
:class:`~illuknit.pipeline.inputs.PictureOptions` (its fields still taken as keywords), the
search and the ranking as their option objects, and no function of the pipeline (nor the
command-line helpers that call it) takes more than 8 named parameters."""

from __future__ import annotations

import ast
import warnings
from pathlib import Path

import numpy as np
import pytest

from illuknit.core.errors import OptionError
from illuknit.design.options import SearchOptions, SolveOptions
from illuknit.pictures.images import quantise_image
from illuknit.pipeline import stages
from illuknit.pipeline.inputs import PictureOptions
from illuknit.pipeline.single import design_single
from illuknit.pipeline.solve import illusion_model
from illuknit.pipeline.tiles import design_double, design_headon, design_tiles

ROOT = Path(__file__).resolve().parents[2]
#: The modules whose every function keeps to the limit (the command functions of illuknit/cli
#: are generated from the option classes and are not counted).
COUNTED = sorted((ROOT / "illuknit" / "pipeline").glob("*.py"))
CLI_HELPERS = {
    "double.py": None,
    "tile_design.py": None,
    "solve.py": ("run_solve", "_check_solve_options", "_write_outputs", "from_switches"),
    "single.py": ("run_single", "from_switches"),
    "knit.py": ("run_knit", "_knit_options"),
    "design_files.py": ("write_candidate",),
    "legible.py": ("parse_widths",),
}
MOST = 8

ONE = SearchOptions(candidates=1, pool=1)


def _pictures(rows: int = 8, cols: int = 10) -> tuple[np.ndarray, np.ndarray]:
    yy, xx = np.mgrid[0:rows, 0:cols]
    a = np.where((xx < cols // 2)[..., None], 20, 235).astype(np.uint8) * np.ones(3, np.uint8)
    b = np.where((yy < rows // 2)[..., None], 20, 235).astype(np.uint8) * np.ones(3, np.uint8)
    return a, b


def _named(fn: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    args = fn.args
    return len(args.posonlyargs) + len(args.args) + len(args.kwonlyargs)


def _functions(path: Path, only: tuple[str, ...] | None = None) -> list[tuple[str, int]]:
    tree = ast.parse(path.read_text())
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        if (only is None or node.name in only) and not any(
            _is_command(d) for d in node.decorator_list
        ):
            found.append((f"{path.name}:{node.name}", _named(node)))
    return found


def _is_command(decorator: ast.expr) -> bool:
    """``@click.command(...)``, ``@main.command(...)``, ``@design_options`` ...: a command
    function, whose parameters are its options."""
    text = ast.unparse(decorator)
    return "command" in text or text.endswith("_options") or "click." in text


def test_no_function_of_the_pipeline_takes_more_than_8_parameters():
    found = [f for path in COUNTED for f in _functions(path)]
    assert len(found) > 30
    over = [(name, n) for name, n in found if n > MOST]
    assert not over, over


def test_no_helper_of_the_design_commands_takes_more_than_8_parameters():
    found = []
    for name, only in CLI_HELPERS.items():
        path = ROOT / "illuknit" / "cli" / name
        if path.exists():
            found += _functions(path, only)
    over = [(name, n) for name, n in found if n > MOST]
    assert not over, over


def test_the_knobs_are_the_picture_options():
    a, b = _pictures()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        short = design_double(a, b, width=6, n_colors=2, search=ONE)
        long = design_double(a, b, pictures=PictureOptions(width=6, n_colors=2), search=ONE)
    assert short.quantised["A"].shape == long.quantised["A"].shape
    assert short.quantised["A"].shape[1] == 6
    assert np.array_equal(short.best.pattern.yarn, long.best.pattern.yarn)
    # a keyword replaces the field of ``pictures``
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        both = design_double(a, b, pictures=PictureOptions(width=8), width=6, search=ONE)
    assert both.quantised["A"].shape == short.quantised["A"].shape


@pytest.mark.parametrize(
    ("call", "named"),
    [
        (lambda a, b: design_double(a, b, widht=6), "widht"),
        (lambda a, b: design_double(a, b, height=6), "height"),
        (lambda a, b: design_double(a, b, pictures=PictureOptions(quantise=False)), "quantise"),
        (lambda a, b: design_headon(a, gauge=7.0), "gauge"),
        (lambda a, b: design_single(a, stretch=True), "stretch"),
        (lambda a, b: illusion_model(a, b, height=3), "height"),
        (lambda a, b: design_double(a, b, pictures={"width": 6}), "pictures"),
        (lambda a, b: design_tiles(quantise_image(a, n_colors=2), colours=2), "colours"),
    ],
)
def test_an_option_a_stage_does_not_take_is_refused_by_name(call, named):
    a, b = _pictures()
    with pytest.raises(OptionError, match=named):
        call(a, b)


def test_design_tiles_still_takes_the_edits_sources_by_keyword():
    a, b = _pictures()
    qa, qb = quantise_image(a, n_colors=2), quantise_image(b, n_colors=2)
    search = SearchOptions(candidates=1, pool=1, edits="suggest")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        design = design_tiles(qa, qb, search=search, sources=(a, b), edit_colors=2)
    assert design.designs
    with pytest.raises(OptionError, match="sources"):
        design_tiles(qa, qb, search=search)


def test_the_old_import_path_keeps_every_name():
    for name in stages.__all__:
        assert getattr(stages, name) is not None
    assert stages.design_double is design_double
    assert stages.PictureOptions is PictureOptions


def test_solve_takes_the_picture_options_as_keywords_too():
    a, b = _pictures()
    opts = SolveOptions(solver="dp")
    one = illusion_model(a, b, options=opts, width=6)
    two = illusion_model(a, b, options=opts, pictures=PictureOptions(width=6))
    assert (one.num_vars, one.num_hard, one.num_soft) == (two.num_vars, two.num_hard, two.num_soft)
