"""Shared stripes (issue 37): double views a hand knitter works one yarn a row, and the bank
flag that keeps their rows in the piece's one phase."""

from __future__ import annotations

import json
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from illuknit.cli import main
from illuknit.core.errors import TileBankError, YarnSpecError
from illuknit.core.pattern import parse_yarns
from illuknit.design.hand_cost import hand_cost
from illuknit.design.tiles.assign import assign_tiles, with_candidates
from illuknit.design.tiles.bank import bank_from_json, bank_to_json, canonical_bank
from illuknit.design.tiles.compile import compile_tiles
from illuknit.design.tiles.stripes import (
    STRIPE,
    STRIPE_BANK_NAME,
    search_stripes,
    stripe_bank,
    stripe_yarns,
)

YARNS = parse_yarns("#202020,#f0f0f0")


def _dark_share(fill) -> Fraction:
    return dict(fill.parts).get(0, Fraction(0))


def test_every_tile_shares_the_stripe_and_the_bank_shows_every_pair_of_three_levels():
    bank = stripe_bank(YARNS)
    assert bank.phase_locked and bank.name == STRIPE_BANK_NAME and len(bank) == 2 ** len(STRIPE)
    assert all(tuple(int(v) for v in t.yarn[:, 0]) == STRIPE for t in bank.tiles)
    quarters = {Fraction(1, 4), Fraction(1, 2), Fraction(3, 4)}
    pairs = {(_dark_share(a), _dark_share(b)) for a, b in bank.index()}
    assert pairs == {(x, y) for x in quarters for y in quarters}  # A and B independent
    assert {_dark_share(f["headon"]) for f in bank.fills} == {Fraction(1, 2)}  # even stripes


def test_two_rows_a_colour_cannot_show_two_views():
    # the module's proof, by enumeration: with stripe 01 every tile shows A the fill it shows B
    bank = stripe_bank(YARNS, stripe=(0, 1))
    assert all(f["A"] == f["B"] for f in bank.fills)


@pytest.mark.parametrize(
    "stripe, match",
    [((0,), "2 to 8"), ((0, 0, 0), "each of the 2 yarns"), ((0, 2), "each of the 2"),
     ((0, 1) * 5, "2 to 8"), (("0", "1"), "yarn numbers")],
)  # fmt: skip
def test_a_bad_stripe_is_refused(stripe, match):
    with pytest.raises(TileBankError, match=match):
        stripe_bank(YARNS, stripe=stripe)


def test_the_stripe_yarns_are_the_darkest_and_the_lightest():
    ys = parse_yarns("tan=#b08455,cream=#f2e8d5,dark=#2b2118")
    assert [y.name for y in stripe_yarns(ys)] == ["dark", "cream"]
    with pytest.raises(YarnSpecError, match="two yarns"):
        stripe_yarns(ys[:1])


def _pictures(bits_a: list[list[int]], bits_b: list[list[int]]):
    pal = np.array([[32, 32, 32], [240, 240, 240]], dtype=np.float64)
    return (np.array(bits_a), pal), (np.array(bits_b), pal)


@settings(max_examples=25, deadline=None)
@given(
    st.integers(2, 6).flatmap(
        lambda w: st.tuples(
            st.lists(st.lists(st.integers(0, 1), min_size=w, max_size=w), min_size=2, max_size=6),
            st.integers(0, 2**31),
        )
    )
)
def test_a_stripe_design_knits_every_row_in_one_yarn(case):
    rows_a, seed = case
    rng = np.random.default_rng(seed)
    rows_b = rng.integers(0, 2, size=np.shape(rows_a)).tolist()
    qa, qb = _pictures(rows_a, rows_b)
    found = search_stripes(qa, qb, yarns=YARNS, candidates=2)
    assert found  # 3 levels a side serve any pair of 2-colour pictures
    for assignment in found:
        assert assignment.bank.phase_locked
        assert all(tuple(int(v) for v in t.yarn[:, 0]) == STRIPE for t in assignment.tiles.values())
        pattern, _ = compile_tiles(assignment)
        yarn = np.asarray(pattern.yarn)
        assert (yarn == yarn[:, :1]).all()  # every unit row one yarn, edge to edge
        cost = hand_cost(pattern)
        assert (cost.max_changes, cost.longest_float, cost.knittable_share) == (0, 0, 1.0)


def test_no_stripe_design_for_a_headon_view_or_too_many_colours():
    qa, qb = _pictures([[0, 1], [1, 0]], [[1, 1], [0, 0]])
    assert search_stripes(qa, qb, yarns=YARNS, views=("headon", "side")) == []
    pal4 = np.array([[0, 0, 0], [80, 80, 80], [160, 160, 160], [250, 250, 250]], float)
    four = (np.array([[0, 1], [2, 3]]), pal4)
    assert search_stripes(four, qb, yarns=YARNS) == []  # 4 colours, 3 levels a side


def test_phase_locked_survives_json_and_is_checked():
    doc = bank_to_json(stripe_bank(YARNS))
    assert doc["phase_locked"] is True
    again = bank_from_json(doc, source="stripes.json")
    assert again.phase_locked and len(again) == 16
    assert "phase_locked" not in bank_to_json(canonical_bank(YARNS))
    with pytest.raises(TileBankError, match="true or false"):
        bank_from_json({**doc, "phase_locked": "yes"}, source="s.json")
    with pytest.raises(TileBankError, match="cannot be `phase_locked`"):
        bank_from_json({**doc, "extends": "canonical"}, source="s.json")


def _speckled(tmp_path):
    """Two speckled pictures (seeded): their regions cross every row many times, so the
    design made for a machine changes colour more often a row than a hand knitter can follow."""
    rng = np.random.default_rng(1)
    for name in ("a", "b"):
        dark = rng.random((12, 24)) < 0.5
        Image.fromarray(np.where(dark, 20, 240).astype(np.uint8)).convert("RGB").save(
            tmp_path / f"{name}.png"
        )
    return [str(tmp_path / "a.png"), str(tmp_path / "b.png")]


def test_double_for_hands_offers_the_stripe_design_beside_the_machine_one(tmp_path, capsys):
    pics = _speckled(tmp_path)
    # the tile designs alone (the constraint model's design, which may rank first, is tested
    # in test_hand_designs)
    main(["double", *pics, "--candidates", "3", "--for", "hands", "--no-read",
          "--hand-model-seconds", "0", "-o", str(tmp_path / "h")])  # fmt: skip
    text = capsys.readouterr().out
    summary = json.loads((tmp_path / "h" / "summary.json").read_text())
    banks = [c["bank"] for c in summary["candidates"]]
    assert banks[0] == STRIPE_BANK_NAME == summary["bank"]["name"]  # every row knittable first
    assert summary["hand"]["max_changes"] == 0 and summary["hand"]["knittable_share"] == 1.0
    machine = summary["machine_design"]
    assert machine["hand"]["knittable_share"] < 1.0  # why the stripe design was chosen
    assert "shared stripes: every row in one yarn" in text
    assert "the design made for a machine: rows knittable by hand" in text
    assert f"correlation {machine['worse_readability']:.3f}" in text
    main(["double", *pics, "--candidates", "3", "--no-read", "-o", str(tmp_path / "m")])
    plain = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert "machine_design" not in plain  # a machine design is compared with nothing
    assert {c["bank"] for c in plain["candidates"]} == {"canonical"}


def test_a_bank_of_your_own_gets_no_stripe_designs(tmp_path, capsys):
    pics = _speckled(tmp_path)
    bank = tmp_path / "bank.json"
    bank.write_text(json.dumps(bank_to_json(canonical_bank(parse_yarns("#141414,#f0f0f0")))))
    main(["double", *pics, "--candidates", "2", "--for", "hands", "--no-read",
          "--yarns", "#141414,#f0f0f0", "--bank", str(bank), "--hand-model-seconds", "0",
          "-o", str(tmp_path / "o")])  # fmt: skip
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert STRIPE_BANK_NAME not in {c["bank"] for c in summary["candidates"]}


def test_a_design_for_hands_is_chosen_from_the_pool_and_the_stripes():
    ia = np.kron([[0, 1, 0], [1, 0, 1]], np.ones((4, 4), int)).astype(np.int16)
    ib = np.kron([[0, 0, 1], [1, 1, 0]], np.ones((4, 4), int)).astype(np.int16)
    grey = np.array([[30, 30, 30], [220, 220, 220]], np.uint8)
    found = assign_tiles((ia, grey), (ib, grey), yarns=YARNS, candidates=2)
    stripes = search_stripes((ia, grey), (ib, grey), yarns=YARNS, candidates=3)
    both = with_candidates(found, [*stripes, *found])  # the pool's own designs come once
    keys = [(a.bank.name, a.fills_a, a.fills_b) for a in both]
    assert both[: len(found)] == found and len(set(keys)) == len(keys)
    assert len(both) == len(found) + len(stripes)
    assert {a.bank.name for a in both[len(found) :]} == {STRIPE_BANK_NAME}
    assert [a.rank for a in both] == list(range(1, len(both) + 1))
