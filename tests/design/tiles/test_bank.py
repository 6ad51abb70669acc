"""Tiles and banks: fills recomputed independently from the cell rules of can_see."""

from __future__ import annotations

import json
from collections import Counter
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import TileBankError
from illuknit.core.pattern import parse_yarns
from illuknit.design.tiles.bank import (
    bank_from_json,
    bank_to_json,
    canonical_bank,
    extend_bank,
    load_bank,
    save_bank,
)
from illuknit.design.tiles.tile import Tile, tile_fills

Y2 = parse_yarns("black=#1b1b1b,white=#f4f0e8")
Y3 = parse_yarns("black=#1b1b1b,white=#f4f0e8,red=#c03030")


def _seen_by_rules(tile: Tile, view: str, periods: int = 7) -> list[int]:
    """Yarns seen over the middle period of a long periodic column, straight from section 4.2."""
    h = tile.height
    out = []
    for c in range(tile.width):
        col = [(int(tile.yarn[i % h, c]), bool(tile.raised[i % h, c])) for i in range(periods * h)]
        mid = range((periods // 2) * h, (periods // 2 + 1) * h)
        for i in mid:
            if view == "A":
                out.append(col[i - 1][0] if col[i - 1][1] else col[i][0])
            elif view == "B":
                out.append(col[i + 1][0] if col[i + 1][1] else col[i][0])
            else:
                out.append(col[i][0])
    return out


def _props(seen: list[int]) -> dict[int, Fraction]:
    n = len(seen)
    return {k: Fraction(v, n) for k, v in Counter(seen).items()}


def _check_fills(tile: Tile, yarns) -> None:
    f = tile_fills(tile, yarns)
    for view in ("A", "B", "headon"):
        assert dict(f[view].parts) == _props(_seen_by_rules(tile, view))


def test_paper_tile_is_stripe_from_one_side_and_solid_from_the_other():
    # c1 flat, c2 flat, c1 bump (section 4.2): a c1/c2 stripe one way, solid c1 the other way
    t = Tile.from_rows(["0", "1", "0^"])
    f = tile_fills(t, Y2)
    assert dict(f["A"].parts) == {0: Fraction(2, 3), 1: Fraction(1, 3)}
    assert f["B"].is_solid and f["B"].yarn_indices == (0,)
    assert f["side"] is None
    assert f["A"].kind == "stripe2"


@pytest.mark.parametrize("yarns", [Y2, Y3], ids=["2 yarns", "3 yarns"])
def test_every_canonical_tile_reproduces_its_fills(yarns):
    bank = canonical_bank(yarns)
    for t in bank.tiles:
        _check_fills(t, yarns)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 5).flatmap(
        lambda h: st.tuples(
            st.lists(st.lists(st.integers(0, 2), min_size=2, max_size=2), min_size=h, max_size=h),
            st.lists(st.lists(st.booleans(), min_size=2, max_size=2), min_size=h, max_size=h),
        )
    )
)
def test_any_tile_fills_match_the_cell_rules(arrays):
    yarn, raised = arrays
    _check_fills(Tile(np.array(yarn), np.array(raised)), Y3)


def test_canonical_bank_is_deduplicated_and_prefers_short_tiles():
    bank = canonical_bank(Y2)
    keys = [(f["A"], f["B"]) for f in bank.fills]
    assert len(keys) == len(set(keys))
    # exhaustive check against all tiles up to height 3: no shorter tile shows the same pair
    import itertools

    units = [(y, r) for y in range(2) for r in (False, True)]
    shortest: dict = {}
    for h in range(1, 4):
        for combo in itertools.product(units, repeat=h):
            t = Tile(np.array([[u[0]] for u in combo]), np.array([[u[1]] for u in combo]))
            f = tile_fills(t, Y2)
            shortest.setdefault((f["A"], f["B"]), h)
    for t, f in zip(bank.tiles, bank.fills, strict=True):
        key = (f["A"], f["B"])
        if key in shortest:
            assert t.height == shortest[key]
    # everything reachable up to height 3 is in the bank
    assert set(shortest) <= set(keys)


def test_canonical_bank_contents():
    bank = canonical_bank(Y2)
    fills_a = {f["A"] for f in bank.fills}
    props = {f.proportion(0) for f in fills_a}
    # solids and stripes of several proportions: 1/3, 1/2, 2/3 are distinct fills
    assert {Fraction(0), Fraction(1), Fraction(1, 3), Fraction(1, 2), Fraction(2, 3)} <= props
    # the stripe-one-side / solid-other-side family exists in both directions
    assert any(not f["A"].is_solid and f["B"].is_solid for f in bank.fills)
    assert any(f["A"].is_solid and not f["B"].is_solid for f in bank.fills)
    # a bump is seen from both sides: no tile is solid black from A and solid white from B
    assert not any(f["A"].is_solid and f["B"].is_solid and f["A"] != f["B"] for f in bank.fills)
    three = canonical_bank(Y3)
    assert any(f["A"].n_colors == 3 for f in three.fills)
    assert all(max(f["A"].n_colors, f["B"].n_colors) <= 3 for f in three.fills)


def test_one_sided_bank_has_a_solid_side():
    bank = canonical_bank(Y2, one_sided_stripes=True)
    assert all(f["A"].is_solid or f["B"].is_solid for f in bank.fills)
    assert len(bank) < len(canonical_bank(Y2))


def test_fill_color_is_a_linear_light_mix():
    from illuknit.core.colors import luminance, mix_rgb

    t = Tile.from_rows(["0", "1"])
    f = tile_fills(t, Y2)["A"]
    want = mix_rgb(np.array([Y2[0].rgb, Y2[1].rgb]), [0.5, 0.5])
    assert np.allclose(f.rgb, want)
    assert f.brightness == pytest.approx(float(luminance(want)))
    # linear-light grey is lighter than the sRGB midpoint
    assert f.rgb[0] > (Y2[0].rgb[0] + Y2[1].rgb[0]) / 2


def test_bank_json_round_trip(tmp_path):
    bank = canonical_bank(Y3)
    save_bank(bank, tmp_path / "bank.json")
    back = load_bank(tmp_path / "bank.json")
    assert back.tiles == bank.tiles
    assert back.yarns == bank.yarns
    assert [f["A"] for f in back.fills] == [f["A"] for f in bank.fills]


def _doc(tiles, **extra):
    return {"format": "illuknit-tile-bank", "version": 1, "tiles": tiles, **extra}


def test_custom_bank_with_correct_declared_fills_loads():
    doc = _doc(
        [
            {
                "name": "paper",
                "rows": ["0", "1", "0^"],
                "fills": {"A": {"0": "2/3", "1": "1/3"}, "B": {"0": 1}},
            }
        ]
    )
    bank = bank_from_json(doc, yarns=Y2)
    assert bank.tiles[0].name == "paper"


@pytest.mark.parametrize(
    ("doc", "message"),
    [
        (
            _doc([{"rows": ["0", "1", "0^"], "fills": {"A": {"0": "1/2", "1": "1/2"}}}]),
            "can_see gives",
        ),
        (_doc([{"rows": ["0", "1", "0^"], "fills": {"B": {"1": "1"}}}]), "can_see gives"),
        (_doc([{"rows": ["0", "1", "0^"], "fills": {"X": {"0": "1"}}}]), "unknown view"),
        (_doc([{"rows": ["0", "5"]}]), "uses yarn 5"),
        (_doc([{"rows": ["0", "1?"]}]), "bad unit"),
        (_doc([{"rows": []}]), "non-empty `rows`"),
        (_doc([{"rows": ["0 1", "0"]}]), "equal width"),
        (_doc("nope"), "`tiles` must be a list"),
        (_doc([]), "no tiles"),
        ({"format": "other", "version": 1, "tiles": []}, "not a tile bank"),
        ({"format": "illuknit-tile-bank", "version": 9, "tiles": []}, "version"),
        (_doc([{"rows": ["0"], "fills": {"A": {"0": "1/2"}}}]), "sum to 1"),
        (_doc([{"rows": ["0"]}], extends="other"), "extends"),
    ],
)
def test_malformed_or_contradictory_bank_is_refused(doc, message):
    with pytest.raises(TileBankError, match=message):
        bank_from_json(doc, yarns=Y2)


def test_bank_file_errors(tmp_path):
    with pytest.raises(TileBankError, match="not found"):
        load_bank(tmp_path / "missing.json", yarns=Y2)
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(TileBankError, match="not valid JSON"):
        load_bank(tmp_path / "bad.json", yarns=Y2)
    (tmp_path / "noyarns.json").write_text(json.dumps(_doc([{"rows": ["0"]}])))
    with pytest.raises(TileBankError, match="no `yarns`"):
        load_bank(tmp_path / "noyarns.json")
    doc = bank_to_json(canonical_bank(Y2))
    with pytest.raises(TileBankError, match="written for 2 yarn"):
        bank_from_json(doc, yarns=Y3)


def test_extend_bank_puts_custom_tiles_first():
    base = canonical_bank(Y2)
    extra = Tile.from_rows(["0", "0", "1", "0^"], name="mine")
    doc = _doc([{"name": "mine", "rows": extra.rows()}], extends="canonical")
    bank = bank_from_json(doc, yarns=Y2)
    assert bank.tiles[0] == extra and len(bank) == len(base) + (extra not in base.tiles)
    f = bank.fills[0]
    assert bank.tile_for(f["A"], f["B"]) == extra
    with pytest.raises(TileBankError, match="uses yarn"):
        extend_bank(base, [Tile.from_rows(["2"])])


def test_wide_tiles_and_row_syntax():
    t = Tile.from_rows(["0 1^", "1 0"])
    assert t.shape == (2, 2) and t.rows() == ["0 1^", "1 0"]
    assert t.color_changes() == 8  # cyclic: 2 per column down, 2 per row across
    _check_fills(t, Y2)


def test_canonical_bank_argument_errors():
    with pytest.raises(TileBankError, match="max_height"):
        canonical_bank(Y2, max_height=9)
    with pytest.raises(TileBankError, match="views"):
        canonical_bank(Y2, views=("A", "Q"))  # type: ignore[arg-type]
