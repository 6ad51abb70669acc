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
    # the far view beside the near one: per side, picture | up close | from 3 m, in one sheet
    seen = np.asarray(Image.open(out / "candidate_1" / "seen.png"))
    assert seen.shape[1] > 2.5 * seen.shape[0] / 2  # three panels across, two sides down


def test_the_table_fits_the_terminal_and_the_message_lists_every_folder(
    tmp_path, capsys, monkeypatch
):
    """At 80 columns no header or number is cut ("perc..."): columns are left out, said so, and
    kept in summary.txt; the last lines name every folder and file written and what the
    suggested edits found."""
    from illuknit.pictures.drawings import draw_text

    for name, word in (("a", "UP"), ("b", "ON")):
        mask = draw_text(word, shape=(16, 24))
        Image.fromarray(np.where(mask[..., None], 24, 246).astype(np.uint8).repeat(3, 2)).save(
            tmp_path / f"{name}.png"
        )
    out = tmp_path / "out"
    monkeypatch.setenv("COLUMNS", "80")
    main([
        "double", str(tmp_path / "a.png"), str(tmp_path / "b.png"),
        "--candidates", "3", "--suggest", "-o", str(out),
    ])  # fmt: skip
    text = capsys.readouterr().out
    lines = text.splitlines()
    assert max(len(line) for line in lines if line.startswith(("┃", "│", "┏"))) <= 80
    assert "…" not in text
    assert "perceptual" in text and "the full table is in summary.txt" in text
    assert "fills of input A" in (out / "summary.txt").read_text()  # the full table
    folders = [line for line in lines if line.strip().startswith("folders:")]
    assert folders and all(f"{p.name}/" in folders[0] for p in out.iterdir() if p.is_dir()), folders
    assert "suggestions/" in folders[0]
    assert any(line.strip().startswith("suggestions/: ") and "measured" in line for line in lines)


def test_double_with_split_bumps(tmp_path, capsys):
    """--split-share 1 (a bump whose each side shows only its own course; implies
    --split-bumps): the design uses split bumps where the pictures differ."""
    from illuknit.core.pattern import load_pattern

    a = np.full((6, 8, 3), 240, np.uint8)
    a[1:5, 1:7] = 20
    b = np.full((6, 8, 3), 20, np.uint8)
    b[2:4, :] = 240
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")
    out = tmp_path / "out"
    argv = ["double", tmp_path / "a.png", tmp_path / "b.png", "--candidates", "1", "--pool", "1"]
    argv += ["--split-share", "1"]
    main([str(v) for v in [*argv, "-o", out]])
    capsys.readouterr()
    pattern = load_pattern(out / "pattern.json")
    assert pattern.upper is not None and pattern.split.any()
