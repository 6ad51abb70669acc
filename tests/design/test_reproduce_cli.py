"""A user's ten-line script reproduces what the design commands write, byte for byte.

For double view, head-on and the constraint models, on a bundled instance (``plus-circle`` of
``instances/manifest.toml``, drawn to PNG files) and on two machines: the library's pattern and
knitout program equal the ``pattern.json`` and ``program.k`` that
``illuknit double|headon|solve ... --knitout --machine NAME`` writes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from illuknit.bench.instances import instance_targets, load_manifest

MACHINES = ("swg091n2", "kniterate")
WIDTH = 12


@pytest.fixture(scope="module")
def plus_circle(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The bundled ``plus-circle`` instance's two pictures, as PNG files."""
    inst = next(i for i in load_manifest().instances if i.name == "plus-circle")
    t = instance_targets(inst)
    folder = tmp_path_factory.mktemp("plus-circle")
    paths = []
    for view, idx in (("a", t.a), ("b", t.b)):
        path = folder / f"{view}.png"
        Image.fromarray(np.asarray(t.palette[idx], dtype=np.uint8)).save(path)
        paths.append(path)
    return paths[0], paths[1]


def _cli_files(run_cli, argv: list[object], out: Path) -> tuple[bytes, bytes]:
    res = run_cli([*argv, "--knitout", "-o", out])
    assert res.code == 0, res.err
    return (out / "pattern.json").read_bytes(), (out / "program.k").read_bytes()


def _saved(pattern, program: str, folder: Path) -> tuple[bytes, bytes]:
    from illuknit import save_pattern

    folder.mkdir()
    save_pattern(pattern, folder / "pattern.json")
    (folder / "program.k").write_text(program)
    return (folder / "pattern.json").read_bytes(), (folder / "program.k").read_bytes()


@pytest.mark.parametrize("machine", MACHINES)
def test_double_view_script_writes_what_the_cli_writes(plus_circle, machine, tmp_path, run_cli):
    a, b = plus_circle
    cli = _cli_files(
        run_cli,
        ["double", a, b, "--width", WIDTH, "--candidates", 2, "--pool", 2, "--machine", machine],
        tmp_path / "cli",
    )
    # the script
    from illuknit import SearchOptions, design_double, knit_pattern

    design = design_double(a, b, width=WIDTH, search=SearchOptions(candidates=2, pool=2))
    program = knit_pattern(design.best.pattern, machine=machine).program
    assert _saved(design.best.pattern, program, tmp_path / "lib") == cli


@pytest.mark.parametrize("machine", MACHINES)
def test_headon_script_writes_what_the_cli_writes(plus_circle, machine, tmp_path, run_cli):
    a, b = plus_circle
    cli = _cli_files(
        run_cli,
        ["headon", a, b, "--width", WIDTH, "--candidates", 2, "--pool", 2, "--machine", machine],
        tmp_path / "cli",
    )
    from illuknit import SearchOptions, design_headon, knit_pattern

    design = design_headon(a, b, width=WIDTH, search=SearchOptions(candidates=2, pool=2))
    program = knit_pattern(design.best.pattern, machine=machine).program
    assert _saved(design.best.pattern, program, tmp_path / "lib") == cli


@pytest.mark.parametrize("machine", MACHINES)
def test_solve_script_writes_what_the_cli_writes(plus_circle, machine, tmp_path, run_cli):
    a, b = plus_circle
    cli = _cli_files(
        run_cli,
        ["solve", a, b, "--width", WIDTH, "--solver", "dp", "--machine", machine],
        tmp_path / "cli",
    )
    from illuknit import SolveOptions, knit_pattern, solve_design

    design = solve_design(a, b, width=WIDTH, options=SolveOptions(solver="dp"))
    program = knit_pattern(design.pattern, machine=machine).program
    assert _saved(design.pattern, program, tmp_path / "lib") == cli


def test_single_view_script_writes_what_the_cli_writes(plus_circle, tmp_path, run_cli):
    a, _ = plus_circle
    cli = _cli_files(
        run_cli, ["single", a, "--width", WIDTH, "--machine", "kniterate"], tmp_path / "cli"
    )
    from illuknit import design_single, knit_pattern

    design = design_single(a, width=WIDTH, knit_on="kniterate")
    program = knit_pattern(design.first("dark").pattern, machine="kniterate").program
    assert _saved(design.first("dark").pattern, program, tmp_path / "lib") == cli
