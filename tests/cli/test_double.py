"""``illuknit double`` prints sizes as rows x columns, like every other command."""

import numpy as np
from PIL import Image

from illuknit.cli import main


def test_double_sizes_are_rows_by_columns(tmp_path, capsys):
    a = np.full((6, 10, 3), 240, np.uint8)
    a[2:4, 2:8] = 20
    b = np.full((6, 10, 3), 20, np.uint8)
    b[1:5, 4:6] = 240
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")
    out = tmp_path / "out"
    main(
        [
            "double",
            str(tmp_path / "a.png"),
            str(tmp_path / "b.png"),
            "--candidates",
            "1",
            "-o",
            str(out),
        ]
    )
    text = capsys.readouterr().out
    assert "6 x 10 units" in text and "10 x 6 units" not in text
    assert (out / "summary.txt").read_text().splitlines()[0].count("6 x 10 units") == 1


def test_automatic_yarns_keep_each_pictures_lightest_and_darkest():
    from illuknit.cli.double import choose_yarns
    from illuknit.colors import luminance

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
