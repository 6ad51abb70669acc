"""The ``render`` and ``calibrate`` commands: outputs, and one-line errors with exit code 2."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import main
from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern
from illuknit.design.render.params import load_params


@pytest.fixture
def pattern_file(tmp_path):
    rng = np.random.default_rng(0)
    p = LogicalPattern(
        rng.integers(0, 2, (6, 5)),
        rng.random((6, 5)) < 0.4,
        (Yarn("white", (250, 250, 250)), Yarn("navy", (0, 0, 128))),
    )
    path = tmp_path / "p.json"
    save_pattern(p, path)
    return path


def _fails(argv, capsys, message):
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert (
        err.startswith("illuknit: error:") and message in err and len(err.strip().splitlines()) == 1
    )


def test_render_writes_pngs_and_gif(tmp_path, pattern_file):
    out = tmp_path / "out"
    main(
        [
            "render",
            str(pattern_file),
            "--angle",
            "25",
            "--scale",
            "3",
            "--frames",
            "5",
            "-o",
            str(out),
        ]
    )
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "contact.png",
        "headon.png",
        "params.json",
        "sweep.gif",
        "view_a.png",
        "view_b.png",
    ]
    # 6 x 5 units at 3 px a unit across, in the fabric's proportions (a unit 0.7 as tall as
    # wide), foreshortened at 25 degrees: head-on 13 rows, view A sin(25) of that
    assert Image.open(out / "headon.png").size == (15, round(18 * 0.7))
    assert Image.open(out / "view_a.png").size == (15, round(18 * 0.7 * math.sin(math.radians(25))))
    with Image.open(out / "sweep.gif") as gif:
        assert gif.n_frames == 8  # 5 out and 3 back
    assert load_params(out / "params.json").theta == 25


def test_render_bad_input(tmp_path, pattern_file, capsys):
    out = tmp_path / "out"
    _fails(["render", str(pattern_file), "--angle", "0", "-o", str(out)], capsys, "(0, 90]")
    _fails(["render", str(pattern_file), "--angle", "91", "-o", str(out)], capsys, "(0, 90]")
    (tmp_path / "p.json").write_text(json.dumps({"bump": 2}))
    _fails(
        ["render", str(pattern_file), "--params", str(tmp_path / "p.json"), "-o", str(out)],
        capsys,
        "unknown render parameter",
    )
    (tmp_path / "p.json").write_text(json.dumps({"flat_height": -1}))
    _fails(
        ["render", str(pattern_file), "--params", str(tmp_path / "p.json"), "-o", str(out)],
        capsys,
        "positive",
    )
    _fails(["render", str(tmp_path / "missing.json"), "-o", str(out)], capsys, "not found")
    assert not out.exists()


def test_calibrate_swatch_then_fit(tmp_path, capsys):
    cal = tmp_path / "cal"
    main(["calibrate", "swatch", "--flat-sizes", "1,2,3", "--bump-sizes", "1", "-o", str(cal)])
    assert sorted(p.name for p in cal.iterdir()) == [
        "measurements.csv",
        "preview.png",
        "swatch.json",
    ]
    rows = (cal / "measurements.csv").read_text().splitlines()
    angles = {"1": "40.0", "2": "22.8", "3": "15.6"}  # relief ~0.84
    filled = [rows[0]] + [
        ",".join([r.split(",")[0], r.split(",")[1], angles[r.split(",")[1]], ""]) for r in rows[1:]
    ]
    (cal / "m.csv").write_text("\n".join(filled) + "\n")
    capsys.readouterr()
    main(
        [
            "calibrate",
            "fit",
            str(cal / "m.csv"),
            "--flat-height",
            "0.2",
            "-o",
            str(tmp_path / "params.json"),
        ]
    )
    out = capsys.readouterr().out
    assert "fitted bump height" in out and "rms residual" in out
    p = load_params(tmp_path / "params.json")
    assert p.flat_height == 0.2 and p.bump_height == pytest.approx(1.04, abs=0.02)


def test_calibrate_fit_bad_input(tmp_path, capsys):
    out = tmp_path / "params.json"
    (tmp_path / "one.csv").write_text("flat_rows,angle_deg\n1,30\n")
    _fails(["calibrate", "fit", str(tmp_path / "one.csv"), "-o", str(out)], capsys, "at least two")
    (tmp_path / "same.csv").write_text("flat_rows,angle_deg\n1,30\n2,30\n")
    _fails(["calibrate", "fit", str(tmp_path / "same.csv"), "-o", str(out)], capsys, "equal")
    _fails(["calibrate", "fit", str(tmp_path / "none.csv"), "-o", str(out)], capsys, "not found")
    _fails(
        ["calibrate", "swatch", "--flat-sizes", "1,x", "-o", str(tmp_path / "s")],
        capsys,
        "positive integers",
    )
    assert not out.exists() and not (tmp_path / "s").exists()


def test_render_refuses_absurd_sizes_with_a_suggestion(tmp_path, capsys):
    from illuknit.cli.render import check_render_size

    rng = np.random.default_rng(1)
    p = LogicalPattern(
        rng.integers(0, 2, (60, 60)),
        rng.random((60, 60)) < 0.4,
        (Yarn("white", (250, 250, 250)), Yarn("navy", (0, 0, 128))),
    )
    path = tmp_path / "p60.json"
    save_pattern(p, path)
    out = tmp_path / "out"
    _fails(
        ["render", str(path), "--scale", "64", "--frames", "400", "-o", str(out)],
        capsys,
        "try --frames",
    )
    assert not out.exists()
    # The suggestion fits.
    err_frames = 14  # 400e6 // (3840 * 3840) // 2 + 1
    check_render_size((60, 60), scale=64, frames=err_frames)
    big = LogicalPattern(np.zeros((1000, 1000), np.int16), np.zeros((1000, 1000), bool), p.yarns)
    save_pattern(big, tmp_path / "big.json")
    _fails(
        ["render", str(tmp_path / "big.json"), "--scale", "8", "-o", str(out)],
        capsys,
        "try --scale 4",
    )
    assert not out.exists()


def test_render_names_only_the_files_it_wrote(tmp_path, pattern_file, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("x")
    main(["render", str(pattern_file), "--frames", "3", "--scale", "2", "-o", str(out)])
    line = capsys.readouterr().out.strip().splitlines()[-1]
    assert line.startswith("wrote 6 files") and "mine.txt" not in line


def test_render_tall_bumps_and_split_bumps(tmp_path, pattern_file):
    """--tall-bumps renders at the tall height (written to params.json), here a pattern with
    split bumps (a version-2 pattern file)."""
    from illuknit.core.pattern import load_pattern

    p = load_pattern(pattern_file)
    split = p.replace(upper=np.where(p.raised, 1 - p.yarn, p.yarn))
    save_pattern(split, tmp_path / "split.json")
    plain, tall = tmp_path / "plain", tmp_path / "tall"
    args = ["render", str(tmp_path / "split.json"), "--scale", "2", "--frames", "2"]
    main([*args, "-o", str(plain)])
    main([*args, "--tall-bumps", "-o", str(tall)])
    assert load_params(tall / "params.json").bump_height == pytest.approx(1.0)
    assert load_params(plain / "params.json").bump_height == pytest.approx(0.7)
    a = np.asarray(Image.open(plain / "view_a.png"))
    assert not np.array_equal(a, np.asarray(Image.open(tall / "view_a.png")))
