"""The pictures in docs/ drawn from the code (architecture, bump diagrams) must match what the
code draws today."""

from __future__ import annotations

import runpy
from pathlib import Path

SCRIPT = Path(__file__).resolve().parent.parent / "docs" / "architecture.py"


def test_architecture_picture_is_current():
    draw = runpy.run_path(str(SCRIPT))
    assert draw["main"](["--check"]) == 0, "run: python docs/architecture.py"


def test_architecture_picture_names_every_stage_module():
    ns = runpy.run_path(str(SCRIPT))
    svg = ns["draw"]()
    for dotted, _, _ in ns["STAGES"]:
        assert dotted.rpartition(".")[2] in svg
    assert "sizing.py -&gt; SizedPair" in svg and "knit/schedule.py -&gt; Schedule" in svg


def test_bump_diagrams_are_current():
    # docs/img/split-bump.svg and tall-bump.svg are the passes the schedulers emit today
    draw = runpy.run_path(str(SCRIPT.parent / "bumps.py"))
    assert draw["main"](["--check"]) == 0, "run: python docs/bumps.py"
    split, tall = draw["draw"](True), draw["draw"](False)
    assert "#c8102e" in split and "tuck, carrier" not in split  # red purls, no tall tucks
    assert "tuck, carrier" in tall
