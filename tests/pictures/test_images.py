import numpy as np
import pytest
from PIL import Image

from illuknit.core.errors import ImageInputError
from illuknit.core.pattern import parse_yarns
from illuknit.pictures.images import (
    load_image,
    quantise_image,
    resize_to_units,
    units_for_width,
)


def _save(tmp_path, name, arr, mode=None, **kw):
    im = Image.fromarray(arr, mode) if mode else Image.fromarray(arr)
    path = tmp_path / name
    im.save(path, **kw)
    return path


def test_formats_and_modes(tmp_path):
    rgb = np.zeros((6, 8, 3), np.uint8)
    rgb[:3] = 255
    for name in ("a.png", "a.bmp", "a.gif"):
        out = load_image(_save(tmp_path, name, rgb))
        assert out.shape == (6, 8, 3)
        assert np.allclose(out[0], 1) and np.allclose(out[-1], 0)
    jpg = load_image(_save(tmp_path, "a.jpg", rgb, quality=95))
    assert abs(jpg[0].mean() - 1) < 0.05
    grey = load_image(_save(tmp_path, "g.png", rgb[..., 0]))
    assert grey.shape == (6, 8, 3)
    pal = Image.fromarray(rgb).convert("P")
    pal.save(tmp_path / "p.png")
    assert load_image(tmp_path / "p.png").shape == (6, 8, 3)


def test_alpha_composited_on_white(tmp_path):
    rgba = np.zeros((4, 4, 4), np.uint8)
    rgba[..., 3] = 0  # fully transparent black
    rgba[:2, :, 3] = 255  # opaque black on top half
    out = load_image(_save(tmp_path, "t.png", rgba))
    assert np.allclose(out[:2], 0) and np.allclose(out[2:], 1)


@pytest.mark.parametrize("content", [b"", b"not an image at all", b"\x89PNG\r\n\x1a\ngarbage"])
def test_non_images(tmp_path, content):
    f = tmp_path / "x.png"
    f.write_bytes(content)
    with pytest.raises(ImageInputError):
        load_image(f)


def test_missing_and_tiny(tmp_path):
    with pytest.raises(ImageInputError, match="not found"):
        load_image(tmp_path / "nope.png")
    with pytest.raises(ImageInputError, match="folder"):
        load_image(tmp_path)
    with pytest.raises(ImageInputError, match="at least 2 x 2"):
        load_image(_save(tmp_path, "one.png", np.zeros((1, 1, 3), np.uint8)))


def test_resize():
    rgb = np.random.default_rng(0).random((40, 80, 3))
    assert resize_to_units(rgb, width=20).shape == (10, 20, 3)
    assert resize_to_units(rgb, height=5).shape == (5, 10, 3)
    assert resize_to_units(rgb, width=20, unit_aspect=0.5).shape == (20, 20, 3)
    for bad in (0, 1001, -3):
        with pytest.raises(ImageInputError, match="between 1 and 1000"):
            resize_to_units(rgb, width=bad)
    assert units_for_width(width_cm=25.4, gauge=7) == 35


def test_quantise_exact_when_few_colors():
    rgb = np.zeros((4, 4, 3))
    rgb[:, 2:] = [1.0, 0.0, 0.0]
    q = quantise_image(rgb)
    assert len(q.yarns) == 2 and sorted(q.counts.tolist()) == [8, 8]
    assert q.yarns[0].rgb == (0, 0, 0)  # darkest first


def test_quantise_to_user_yarns_and_refusal():
    rgb = np.random.default_rng(1).random((10, 10, 3))
    ys = parse_yarns("black,white")
    q = quantise_image(rgb, yarns=ys)
    assert q.yarns == ys and set(np.unique(q.indices)) <= {0, 1}
    # darker pixels go to black
    lum = rgb.mean(-1)
    assert lum[q.indices == 0].mean() < lum[q.indices == 1].mean()
    with pytest.raises(ImageInputError, match="100 colours but only 2"):
        quantise_image(rgb, yarns=ys, allow_quantise=False)
    legend = q.legend()
    assert sum(e["pixels"] for e in legend) == 100


def test_quantise_is_deterministic():
    rgb = np.random.default_rng(2).random((16, 16, 3))
    a, b = quantise_image(rgb, n_colors=3), quantise_image(rgb, n_colors=3)
    assert np.array_equal(a.indices, b.indices)


def test_flat_color_count_counts_flat_drawings_and_refuses_photos() -> None:
    from illuknit.pictures.images import flat_color_count

    drawing = np.zeros((60, 90, 3), np.uint8)
    drawing[:, 30:] = (200, 40, 40)
    drawing[20:25, 70:] = (250, 250, 250)  # a colour the spread sample may miss
    assert flat_color_count(drawing) == 3
    photo = np.random.default_rng(0).integers(0, 256, (60, 90, 3), dtype=np.uint8)
    assert flat_color_count(photo) is None
    assert flat_color_count(drawing, most=2) is None
