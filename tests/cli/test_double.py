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
    # 6 x 10 pixels at units 0.7 as tall as wide: 9 rows keep the picture's proportions
    assert "9 x 10 units" in text and "10 x 9 units" not in text
    assert (out / "summary.txt").read_text().splitlines()[0].count("9 x 10 units") == 1
    assert "finished size: 7.3 x 4.6 cm" in text  # 20 x 18 stitches at 7 x 9.8 per inch
