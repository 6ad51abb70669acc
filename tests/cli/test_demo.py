"""The demo's first lines are for a person (issue 33, item 9): it once opened with 600
characters of key=value, the time, its range and the bind-off each twice."""

from __future__ import annotations

import re
import subprocess
import sys


def test_the_demo_opens_with_lines_a_person_reads(tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "illuknit", "demo", "--width", "16", "-o", str(tmp_path / "d")],
        capture_output=True,
        text=True,
        check=True,
    )
    lines = run.stdout.splitlines()
    assert lines[0].startswith("illuknit demo: a single-view illusion")
    assert len(lines[0]) - len(str(tmp_path)) < 100
    knitout = next(line for line in lines if line.startswith("knitout:"))
    time = next(line for line in lines if line.startswith("time:"))
    for line in (knitout, time):
        assert len(line) <= 200 and "=" not in line, line
    # every figure once: the time, the model's range and the bind-off
    times = re.findall(r"\d+ min \d+ s", knitout + time)
    assert len(times) == len(set(times)) == 4, time  # time, range (2 ends), bind-off
    assert "time model's range" in time and "seconds" not in time
    assert not re.search(r"\b1 needles\b", run.stdout), run.stdout  # "1 needle skipped"
