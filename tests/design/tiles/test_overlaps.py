"""The overlap table grouped by fill with the rare overlaps folded (tiles.overlaps)."""

from __future__ import annotations

import json
from functools import cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from illuknit.core.errors import OptionError
from illuknit.design.tiles.overlaps import RARE_SHARE, group_overlaps


@cache
def _photo_design():
    """The best tile design of the bundled coffee / chelsea photos at 4 colours each, on the
    4 yarns ``illuknit double --colors 4`` chooses."""
    from illuknit.design.tiles.assign import assign_tiles
    from illuknit.design.tiles.yarn_choice import choose_yarns
    from illuknit.pictures.drawings import skimage_image
    from illuknit.pictures.images import quantise_image

    pictures = [skimage_image(n, (24, 32)) for n in ("coffee", "chelsea")]
    qa, qb = (quantise_image(p, n_colors=4) for p in pictures)
    return assign_tiles(qa, qb, yarns=choose_yarns(pictures, 4), candidates=1)[0]


@given(st.floats(0, 1), st.sampled_from(["A", "B", "both"]))
@settings(max_examples=40, deadline=None)
def test_groups_and_rare_line_partition_the_overlaps(rare_share, by):
    from illuknit.design.tiles.assignment import overlap_pairs

    design = _photo_design()
    table = group_overlaps(design, by=by, rare_share=rare_share)
    counts = overlap_pairs(design.indices_a, design.indices_b)
    pairs = [(r.a, r.b) for r in table.rows]
    assert sorted(pairs) == sorted(counts)  # every overlap exactly once
    assert sum(r.units for r in table.rows) == table.total_units == design.indices_a.size
    assert table.rare_units == sum(r.units for r in table.rare)
    assert table.rare_fraction == pytest.approx(sum(r.share for r in table.rare))
    for r in table.rows:
        assert r.units == counts[r.a, r.b] and r.tile == design.tiles[r.a, r.b].code()
        assert (r in table.rare) == (r.units < rare_share * table.total_units)
    for g in table.groups:
        pos = {"A": [0], "B": [1], "both": [0, 1]}[by]
        assert len({tuple(r.fills[p] for p in pos) for r in g.rows}) == 1
        assert g.units == sum(r.units for r in g.rows)
    keys = [g.fill for g in table.groups]
    assert len(keys) == len(set(keys))
    assert [g.units for g in table.groups] == sorted((g.units for g in table.groups), reverse=True)


def test_four_colours_fold_to_a_few_groups():
    design = _photo_design()
    table = group_overlaps(design)
    assert table.by == "A" and table.rare_share == RARE_SHARE
    # one group per fill picture A is repainted with
    assert len(table.groups) <= len({f for f in design.fills_a if f is not None})
    shown = [g.fill for g in table.groups]
    assert set(shown) <= {f.label(design.yarns) for f in design.fills_a if f is not None}
    lines = table.lines()
    assert lines[0].startswith(f"{len(table.rows)} overlap pairs, grouped by the fill seen from A")
    assert sum(ln.startswith("    ") for ln in lines) == len(table.rows) - len(table.rare)
    if table.rare:
        assert f"{len(table.rare)} rare overlaps" in lines[-1]
    j = table.to_json()
    assert j["pairs"] == len(table.rows)
    assert j["rare"]["count"] + sum(len(g["overlaps"]) for g in j["groups"]) == j["pairs"]


def test_an_overridden_tile_is_grouped_by_what_it_shows():
    design = _photo_design()
    table = group_overlaps(design, rare_share=0)
    row = table.groups[0].rows[0]
    # a plain tile of the darkest yarn: seen from A it shows that yarn solid
    edited = design.with_tile((row.a, row.b), "0")
    moved = next(
        r for r in group_overlaps(edited, rare_share=0).rows if (r.a, r.b) == (row.a, row.b)
    )
    assert moved.overridden and moved.tile == "0"
    assert moved.fills[0] == design.yarns[0].name


def test_bad_options_are_option_errors():
    design = _photo_design()
    with pytest.raises(OptionError, match="`by`"):
        group_overlaps(design, by="side")
    with pytest.raises(OptionError, match="rare_share"):
        group_overlaps(design, rare_share=1.5)


def test_double_writes_the_grouped_table(tmp_path, run_cli):
    from illuknit.pictures.drawings import skimage_image

    for name, photo in (("a.png", "coffee"), ("b.png", "chelsea")):
        pic = (skimage_image(photo, (24, 32)) * 255).round().astype(np.uint8)
        Image.fromarray(pic).save(tmp_path / name)
    code, out, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--colors", "4",
         "--candidates", "1", "-o", str(tmp_path / "out")])  # fmt: skip
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    table = summary["candidates"][0]["overlaps"]
    fills = json.loads((tmp_path / "out" / "candidate_1" / "fills.json").read_text())
    assert fills["overlaps"] == table
    assert table["pairs"] == len(fills["tiles"])
    text = (tmp_path / "out" / "summary.txt").read_text()
    assert "grouped by the fill seen from A" in text and "grouped by the fill" in out
    for g in table["groups"]:
        assert g["fill"] in out  # the console shows one line per group
    if table["rare"]["count"]:
        assert f"{table['rare']['count']} rare overlaps" in text
