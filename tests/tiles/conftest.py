"""Shared fixtures of the tile tests."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import pytest

from illuknit.cli import main


@pytest.fixture
def run_cli(capsys: pytest.CaptureFixture[str]) -> Callable[[Sequence[str]], tuple[Any, Any]]:
    """Run ``illuknit ARGV`` in-process: ``(exit code, captured out/err)``."""

    def run(argv: Sequence[str]) -> tuple[Any, Any]:
        try:
            main(list(argv))
            code: Any = 0
        except SystemExit as e:
            code = e.code
        return code, capsys.readouterr()

    return run
