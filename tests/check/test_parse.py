"""The strict knitout parser: structure, line numbers, and every malformed-line error."""

from __future__ import annotations

import pytest

from illuknit.core.errors import KnitoutParseError
from illuknit.knitout.parse import Needle, parse_knitout

GOOD = """;!knitout-2
;;Machine: SWG091N2
;;Carriers: 1 2 3 4 5 6 7 8 9 10
;;Yarn-3: 50-50 Rust

; a comment
inhook 3
tuck - f-2 3 ; trailing comment
knit + b4 3 4
split + f1 b1 3
xfer fs2 b2
rack -0.75
stitch 10 20
x-stitch-number 61
pause
drop f1
amiss b0
releasehook 3
"""


def test_parse_structure_and_lines() -> None:
    prog = parse_knitout(GOOD)
    assert prog.version == 2
    assert prog.header("Carriers") == ("1 2 3 4 5 6 7 8 9 10", 3)
    assert prog.header("Yarn-3") == ("50-50 Rust", 4)
    assert prog.header("Width") is None
    ops = prog.operations
    assert [op.line for op in ops] == list(range(7, 19))
    assert ops[1].op == "tuck" and ops[1].direction == "-"
    assert ops[1].needles == (Needle("f", -2),) and ops[1].carriers == ("3",)
    assert ops[2].carriers == ("3", "4") and ops[2].needle.bed == "b"
    assert ops[3].needles == (Needle("f", 1), Needle("b", 1))
    assert ops[4].needle.is_slider and ops[4].needle.is_front
    assert ops[5].value == -0.75
    assert ops[6].args == ("10", "20")
    assert ops[7].op == "x-stitch-number"
    assert str(ops[2]) == "knit + b4 3 4"
    assert prog.n_lines == 18
    assert not prog.crlf


def test_header_ends_at_first_non_header_line() -> None:
    prog = parse_knitout(";!knitout-2\n;;A: 1\nin 3\n;;B: 2\n")
    assert [h[0] for h in prog.headers] == ["A"]


def test_crlf_and_tabs_are_flagged_not_refused() -> None:
    prog = parse_knitout(";!knitout-2\r\n;;Carriers: 1 2 3\r\nknit\t+ f1 3\r\n")
    assert prog.crlf
    assert prog.operations[0].tabs and prog.operations[0].line == 3


@pytest.mark.parametrize(
    ("text", "line", "fragment"),
    [
        ("", 1, "empty"),
        ("knit + f1 3\n", 1, "magic"),
        (";!knitout-x\n", 1, "magic"),
        (";!knitout-2\nfrobnicate f1\n", 2, "unknown operation"),
        (";!knitout-2\nknit f1 3\n", 2, "direction"),
        (";!knitout-2\nknit + g1 3\n", 2, "not a needle"),
        (";!knitout-2\nknit +\n", 2, "needle"),
        (";!knitout-2\nxfer f1\n", 2, "needle"),
        (";!knitout-2\nxfer f1 b1 3\n", 2, "no carriers"),
        (";!knitout-2\ndrop f1 3\n", 2, "no carriers"),
        (";!knitout-2\nin\n", 2, "at least one carrier"),
        (";!knitout-2\n\n\nrack\n", 4, "one racking"),
        (";!knitout-2\nrack one\n", 2, "number"),
        (";!knitout-2\nrack nan\n", 2, "finite"),
        (";!knitout-2\nstitch 10\n", 2, "two values"),
        (";!knitout-2\nknit + f1 f2\n", 2, "carrier name"),
        (";!knitout-2\nknit + f1 3\x01\n", 2, "control"),
        (";!knitout-2\nknit + f\uff13 3\n", 2, "not a needle"),
    ],
)
def test_malformed_lines_raise_with_line(text: str, line: int, fragment: str) -> None:
    with pytest.raises(KnitoutParseError) as info:
        parse_knitout(text)
    assert info.value.line == line
    assert fragment in str(info.value)


def test_binary_input_refused() -> None:
    with pytest.raises(KnitoutParseError, match="binary"):
        parse_knitout(";!knitout-2\n\x00\x01\x02")


def test_non_str_refused() -> None:
    with pytest.raises(KnitoutParseError, match="str"):
        parse_knitout(b";!knitout-2\n")  # type: ignore[arg-type]
