"""The default order of tile designs (issue 38): ``RankBy.AUTO`` becomes the reader's order
for two pictures of words when tesseract is installed and perception otherwise, an explicit
order always wins, and the design says which order it used and why.

The words here are never the benchmark's (benchmarks/legibility_words.py).
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from illuknit.core.errors import OptionError
from illuknit.design import legibility
from illuknit.design.options import RankBy, RankOptions, SearchOptions
from illuknit.design.rank_choice import RankChoice
from illuknit.pipeline.tile_search import choose_order
from tests.design.test_legibility import word

#: Two small targets (what choose_order is shown); their content only matters to the reader.
TARGETS = [np.full((10, 20, 3), 240, np.uint8), np.full((10, 20, 3), 20, np.uint8)]


def blob(flip: bool = False) -> np.ndarray:
    """A dark disc off centre on a light field: a picture, not words."""
    yy, xx = np.mgrid[0:40, 0:90]
    cx = 60 if flip else 30
    img = np.where((((xx - cx) ** 2 + (yy - 20) ** 2) < 150)[..., None], 25, 235)
    return img.astype(np.uint8).repeat(3, axis=2)


@pytest.fixture
def installed(monkeypatch: pytest.MonkeyPatch):
    """The reader said to be installed, with ``words`` what it reads on each picture (no
    tesseract run): returns a list the calls to ``words_of`` are counted in."""
    calls: list[int] = []

    def use(words: list[str | None]) -> list[int]:
        monkeypatch.setattr(legibility, "reader_available", lambda: True)

        def words_of(pictures):
            calls.append(len(pictures))
            return list(words)

        monkeypatch.setattr(legibility, "words_of", words_of)
        return calls

    return use


def _no_tesseract(monkeypatch: pytest.MonkeyPatch) -> None:
    real = shutil.which
    monkeypatch.setattr(shutil, "which", lambda name: None if name == "tesseract" else real(name))


# -- the choice, without the reader running ----------------------------------------------------


def test_auto_is_the_default_and_has_no_key_of_its_own():
    assert RankOptions().rank_by is RankBy.AUTO
    with pytest.raises(OptionError, match="resolved"):
        RankOptions().key_fields  # noqa: B018
    with pytest.raises(OptionError, match="not auto"):
        RankChoice(RankBy.AUTO, RankBy.AUTO, "why")


def test_auto_ranks_two_pictures_of_words_by_the_reader(installed):
    calls = installed(["MILK", "HAZE"])
    got = choose_order("double", TARGETS, RankOptions())
    assert got.by is RankBy.LEGIBILITY and got.asked is RankBy.AUTO
    assert got.reason == "both pictures are words (MILK, HAZE)"
    assert got.words == ("MILK", "HAZE") and calls == [2]
    assert got.sentence().startswith("ranked by the reader (legibility): both pictures")
    assert got.to_json()["by"] == "legibility" and got.to_json()["asked"] == "auto"


@pytest.mark.parametrize(
    ("words", "said"),
    [
        (["MILK", None], "picture B is not words"),
        ([None, "HAZE"], "picture A is not words"),
        ([None, None], "neither picture is words"),
    ],
)
def test_auto_keeps_perception_unless_both_pictures_are_words(installed, words, said):
    installed(words)
    got = choose_order("double", TARGETS, RankOptions())
    assert got.by is RankBy.PERCEPTION and got.reason.startswith(said)


def test_auto_keeps_perception_without_the_reader_and_says_so(monkeypatch):
    _no_tesseract(monkeypatch)
    monkeypatch.setattr(legibility, "words_of", lambda p: pytest.fail("the reader was asked"))
    got = choose_order("double", TARGETS, RankOptions())
    assert got.by is RankBy.PERCEPTION and got.words is None
    assert "tesseract" in got.reason and "not installed" in got.reason


def test_auto_keeps_perception_for_a_head_on_design(installed):
    calls = installed(["MILK", "HAZE"])
    got = choose_order("headon", TARGETS, RankOptions())
    assert got.by is RankBy.PERCEPTION and "head-on" in got.reason and calls == []


@pytest.mark.parametrize("by", [b for b in RankBy if b is not RankBy.AUTO])
def test_an_explicit_order_always_wins_and_the_pictures_are_not_read(installed, by):
    calls = installed(["MILK", "HAZE"])
    got = choose_order("double", TARGETS, RankOptions(rank_by=by))
    assert (got.by, got.asked, got.reason) == (by, by, "as asked") and calls == []


def test_the_design_carries_the_order_used_and_its_key(installed):
    # the stand-in reader reads no words: the design is ranked by perception, says so, and
    # its ranking and keys are perception's (not auto's, which has none)
    from illuknit.pipeline.stages import design_double

    installed([None, None])
    d = design_double(blob(), blob(flip=True), width=30, search=SearchOptions(candidates=2, pool=3))
    assert d.order is not None and d.order.by is RankBy.PERCEPTION
    assert d.ranking.rank_by is RankBy.PERCEPTION  # resolved: the order used
    assert d.best.rank_fields == RankBy.PERCEPTION.key_fields


# -- with the reader ---------------------------------------------------------------------------


def test_a_word_pair_is_ranked_by_the_reader_by_default(reader):
    from illuknit.pipeline.stages import design_double

    d = design_double(word("MILK"), word("HAZE"), width=60, search=SearchOptions(candidates=3))
    assert d.order is not None and d.order.by is RankBy.LEGIBILITY, d.order
    assert d.order.words == ("MILK", "HAZE")
    assert d.ranking.rank_by is RankBy.LEGIBILITY
    assert d.best.rank_fields[0] == "-sides that read"
    verdicts = [x.legibility for x in d.designs]
    assert all(v is not None for v in verdicts)  # read, though RankOptions().read is off
    assert verdicts[0].sides_read == max(v.sides_read for v in verdicts)


def test_pictures_are_ranked_by_perception_by_default(reader):
    from illuknit.pipeline.stages import design_double

    d = design_double(blob(), blob(flip=True), width=30, search=SearchOptions(candidates=2, pool=3))
    assert d.order is not None and d.order.by is RankBy.PERCEPTION
    assert d.order.reason.startswith("neither picture is words")
    assert all(x.legibility is None for x in d.designs)  # nothing read: read is off
