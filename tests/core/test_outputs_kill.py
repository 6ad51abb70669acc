"""A folder commit survives ``kill -9`` at any moment (illuknit.core.files, the journal).

A real ``python -m illuknit view`` writes a new design into a folder that holds an earlier run's
design and the user's own files, and is killed with SIGKILL: at 30 random moments of its run, and
right after 10 chosen steps of its commit (the test-only ``ILLUKNIT_TEST_KILL_AT_COMMIT_STEP``
hook). Every time:

- without a journal the folder's visible entries are exactly the old or exactly the new design;
- after recovery (what the next run does first; done here on a copy) the whole folder, hidden
  entries included, is exactly the old or the new design plus the user's files;
- the next real run into the folder says in at most one ``note:`` line what it finished or undid,
  and leaves no hidden ``.illuknit-*`` entry behind.
"""

from __future__ import annotations

import hashlib
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from illuknit.cli import main
from illuknit.core.files import KILL_AT_COMMIT_STEP_ENV, recover_output_dir
from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern

ROOT = Path(__file__).resolve().parents[2]
RANDOM_KILLS = 30
# The commit of `view` (12 entries, each replacing an old one) has 29 steps: 1 staging synced,
# 2 journal written, 3-26 the renames, 27 backup removed, 28 journal removed, 29 staging removed.
CHOSEN_STEPS = (1, 2, 3, 4, 9, 14, 19, 26, 27, 28)

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL and flock are POSIX")


def hashes(root: Path) -> dict[str, str]:
    """relative path -> sha256 (``<dir>`` for folders) of everything under ``root``."""
    out = {}
    for p in sorted(root.rglob("*")):
        rel = str(p.relative_to(root))
        out[rel] = "<dir>" if p.is_dir() else hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def visible(h: dict[str, str]) -> dict[str, str]:
    return {k: v for k, v in h.items() if not k.startswith(".")}


def hidden_leftovers(root: Path) -> list[str]:
    return sorted(p.name for p in root.iterdir() if p.name.startswith(".illuknit-"))


def pattern(seed: int) -> LogicalPattern:
    rng = np.random.default_rng(seed)
    return LogicalPattern(
        rng.integers(0, 2, (10, 12)),
        rng.random((10, 12)) < 0.5,
        (Yarn("black", (27, 27, 27)), Yarn("linen", (244, 240, 232))),
    )


def run_view(pattern_file: Path, outdir: Path, capsys) -> str:
    """One real run of ``illuknit view`` in this process; its stderr."""
    capsys.readouterr()
    assert main(["view", str(pattern_file), "-o", str(outdir)]) == 0
    return capsys.readouterr().err


def add_users_files(folder: Path) -> dict[str, str]:
    (folder / "my notes.txt").write_text("the user's own file")
    (folder / "photos").mkdir()
    (folder / "photos" / "swatch.jpg").write_bytes(b"\xff\xd8 not really")
    return {k: v for k, v in hashes(folder).items() if k.startswith(("my notes", "photos"))}


def start(pattern_file: Path, outdir: Path, *, kill_at: int | None = None) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    if kill_at is not None:
        env[KILL_AT_COMMIT_STEP_ENV] = str(kill_at)
    return subprocess.Popen(
        [sys.executable, "-m", "illuknit", "view", str(pattern_file), "-o", str(outdir)],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


@pytest.fixture(scope="module")
def designs(tmp_path_factory) -> tuple[Path, Path, Path, float]:
    """Two pattern files, the folder ``view`` writes for the first, and how long a real run
    of the second takes."""
    root = tmp_path_factory.mktemp("designs")
    p_old, p_new = root / "old.json", root / "new.json"
    save_pattern(pattern(1), p_old)
    save_pattern(pattern(2), p_new)
    assert main(["view", str(p_old), "-o", str(root / "ref_old")]) == 0
    t0 = time.monotonic()
    assert start(p_new, root / "ref_new").wait(timeout=120) == 0  # a real run, timed
    duration = time.monotonic() - t0
    assert hashes(root / "ref_old") != hashes(root / "ref_new")
    assert not hidden_leftovers(root / "ref_new")
    assert len(hashes(root / "ref_new")) == 12  # the step numbers above count 12 entries
    return p_new, root / "ref_old", root / "ref_new", duration


def kill_and_recover(moments, designs, tmp_path, capsys) -> dict[str, int]:
    """Kill a real ``view`` at each moment, over a folder that held the old design and the
    user's own files; check what is left, what recovery makes of it and what the next run
    does. Returns how often each outcome was seen."""
    p_new, ref_old_dir, ref_new_dir, _ = designs
    ref_old, ref_new = hashes(ref_old_dir), hashes(ref_new_dir)
    seen = {"old": 0, "new": 0, "journal": 0, "notes": 0}
    for i, (how, when) in enumerate(moments):
        folder = tmp_path / f"trial{i}"
        shutil.copytree(ref_old_dir, folder)
        users = add_users_files(folder)
        old, new = ref_old | users, ref_new | users
        if how == "random":
            proc = start(p_new, folder)
            time.sleep(when)
            proc.send_signal(signal.SIGKILL)
            proc.wait(timeout=60)
        else:
            proc = start(p_new, folder, kill_at=int(when))
            assert proc.wait(timeout=60) == -signal.SIGKILL, f"step {when} was not reached"

        state = hashes(folder)
        leftovers = hidden_leftovers(folder)
        journal = any(name.endswith(".journal") for name in leftovers)
        unfinished = any(
            name.endswith(".partial") and os.listdir(folder / name) for name in leftovers
        )
        seen["journal"] += journal
        if not journal:  # before the decision point or after the last move: no mix
            assert visible(state) in (old, new), f"{how} {when}: a mix of two designs"

        copy = tmp_path / f"copy{i}"
        shutil.copytree(folder, copy, symlinks=True)
        recover_output_dir(copy)
        recovered = hashes(copy)
        assert recovered in (old, new), f"{how} {when}: not one whole design after recovery"
        seen["old" if recovered == old else "new"] += 1
        if journal:
            assert recovered == new  # the journal is the decision: roll forward

        err = run_view(p_new, folder, capsys)
        notes = [line for line in err.splitlines() if "note:" in line]
        assert len(notes) == (1 if journal or unfinished else 0), f"{how} {when}: {err}"
        seen["notes"] += len(notes)
        assert hidden_leftovers(folder) == [], f"{how} {when}: hidden leftovers"
        assert hashes(folder) == new
        shutil.rmtree(copy)
        shutil.rmtree(folder)
    assert seen["old"] + seen["new"] == len(moments)
    assert seen["notes"] >= seen["journal"], seen
    return seen


@pytest.mark.parametrize("half", [0, 1])
def test_a_kill_at_a_random_moment_leaves_one_whole_design(half, designs, tmp_path, capsys):
    rng = random.Random(22)
    duration = designs[3]
    moments = [("random", rng.uniform(0, duration)) for _ in range(RANDOM_KILLS)]
    # In two halves, so that test workers share them.
    kill_and_recover(moments[half::2], designs, tmp_path, capsys)


def test_a_kill_at_each_commit_step_leaves_one_whole_design(designs, tmp_path, capsys):
    seen = kill_and_recover([("step", k) for k in CHOSEN_STEPS], designs, tmp_path, capsys)
    # The chosen steps land inside the commit: at least those from the journal on roll forward.
    assert seen["journal"] >= sum(2 <= k <= 23 for k in CHOSEN_STEPS), seen
