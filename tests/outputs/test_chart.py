import re

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.outputs.chart import chart_png_rgb, hand_rows, written_instructions

Y = parse_yarns("Dark=#1b1b1b,Light=#f4f0e8")


@st.composite
def patterns(draw):
    n, m = draw(st.integers(1, 6)), draw(st.integers(1, 6))
    return LogicalPattern(
        draw(arrays(np.int16, (n, m), elements=st.integers(0, 1))),
        draw(arrays(np.bool_, (n, m))),
        Y,
    )


def _tokens(text, yarn):
    """Stitches of a comma list: 'k2, p4' (in ``yarn``) or 'k2 Dark, p4 Light'."""
    out = []
    for tok in text.split(", "):
        op_count, _, name = tok.partition(" ")
        out += [(op_count[0], name or yarn)] * int(op_count[1:])
    return out


def _parse_row(line):
    """Expand 'Row k (WS): with Dark, *k2, p4; rep from * to last 2 sts, k2 (8 sts). [note]'
    or runs with colours into (op, yarn-name) stitches, checking the stitch count."""
    body = line.split(": ", 1)[1]
    body = re.sub(r" \[[^]]*\]$", "", body).rstrip(".")
    m = re.match(r"^(.*) \((\d+) sts\)$", body)
    assert m is not None, line
    body, total = m[1], int(m[2])
    yarn = None
    if body.startswith("with "):
        yarn, _, body = body[5:].partition(", ")
        if body.startswith(("knit across", "purl across")):
            return [(body[0], yarn)] * total
    rep = re.match(r"^(?:(.*?), )?\*(.*?); rep from \*(?: to end| to last (\d+) sts?, (.*))$", body)
    if rep is None:
        out = _tokens(body, yarn)
    else:
        pre = _tokens(rep[1], yarn) if rep[1] else []
        unit = _tokens(rep[2], yarn)
        suffix = _tokens(rep[4], yarn) if rep[4] else []
        reps, left = divmod(total - len(pre) - len(suffix), len(unit))
        assert left == 0 and reps >= 2, line
        out = pre + unit * reps + suffix
    assert len(out) == total, line
    return out


@given(patterns())
def test_instructions_rebuild_the_pattern(p):
    """Reading the written instructions back gives the pattern's yarns and bumps."""
    n, m = p.shape
    lines = [ln for ln in written_instructions(p).splitlines() if ln.startswith("Row ")]
    assert len(lines) == 2 * n
    names = [y.name for y in p.yarns]
    for k, line in enumerate(lines):
        stitches = _parse_row(line)
        assert len(stitches) == 2 * m
        unit_row = n - 1 - k // 2
        if k % 2 == 0:  # RS, right to left: all knit
            stitches = stitches[::-1]
            assert all(op == "k" for op, _ in stitches)
        else:  # WS, left to right: knit where raised
            assert [op == "k" for op, _ in stitches] == np.repeat(p.raised[unit_row], 2).tolist()
        assert [names.index(y) for _, y in stitches] == np.repeat(p.yarn[unit_row], 2).tolist()


def test_rows_and_chart_image():
    p = LogicalPattern(np.array([[0, 1], [1, 1]]), np.array([[1, 0], [0, 0]]), Y)
    rows = hand_rows(p)
    assert [r.side for r in rows] == ["RS", "WS", "RS", "WS"]
    assert rows[3].purl_on_rs.tolist() == [True, True, False, False]
    img = chart_png_rgb(p)
    assert img.ndim == 3 and img.shape[2] == 3


def test_chart_has_a_key_for_its_dots_and_yarns():
    from illuknit.outputs.chart import chart_key

    p = LogicalPattern(
        np.array([[0, 1], [1, 0]], np.int16), np.array([[True, False], [False, True]]), Y
    )
    key = chart_key(p)
    assert any("dot" in line and "purl on the right side" in line for line in key)
    assert [line for line in key if line.startswith("square")] == [
        "square = a stitch in Dark (#1b1b1b)",
        "square = a stitch in Light (#f4f0e8)",
    ]
    img = chart_png_rgb(p, cell=10)
    body_h = 4 * 10 + 2 * 40  # 4 stitch rows of 10 px, 40 px margins
    below = img[body_h:].reshape(-1, 3)
    for y in Y:  # each yarn's swatch is drawn in the key below the chart
        assert (below == np.array(y.rgb, np.uint8)).all(axis=1).any(), y.name


@given(st.tuples(*[st.integers(0, 255)] * 3))
def test_chart_ink_contrasts_with_every_yarn(rgb):
    """Grid lines, hatching and dots are drawn in black or white, whichever contrasts more with
    the yarn: at least 4.5 : 1 (WCAG AA) on any colour, where a fixed grey vanished."""
    from illuknit.outputs.chart import contrast_ratio, ink_on

    assert contrast_ratio(ink_on(rgb), rgb) >= 4.5


def test_chart_png_numbers_stitches_and_both_sides_rows_on_a_mid_grey_yarn():
    """Issue 37: chart.png has stitch numbers along the bottom, WS row numbers at the left and
    RS row numbers at the right, and its grid shows on a mid-grey yarn."""
    grey = parse_yarns("#808080,white")
    p = LogicalPattern(np.zeros((6, 8), np.int16), np.zeros((6, 8), bool), grey)
    img = chart_png_rgb(p, cell=12, unit_aspect=1.0).astype(int)
    margin, w, h = 40, 16 * 12, 12 * 12
    ink = img.sum(axis=2) < 3 * 100
    left, right = ink[margin : margin + h, :margin], ink[margin : margin + h, margin + w :]
    bottom = ink[margin + h + 2 : margin + h + margin - 2, margin : margin + w]
    rows_with_text = lambda band: int(band.any(axis=1).sum())  # noqa: E731
    assert rows_with_text(left) > h / 3 and rows_with_text(right) > h / 3
    assert bottom.any(), "stitch numbers along the bottom"
    grid = img[margin + 1 : margin + h - 1, margin + 1 : margin + w - 1]
    # one line in every cell's width: at least 1/12 of the grid drawn in black on the grey
    assert (grid.sum(axis=2) < 3 * 30).mean() > 1 / 12
    from illuknit.outputs.chart import chart_row_labels

    labels = chart_row_labels(12, 4)
    assert {s for _, s in labels} == {"left", "right"}
    assert all((r % 2 == 1) == (s == "right") for r, s in labels)
