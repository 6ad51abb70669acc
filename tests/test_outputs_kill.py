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

ROOT = Path(__file__).resolve().parent.parent
RANDOM_KILLS = 30
# The commit of `view` (10 entries, each replacing an old one) has 25 steps: 1 staging synced,
# 2 journal written, 3-22 the renames, 23 backup removed, 24 journal removed, 25 staging removed.
CHOSEN_STEPS = (1, 2, 3, 4, 7, 12, 17, 22, 23, 24)

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


def test_kill_at_any_moment_leaves_one_whole_design(tmp_path, capsys):
    p_old, p_new = tmp_path / "old.json", tmp_path / "new.json"
    save_pattern(pattern(1), p_old)
    save_pattern(pattern(2), p_new)
    run_view(p_old, tmp_path / "ref_old", capsys)
    t0 = time.monotonic()
    assert start(p_new, tmp_path / "ref_new").wait(timeout=120) == 0  # a real run, timed
    duration = time.monotonic() - t0
    ref_old, ref_new = hashes(tmp_path / "ref_old"), hashes(tmp_path / "ref_new")
    assert ref_old != ref_new and not hidden_leftovers(tmp_path / "ref_new")
    assert len(ref_new) == 10  # the step numbers above count a commit of 10 entries

    rng = random.Random(22)
    moments = [("random", rng.uniform(0, duration)) for _ in range(RANDOM_KILLS)]
    moments += [("step", k) for k in CHOSEN_STEPS]
    seen = {"old": 0, "new": 0, "journal": 0, "notes": 0}
    for i, (how, when) in enumerate(moments):
        folder = tmp_path / f"trial{i}"
        shutil.copytree(tmp_path / "ref_old", folder)
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
    # The chosen steps land inside the commit: at least those from the journal on roll forward.
    assert seen["journal"] >= sum(2 <= k <= 23 for k in CHOSEN_STEPS), seen
    assert seen["old"] + seen["new"] == RANDOM_KILLS + len(CHOSEN_STEPS)
    assert seen["notes"] >= seen["journal"], seen
