"""Automatic yarns keep each picture's darkest and lightest colour (tiles.yarn_choice)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from illuknit.core.colors import lab_from_rgb, luminance
from illuknit.core.errors import YarnSpecError
from illuknit.design.tiles.yarn_choice import SAME_COLOUR_LAB, choose_yarns, picture_extremes


def _logo_and_photo() -> list[np.ndarray]:
    """Picture A of the bundled logos-4 instance (white background, red and blue logo) and the
    bundled coffee photo: clustered jointly into 4 colours, the photo's lightest is lost."""
    from illuknit.bench.instances import instance_targets, load_manifest
    from illuknit.pictures.drawings import skimage_image

    logo = instance_targets(load_manifest().get("logos-4")).rgb("A")
    photo = skimage_image("coffee", logo.shape[:2])
    return [(np.asarray(p) * 255).round().astype(np.uint8) for p in (logo, photo)]


def _worst_miss(pictures: list[np.ndarray], yarn_rgb: np.ndarray) -> float:
    """The largest CIELAB distance from a picture's darkest or lightest colour to its nearest
    yarn."""
    labs = lab_from_rgb(yarn_rgb.astype(np.float64))
    worst = 0.0
    for p in pictures:
        for e in lab_from_rgb(picture_extremes(p / 255.0, 4)):
            worst = max(worst, min(float(np.linalg.norm(e - y)) for y in labs))
    return worst


def test_double_with_four_colours_keeps_both_pictures_lightest_and_darkest(tmp_path, run_cli):
    pictures = _logo_and_photo()
    # the pair is a real test: yarns from joint clusters alone lose an extreme
    from illuknit.pictures.images import quantise_image

    joint = quantise_image(np.concatenate(pictures) / 255.0, n_colors=4).colors
    assert _worst_miss(pictures, joint) > 2 * SAME_COLOUR_LAB
    for name, pic in zip(("a.png", "b.png"), pictures, strict=True):
        Image.fromarray(pic).save(tmp_path / name)
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--colors", "4",
         "--candidates", "1", "-o", str(tmp_path / "out")])  # fmt: skip
    assert code == 0, err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    yarns = np.array([[int(y["rgb"][i : i + 2], 16) for i in (1, 3, 5)] for y in summary["yarns"]])
    assert len(yarns) == 4
    assert _worst_miss(pictures, yarns) <= SAME_COLOUR_LAB, summary["yarns"]


@pytest.mark.parametrize("n", [2, 3, 4])
def test_the_overall_extremes_always_get_a_yarn(n):
    pictures = [p / 255.0 for p in _logo_and_photo()]
    ys = choose_yarns(pictures, n)
    assert 1 <= len(ys) <= n
    lum = [float(luminance(np.array(y.rgb, np.float64))) for y in ys]
    assert lum == sorted(lum)  # darkest first
    extremes = np.concatenate([picture_extremes(p, n) for p in pictures])
    ext_lab = lab_from_rgb(extremes)
    yarn_lab = lab_from_rgb(np.array([y.rgb for y in ys], np.float64))
    lum_ext = luminance(extremes)
    for k in (int(np.argmin(lum_ext)), int(np.argmax(lum_ext))):
        assert min(np.linalg.norm(ext_lab[k] - y) for y in yarn_lab) <= SAME_COLOUR_LAB


def test_yarn_count_out_of_range_is_a_yarn_error():
    with pytest.raises(YarnSpecError, match="between 1 and 8"):
        choose_yarns([np.zeros((4, 4, 3))], 9)


def test_automatic_yarns_keep_each_pictures_lightest_and_darkest():
    a = np.full((40, 40, 3), 30, np.uint8)
    a[:, :3] = 250  # a thin white edge: picture A's lightest colour
    a[10:30, 10:30] = (120, 40, 40)
    b = np.zeros((40, 40, 3), np.uint8)
    for i in range(40):  # many dark shades that win a joint clustering
        b[:, i] = (20 + 3 * i, 20 + i, 60)
    for n in (3, 4):
        ys = choose_yarns([a / 255.0, b / 255.0], n)
        assert len(ys) == n
        lum = luminance(np.array([y.rgb for y in ys], np.float64))
        assert lum.max() > 0.8, [y.hex for y in ys]  # A's white is readable
        assert lum.min() < 0.02  # and the darkest colour
