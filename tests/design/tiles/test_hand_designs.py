"""Designs made for hands (issue 37 item 1): the hand knitter's cost of a pattern, the ranking
that puts knittable rows first, and ``illuknit double --for hands``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from illuknit.cli import main
from illuknit.cli.design_files import HAND_TABLE_HEADS, summary_text
from illuknit.cli.double import print_summary
from illuknit.cli.tile_design import DesignRequest, _hand_model_note
from illuknit.core.errors import OptionError
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.design.hand_cost import (
    COLOUR_STITCHES_PER_MINUTE,
    MAX_FLOAT,
    MINUTES_PER_CHANGE,
    PLAIN_STITCHES_PER_MINUTE,
    hand_cost,
    hand_rows,
)
from illuknit.design.options import RankOptions
from illuknit.design.tiles.perception import CandidateMeasures, rank_candidates, rank_key
from illuknit.outputs.hand_pattern import row_colourwork

YARNS2 = parse_yarns("black,white")
YARNS3 = parse_yarns("black,white,#c03030")


def _pattern(rows: list[list[int]], yarns=YARNS2) -> LogicalPattern:
    yarn = np.array(rows, dtype=np.int16)
    return LogicalPattern(yarn, np.zeros(yarn.shape, bool), yarns)


def test_rows_are_counted_as_a_hand_knitter_works_them():
    # bottom unit row: 4 units of black, 4 of white, 4 of black -> a float of 8 stitches
    p = _pattern([[0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1], [0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0]])
    rows = hand_rows(p)
    assert [r.number for r in rows] == [1, 2, 3, 4]
    first = rows[0]  # the cast-on edge is the chart's last row
    assert (first.yarns, first.changes, first.blocks, first.longest_float) == (2, 2, 3, 8)
    assert first.catches == 1  # a float of 8 is caught once, after 5
    assert not first.stranded_ok and first.intarsia_ok and first.knittable
    top = rows[2]  # units alternate: 12 blocks of 2 stitches, floats of 2
    assert (top.changes, top.longest_float) == (11, 2)
    assert top.stranded_ok and not top.intarsia_ok and top.knittable
    assert first.in_intarsia and not top.in_intarsia
    cost = hand_cost(p)
    # the bottom rows are worked in intarsia, a bobbin a block: their 8-stitch gap floats
    # nothing, so the longest float is the top rows' 2 stitches, and nothing needs catching
    assert (cost.rows, cost.knittable_rows, cost.longest_float, cost.max_changes) == (4, 4, 2, 11)
    assert cost.catches == 0
    assert cost.mean_changes == pytest.approx((2 + 2 + 11 + 11) / 4)


def test_a_row_of_three_yarns_in_small_blocks_is_not_knittable():
    p = _pattern([[0, 1, 2, 0, 1, 2, 0, 1, 2]], YARNS3)
    (row, _) = hand_rows(p)
    assert row.yarns == 3 and row.blocks == 9 and row.longest_float <= MAX_FLOAT
    assert not row.knittable  # 3 yarns cannot be stranded; 9 blocks are too many bobbins
    assert hand_cost(p).knittable_share == 0.0


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 5).flatmap(
        lambda n: st.lists(
            st.lists(st.integers(0, 2), min_size=n, max_size=n), min_size=1, max_size=5
        )
    )
)
def test_the_cost_agrees_with_the_written_pattern(rows):
    """The ranking and the hand pattern count the same floats and colour changes."""
    p = _pattern(rows, YARNS3)
    mine = hand_rows(p)
    written = row_colourwork(p)
    assert len(mine) == len(written) == 2 * len(rows)
    for a, b in zip(mine, written, strict=True):
        assert (a.yarns, a.changes, a.blocks, a.longest_float) == (
            b.yarns,
            b.changes,
            b.blocks,
            b.longest_float,
        )
        assert a.knittable == (a.yarns == 1 or a.stranded_ok or a.intarsia_ok)
    cost = hand_cost(p)
    assert 0 <= cost.knittable_rows <= cost.rows
    # the hours from the sums are the hours row by row, at the cover's rates
    width = 2 * len(rows[0])
    minutes = sum(
        width / PLAIN_STITCHES_PER_MINUTE
        if r.yarns == 1
        else width / COLOUR_STITCHES_PER_MINUTE + r.changes * MINUTES_PER_CHANGE
        for r in mine
    )
    assert cost.hours == pytest.approx(minutes / 60)
    if all(len(set(r)) == 1 for r in rows):
        assert cost.knittable_share == 1.0 and cost.longest_float == 0


def _save_pair(tmp_path: Path, h: int, w: int) -> None:
    """``a.png``, a dark box on light, and ``b.png``, a light bar on dark, ``h`` x ``w`` pixels."""
    a = np.full((h, w, 3), 240, np.uint8)
    a[h // 4 : 3 * h // 4, w // 6 : 5 * w // 6] = 20
    b = np.full((h, w, 3), 20, np.uint8)
    b[h // 8 : 7 * h // 8, 5 * w // 12 : 2 * w // 3] = 240
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")


def _measured(read: float, pattern: LogicalPattern) -> CandidateMeasures:
    return CandidateMeasures(
        ("A", "B"), (read, read), (0.5, 0.5), (0.0, 0.0), hand=hand_cost(pattern)
    )


def test_for_hands_the_knittable_design_ranks_first_and_then_the_one_that_reads_best():
    hard = _pattern([[0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 1]])  # float 12, 7 blocks
    easy = _pattern([[0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0]])  # 3 blocks
    measures = [_measured(0.95, hard), _measured(0.80, easy), _measured(0.85, easy)]
    scores = [0.0, 0.0, 0.0]
    assert rank_candidates(measures, scores) == [0, 2, 1]  # for a machine: readability
    assert rank_candidates(measures, scores, hands=True) == [2, 1, 0]
    assert rank_key(measures[2], 0.0, "perception", hands=True)[0] == -1.0
    with pytest.raises(OptionError, match="hand cost"):
        rank_key(CandidateMeasures(("A",), (0.9,), (0.5,), (None,)), 0.0, "score", hands=True)


def test_hand_time_ranks_the_quickest_by_hand_first_however_it_reads():
    plain = _pattern([[0] * 12, [1] * 12])  # one yarn a row: quickest
    busy = _pattern([[0, 1] * 6, [1] * 12])  # a colour row with 11 changes
    hard = _pattern([[0, 1, 0, 1, 0, 0, 0, 0, 0, 1, 1, 1]] * 2)  # 6 blocks: intarsia
    measures = [_measured(0.95, busy), _measured(0.70, plain), _measured(0.90, hard)]
    hours = [m.hand.hours for m in measures]
    assert hours[1] < hours[0] < hours[2]
    assert rank_candidates(measures, [0.0] * 3, by="hand-time") == [1, 0, 2]
    # made for hands, the rows a hand knitter can work still come first
    assert measures[2].hand.knittable_share == 1.0 == measures[0].hand.knittable_share
    tied = [_measured(0.80, plain), _measured(0.85, plain)]
    assert rank_candidates(tied, [0.0, 0.0], by="hand-time", hands=True) == [1, 0]
    assert RankOptions(rank_by="hand-time", made_for="hands").key_fields[:2] == (
        "-share of rows knittable by hand",
        "hours by hand",
    )
    with pytest.raises(OptionError, match="hand cost"):
        rank_key(CandidateMeasures(("A",), (0.9,), (0.5,), (None,)), 0.0, "hand-time")


def test_made_for_is_checked_and_names_the_rank_key():
    # an explicit order: the default (auto) has no key until the designs are ranked
    ranking = RankOptions(rank_by="perception", made_for="hands")
    assert ranking.key_fields[0] == "-share of rows knittable by hand"
    machine = RankOptions(rank_by="perception")
    assert machine.key_fields == machine.rank_by.key_fields
    with pytest.raises(OptionError, match="made_for"):
        RankOptions(made_for="feet")


def test_double_for_hands_prints_and_records_the_hand_cost(tmp_path, capsys):
    _save_pair(tmp_path, 8, 12)
    out = tmp_path / "out"
    main([
        "double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--candidates", "2",
        "--for", "hands", "-o", str(out),
    ])  # fmt: skip
    text = capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["made_for"] == "hands"
    hand = summary["hand"]
    assert hand["rows"] == 2 * summary["size"]["rows"]
    assert f"rows knittable by hand {hand['knittable_rows']} of {hand['rows']}" in text
    assert f"longest float {hand['longest_float']} sts" in text
    shares = [c["hand"]["knittable_share"] for c in summary["candidates"]]
    assert shares == sorted(shares, reverse=True)  # ranked by it first
    assert f"about {hand['hours']:.1f} hours (estimated)" in text
    # summary.txt has each candidate's figures by hand, under their own heads
    lines = (out / "summary.txt").read_text().splitlines()
    head = lines.index("  ".join(HAND_TABLE_HEADS))
    for c, line in zip(summary["candidates"], lines[head + 1 :], strict=False):
        h = c["hand"]
        assert line.split()[:1] == [str(c["rank"])]
        assert f"{h['knittable_rows']} of {h['rows']}" in line and line.endswith(
            f"{h['hours']:.1f}"
        )
    # quickest by hand first: the order says so, and the machine's design is how it reads
    quick = tmp_path / "quick"
    main([
        "double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--candidates", "3",
        "--for", "hands", "--rank-by", "hand-time", "--hand-model-seconds", "3", "-o", str(quick),
    ])  # fmt: skip
    ranked = json.loads((quick / "summary.json").read_text())
    assert ranked["ranked_by"] == "hand-time"
    keys = [(-c["hand"]["knittable_share"], c["hand"]["hours"]) for c in ranked["candidates"]]
    assert keys == sorted(keys)
    # a machine design unranked by hours: with the same pool, what perception puts first
    by_reading = json.loads((out / "summary.json").read_text())["machine_design"]
    assert ranked["machine_design"]["worse_readability"] == by_reading["worse_readability"]


def test_double_for_hands_ranks_the_constraint_models_design_with_the_tile_designs(
    tmp_path, capsys
):
    rng = np.random.default_rng(5)  # speckled pictures: the tile designs change colour often
    pics = []
    for name in ("a", "b"):
        grey = np.where(rng.random((14, 20)) < 0.5, 30, 230).astype(np.uint8)
        Image.fromarray(np.stack([grey] * 3, -1)).save(tmp_path / f"{name}.png")
        pics.append(str(tmp_path / f"{name}.png"))
    out = tmp_path / "out"
    main(["double", *pics, "--candidates", "3", "--for", "hands", "--no-read",
          "--hand-model-seconds", "3", "-o", str(out)])  # fmt: skip
    text = capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    model = summary["hand_model"]
    assert model["backend"] == "cpsat" and model["seconds"] == 3
    rows = [c for c in summary["candidates"] if c["bank"] is None]
    assert len(rows) == 1 and model["rank"] == rows[0]["rank"]  # ranked with the tiles
    row = rows[0]
    assert row["method"] == "constraint model made for hands" and row["score"] is None
    assert row["hand"]["knittable_rows"] == row["hand"]["rows"]  # measured, every row
    folder = out / row["folder"]
    assert (folder / "pattern.pdf").is_file() and (folder / "seen.png").is_file()
    assert not (folder / "fills.json").exists()  # no tiles to list
    keys = [(-c["hand"]["knittable_share"], -c["perceptual_score"]) for c in summary["candidates"]]
    assert keys == sorted(keys)  # one order for both kinds of design
    assert f"the constraint model made for hands ({model['status']}" in text
    assert "constraint model made for hands:" in (out / "summary.txt").read_text()
    # a cleaner candidate is named exactly when one qualifies
    default = next(c for c in summary["candidates"] if c["default"])

    def shows(c):
        return max(g for g in c["visible_ghosting"] if g is not None)

    qualify = [
        c["rank"] for c in summary["candidates"]
        if not c["default"] and shows(c) <= min(shows(default) / 2, shows(default) - 0.1)
        and c["perceptual_score"] >= default["perceptual_score"] - 0.05
        and c["hand"]["knittable_share"] >= default["hand"]["knittable_share"]
    ]  # fmt: skip
    assert (summary.get("cleaner") or {}).get("rank") in (qualify or [None])
    summary["cleaner"] = {
        "rank": 2, "visible_ghosting": 0.041, "perceptual_score": 0.935,
        "default_visible_ghosting": 0.263, "default_perceptual_score": 0.944, "made_for": "hands",
    }  # fmt: skip
    line = (
        "the other picture shows through the default's worse view on 26% of its variation "
        "(visible ghosting); in candidate 2 on 4%, at a perceptual score 0.009 lower (0.935 "
        "against 0.944), with as many rows knittable by hand: --pick 2 to make it the default"
    )
    assert line in summary_text(summary, [])
    print_summary(summary, out)
    assert line in " ".join(capsys.readouterr().out.split())
    # not made for hands: the switch changed nothing, and says so
    main(["double", *pics, "--candidates", "1", "--no-read", "--hand-model-seconds", "3",
          "-o", str(tmp_path / "m")])  # fmt: skip
    plain = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert "hand_model" not in plain
    assert any("--hand-model-seconds changed nothing" in n for n in plain["notes"])
    # the switch given at its default value changed nothing all the same
    request = DesignRequest.from_switches(*map(Path, pics), tmp_path / "d", hand_model_seconds=20.0)
    assert request.hand_model_asked and _hand_model_note(request)
    assert not _hand_model_note(DesignRequest.from_switches(*map(Path, pics), tmp_path / "d"))


def test_headon_takes_for_hands_and_a_machine_design_says_what_it_costs_by_hand(tmp_path, capsys):
    front = np.full((8, 12, 3), 240, np.uint8)
    front[2:6, 3:9] = 20
    Image.fromarray(front).save(tmp_path / "f.png")
    main(["headon", str(tmp_path / "f.png"), "--candidates", "1", "--for", "hands",
          "-o", str(tmp_path / "h")])  # fmt: skip
    assert json.loads((tmp_path / "h" / "summary.json").read_text())["made_for"] == "hands"
    assert "by hand (made for hands): rows knittable by hand" in capsys.readouterr().out
    main(["headon", str(tmp_path / "f.png"), "--candidates", "1", "-o", str(tmp_path / "m")])
    summary = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert summary["made_for"] == "machine" and summary["hand"]["rows"] > 0
    assert "by hand (made for a machine)" in capsys.readouterr().out


def test_a_cleaner_design_for_hands_has_as_many_rows_knittable():
    from dataclasses import replace

    from illuknit.design.tiles.perception import cleaner_alternative

    hard = _pattern([[0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 1]])  # float 12, 7 blocks
    easy = _pattern([[0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0]])
    ghostly = replace(_measured(0.944, easy), ghosting=(0.8, 0.8))
    clean_but_hard = _measured(0.94, hard)
    assert cleaner_alternative([ghostly, clean_but_hard], 0) == 1  # for a machine
    assert cleaner_alternative([ghostly, clean_but_hard], 0, hands=True) is None
    assert cleaner_alternative([ghostly, _measured(0.94, easy)], 0, hands=True) == 1


def test_a_quicker_design_by_hand_is_named_when_it_reads_nearly_as_well():
    from illuknit.design.tiles.perception import QUICKER_HOURS_SHARE, quicker_alternative

    hard = _pattern([[0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 1]])  # not knittable
    easy = _pattern([[0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0]])
    best, close, far, unknittable = (
        _measured(0.98, easy), _measured(0.96, easy), _measured(0.90, easy), _measured(0.99, hard)
    )  # fmt: skip
    measures = [best, close, far, unknittable]
    assert quicker_alternative(measures, [10.0, 7.0, 5.0, 1.0], 0) == 1
    # not quick enough, or reading too much worse, or not every row knittable: none
    share = QUICKER_HOURS_SHARE * 10.0
    assert quicker_alternative(measures, [10.0, share + 0.01, 5.0, 1.0], 0) is None
    assert quicker_alternative(measures, [10.0, share, 5.0, 1.0], 0) == 1
    assert quicker_alternative([best, far], [10.0, 1.0], 0) is None
    assert quicker_alternative([best, unknittable], [10.0, 1.0], 0) is None
    # of two quick ones, the one that reads better
    assert quicker_alternative([best, close, _measured(0.97, easy)], [10.0, 2.0, 7.0], 0) == 2


def test_the_summary_names_a_quicker_design_by_hand():
    summary = {
        "quicker_by_hand": {
            "rank": 2, "hours": 4.6, "colour_rows": 24, "perceptual_score": 0.966,
            "default_hours": 6.9, "default_colour_rows": 74, "default_perceptual_score": 0.98,
            "rows": 86,
        }
    }  # fmt: skip
    from illuknit.cli.design_files import alternative_lines

    (line, blank) = alternative_lines(summary)
    assert line == (
        "by hand, candidate 2 is quicker: colour in 24 of 86 rows against the default's 74, "
        "about 4.6 hours against 6.9 (the cover's estimate), at a perceptual score 0.014 lower "
        "(0.966 against 0.980), every row as knittable: --pick 2 to make it the default"
    )
    assert blank == "" and alternative_lines({}) == []


def test_made_for_hands_a_square_picture_knits_square_by_hand(tmp_path, capsys):
    """Made for hands, the grid is sized for the hand pattern's gauge (the estimate for
    hand-knitted illusion fabric), so a square picture knits square by hand, and the pattern
    says it is drawn for that gauge; made for a machine it is square on the machine."""
    import subprocess

    _save_pair(tmp_path, 20, 20)
    sizes = {}
    for made_for in ("hands", "machine"):
        out = tmp_path / made_for
        main([
            "double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--candidates", "1",
            "--width", "20", "--for", made_for, "--hand-model-seconds", "0", "--no-read",
            "-o", str(out),
        ])  # fmt: skip
        sizes[made_for] = json.loads((out / "summary.json").read_text())

    def square(summary, size):  # within the height of a unit row (the grid's rounding)
        return abs(size["height_cm"] - size["width_cm"]) <= size["height_cm"] / (
            summary["size"]["rows"] - 1
        )

    hands = sizes["hands"]["hand_finished_size"]
    assert square(sizes["hands"], hands) and hands["estimate"] is True
    machine = sizes["machine"]["finished_size"]
    assert square(sizes["machine"], machine)
    assert sizes["hands"]["size"]["rows"] > sizes["machine"]["size"]["rows"]  # shorter rows
    assert "hand_finished_size" not in sizes["machine"]
    text = " ".join(capsys.readouterr().out.split())
    assert f"finished size by hand: about {hands['width_cm']} x {hands['height_cm']} cm" in text
    # the documents describe the piece knitted by hand
    report = json.loads((tmp_path / "hands" / "candidate_1" / "report.json").read_text())
    assert report["finished_size"]["height_cm"] == hands["height_cm"]
    pdftotext = pytest.importorskip("shutil").which("pdftotext")
    if pdftotext:
        words = subprocess.run(
            [pdftotext, str(tmp_path / "hands" / "pattern.pdf"), "-"],
            capture_output=True, text=True, check=True,
        ).stdout  # fmt: skip
        words = " ".join(words.split())
        assert "The design is drawn for hand-knitted illusion fabric" in words
        assert "as tall as drawn" not in words
        assert f"Finished size by hand: about {hands['width_cm']:g} x" in words
