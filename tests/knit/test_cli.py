"""``illuknit knit``: output, summary, and one-line errors (exit 2) with nothing written."""

from __future__ import annotations

import json

import numpy as np
import pytest

from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern

YARNS = tuple(Yarn(f"y{i}", (i * 20, 255 - i * 20, 3 * i)) for i in range(12))


def save(tmp_path, yarn, raised=None, k=2, name="p.json"):
    yarn = np.asarray(yarn)
    raised = np.zeros(yarn.shape, bool) if raised is None else raised
    path = tmp_path / name
    save_pattern(LogicalPattern(yarn, raised, YARNS[:k]), path)
    return path


def test_knit_writes_a_program_and_reports_passes_time_and_check(tmp_path, run_cli):
    yarn = np.repeat((np.arange(4) % 2)[:, None], 3, axis=1)
    pat = save(tmp_path, yarn, np.eye(4, 3, dtype=bool))
    out = tmp_path / "prog.k"
    code, stdout, err = run_cli(["knit", str(pat), "-o", str(out)])
    assert code == 0, err
    text = out.read_text()
    assert text.startswith(";!knitout-2\n")
    assert "lower bound" in stdout and "ratio 1.0" in stdout
    assert "estimated knitting time" in stdout
    assert "check: 0 error(s)" in stdout


def test_knit_json_summary_and_overrides(tmp_path, run_cli):
    pat = save(tmp_path, np.zeros((2, 2), int), k=1)
    out = tmp_path / "prog.k"
    args = ["knit", str(pat), "-o", str(out), "--json", "--gauge", "14", "--machine-width", "60"]
    code, stdout, _ = run_cli([*args, "--seconds-per-needle", "0", "--seconds-per-turn", "2"])
    assert code == 0
    s = json.loads(stdout)
    assert s["gauge"] == 14 and s["wales"] == 4 and s["courses"] == 4
    # Time is counted on the machine's passes, hook passes included.
    assert s["time_seconds"] == pytest.approx(2 * s["passes"])
    assert ";;Width: 60" in out.read_text() and s["check"]["errors"] == 0


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("mixed", "needs 11 carriers at once"),
        ("wide", "machine-width"),
        ("yarns", "11 yarns"),
        ("malformed", "not valid JSON"),
        ("missing", "not found"),
        ("version", "version"),
    ],
)
def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, run_cli, case, message):
    out = tmp_path / "prog.k"
    extra = []
    if case == "mixed":  # one course with more colours than the machine has carriers
        pat = save(tmp_path, [list(range(11))], k=11)
    elif case == "wide":
        pat = save(tmp_path, np.zeros((2, 40), int), k=1)
        extra = ["--machine-width", "50"]
    elif case == "yarns":
        pat = save(tmp_path, np.repeat(np.arange(11)[:, None], 2, axis=1), k=11)
    elif case == "malformed":
        pat = tmp_path / "bad.json"
        pat.write_text("{not json")
    elif case == "missing":
        pat = tmp_path / "nope.json"
    else:
        pat = save(tmp_path, np.zeros((2, 2), int), k=1)
        doc = json.loads(pat.read_text())
        doc["version"] = 99
        pat.write_text(json.dumps(doc))
    code, _, err = run_cli(["knit", str(pat), "-o", str(out), *extra])
    assert code == 2
    assert err.startswith("illuknit: error:") and message in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()
    assert not list(tmp_path.glob(".prog.k*"))
