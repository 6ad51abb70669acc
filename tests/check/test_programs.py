"""The hand-written fixture programs in tests/check/data, checked by illuknit and the PyPI VM.

Each faulty program is found with the right line and code, and nothing else blocks; the clean
programs have no blocking finding under either opinion.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from illuknit.check import check_knitout
from illuknit.check.vm import rewrite_for_vm, run_vm
from illuknit.core.errors import BackendUnavailableError
from illuknit.knitout import parse_knitout

DATA = Path(__file__).parent / "data"

#: file -> the blocking (line, code) pairs illuknit must report, and nothing else
BAD = {
    "bad_face_float.k": {(35, "face-float")},
    "bad_wrong_side.k": {(31, "wrong-side-carrier")},
    "bad_intarsia_no_catch.k": {(23, "pieces")},
    "bad_carrier_left_in.k": {(36, "carrier-left-in")},
    # the misaligned transfer also strands the loop on b5 until the end
    "bad_misaligned_xfer.k": {(33, "xfer-misaligned"), (60, "loops-left")},
}
CLEAN = ["clean_stockinette.k", "clean_garter.k", "clean_intarsia_plated.k"]


def read(name: str) -> str:
    return (DATA / name).read_text()


@pytest.mark.parametrize("name", sorted(BAD))
def test_faulty_program_found_at_its_line(name: str) -> None:
    report = check_knitout(read(name))
    got = {(f.line, f.code) for f in report.blocking if f.source == "illuknit"}
    assert got == BAD[name], report.to_text()
    # the line really is the culprit named in the comment of each fixture
    lines = read(name).splitlines()
    for line, _ in BAD[name]:
        assert lines[line - 1].strip() and not lines[line - 1].startswith(";")


def test_faulty_intarsia_has_two_pieces() -> None:
    assert check_knitout(read("bad_intarsia_no_catch.k")).pieces == 2


@pytest.mark.parametrize("name", CLEAN)
def test_clean_program_has_no_blocking_finding_in_either_opinion(name: str) -> None:
    report = check_knitout(read(name), simulate=True)
    assert report.ok, report.to_text()
    assert report.findings == (), report.to_text()
    assert report.pieces == 1
    assert report.vm is not None and report.vm["ran"] and report.vm["pieces"] == 1


def test_vm_agrees_on_the_misaligned_transfer_and_misses_the_fabric_failures() -> None:
    """What the PyPI simulator does and does not see (documented in docs/checker.md)."""
    mis = check_knitout(read("bad_misaligned_xfer.k"), simulate=True)
    assert any(f.source == "vm" and f.line == 33 and f.blocking for f in mis.findings)
    for name in ("bad_face_float.k", "bad_wrong_side.k", "bad_intarsia_no_catch.k"):
        text = read(name)
        vm = run_vm(text, parse_knitout(text))
        assert not [f for f in vm.findings if f.blocking], (name, vm.findings)
    # it does build the knit graph: the two intarsia blocks are two components there too
    text = read("bad_intarsia_no_catch.k")
    assert run_vm(text, parse_knitout(text)).pieces == 2


def test_vm_rewrite_keeps_line_numbers() -> None:
    text = (
        ";!knitout-2\n"
        ";;Machine: SWG091N2\n"
        ";;Width: 540\n"
        ";;X-Presser: on\n"
        ";;Yarn-3: Red\n"
        ";;Carriers: 1 2 3 4 5 6 7 8 9 10\n"
        "in 3 4\n"  # 7: split into two lines for the VM
        "stitch 10 20\n"  # 8
        "x-speed-number 5\n"  # 9
        "tuck - f-1 3 4\n"  # 10: needles shifted by +3
        "tuck - f-3 3 4\n"  # 11
        "rack 1\n"  # 12
        "xfer f-1 b-1\n"  # 13: misaligned, must map back to line 13
        "rack 0\n"
        "out 3 4\n"
        "drop f-1\n"
        "drop f-3\n"
    )
    prog = parse_knitout(text)
    rw = rewrite_for_vm(text, prog)
    assert rw.shift == 3
    assert "f2" in rw.text and "f-1" not in rw.text
    assert ";;Width" not in rw.text and "stitch 10 20" not in rw.text
    assert rw.origin.count(7) == 2 and rw.extra[rw.origin.index(7) + 1]
    vm = run_vm(text, prog)
    errors = [(f.line, f.code) for f in vm.findings if f.blocking]
    assert errors and all(line == 13 for line, _ in errors), vm.findings


def test_missing_sim_extra_is_reported_clearly(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "knitout_interpreter.knitout_execution", None)
    with pytest.raises(BackendUnavailableError, match=r"illuknit\[sim\]"):
        check_knitout(read("clean_stockinette.k"), simulate=True)


@pytest.mark.parametrize("machine", ["generic540", "kniterate"])
def test_a_drop_just_before_the_bind_off_is_a_dropped_stitch(machine: str) -> None:
    """A generated program checks clean; the same program with one live loop dropped right
    before its bind-off (or mid-piece) does not."""
    import numpy as np

    from illuknit.core.machine import get_machine
    from illuknit.core.pattern import LogicalPattern, parse_yarns
    from illuknit.knitting import knit_pattern

    rng = np.random.default_rng(5)
    pattern = LogicalPattern(
        rng.integers(0, 2, size=(3, 8)), rng.random((3, 8)) < 0.3, parse_yarns("#111111,#eeeeee")
    )
    text = knit_pattern(pattern, machine=get_machine(machine)).text
    assert not check_knitout(text).findings
    lines = text.split("\n")
    start = next(i for i, ln in enumerate(lines) if ln.startswith("rack ") and ln != "rack 0")
    needle = next(ln for ln in reversed(lines[:start]) if ln.startswith("knit ")).split()[2]
    dropped = "\n".join([*lines[:start], f"drop {needle}", *lines[start:]])
    found = [f for f in check_knitout(dropped).findings if f.code == "dropped-stitch"]
    assert [f.line for f in found] == [start + 1] and found[0].severity == "error"
    mid = next(i for i, ln in enumerate(lines) if ln.startswith("; course 3"))
    needle = next(ln for ln in reversed(lines[:mid]) if ln.startswith("knit ")).split()[2]
    dropped = "\n".join([*lines[:mid], f"drop {needle}", *lines[mid:]])
    codes = {f.code for f in check_knitout(dropped).findings}
    assert {"dropped-stitch", "knit-empty"} <= codes
