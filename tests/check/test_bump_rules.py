"""The bump rules of the checker on tiny hand-written programs: a yarn change inside a bump
(``bump-yarn-change``, allowed only when split bumps are meant) and a bump's tuck moved before
the knit that clears it (``tuck-not-cleared``).

Programs start with a two-line header, so the first operation is line 3; the cast-on and the end
are those of ``test_rules``.
"""

from __future__ import annotations

from illuknit.check import check_knitout
from illuknit.check.fabric import FABRIC_RULES
from tests.check.test_rules import CAST_ON, END, HEAD

#: one course '+' with a bump on the right edge needle 3: its knit loop (carrier 3, cast-on
#: course) moves to the back and is purled, then comes back
BUMP = ["xfer f3 b3", "knit + f0 3", "knit + f1 3", "knit + f2 3", "knit + b3 3", "xfer b3 f3"]
#: the same bump purled in carrier 4: a split bump (lines 15-24)
SPLIT = [
    "xfer f3 b3",
    "knit + f0 3",
    "knit + f1 3",
    "knit + f2 3",
    "inhook 4",
    "knit - b3 4",
    "releasehook 4",
    "xfer b3 f3",
    "outhook 4",
]


def codes(text: str, **kw: object) -> list[tuple[int, str]]:
    report = check_knitout(text, **kw)  # type: ignore[arg-type]
    return sorted((f.line, f.code) for f in report.findings)


def test_a_plain_bump_is_clean() -> None:
    assert codes(HEAD + "\n".join([*CAST_ON, *BUMP, *END]) + "\n") == []


def test_a_yarn_change_inside_a_bump_is_an_error_unless_split_bumps_are_meant() -> None:
    text = HEAD + "\n".join([*CAST_ON, *SPLIT, *END]) + "\n"
    assert codes(text) == [(20, "bump-yarn-change")]
    assert FABRIC_RULES["bump-yarn-change"][0] == "error"
    assert codes(text, split_bumps=True) == []


def test_a_bump_tuck_moved_before_its_knit_is_reported_and_a_cleared_one_is_not() -> None:
    moved = [
        "xfer f1 b1",
        "tuck + b1 3",  # line 16: joins the loop b1 holds
        "xfer b1 f1",  # line 17: moved before any knit on b1
        "miss + f4 3",
        "knit - f3 3",
        "knit - f2 3",
        "knit - f1 3",
        "knit - f0 3",
    ]
    assert codes(HEAD + "\n".join([*CAST_ON, *moved, *END]) + "\n") == [(17, "tuck-not-cleared")]
    cleared = [
        "xfer f1 b1",
        "tuck + b1 3",
        "miss + f4 3",
        "knit - f3 3",
        "knit - f2 3",
        "knit - b1 3",  # the purl pulls the bump's loop and its tuck through: cleared
        "knit - f0 3",
        "xfer b1 f1",
    ]
    assert codes(HEAD + "\n".join([*CAST_ON, *cleared, *END]) + "\n") == []


def test_a_tuck_on_an_empty_back_needle_is_no_bump_tuck() -> None:
    # (a float tuck on a free back needle, later joined by a transfer, is not a bump's tuck)
    body = [
        "tuck + b1 3",
        "xfer b1 f1",
        "miss + f4 3",
        "knit - f3 3",
        "knit - f2 3",
        "knit - f1 3",
        "knit - f0 3",
    ]
    assert "tuck-not-cleared" not in {
        c for _, c in codes(HEAD + "\n".join([*CAST_ON, *body, *END]) + "\n")
    }
