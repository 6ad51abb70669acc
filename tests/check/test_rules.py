"""Every machine rule and fabric check on tiny hand-written programs, with its line number.

Programs start with a two-line header (magic + ;;Carriers), so the first operation is line 3.
"""

from __future__ import annotations

import pytest

from illuknit.check import CheckReport, check_knitout
from illuknit.check.fabric import FABRIC_RULES
from illuknit.check.rules import RULES
from illuknit.core.errors import OptionError

HEAD = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n"

#: a clean 4-needle start: hooked tuck cast-on, one course leftward, hook released (lines 3-14)
CAST_ON = [
    "inhook 3",
    "tuck - f3 3",
    "tuck - f1 3",
    "miss - f0 3",
    "tuck + f0 3",
    "tuck + f2 3",
    "miss + f3 3",
    "knit - f3 3",
    "knit - f2 3",
    "knit - f1 3",
    "knit - f0 3",
    "releasehook 3",
]
END = ["outhook 3", "drop f0", "drop f1", "drop f2", "drop f3"]


def run(*body: str, **kw: object) -> CheckReport:
    return check_knitout(HEAD + "\n".join(body) + "\n", **kw)  # type: ignore[arg-type]


def hits(report: CheckReport) -> set[tuple[int, str]]:
    return {(f.line, f.code) for f in report.findings}


def test_clean_minimal_program() -> None:
    r = run(*CAST_ON, *END)
    assert r.findings == ()
    assert r.ok and r.pieces == 1 and r.n_loops == 8


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        (["inhook 3", "tuck - f2 3", "tuck + f3 3"], (5, "hook-blocked")),
        (["inhook 3", "tuck - f2 3", "miss + f4 3"], (5, "hook-blocked")),
        (["inhook 3", "tuck + f0 3"], (4, "hook-rightward")),
        (["inhook 3", "inhook 4"], (4, "hook-busy")),
        (["inhook 3", "tuck - f1 3", "releasehook 4"], (5, "release-wrong-set")),
        (["inhook 3", "releasehook 3"], (4, "release-before-stitch")),
        (["releasehook 3"], (3, "release-empty")),
        (
            ["in 4", "tuck - f5 4", "inhook 3", "tuck - f1 3", "outhook 4"],
            (7, "outhook-hook-busy"),
        ),
        (["inhook 3", "tuck - f1 3", "out 3"], (5, "out-hooked")),
        (["in 11"], (3, "carrier-unknown")),
        (["knit - f1 3"], (3, "carrier-not-in")),
        (["in 3", "tuck - f1 3", "out 3", "tuck + f1 3"], (6, "carrier-not-in")),
        (["in 3", "tuck - f1 3", "in 3"], (5, "in-active-carrier")),
        (["in 3 4", "tuck - f1 3"], (4, "first-use-mismatch")),
        (["in 3 4", "tuck - f1 4 3"], (4, "first-use-mismatch")),
        (["out 3"], (3, "out-inactive")),
        (["in 3", "out 3"], (4, "out-unused")),
        (["miss + f1"], (3, "miss-without-carriers")),
        (["rack 5"], (3, "rack-range")),
        (["rack -4.25"], (3, "rack-range")),
        (["rack 0.5"], (3, "rack-fraction")),
        (["rack 1", "xfer f1 b1"], (4, "xfer-misaligned")),
        (["rack 0.25", "xfer f1 b1"], (4, "xfer-misaligned")),
        (["rack -2", "split + b3 f2 3"], (4, "xfer-misaligned")),
        (["xfer f1 f2"], (3, "xfer-same-bed")),
        (["xfer fs1 bs1"], (3, "xfer-slider-slider")),
        (["in 3", "tuck - fs1 3"], (4, "stitch-on-slider")),
        (["in 3", "tuck - f1 3 3"], (4, "duplicate-carrier")),
        (
            ["in 3", "tuck - f1 3", "tuck + f1 3", "tuck - f1 3", "tuck + f1 3", "tuck - f1 3"],
            (8, "too-many-loops"),
        ),
        (["in 3", "tuck - f1 3", "xfer f1 b1", "knit + f1 3"], (6, "knit-empty")),
    ],
)
def test_machine_rule(body: list[str], expected: tuple[int, str]) -> None:
    r = run(*body)
    assert expected in hits(r), r.findings
    f = next(f for f in r.findings if (f.line, f.code) == expected)
    assert f.severity == RULES[f.code][0]
    assert f.message


def test_racking_quarter_pitch_and_limits_accepted() -> None:
    r = run("rack 0.25", "rack -0.75", "rack 4", "rack -4")
    assert not r.findings
    assert ("rack 3", "rack-range") and (3, "rack-range") in hits(run("rack 3", max_racking=2))


def test_aligned_transfers_accepted() -> None:
    r = run(*CAST_ON, "rack -1", "xfer f3 b4", "rack 2", "xfer b0 f2", "rack 0", *END, "drop b4")
    assert not r.blocking, r.findings


def test_header_findings() -> None:
    assert (1, "header-carriers") in hits(check_knitout(";!knitout-2\n"))
    assert (2, "header-carriers") in hits(check_knitout(";!knitout-2\n;;Carriers: 1 2 3\n"))
    assert (2, "header-value") in hits(check_knitout(";!knitout-2\n;;Width: wide\n"))
    assert (2, "header-value") in hits(check_knitout(";!knitout-2\n;;Gauge: -3\n"))
    assert (2, "header-value") in hits(check_knitout(";!knitout-2\n;;Position: Middle\n"))
    assert (2, "header-machine") in hits(check_knitout(";!knitout-2\n;;Machine: Stoll\n"))
    assert (1, "header-version") in hits(check_knitout(";!knitout-3\n"))
    assert (4, "tab-separator") in hits(check_knitout(HEAD + "in 3\nrack\t1\n"))
    assert (1, "crlf") in hits(check_knitout(HEAD.replace("\n", "\r\n")))


def test_bed_width() -> None:
    body = ["in 3", *[f"tuck - f{n} 3" for n in (5, 3, 1)]]
    assert (6, "too-wide") in hits(run(*body, bed_width=4))
    assert not any(f.code == "too-wide" for f in run(*body, bed_width=6).findings)
    keep = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n;;Width: 10\n;;Position: Keep\n"
    assert (6, "too-wide") in hits(check_knitout(keep + "in 3\ntuck - f0 3\n"))


# ---- fabric checks ------------------------------------------------------------------------------


def test_wrong_side_both_directions() -> None:
    plus_twice = run(*CAST_ON, "knit + f0 3", "knit + f1 3", "knit + f0 3")
    assert (17, "wrong-side-carrier") in hits(plus_twice)
    minus_twice = run(*CAST_ON, "knit - f2 3")  # carrier parked left of f0 after the cast-on
    assert (15, "wrong-side-carrier") in hits(minus_twice)
    f = next(f for f in minus_twice.findings if f.code == "wrong-side-carrier")
    assert f.severity == FABRIC_RULES["wrong-side-carrier"][0] == "error"


def test_turning_at_the_same_needle_is_fine() -> None:
    r = run(*CAST_ON, "knit + f0 3", "knit - f0 3", "knit + f0 3", *END)
    assert not r.findings


def test_miss_parks_the_carrier() -> None:
    bad = run(*CAST_ON, "knit + f0 3", "knit + f1 3", "knit + f0 3")
    good = run(*CAST_ON, "knit + f0 3", "knit + f1 3", "miss - f0 3", "knit + f0 3")
    assert "wrong-side-carrier" in {f.code for f in bad.findings}
    assert "wrong-side-carrier" not in {f.code for f in good.findings}


def test_all_needle_quarter_pitch_pass_is_not_wrong_side() -> None:
    body = ["in 3", "rack 0.25"]
    body += [f"tuck + {b}{n} 3" for n in range(4) for b in ("f", "b")]
    body += [f"knit - {b}{n} 3" for n in range(3, -1, -1) for b in ("b", "f")]
    body += ["rack 0", "out 3"] + [f"drop {b}{n}" for n in range(4) for b in "fb"]
    r = run(*body)
    assert not r.findings, r.findings


def test_face_float_only_where_no_front_loop_hides_it() -> None:
    purls = [*CAST_ON, "xfer f1 b1", "xfer f2 b2"]
    bad = run(*purls, "knit + f0 3", "knit + f3 3")
    assert (18, "face-float") in hits(bad)
    assert "b1, b2" in next(f.message for f in bad.findings if f.code == "face-float")
    # purls knit in the same pass: no float
    good = run(*purls, "knit + f0 3", "knit + b1 3", "knit + b2 3", "knit + f3 3")
    assert "face-float" not in {f.code for f in good.findings}
    # a front loop in the same slot hides the yarn (double layer)
    both = run(*CAST_ON, "tuck + b1 3", "knit + f3 3")  # f1 still holds its loop
    assert "face-float" not in {f.code for f in both.findings}


def test_long_float_respects_limit() -> None:
    body = [
        "in 3",
        *[f"tuck - f{n} 3" for n in (20, 0)],
        "knit + f0 3",
        "knit + f20 3",
        "out 3",
        "drop f0",
        "drop f20",
    ]
    r = run(*body, float_limit=10)
    longs = [f for f in r.findings if f.code == "long-float"]
    assert [(f.line, f.severity) for f in longs] == [(5, "warning"), (7, "warning")]
    assert not [f for f in run(*body, float_limit=19).findings if f.code == "long-float"]


def test_end_of_program_checks() -> None:
    r = run(*CAST_ON)
    codes = hits(r)
    assert (14, "loops-left") in codes
    assert (13, "carrier-left-in") in codes
    hooked = run("inhook 3", "tuck - f1 3")
    assert (4, "hook-left") in hits(hooked)


def test_pieces_count_and_first_line_of_second_piece() -> None:
    r = run("in 3", "tuck - f1 3", "in 4", "tuck - f5 4", "out 3", "out 4", "drop f1", "drop f5")
    assert r.pieces == 2
    assert (6, "pieces") in hits(r)
    joined = run(
        "in 3",
        "tuck - f1 3",
        "in 4",
        "tuck - f5 4",
        "knit + f1 4 3",
        "out 3",
        "out 4",
        "drop f1",
        "drop f5",
    )
    assert joined.pieces == 1


def test_bad_options() -> None:
    for kw in ({"float_limit": 0}, {"float_limit": 2.5}, {"max_racking": 0}, {"bed_width": 0}):
        with pytest.raises(OptionError):
            check_knitout(HEAD, **kw)  # type: ignore[arg-type]


def test_report_json_roundtrip_and_caps() -> None:
    import json

    body = ["in 3", *[f"tuck - f{n} 3" for n in range(300, 0, -1)]]
    body += [f"xfer f{n} b{n}" for n in range(1, 301)]  # every needle emptied: knits find none
    body += [*[f"knit + f{n} 3" for n in range(1, 301)], "out 3"]
    r = run(*body)
    doc = json.loads(r.to_json())
    assert doc["blocking"] == 1  # loops left; knit-empty is only a warning
    assert doc["warnings"] == 300 and len(doc["findings"]) == 201  # true count, capped list
    assert r.suppressed == {"knit-empty": 100}
    assert r.codes()["knit-empty"] == 300
    assert "100 more knit-empty" in r.to_text()


def test_huge_needle_numbers_stay_fast() -> None:
    """A float across a billion needles must not walk every slot."""
    r = run("in 3", "tuck - f1 3", "xfer f1 b1", "tuck + f0 3", "tuck + f1000000000 3")
    assert (7, "face-float") in hits(r)
    assert (7, "long-float") in hits(r)


# ---- casting on and dropping: recognised by structure ------------------------------------------


def test_knitting_needles_that_never_held_a_loop_casts_on() -> None:
    # the waste yarn's cast-on: knits on alternate beds of empty needles, then a course back
    body = ["in 3", *[f"knit + {'fb'[n % 2]}{n} 3" for n in range(6)]]
    body += [f"knit - {'bf'[n % 2]}{n} 3" for n in range(5, -1, -1)]
    r = run(*body, "out 3", *[f"drop {b}{n}" for n in range(6) for b in "fb"])
    assert not r.findings, r.findings


def test_a_knit_where_the_loop_was_dropped_is_reported() -> None:
    r = run(*CAST_ON, "drop f2", "knit + f0 3", "knit + f1 3", "knit + f2 3", "knit + f3 3")
    assert {(15, "dropped-stitch"), (18, "knit-empty")} <= hits(r)
    f = next(f for f in r.findings if f.code == "dropped-stitch")
    assert f.severity == "error" and "f2" in f.message and "ladders" in f.message


def test_the_final_release_and_a_tail_are_not_dropped_stitches() -> None:
    assert not run(*CAST_ON, *END).findings  # everything dropped after the last stitch
    # a chain ending in a tail on f0, its last loop dropped, then more work elsewhere
    tail = ["knit + f0 3", "knit - f0 3", "knit + f0 3", "drop f0"]
    r = run(*CAST_ON, *tail, "miss + f0 3", "knit + f1 3", "knit + f2 3", "knit + f3 3", *END)
    assert "dropped-stitch" not in {f.code for f in r.findings}, r.findings


def test_waste_yarn_released_below_a_draw_thread_is_not_a_dropped_stitch() -> None:
    # waste yarn 6 on both beds, taken out; its back loops dropped; draw thread 1 knits every
    # loop left and goes out; the piece (3) knits on the draw thread
    waste = ["in 6", *[f"knit + {'fb'[n % 2]}{n} 6" for n in range(4)]]
    waste += [f"knit - {'bf'[n % 2]}{n} 6" for n in range(3, -1, -1)]
    waste += ["knit + f0 6", "knit + f1 6", "knit + f2 6", "knit + f3 6", "out 6"]
    waste += [f"drop b{n}" for n in range(4)]
    draw = ["in 1", *[f"knit - f{n} 1" for n in range(3, -1, -1)], "out 1"]
    piece = ["in 3", *[f"knit + f{n} 3" for n in range(4)]]
    piece += [*[f"knit - f{n} 3" for n in range(3, -1, -1)], "out 3"]
    piece += [f"drop f{n}" for n in range(4)]
    r = run(*waste, *draw, *piece)
    assert not r.findings, r.findings
    # without the draw thread the same drops lose loops of the fabric
    r = run(*waste, *piece)
    assert "dropped-stitch" in {f.code for f in r.findings}
