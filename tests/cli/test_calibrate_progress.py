"""``calibrate swatch`` reports its progress through the shared bar (core.progress.work_bar),
as every other long command does: it had none."""

from __future__ import annotations

import contextlib

import pytest

import illuknit.core.progress as progress_module
from illuknit.cli import main


@pytest.mark.parametrize("knitout", [False, True])
def test_calibrate_swatch_has_a_work_bar(tmp_path, monkeypatch, knitout):
    seen: list[tuple[str, float, str]] = []

    @contextlib.contextmanager
    def recording_bar(label, **_):
        yield lambda fraction, message: seen.append((label, fraction, message))

    monkeypatch.setattr(progress_module, "work_bar", recording_bar)
    args = ["calibrate", "swatch", "--bump-sizes", "1", "--flat-sizes", "1,2", "-o"]
    args += [str(tmp_path / "s")] + (["--knitout"] if knitout else [])
    with contextlib.suppress(SystemExit):
        main(args)
    assert (tmp_path / "s" / "swatch.json").exists()
    assert {label for label, _, _ in seen} == {"calibrate swatch"}
    fractions = [f for _, f, _ in seen]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0
    assert any("knitout" in m for _, _, m in seen) == knitout
