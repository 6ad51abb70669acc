"""A single-file write leaves no temporary file behind, not even after ``kill -9`` (issue 34, 6).

``knit -o piece.k`` writes through ``.piece.k.illuknit-<pid>-<random>.tmp`` beside the target.

- Every error, Ctrl-C, and SIGTERM (which the command line unwinds like Ctrl-C) removes it.
- A real ``python -m illuknit knit`` killed with SIGKILL right after the temporary file is written
  (the test-only ``ILLUKNIT_TEST_SIGNAL_IN_FILE_WRITE`` hook), and at random moments of its run,
  leaves the old ``piece.k`` or none; the next run into the folder removes the leftover with one
  ``note:`` line and leaves only ``piece.k``.
- Only illuknit's own temporary files are removed, and only abandoned ones: never one whose
  writer is alive (it holds a lock on it, and its pid is in the name), never a file of another
  name.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from illuknit.core.files import (
    SIGNAL_IN_FILE_WRITE_ENV,
    OutputRecoveryWarning,
    atomic_write_bytes,
    remove_stale_temp_files,
)
from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern

ROOT = Path(__file__).resolve().parents[2]
RANDOM_KILLS = 4

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL and flock are POSIX")


def temps(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


@pytest.fixture
def pattern_file(tmp_path: Path) -> Path:
    rng = np.random.default_rng(1)
    path = tmp_path / "design.json"
    save_pattern(
        LogicalPattern(
            rng.integers(0, 2, (10, 12)),
            rng.random((10, 12)) < 0.5,
            (Yarn("black", (27, 27, 27)), Yarn("linen", (244, 240, 232))),
        ),
        path,
    )
    return path


def knit(pattern_file: Path, out: Path, **env: str) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [sys.executable, "-m", "illuknit", "knit", str(pattern_file), "-o", str(out)],
        cwd=ROOT,
        env={**os.environ, **env},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )


def test_kill_9_inside_the_write_and_the_next_run_cleans_up(pattern_file, tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "notes.tmp").write_text("the user's own .tmp file")
    proc = knit(pattern_file, folder / "piece.k", **{SIGNAL_IN_FILE_WRITE_ENV: "KILL"})
    proc.communicate(timeout=300)
    assert proc.returncode == -signal.SIGKILL
    left = [t for t in temps(folder) if t != "notes.tmp"]
    assert len(left) == 1 and left[0].startswith(".piece.k.illuknit-"), left
    assert not (folder / "piece.k").exists()

    proc = knit(pattern_file, folder / "piece.k")
    err = proc.communicate(timeout=300)[1].decode()
    assert proc.returncode == 0, err
    assert "illuknit: note: removed .piece.k.illuknit-" in err and err.count("note:") == 1
    assert temps(folder) == ["notes.tmp"]
    assert (folder / "piece.k").read_text().startswith(";!knitout-2")


def test_sigterm_inside_the_write_removes_the_temporary_file(pattern_file, tmp_path):
    (tmp_path / "piece.k").write_text("old")
    proc = knit(pattern_file, tmp_path / "piece.k", **{SIGNAL_IN_FILE_WRITE_ENV: "TERM"})
    err = proc.communicate(timeout=300)[1].decode()
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert err.strip().splitlines()[-1] == "illuknit: stopped by SIGTERM"
    assert "Traceback" not in err
    assert temps(tmp_path) == [] and (tmp_path / "piece.k").read_text() == "old"


def test_kill_9_at_random_moments(pattern_file, tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "piece.k").write_text("old")
    rng = random.Random(34)
    # how long a whole run takes here, to kill inside it
    start = time.monotonic()
    knit(pattern_file, tmp_path / "probe.k").communicate(timeout=300)
    whole = time.monotonic() - start
    for _ in range(RANDOM_KILLS):
        proc = knit(pattern_file, folder / "piece.k")
        time.sleep(rng.uniform(0.3, 1.0) * whole)
        proc.kill()
        proc.communicate(timeout=300)
        text = (folder / "piece.k").read_text()
        assert text == "old" or text.startswith(";!knitout-2")  # never a part
    proc = knit(pattern_file, folder / "piece.k")
    err = proc.communicate(timeout=300)[1].decode()
    assert proc.returncode == 0, err
    assert temps(folder) == [] and (folder / "piece.k").read_text().startswith(";!knitout-2")


def test_errors_and_ctrl_c_remove_the_temporary_file(tmp_path, monkeypatch):
    target = tmp_path / "piece.k"

    def refuse(*args: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "replace", refuse)
    with pytest.raises(KeyboardInterrupt):
        atomic_write_bytes(target, b"data")
    assert os.listdir(tmp_path) == []

    def full(*args: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", full)
    with pytest.raises(OSError, match="No space left"):
        atomic_write_bytes(target, b"data")
    assert os.listdir(tmp_path) == []


def dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid  # gone (reuse within the test is all but impossible)


def test_only_abandoned_temporary_files_of_ours_are_removed(tmp_path):
    dead = tmp_path / f".piece.k.illuknit-{dead_pid()}-abc123.tmp"
    dead.write_text("left by a kill")
    mine = tmp_path / f".piece.k.illuknit-{os.getpid()}-xyz789.tmp"
    mine.write_text("a live writer's (this process), fresh")
    other = [".piece.k.abc123.tmp", "piece.k.illuknit-1-abc.tmp", ".x.illuknit-12.tmp"]
    for name in other:
        (tmp_path / name).write_text("not ours, or not in our form")
    link = tmp_path / f".l.illuknit-{dead_pid()}-abc.tmp"
    link.symlink_to(tmp_path / "elsewhere")
    assert remove_stale_temp_files(tmp_path) == [dead]
    assert sorted(os.listdir(tmp_path)) == sorted([mine.name, link.name, *other])
    # an old file of a live pid that nobody holds is abandoned too
    old = time.time() - 2 * 24 * 3600
    os.utime(mine, (old, old))
    assert remove_stale_temp_files(tmp_path) == [mine]


def test_a_temporary_file_held_by_a_live_writer_is_kept(tmp_path):
    """A writer in another process holds the lock: even an old file of a 'dead' pid stays."""
    held = tmp_path / f".piece.k.illuknit-{dead_pid()}-held01.tmp"
    held.write_text("being written")
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import fcntl, sys, time\n"
            f"f = open({str(held)!r}, 'rb'); fcntl.flock(f, fcntl.LOCK_EX)\n"
            "print('locked', flush=True); time.sleep(60)",
        ],
        stdout=subprocess.PIPE,
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == b"locked"
        assert remove_stale_temp_files(tmp_path) == []
        assert held.exists()
    finally:
        holder.kill()
        holder.wait()
    assert remove_stale_temp_files(tmp_path) == [held]


def test_the_next_write_says_what_it_removed(tmp_path):
    (tmp_path / f".piece.k.illuknit-{dead_pid()}-abc.tmp").write_text("x")
    with pytest.warns(OutputRecoveryWarning, match="removed .piece.k.illuknit-"):
        atomic_write_bytes(tmp_path / "piece.k", b"new")
    assert os.listdir(tmp_path) == ["piece.k"]


def test_the_temporary_name_fits_a_long_target_name(tmp_path):
    target = tmp_path / ("n" * 250 + ".k")
    atomic_write_bytes(target, b"x")
    assert target.read_bytes() == b"x" and os.listdir(tmp_path) == [target.name]
