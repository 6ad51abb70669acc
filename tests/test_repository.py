"""The checkout holds only what belongs to it (issue 33, item 9): a stray ``--04.png`` (page 4
of a pattern.pdf, written by ``pdftoppm ... -`` into the repository root: pdftoppm takes "-" as
a file-name root, not standard output) was once committed."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _tracked() -> list[str]:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    run = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True)
    return run.stdout.splitlines()


def test_no_file_is_named_like_an_option():
    assert [f for f in _tracked() if any(part.startswith("-") for part in f.split("/"))] == []


def test_git_ignores_files_named_like_an_option_at_the_root():
    run = subprocess.run(
        ["git", "check-ignore", "--no-index", "-q", "--", "--04.png"], cwd=ROOT, check=False
    )
    assert run.returncode == 0
