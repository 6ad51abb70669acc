"""Hand-knitting rows: repeats folded without losing a stitch, colourwork counted by brute force,
advice that follows the numbers, yarn estimates that add up."""

from __future__ import annotations

import re
from itertools import pairwise

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.gauge import parse_gauge
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.design.hand_cost import MAX_FLOAT, MAX_HAND_BLOCKS
from illuknit.design.hand_cost import hand_rows as cost_rows
from illuknit.outputs.chart import hand_rows, written_instructions
from illuknit.outputs.hand_pattern import (
    CATCH_EVERY,
    MIN_INTARSIA_BLOCK,
    compress_repeats,
    hand_advice,
    row_colourwork,
    written_row,
    yarn_estimate,
)

YARNS3 = parse_yarns("black,firebrick,linen")


def expand(text: str, total: int) -> list[str]:
    """Stitches of a written row back from its text (``*...; rep from * to last K sts, ...``)."""
    m = re.match(r"^(?:(?P<pre>.*?), )?\*(?P<unit>.*?); rep from \*(?P<rest>.*)$", text)
    if m is None:
        return [t for tok in text.split(", ") for t in [tok[0]] * int(tok[1:])]
    pre = expand(m["pre"], 0) if m["pre"] else []
    unit = expand(m["unit"], 0)
    rest = m["rest"]
    suffix: list[str] = []
    last = 0
    if rest != " to end":
        lm = re.match(r" to last (\d+) sts?, (.*)$", rest)
        assert lm is not None, rest
        last, suffix = int(lm[1]), expand(lm[2], 0)
        assert len(suffix) == last
    body = total - len(pre) - last
    assert body % len(unit) == 0 and body // len(unit) >= 2
    return pre + unit * (body // len(unit)) + suffix


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("kp"), st.integers(1, 5)), min_size=1, max_size=30))
def test_folded_repeats_expand_to_the_same_stitches(runs):
    # merge neighbouring runs of one stitch, as written rows have them
    merged: list[list] = []
    for op, n in runs:
        if merged and merged[-1][0] == op:
            merged[-1][1] += n
        else:
            merged.append([op, n])
    tokens = [(f"{op}{n}", n) for op, n in merged]
    stitches = [op for op, n in merged for _ in range(n)]
    assert expand(compress_repeats(tokens), len(stitches)) == stitches


def test_written_rows_carry_their_stitch_count_and_fold_ribbing():
    worked = [("k", 0), ("k", 0), ("p", 0), ("p", 0), ("p", 0), ("p", 0)] * 5 + [("k", 0)] * 2
    assert written_row(worked, ["black"]) == (
        "with black, *k2, p4; rep from * to last 2 sts, k2 (32 sts)."
    )


def brute_float(yarn_row: np.ndarray) -> int:
    best = 0
    for y in set(yarn_row.tolist()):
        idx = np.flatnonzero(yarn_row == y)
        best = max([best, *(int(b - a - 1) for a, b in pairwise(idx))])
    return best


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 3), st.integers(1, 4), st.integers(1, 9))
def test_row_colourwork_counts_match_brute_force(seed, k, n, m):
    rng = np.random.default_rng(seed)
    p = LogicalPattern(rng.integers(0, k, (n, m)), rng.random((n, m)) < 0.3, YARNS3[:k])
    rows = row_colourwork(p)
    assert len(rows) == 2 * n
    for row, hr, cost in zip(rows, hand_rows(p), cost_rows(p), strict=True):
        y = hr.yarn
        assert row.changes == int((np.diff(y) != 0).sum())
        assert row.yarns == len(set(y.tolist()))
        assert row.longest_float == brute_float(y)
        if row.technique == "intarsia":
            large = row.shortest_block >= MIN_INTARSIA_BLOCK and row.blocks <= 8
            assert large or row.blocks <= MAX_HAND_BLOCKS
        if cost.knittable:  # the ranking's rule: the advice works it without long floats
            assert row.technique != "not-sensible"
            assert row.technique != "stranded" or row.longest_float <= MAX_FLOAT


def test_advice_follows_the_blocks():
    stripes = LogicalPattern(np.array([[0] * 6, [1] * 6]), np.zeros((2, 6), bool), YARNS3[:2])
    assert hand_advice(stripes).technique == "stripes"
    big = LogicalPattern(np.array([[0] * 4 + [1] * 4] * 2), np.zeros((2, 8), bool), YARNS3[:2])
    a = hand_advice(big)
    assert a.knittable and a.technique == "intarsia"
    assert "Bobbins to wind: black 1, firebrick 1." in " ".join(a.lines)  # issue 37 item 5
    three = LogicalPattern(
        np.array([[0] * 3 + [1] * 3 + [0] * 3] * 2), np.zeros((2, 9), bool), YARNS3[:2]
    )
    assert "Bobbins to wind: black 2, firebrick 1." in " ".join(hand_advice(three).lines)
    # 2-stitch blocks of 3 yarns: neither strandable nor intarsia, said with the numbers
    tiny = LogicalPattern(np.array([[0, 1, 2] * 5] * 2), np.zeros((2, 15), bool), YARNS3)
    a = hand_advice(tiny)
    assert not a.knittable and a.technique == "not-sensible"
    text = " ".join(a.lines)
    assert "not sensibly knitted by hand" in text and "3 yarns" in text and "2 yarns" in text
    # 2 yarns in many small blocks with long floats: stranded, caught every 5
    long_float = LogicalPattern(
        np.array([[0] + [1] * 5 + [0, 1] * 3 + [0]] * 2), np.zeros((2, 13), bool), YARNS3[:2]
    )
    a = hand_advice(long_float)
    assert a.technique == "stranded" and f"every {CATCH_EVERY} stitches" in " ".join(a.lines)
    text = written_instructions(long_float)
    assert "[stranded, 8 colour changes, longest float 10 sts, catch every 5]" in text
    # few blocks, one narrow: intarsia (a bobbin for the narrow one), not a 10-stitch float
    few = LogicalPattern(
        np.array([[0] + [1] * 5 + [0] + [1] * 2] * 2), np.zeros((2, 9), bool), YARNS3[:2]
    )
    assert hand_advice(few).technique == "intarsia"
    assert "[intarsia, 4 blocks, 3 colour changes]" in written_instructions(few)


def test_yarn_estimate_adds_up():
    g = parse_gauge("20x28/10cm")
    p = LogicalPattern(np.array([[0, 0, 1, 1]] * 3), np.zeros((3, 4), bool), YARNS3[:2])
    est = yarn_estimate(p, g, margin=0.0, floats=False)
    assert [e.stitches for e in est] == [24, 24]
    # 24 stitches x 3.8 stitch widths of 0.5 cm
    assert abs(est[0].metres - 24 * 3.8 * 0.5 / 100) < 1e-9
    with_margin = yarn_estimate(p, g, margin=0.2, floats=False)
    assert abs(with_margin[0].metres / est[0].metres - 1.2) < 1e-9


def test_the_verdict_says_hours_and_when_a_design_is_for_machines_only():
    """Issue 37 item 2: hours from stitch counts and colour work, rates stated; a design whose
    rows change colour all along with long floats is for machines only, stripes are not."""
    from illuknit.outputs.hand_pattern import (
        PLAIN_STITCHES_PER_MINUTE,
        hand_verdict,
    )

    stripes = LogicalPattern(
        np.repeat(np.arange(10)[:, None] % 2, 20, axis=1), np.zeros((10, 20), bool), YARNS3[:2]
    )
    v = hand_verdict(stripes)
    assert not v.machine_only and v.technique == "stripes"
    assert abs(v.hours - 40 * 20 / PLAIN_STITCHES_PER_MINUTE / 60) < 1e-9
    assert "By hand: about 1 hour " in v.text and "rules of thumb" in v.text
    rng = np.random.default_rng(0)
    noisy = LogicalPattern(rng.integers(0, 2, (10, 60)), rng.random((10, 60)) < 0.3, YARNS3[:2])
    v = hand_verdict(noisy)
    assert v.machine_only and "for machines only" in v.text and v.hours > 1
    wide = np.zeros((10, 60), np.int16)
    wide[:, 1:10:2] = 1
    wide[:, 10:] = 1
    wide[:, 59] = 0  # 12 blocks a row and a float of 98 stitches: stranded, caught all along
    assert hand_verdict(LogicalPattern(wide, np.zeros((10, 60), bool), YARNS3[:2])).machine_only
    # three blocks, the last one unit: intarsia, no float at all -- not for machines only
    few = np.zeros((10, 60), np.int16)
    few[:, 20:59] = 1
    assert not hand_verdict(LogicalPattern(few, np.zeros((10, 60), bool), YARNS3[:2])).machine_only
    # a yarn change every unit: 59 changes a row, but floats of 2 stitches -- two-handed
    # stranded work, not for machines only
    check = np.indices((10, 60)).sum(axis=0) % 2
    v = hand_verdict(LogicalPattern(check, np.zeros((10, 60), bool), YARNS3[:2]))
    assert not v.machine_only and v.technique == "stranded"
