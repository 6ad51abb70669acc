"""The one pair-sizing policy (illuknit.pictures.sizing), and that every entry point follows it."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import main
from illuknit.core.errors import ImageInputError, PictureSizeMismatchError
from illuknit.pictures.sizing import (
    DEFAULT_MAX_WIDTH,
    grid_width,
    prepare_image,
    size_pair,
    size_picture,
)


def two_tone(h: int, w: int, seed: int = 0) -> np.ndarray:
    """A two-colour picture with a blob, uint8 RGB."""
    rng = np.random.default_rng(seed)
    m = np.zeros((h, w), bool)
    m[h // 4 : 3 * h // 4, w // 5 : w // 2] = True
    m[rng.integers(0, h, 5), rng.integers(0, w, 5)] = True
    return np.where(m[..., None], np.uint8(20), np.uint8(235)).astype(np.uint8) * np.ones(
        3, np.uint8
    )


def photo(h: int, w: int) -> np.ndarray:
    y, x = np.mgrid[0:h, 0:w]
    return np.stack([x / w, y / h, (x + y) / (h + w)], axis=-1)


def test_default_width_is_the_picture_width_capped():
    assert grid_width(64) == 64
    assert grid_width(640) == DEFAULT_MAX_WIDTH
    assert grid_width(640, width=30) == 30
    assert grid_width(640, width_cm=10 * 2 * 2.54 / 7) == 10
    assert grid_width(640, height=20) is None
    with pytest.raises(ImageInputError, match="not both"):
        grid_width(640, width=10, width_cm=5.0)
    with pytest.raises(ImageInputError, match="between 1 and"):
        grid_width(640, width=0)


def test_height_follows_picture_a():
    # a unit (2 stitches x 2 rows) is 0.7 as tall as wide: 1 / 0.7 the rows keep the proportions
    pair = size_pair(two_tone(300, 600), two_tone(150, 300))
    assert pair.shape == (71, 100) and pair.b is not None and pair.b.shape == pair.a.shape
    assert size_picture(two_tone(30, 60), height=10).shape[:2] == (10, 14)
    # square units on request: as many rows as the picture's proportions in units
    assert size_pair(two_tone(300, 600), unit_aspect=1.0).shape == (50, 100)
    assert size_picture(two_tone(30, 60), height=10, unit_aspect=1.0).shape[:2] == (10, 20)


@pytest.mark.parametrize("gauge", ["22x30/10cm", "27.6x39.4/10cm", "5x8/in", "18x20/4in"])
@pytest.mark.parametrize("width", [24, 60, 97])
def test_a_square_picture_knits_square_at_the_gauge(gauge, width):
    """The grid keeps the picture's proportions in the finished fabric, within 3 %."""
    from illuknit.core.gauge import finished_size, parse_gauge

    g = parse_gauge(gauge)
    pair = size_pair(two_tone(200, 200), width=width, unit_aspect=g.unit_aspect)
    size = finished_size(pair.shape, g)
    assert abs(size.height_cm / size.width_cm - 1) <= 0.03, (pair.shape, size)
    # and the head-on preview is drawn in the same proportion
    from illuknit.core.pattern import LogicalPattern, parse_yarns
    from illuknit.outputs.previews import chart_rgb

    n, m = pair.shape
    pattern = LogicalPattern(
        np.zeros((n, m), int), np.zeros((n, m), bool), parse_yarns("black,white")
    )
    img = chart_rgb(pattern, unit_aspect=g.unit_aspect)
    assert abs(img.shape[0] / img.shape[1] - size.height_cm / size.width_cm) <= 0.01


def test_b_within_the_aspect_tolerance_is_fitted_silently():
    # 1 % taller: at 40 units wide it would be 58 rows, but it covers the same piece.
    pair = size_pair(two_tone(200, 200), two_tone(202, 200), width=40)
    assert pair.shape == (57, 40) and not pair.stretched and pair.notes == ()


def test_b_of_another_aspect_is_an_error_unless_stretched():
    with pytest.raises(PictureSizeMismatchError, match=r"different sizes.*--resize") as e:
        size_pair(two_tone(200, 200), two_tone(260, 200), width=40, names=("a.png", "b.png"))
    assert e.value.a_pixels == (200, 200) and e.value.b_pixels == (260, 200)
    assert "a.png" in str(e.value) and isinstance(e.value, ImageInputError)
    pair = size_pair(two_tone(200, 200), two_tone(260, 200), width=40, stretch=True)
    assert pair.shape == (57, 40) and pair.stretched and "stretched" in pair.notes[0]


def test_resampling_is_nearest_for_few_colors_and_smooth_for_photos():
    few = size_picture(two_tone(100, 100), width=33)
    assert len(np.unique(few.reshape(-1, 3), axis=0)) == 2  # no blend colours
    many = size_picture(photo(100, 100), width=33)
    assert len(np.unique(many.reshape(-1, 3), axis=0)) > 100


@pytest.fixture()
def pictures(tmp_path):
    """Two pictures of nearly one aspect (0.5 % apart), wider than the default cap."""
    a, b = two_tone(120, 160, 1), two_tone(121, 160, 2)
    pa, pb = tmp_path / "a.png", tmp_path / "b.png"
    Image.fromarray(a).save(pa)
    Image.fromarray(b).save(pb)
    return pa, pb


def test_cli_double_solve_app_and_bench_size_the_same_pictures_alike(pictures, tmp_path):
    """One grid for the same two pictures whichever entry point sizes them."""
    pa, pb = pictures
    expected = size_pair(pa, pb, width=48)
    grids = {}
    main(
        [
            "double",
            str(pa),
            str(pb),
            "--width",
            "48",
            "--candidates",
            "1",
            "-o",
            str(tmp_path / "d"),
        ]
    )
    grids["double"] = json.loads((tmp_path / "d" / "pattern.json").read_text())
    main(["solve", str(pa), str(pb), "--width", "48", "--solver", "dp", "-o", str(tmp_path / "s")])
    grids["solve"] = json.loads((tmp_path / "s" / "pattern.json").read_text())
    shapes = {k: (len(v["yarn"]), len(v["yarn"][0])) for k, v in grids.items()}
    assert set(shapes.values()) == {expected.shape} == {(51, 48)}

    # the app, at the same width, resizes the same pixels to the same grid
    pytest.importorskip("pydantic", reason="the app extra is not installed")
    from illuknit.app.design import prepare_inputs
    from illuknit.app.schemas import DesignSettings

    images = {s: SimpleNamespace(rgb=np.asarray(Image.open(p))) for s, p in (("a", pa), ("b", pb))}
    settings = DesignSettings(mode="double", width_units=48, smooth=False)
    prepared = prepare_inputs(images, settings)
    assert prepared.shape == expected.shape
    # and the bench's picture inputs go through the same stage (drawings.skimage_image)
    assert np.array_equal(size_picture(np.asarray(Image.open(pa)), width=48), expected.a)


def test_default_width_is_the_same_for_single_double_and_solve(pictures, tmp_path):
    pa, pb = pictures  # 160 pixels wide: capped to DEFAULT_MAX_WIDTH everywhere
    main(["single", str(pa), "-o", str(tmp_path / "1")])
    main(["double", str(pa), str(pb), "--candidates", "1", "-o", str(tmp_path / "2")])
    main(["solve", str(pa), str(pb), "--solver", "dp", "-o", str(tmp_path / "3")])
    for out in ("1", "2", "3"):
        doc = json.loads((tmp_path / out / "pattern.json").read_text())
        assert len(doc["yarn"][0]) == DEFAULT_MAX_WIDTH, out


def test_prepare_image_widths(tmp_path):
    rgb = np.random.default_rng(3).random((30, 60, 3))
    assert prepare_image(rgb, width=10, n_colors=2).shape == (7, 10)
    assert prepare_image(rgb, width_cm=10 * 2 * 2.54 / 7, n_colors=2).shape[1] == 10
    with pytest.raises(ImageInputError, match="not both"):
        prepare_image(rgb, width=10, width_cm=5)


def test_the_keywords_are_a_shorthand_for_the_grid_size():
    """``width=40, unit_aspect=1.0`` is ``size=GridSize(width=40, unit_aspect=1.0)``."""
    from illuknit.core.errors import OptionError
    from illuknit.pictures.sizing import GridSize

    a = two_tone(100, 200)
    by_keywords = size_pair(a, width=40, unit_aspect=1.0)
    by_size = size_pair(a, size=GridSize(width=40, unit_aspect=1.0))
    assert by_size.shape == by_keywords.shape == (20, 40)
    assert np.array_equal(by_size.a, by_keywords.a)
    assert prepare_image(a, size=GridSize(width=40), n_colors=2).indices.shape == (
        prepare_image(a, width=40, n_colors=2).indices.shape
    )
    with pytest.raises(OptionError, match="widht"):
        size_pair(a, widht=40)
    with pytest.raises(ImageInputError, match="`width`"):
        GridSize(width=0)
