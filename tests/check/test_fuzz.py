"""Hypothesis properties of the checker.

* Any text built from knitout-like lines (valid, mutated or garbage) gives a report or a
  KnitoutParseError, never another exception.
* Well-formed knit/purl programs (a generator written here from the knitout notes) have no
  finding; breaking them in one known way is found at the right line.
* illuknit's piece count agrees with the PyPI simulator's knit graph on small random programs.
"""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.check import CheckReport, check_knitout
from illuknit.check.vm import run_vm
from illuknit.core.errors import KnitoutParseError
from illuknit.knitout import parse_knitout

HEAD = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n"

needles = st.builds(
    lambda b, i: f"{b}{i}", st.sampled_from(["f", "b", "fs", "bs"]), st.integers(-3, 12)
)
carriers = st.lists(st.sampled_from(["1", "3", "4", "11", "x"]), min_size=0, max_size=3).map(
    " ".join
)
direction = st.sampled_from(["+", "-"])
valid_line = st.one_of(
    st.builds(
        lambda o, c: f"{o} {c or '3'}",
        st.sampled_from(["in", "inhook", "out", "outhook", "releasehook"]),
        carriers,
    ),
    st.builds(
        lambda o, d, n, c: f"{o} {d} {n} {c}",
        st.sampled_from(["knit", "tuck", "miss"]),
        direction,
        needles,
        carriers,
    ),
    st.builds(lambda d, a, b, c: f"split {d} {a} {b} {c}", direction, needles, needles, carriers),
    st.builds(lambda a, b: f"xfer {a} {b}", needles, needles),
    st.builds(lambda o, n: f"{o} {n}", st.sampled_from(["drop", "amiss"]), needles),
    st.builds(
        lambda r: f"rack {r}", st.sampled_from(["0", "1", "-1", "0.25", "-0.75", "0.5", "5", "2"])
    ),
    st.sampled_from(["pause", "stitch 10 20", "x-speed-number 3", "; comment", ""]),
)
junk_line = st.text(
    alphabet=st.sampled_from(list("knituckfbs+-0123456789 ;\t!:xrXa\r")), max_size=20
)
any_line = st.one_of(valid_line, valid_line, junk_line)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(any_line, max_size=40), st.booleans())
def test_never_crashes(lines: list[str], with_header: bool) -> None:
    text = (HEAD if with_header else "") + "\n".join(lines)
    try:
        report = check_knitout(text)
    except KnitoutParseError as e:
        assert e.line is None or e.line >= 1
        return
    assert isinstance(report, CheckReport)
    assert report.pieces >= 0
    assert all(f.line <= report.n_lines for f in report.findings)
    report.to_json()
    report.to_text()


@settings(max_examples=200, deadline=None)
@given(st.lists(valid_line, max_size=40))
def test_valid_lines_always_parse(lines: list[str]) -> None:
    prog = parse_knitout(HEAD + "\n".join(lines) + "\n")
    assert len(prog.operations) == sum(1 for ln in lines if ln and not ln.startswith(";"))


# ---- a well-formed generator -----------------------------------------------------------------


def textured_program(width: int, masks: list[list[bool]], carrier: str = "3") -> list[str]:
    """Hooked tuck cast-on, then one course per mask (True = purl) knitting front and back
    stitches in the same pass, alternating directions; loops change bed by transfers batched
    before each course; ends with outhook and drops. Returns the body lines."""
    c = carrier
    hi = width - 1
    odd = list(range(hi, -1, -2))
    body = [f"inhook {c}", *[f"tuck - f{n} {c}" for n in odd], f"miss - f0 {c}"]
    body += [f"tuck + f{n} {c}" for n in range(width) if n not in odd]
    body += [f"miss + f{hi} {c}", *[f"knit - f{n} {c}" for n in range(hi, -1, -1)]]
    body.append(f"releasehook {c}")
    back = [False] * width
    d = "+"
    for mask in masks:
        for n in range(width):
            if mask[n] != back[n]:
                body.append(f"xfer f{n} b{n}" if mask[n] else f"xfer b{n} f{n}")
                back[n] = mask[n]
        order = range(width) if d == "+" else range(hi, -1, -1)
        body += [f"knit {d} {'b' if back[n] else 'f'}{n} {c}" for n in order]
        d = "-" if d == "+" else "+"
    body += [f"xfer b{n} f{n}" for n in range(width) if back[n]]
    body += [f"outhook {c}", *[f"drop f{n}" for n in range(width)]]
    return body


@st.composite
def textures(draw: st.DrawFn) -> tuple[int, list[list[bool]]]:
    width = draw(st.integers(2, 8))
    rows = draw(st.integers(1, 6))
    masks = draw(
        st.lists(
            st.lists(st.booleans(), min_size=width, max_size=width), min_size=rows, max_size=rows
        )
    )
    return width, masks


@settings(max_examples=60, deadline=None)
@given(textures())
def test_well_formed_programs_are_clean(texture: tuple[int, list[list[bool]]]) -> None:
    width, masks = texture
    report = check_knitout(HEAD + "\n".join(textured_program(width, masks)) + "\n")
    assert report.findings == (), report.to_text()
    assert report.pieces == 1
    assert report.n_loops == width * (len(masks) + 2)  # tucks, cast-on course, courses


@settings(max_examples=60, deadline=None)
@given(textures(), st.data())
def test_repeated_direction_is_found_at_its_first_stitch(
    texture: tuple[int, list[list[bool]]], data: st.DataObject
) -> None:
    width, masks = texture
    body = textured_program(width, masks)
    knits = [i for i, ln in enumerate(body) if ln.startswith("knit ")][width:]  # after cast-on
    course = data.draw(st.integers(0, len(masks) - 1))
    first = knits[course * width]
    # knit this course in the same direction as the previous one (the cast-on course went '-')
    flipped = "-" if course % 2 == 0 else "+"
    block = body[first : first + width]
    body[first : first + width] = [
        ln.replace(" + ", f" {flipped} ").replace(" - ", f" {flipped} ") for ln in reversed(block)
    ]
    report = check_knitout(HEAD + "\n".join(body) + "\n")
    wrong = [f.line for f in report.findings if f.code == "wrong-side-carrier"]
    assert wrong and wrong[0] == first + 3  # two header lines, 1-based


@settings(max_examples=6, deadline=None)
@given(textures(), st.booleans())
def test_pieces_agree_with_the_pypi_simulator(
    texture: tuple[int, list[list[bool]]], second: bool
) -> None:
    width, masks = texture
    body = textured_program(width, masks)
    if second:  # an unconnected swatch of carrier 4 beside it (shifted right)
        other = textured_program(2, [[False, True]], carrier="4")
        body += [_shift(ln, width + 2) for ln in other]
    text = HEAD + "\n".join(body) + "\n"
    report = check_knitout(text)
    vm = run_vm(text, parse_knitout(text))
    assert report.pieces == vm.pieces == (2 if second else 1)
    assert not [f for f in vm.findings if f.blocking], vm.findings


def _shift(line: str, k: int) -> str:
    out = []
    for t in line.split():
        if t[:1] in "fb" and t[1:].lstrip("-").isdigit():
            out.append(f"{t[0]}{int(t[1:]) + k}")
        else:
            out.append(t)
    return " ".join(out)
