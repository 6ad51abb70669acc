"""Fixtures shared by the whole suite."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NamedTuple

import pytest

from illuknit.cli import main


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
