"""A program says what it is (issue 33, item 3): split or tall bumps are declared in a comment
line after the header, ``illuknit check`` reads it, so one file has one verdict; the reference
backends ignore the line (their ``.dat`` / ``.kc`` are byte-identical with and without it)."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.core.pattern import LogicalPattern, parse_yarns, save_pattern
from illuknit.knitout.bumps import BUMPS_COMMENT, DeclaredBumps, declare_bumps, declared_bumps
from illuknit.knitting import knit_pattern

YARNS = parse_yarns("#1b1b1b,#f4f0e8")


def _split_pattern() -> LogicalPattern:
    """Stripes of two yarns whose bumps show the other yarn to the other side."""
    yarn = np.tile(np.array([[0, 0, 1, 1, 0, 0, 1, 1]]), (6, 1)).astype(np.int16)
    raised = np.zeros_like(yarn, bool)
    raised[1::2] = True
    return LogicalPattern(yarn, raised, YARNS, upper=np.where(raised, 1 - yarn, yarn))


def _strip(text: str) -> str:
    return "\n".join(x for x in text.split("\n") if not x.startswith(BUMPS_COMMENT))


def test_a_split_bump_program_has_one_verdict(tmp_path, run_cli):
    result = knit_pattern(_split_pattern())
    assert result.split_bumps > 0
    assert declared_bumps(result.text) == DeclaredBumps(result.split_bumps, False)
    report = check_knitout(result.text)  # no split_bumps=: the program says it
    assert report.ok and "bump-yarn-change" not in report.codes()
    assert report.bumps == f"{result.split_bumps} split bumps, as the program declares"
    # the declaration is what makes it: without the line the same program is blocked
    assert "bump-yarn-change" in check_knitout(_strip(result.text)).codes()
    (tmp_path / "prog.k").write_text(result.text)
    code, out, _ = run_cli(["check", tmp_path / "prog.k"])
    assert code == 0 and f"bumps: {result.split_bumps} split bumps" in out
    # and knit says it too
    save_pattern(_split_pattern(), tmp_path / "p.json")
    code, out, _ = run_cli(["knit", tmp_path / "p.json", "-o", tmp_path / "k.k"])
    assert code == 0 and "bumps: " in out and "split bumps, declared in the program" in out


def test_tall_bumps_are_declared_and_plain_programs_say_nothing():
    plain = LogicalPattern(np.array([[0, 1], [1, 0]]), np.array([[1, 0], [0, 1]], bool), YARNS)
    assert not declared_bumps(knit_pattern(plain).text)
    tall = knit_pattern(plain, tall_bumps=True).text
    assert declared_bumps(tall) == DeclaredBumps(0, True)
    assert check_knitout(tall).bumps == "tall bumps, as the program declares"


@settings(max_examples=30, deadline=None)
@given(split=st.integers(0, 5000), tall=st.booleans())
def test_declaring_round_trips(split, tall):
    text = ";!knitout-2\n;;Machine: X\n;;Width: 540\n; comment\nknit + f1 1\n"
    out = declare_bumps(text, split=split, tall=tall)
    assert declared_bumps(out) == DeclaredBumps(split, tall)
    assert _strip(out) == text and out.split("\n")[:3] == text.split("\n")[:3]


def _convert(backend, text: str, tmp_path, name: str, suffix: str) -> bytes:
    src, dst = tmp_path / f"{name}.k", tmp_path / f"{name}{suffix}"
    src.write_text(text)
    subprocess.run(["node", str(backend), str(src), str(dst)], check=True, capture_output=True)
    return dst.read_bytes()


@pytest.mark.parametrize("machine", ["generic540", "kniterate"])
def test_the_reference_backends_ignore_the_declaration(
    machine, swg_backend, kniterate_backend, tmp_path
):
    text = knit_pattern(_split_pattern(), machine=machine, tall_bumps=True).text
    assert declared_bumps(text).split and declared_bumps(text).tall
    backend, suffix = (
        (swg_backend, ".dat") if machine == "generic540" else (kniterate_backend, ".kc")
    )
    with_line = _convert(backend, text, tmp_path, "a", suffix)
    without = _convert(backend, _strip(text), tmp_path, "a", suffix)  # same name: .kc line 3
    assert with_line == without
