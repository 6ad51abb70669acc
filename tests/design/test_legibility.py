"""The reader's verdict on each side (illuknit.design.legibility), the ranking that puts designs
whose both sides read first, and the smallest width that reads (illuknit.pipeline.legible).

The words here are never the benchmark's (benchmarks/legibility_words.py).
"""

from __future__ import annotations

import os
import shutil
from importlib.resources import files

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image, ImageDraw, ImageFont

from illuknit.core.errors import BackendUnavailableError, OptionError
from illuknit.design.legibility import (
    Legibility,
    SideReading,
    read_images,
    read_sides,
    seen_far,
    words_of,
)
from illuknit.design.options import RankBy, RankOptions
from illuknit.design.tiles.perception import CandidateMeasures, rank_candidates


def word(text: str, size: tuple[int, int] = (360, 130)) -> np.ndarray:
    font = ImageFont.truetype(str(files("illuknit") / "data" / "DejaVuSans-Bold.ttf"), 100)
    box = ImageDraw.Draw(Image.new("L", (1, 1))).textbbox((0, 0), text, font=font)
    im = Image.new("RGB", size, "white")
    at = ((size[0] - box[2] + box[0]) // 2 - box[0], (size[1] - box[3] + box[1]) // 2 - box[1])
    ImageDraw.Draw(im).text(at, text, font=font, fill="black")
    return np.asarray(im)


def _m(read: tuple[float, float], sides: int | None) -> CandidateMeasures:
    return CandidateMeasures(
        views=("A", "B"), readability=read, contrast=(0.4, 0.4), ghosting=(0.0, 0.0),
        sides_read=sides,
    )  # fmt: skip


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(0, 1), st.floats(0, 1), st.integers(0, 2), st.floats(0, 100)),
        min_size=1,
        max_size=8,
    )
)
def test_legibility_order_puts_more_sides_read_first_then_perception(rows):
    ms = [_m((a, b), n) for a, b, n, _ in rows]
    scores = [s for *_, s in rows]
    order = rank_candidates(ms, scores, by="legibility")
    assert sorted(order) == list(range(len(ms)))
    keys = [(-ms[i].sides_read, -ms[i].perceptual_score) for i in order]  # type: ignore[operator]
    assert keys == sorted(keys)


def test_legibility_order_needs_the_verdict_of_every_candidate():
    with pytest.raises(OptionError, match="legibility needs the reader"):
        rank_candidates([_m((0.9, 0.9), None)], [1.0], by="legibility")
    assert RankBy("legibility").key_fields[0] == "-sides that read"


@given(st.booleans(), st.booleans(), st.floats(-1, 1), st.floats(-1, 1))
def test_the_weaker_side_is_said_first(a_reads, b_reads, ca, cb):
    sides = (
        SideReading("A", "DOG", "DOG" if a_reads else "D0", a_reads, ca),
        SideReading("B", "CAT", "CAT" if b_reads else "", b_reads, cb),
    )
    verdict = Legibility(sides, 30.0, 3.0)
    first = verdict.weaker_first[0]
    assert first.reads == (a_reads and b_reads)
    assert verdict.sentence().startswith(first.sentence())
    assert verdict.all_read == (a_reads and b_reads)
    assert verdict.sides_read == a_reads + b_reads
    if not b_reads:
        assert "side B does not read CAT" in verdict.sentence()


def test_a_picture_side_says_its_verdict_is_an_estimate():
    side = SideReading("B", None, None, False, 0.97, 0.81)
    assert "a picture" in side.sentence() and "not a reader's verdict" in side.sentence()
    assert "81 %" in side.sentence()
    assert side.judge == "shapes" and side.to_json()["reads"] is False


def test_shape_agreement_is_one_for_a_faithful_view_and_falls_for_a_wrong_picture():
    from illuknit.design.legibility import shape_agreement
    from illuknit.pictures.drawings import draw_shape
    from illuknit.pipeline.stages import design_double

    pics = [
        np.where(draw_shape(n, (30, 30))[..., None], 30, 240).astype(np.uint8).repeat(3, axis=2)
        for n in ("plus", "circle")
    ]
    d = design_double(pics[0], pics[1], width=30, unit_aspect=1.0)
    p = d.designs[0].pattern
    own = shape_agreement(p, d.targets[0], "A")
    other = shape_agreement(p, d.targets[1], "A")
    assert 0.0 <= other < own <= 1.0
    with pytest.raises(OptionError, match="`picture`"):
        shape_agreement(p, d.targets[0][:5], "A")


def test_without_the_reader_reading_says_what_to_install(monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(BackendUnavailableError, match="apt-get install tesseract-ocr"):
        read_images([np.zeros((10, 10), np.uint8)])


def test_a_reader_that_fails_says_why_instead_of_reading_nothing(tmp_path, monkeypatch):
    # a broken install (no language data) exits non-zero and prints nothing to parse: that is
    # said, never taken for "the reader saw nothing" on every side
    fake = tmp_path / "tesseract"
    fake.write_text("#!/bin/sh\necho 'Error opening data file eng.traineddata' >&2\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    with pytest.raises(BackendUnavailableError, match="failed: Error opening data file"):
        read_images([np.zeros((10, 10), np.uint8)])


def test_bad_arguments_are_named():
    from illuknit.core.pattern import LogicalPattern  # noqa: F401  (the IR seen_far takes)

    with pytest.raises(OptionError, match="`view`"):
        seen_far(None, "C")  # type: ignore[arg-type]
    with pytest.raises(OptionError, match="`pictures`"):
        read_sides(None, [np.zeros((2, 2, 3))])  # type: ignore[arg-type]


def test_the_reader_reads_a_sharp_word_and_nothing_in_a_blank(reader):
    got = read_images([word("GLOBE")[:, :, 0], word("PLUM")])
    assert [r.text for r in got] == ["GLOBE", "PLUM"]
    assert min(r.confidence for r in got) >= 80
    assert words_of([word("GLOBE"), np.full((40, 90, 3), 255, np.uint8)]) == ["GLOBE", None]


def test_drawn_shapes_are_pictures_not_words(reader):
    # the bundled drawings read as letters with little confidence at most ("Lh" for the ECG)
    from illuknit.pictures.drawings import draw_shape

    shapes = [draw_shape(name, (40, 40)) for name in ("heart", "ecg", "plus", "circle")]
    rgb = [np.where(m[..., None], 30, 240).astype(np.uint8).repeat(3, axis=2) for m in shapes]
    assert words_of(rgb) == [None] * 4


def test_a_design_is_read_per_side_and_the_result_carries_it(reader):
    from illuknit.pipeline.stages import design_double

    ranking = RankOptions(rank_by="legibility", read=True)
    d = design_double(word("ZEBRA"), word("HUMID"), width=100, ranking=ranking)
    verdicts = [x.legibility for x in d.designs]
    assert all(isinstance(v, Legibility) for v in verdicts)
    assert [v.sides[0].words for v in verdicts] == ["ZEBRA"] * len(verdicts)
    # the reader's order: no design reads on more sides than the first
    assert verdicts[0].sides_read == max(v.sides_read for v in verdicts)
    assert verdicts[0].all_read, verdicts[0].sentence()
    assert d.designs[0].rank_fields[0] == "-sides that read"
    # the same verdict from the library call on the pattern alone
    again = read_sides(d.designs[0].pattern, list(d.targets))
    assert [s.reads for s in again.sides] == [s.reads for s in verdicts[0].sides]


def test_a_head_on_design_cannot_be_ranked_by_legibility():
    from illuknit.pipeline.stages import design_headon

    with pytest.raises(OptionError, match="double-view"):
        design_headon(word("OWL")[:, :, :], width=20, ranking=RankOptions(rank_by="legibility"))


def test_the_smallest_legible_width_stops_at_the_first_width_that_reads(reader):
    from illuknit.pipeline.legible import smallest_legible_width

    got = smallest_legible_width(word("MOB"), word("KIT"), widths=(40, 16, 60), unit_aspect=1.0)
    widths = [v.width for v in got.tried]
    assert widths[0] == 16 and widths == sorted(widths)  # narrowest first
    assert got.words == ("MOB", "KIT")
    if got.both is None:
        assert widths == [16, 40, 60] and got.sentence().startswith("no width up to 60")
    else:
        assert widths[-1] == got.both and got.tried[-1].both_read
        assert not any(v.both_read for v in got.tried[:-1])
    for v in got.tried:
        assert v.both_read <= (v.a_reads and v.b_reads)


def test_the_smallest_legible_width_takes_the_grid_proportions_not_the_yarns(monkeypatch):
    import illuknit.design.legibility as legibility
    from illuknit.core.pattern import parse_yarns
    from illuknit.pipeline.legible import smallest_legible_width

    pic = word("MOB")
    with pytest.raises(OptionError, match="`yarns` is not an option of this stage"):
        smallest_legible_width(pic, pic, widths=(16,), yarns=parse_yarns("#000000,#ffffff"))
    # the grid's proportions pass the options' check (a design app sizes by its gauge)
    monkeypatch.setattr(legibility, "reader_available", lambda: False)
    with pytest.raises(BackendUnavailableError, match="tesseract"):
        smallest_legible_width(pic, pic, widths=(16,), unit_aspect=0.7)


def test_the_reader_is_the_program_illuknit_reader_names(tmp_path, monkeypatch):
    from illuknit.design.legibility import READER_ENV, reader_available, reader_path

    fake = tmp_path / "my-tesseract"
    fake.write_text("#!/bin/sh\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setenv(READER_ENV, str(fake))
    assert reader_path() == str(fake) and reader_available()
    monkeypatch.setenv(READER_ENV, "no-such-reader-here")
    assert reader_path() is None and not reader_available()
    with pytest.raises(BackendUnavailableError, match="ILLUKNIT_READER names 'no-such-reader"):
        read_images([np.zeros((8, 8), np.uint8)])
