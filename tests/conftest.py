"""Fixtures shared by the whole suite."""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import main

#: The reference machine backends: ``shared/oracles`` beside the checkout (``ILLUKNIT_ORACLES``
#: names another folder). They are judges only; see their README.
ORACLES = Path(
    os.environ.get("ILLUKNIT_ORACLES")
    or Path(__file__).resolve().parents[1].parent / "shared" / "oracles"
)


def reference_backend(script: str) -> Path:
    """The reference backend ``ORACLES/script``, runnable with ``node``.

    Skips the test when node or the backend is missing, with the reason; under ``CI=true`` (a
    clean clone with ``shared/`` beside it) a missing backend fails the test instead, so a run
    that judged nothing never passes for one that did.
    """
    path = ORACLES / script
    reason = None
    if shutil.which("node") is None:
        reason = "node is not installed: the reference backends cannot run"
    elif not path.is_file():
        reason = f"the reference backend {path} is missing (set ILLUKNIT_ORACLES to its folder)"
    if reason is None:
        return path
    if os.environ.get("CI") == "true":
        pytest.fail(f"{reason}; under CI=true every reference backend must run", pytrace=False)
    pytest.skip(reason)


@pytest.fixture(scope="module")
def reader() -> None:
    """Skip when tesseract is missing, saying so; under ``CI=true`` fail instead (.ci/run
    installs it), as the reference backends do (:func:`reference_backend`)."""
    if shutil.which("tesseract") is not None:
        return
    reason = "tesseract is not installed: the reader cannot run (apt-get install tesseract-ocr)"
    if os.environ.get("CI") == "true":
        pytest.fail(f"{reason}; under CI=true the reader must run", pytrace=False)
    pytest.skip(reason)


@pytest.fixture(scope="session")
def swg_backend() -> Path:
    """The reference Shima SWG backend, ``knitout-to-dat.js``."""
    return reference_backend("swg/knitout-to-dat.js")


@pytest.fixture(scope="session")
def kniterate_backend() -> Path:
    """The reference Kniterate backend, ``knitout-to-kcode.js``."""
    return reference_backend("kniterate/knitout-to-kcode.js")


class CliRun(NamedTuple):
    """What one in-process ``illuknit`` run printed and how it exited."""

    code: int
    out: str
    err: str


@pytest.fixture
def run_cli(capsys: pytest.CaptureFixture[str]) -> Callable[[Sequence[object]], CliRun]:
    """Run ``illuknit ARGV`` in-process: ``(exit code, stdout, stderr)``.

    The code is 0 when the command returns normally, else its ``SystemExit`` code. Arguments
    may be paths (they are passed as strings).
    """

    def run(argv: Sequence[object]) -> CliRun:
        try:
            main([str(a) for a in argv])
            code = 0
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else int(e.code is not None)
        out, err = capsys.readouterr()
        return CliRun(code, out, err)

    return run


@pytest.fixture
def box_picture(tmp_path: Path) -> Callable[[tuple[int, int]], Path]:
    """Write a light RGB picture of ``shape`` with a dark box over its middle half; its path."""

    def write(shape: tuple[int, int]) -> Path:
        rows, cols = shape
        rgb = np.full((rows, cols, 3), 240, np.uint8)
        rgb[round(rows / 4) : round(3 * rows / 4), round(cols / 4) : round(3 * cols / 4)] = 20
        path = tmp_path / "pic.png"
        Image.fromarray(rgb).save(path)
        return path

    return write


@pytest.fixture
def picture(box_picture: Callable[[tuple[int, int]], Path]) -> Path:
    """A 20 x 30 picture of a dark box on a light ground (``box_picture``)."""
    return box_picture((20, 30))
