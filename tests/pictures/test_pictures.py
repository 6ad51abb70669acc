"""Pictures read right: 16-bit, palettes with transparency, CMYK, EXIF orientation, animations,
the pixel cap and reduction while decoding (illuknit.pictures.decode)."""

import io
import struct
import zlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from PIL import Image

from illuknit.cli import main
from illuknit.core.errors import ImageInputError
from illuknit.pictures.decode import MAX_PIXELS, read_picture
from illuknit.pictures.sizing import prepare_image


def png_chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png16(a: np.ndarray) -> bytes:
    """A 16-bit PNG (grey for (H, W), RGB for (H, W, 3)) of uint16 ``a`` (Pillow cannot write RGB 16)."""
    h, w = a.shape[:2]
    color_type = 0 if a.ndim == 2 else 2
    rows = a.reshape(h, -1).astype(">u2").tobytes()
    stride = rows and len(rows) // h
    raw = b"".join(b"\0" + rows[i * stride : (i + 1) * stride] for i in range(h))
    ihdr = struct.pack(">IIBBBBB", w, h, 16, color_type, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + png_chunk(b"IHDR", ihdr)
        + png_chunk(b"IDAT", zlib.compress(raw))
        + png_chunk(b"IEND", b"")
    )


def png8(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(a).save(buf, format="PNG")
    return buf.getvalue()


def test_16bit_grey_is_not_washed_out():
    grey = np.array([[0, 64], [128, 255]], np.uint8).repeat(4, 0).repeat(4, 1)
    pic = read_picture(png16(grey.astype(np.uint16) * 257))
    assert np.array_equal(pic.rgb[..., 0], grey) and np.array_equal(pic.rgb[..., 2], grey)
    q = prepare_image(pic.rgb, n_colors=2, unit_aspect=1.0)  # square units: pixel for pixel
    assert sorted(np.round(q.counts / q.counts.sum(), 2)) == [0.5, 0.5]  # not 99.98 % white


@settings(max_examples=25, deadline=None)
@given(
    arrays(np.uint8, st.tuples(st.integers(2, 9), st.integers(2, 9), st.sampled_from([1, 3]))),
)
def test_8bit_and_16bit_give_the_same_pattern(a):
    a = a[..., 0] if a.shape[2] == 1 else a
    p8, p16 = read_picture(png8(a)), read_picture(png16(a.astype(np.uint16) * 257))
    assert np.array_equal(p8.rgb, p16.rgb)
    q8, q16 = prepare_image(p8.rgb, n_colors=2), prepare_image(p16.rgb, n_colors=2)
    assert np.array_equal(q8.indices, q16.indices)


def test_palette_with_transparency_is_composited_on_white():
    idx = np.array([[0, 1], [1, 0]], np.uint8).repeat(3, 0).repeat(3, 1)
    im = Image.fromarray(idx, "P")
    im.putpalette([0, 0, 0, 200, 0, 0] + [0] * 762)
    buf = io.BytesIO()
    im.save(buf, format="PNG", transparency=0)
    rgb = read_picture(buf.getvalue()).rgb
    assert tuple(rgb[0, 0]) == (255, 255, 255) and tuple(rgb[0, 3]) == (200, 0, 0)


def test_cmyk_jpeg():
    cmyk = np.zeros((16, 16, 4), np.uint8)
    cmyk[:, 8:, 0] = 255  # right half cyan, left half paper white
    buf = io.BytesIO()
    Image.fromarray(cmyk, "CMYK").save(buf, format="JPEG", quality=95)
    pic = read_picture(buf.getvalue())
    assert pic.rgb.shape == (16, 16, 3)
    assert np.abs(pic.rgb[8, 2].astype(int) - 255).max() < 12
    assert np.abs(pic.rgb[8, 13].astype(int) - (0, 255, 255)).max() < 12
    assert any("CMYK" in n for n in pic.notes)


def test_exif_orientation_is_applied():
    a = np.zeros((10, 20, 3), np.uint8)
    a[:, :5] = 255  # white on the left
    im = Image.fromarray(a)
    exif = im.getexif()
    exif[0x0112] = 6  # stored rotated: display = rotate 90 degrees clockwise
    buf = io.BytesIO()
    im.save(buf, format="PNG", exif=exif.tobytes())
    rgb = read_picture(buf.getvalue()).rgb
    assert rgb.shape == (20, 10, 3)
    assert rgb[:5].min() == 255 and rgb[6:].max() == 0  # white now at the top


def test_animated_gif_first_frame_said_in_the_output(tmp_path, capsys):
    frames = [np.full((12, 16, 3), v, np.uint8) for v in (0, 255, 128)]
    frames[0][3:9, 4:12] = 255
    path = tmp_path / "anim.gif"
    Image.fromarray(frames[0]).save(
        path, save_all=True, append_images=[Image.fromarray(f) for f in frames[1:]]
    )
    pic = read_picture(path)
    assert pic.rgb[0, 0, 0] == 0 and pic.rgb[5, 6, 0] == 255
    assert pic.notes == ("animated picture: the first of its 3 frames is used",)
    main(["single", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert "illuknit: note: " in err and "first of its 3 frames" in err


def test_pixel_cap_from_the_header(tmp_path, capsys):
    # A 20000 x 20000 PNG header: refused before any decoding (Pillow would raise its bomb error).
    ihdr = struct.pack(">IIBBBBB", 20000, 20000, 8, 2, 0, 0, 0)
    path = tmp_path / "bomb.png"
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) + png_chunk(b"IEND", b""))
    with pytest.raises(ImageInputError, match="megapixel limit"):
        read_picture(path)
    with pytest.raises(SystemExit) as e:
        main(["single", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert e.value.code == 2 and len(err.strip().splitlines()) == 1 and "400 megapixels" in err
    assert not (tmp_path / "out").exists()
    assert MAX_PIXELS >= 50_000_000


def test_large_pictures_are_reduced_while_decoding():
    y, x = np.mgrid[0:1200, 0:3000]
    smooth = np.stack([(x % 256), (y % 256), ((x + y) % 256)], axis=2).astype(np.uint8)
    pic = read_picture(png8(smooth), max_side=1000)
    assert pic.rgb.shape == (400, 1000, 3) and pic.original_size == (1200, 3000)
    assert any("reduced from 3000 x 1200" in n for n in pic.notes)
    two = np.where((x // 7 + y // 5) % 2 == 0, 20, 240).astype(np.uint8)
    few = read_picture(png8(two), max_side=1000).rgb
    assert set(np.unique(few)) == {20, 240}  # nearest-neighbour: no blend colours
