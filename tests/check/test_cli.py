"""``illuknit check``: exit codes 0/1/2, human and JSON output, one-line errors for bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"


def test_clean_exits_0(run_cli) -> None:
    code, out, err = run_cli(["check", str(DATA / "clean_garter.k")])
    assert code == 0 and err == ""
    assert "OK" in out and "1 piece" in out


def test_blocking_exits_1_with_line(run_cli) -> None:
    path = DATA / "bad_face_float.k"
    code, out, _ = run_cli(["check", str(path)])
    assert code == 1
    assert f"{path}:35: error face-float" in out
    assert "BLOCKED" in out


def test_json_output(run_cli) -> None:
    code, out, _ = run_cli(["check", "--json", str(DATA / "bad_intarsia_no_catch.k")])
    assert code == 1
    doc = json.loads(out)
    assert doc["pieces"] == 2 and not doc["ok"]
    assert {"line": 23, "code": "pieces"}.items() <= doc["findings"][0].items()


def test_float_limit_option(run_cli, tmp_path: Path) -> None:
    prog = tmp_path / "float.k"
    prog.write_text(
        ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\nin 3\ntuck - f8 3\ntuck - f0 3\n"
        "out 3\ndrop f8\ndrop f0\n"
    )
    code, out, _ = run_cli(["check", "--json", "--float-limit", "3", str(prog)])
    assert code == 0
    assert [f["code"] for f in json.loads(out)["findings"]] == ["long-float"]
    code, out, _ = run_cli(["check", "--json", "--float-limit", "7", str(prog)])
    assert json.loads(out)["findings"] == []


def test_simulate_flag(run_cli) -> None:
    code, out, _ = run_cli(["check", "--simulate", "--json", str(DATA / "bad_misaligned_xfer.k")])
    assert code == 1
    doc = json.loads(out)
    assert doc["vm"]["ran"] is True
    assert any(f["source"] == "vm" and f["line"] == 33 for f in doc["findings"])


@pytest.mark.parametrize(
    ("content", "fragment"),
    [
        (b"\x00\x01binary", "binary file"),
        (b";!knitout-2\n\xff\xfe\n", "not UTF-8"),
        (b"hello\n", "line 1: first line must be the magic line"),
        (b";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\nknit + f1\nknit x f1 3\n", "line 4:"),
    ],
)
def test_unreadable_input_exits_2_with_one_line(
    content: bytes, fragment: str, tmp_path: Path, run_cli
) -> None:
    prog = tmp_path / "PROGRAM.k"
    prog.write_bytes(content)
    code, out, err = run_cli(["check", str(prog)])
    assert code == 2 and out == ""
    assert err.startswith("illuknit: error: ") and err.count("\n") == 1
    assert fragment in err and "PROGRAM.k" in err


def test_missing_file_and_bad_option_exit_2(tmp_path: Path, run_cli) -> None:
    code, _, err = run_cli(["check", str(tmp_path / "nope.k")])
    assert code == 2 and err.startswith("illuknit: error:")
    code, _, err = run_cli(["check", "--float-limit", "0", str(DATA / "clean_garter.k")])
    assert code == 2 and "float-limit" in err


def test_python_m_exit_code() -> None:
    """The exit code survives `python -m illuknit` (not only the console script)."""
    proc = subprocess.run(
        [sys.executable, "-m", "illuknit", "check", str(DATA / "bad_wrong_side.k")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1, proc.stderr
    assert "wrong-side-carrier" in proc.stdout
