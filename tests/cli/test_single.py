"""The single / view / demo commands, including every bad input the foundation issue names."""

import json
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import COMMANDS, main
from illuknit.core.pattern import load_pattern


def ok(args, capsys):
    # A successful click command returns normally (standalone_mode=False).
    main([*args])
    return capsys.readouterr().out


def test_single_writes_bundle(picture, tmp_path, capsys):
    out = tmp_path / "out"
    text = ok(["single", str(picture), "--width", "30", "-o", str(out)], capsys)
    assert "wrote" in text
    for name in (
        "pattern.json",
        "headon.png",
        "view_a.png",
        "view_b.png",
        "contact.png",
        "chart.png",
        "instructions.txt",
        "legend.json",
        "report.json",
    ):
        assert (out / name).is_file(), name
    p = load_pattern(out / "pattern.json")
    assert p.shape == (29, 30)  # the picture's 2:3, at units 0.7 as tall as wide
    assert "finished size: 21.8 x 14.7 cm" in text  # 60 x 58 stitches at 7 x 9.8 per inch
    report = json.loads((out / "report.json").read_text())
    assert report["logical_error"]["A"] == 0.0
    assert "Row 1 (RS)" in (out / "instructions.txt").read_text()
    assert not list(tmp_path.glob(".*partial"))


def test_view_command(picture, tmp_path, capsys):
    ok(["single", str(picture), "-o", str(tmp_path / "a")], capsys)
    ok(["view", str(tmp_path / "a" / "pattern.json"), "-o", str(tmp_path / "b")], capsys)
    assert (tmp_path / "b" / "contact.png").is_file()


def _bad_pattern(tmp_path, **changes):
    doc = {
        "format": "illuknit-pattern",
        "version": 1,
        "rows": 2,
        "cols": 2,
        "yarns": [{"name": "a", "rgb": "#000000"}, {"name": "b", "rgb": "#ffffff"}],
        "yarn": ["01", "10"],
        "raised": ["00", "11"],
        "meta": {},
    }
    doc.update(changes)
    f = tmp_path / "bad.json"
    f.write_text(json.dumps(doc))
    return f


@pytest.mark.parametrize(
    ("make_args", "message"),
    [
        (lambda t, p: ["single", str(t / "missing.png"), "-o", str(t / "o")], "not found"),
        (
            lambda t, p: ["single", str(_write(t / "x.png", b"hello")), "-o", str(t / "o")],
            "not an image",
        ),
        (
            lambda t, p: ["single", str(_write(t / "e.png", b"")), "-o", str(t / "o")],
            "not an image",
        ),
        (lambda t, p: ["single", str(_tiny(t)), "-o", str(t / "o")], "at least 2 x 2"),
        (
            lambda t, p: [
                "single",
                str(_noisy(t)),
                "--yarns",
                "black,white",
                "--colors",
                "2",
                "--no-quantise",
                "-o",
                str(t / "o"),
            ],
            "colours but only 2",
        ),
        (lambda t, p: ["single", str(p), "--width", "0", "-o", str(t / "o")], "1<=x<=1000"),
        (
            lambda t, p: ["single", str(p), "--width", "1001", "-o", str(t / "o")],
            "1<=x<=1000",
        ),
        (
            lambda t, p: ["single", str(p), "--yarns", "black,blurple", "-o", str(t / "o")],
            "unknown yarn colour",
        ),
        (
            lambda t, p: ["single", str(p), "--yarns", "white,#FFF", "-o", str(t / "o")],
            "duplicate yarn colour",
        ),
        (lambda t, p: ["view", str(_bad_pattern(t, version=7)), "-o", str(t / "o")], "version 7"),
        (
            lambda t, p: ["view", str(_bad_pattern(t, yarn=["05", "10"])), "-o", str(t / "o")],
            "out of range",
        ),
        (lambda t, p: ["view", str(t / "none.json"), "-o", str(t / "o")], "not found"),
        (lambda t, p: ["nonsense"], "No such command"),
    ],
)
def test_bad_input_one_line_exit_2(make_args, message, tmp_path, picture, run_cli):
    code, _, err = run_cli(make_args(tmp_path, picture))
    assert code == 2
    assert message in err
    assert err.startswith("illuknit: error:") and err.count("\n") == 1
    assert "Traceback" not in err
    assert not (tmp_path / "o").exists()
    assert not list(tmp_path.glob(".o.*"))


def _write(path, data):
    path.write_bytes(data)
    return path


def _tiny(t):
    Image.fromarray(np.zeros((1, 1, 3), np.uint8)).save(t / "tiny.png")
    return t / "tiny.png"


def _noisy(t):
    Image.fromarray(np.random.default_rng(0).integers(0, 255, (10, 10, 3), dtype=np.uint8)).save(
        t / "n.png"
    )
    return t / "n.png"


def test_failure_leaves_existing_output_alone(picture, tmp_path, run_cli):
    out = tmp_path / "keep"
    out.mkdir()
    (out / "mine.txt").write_text("user file")
    code, _, _ = run_cli(["single", str(picture), "--width", "0", "-o", str(out)])
    assert code == 2
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]


def test_help_everywhere_and_version():
    for cmd in [[], *[[c] for c in COMMANDS]]:
        r = subprocess.run(
            [sys.executable, "-m", "illuknit", *cmd, "--help"], capture_output=True, text=True
        )
        assert r.returncode == 0, (cmd, r.stderr)
        assert "Usage:" in r.stdout
    r = subprocess.run(
        [sys.executable, "-m", "illuknit", "--version"], capture_output=True, text=True
    )
    assert r.returncode == 0 and "illuknit" in r.stdout


def test_demo_runs(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "illuknit", "demo", "-o", str(tmp_path / "d"), "--no-knitout"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "d" / "contact.png").is_file()
    p = load_pattern(tmp_path / "d" / "pattern.json")
    assert p.meta["middle"] is not None  # the bundled picture has a middle colour


def test_single_dot_writes_into_the_current_folder(picture, tmp_path, capsys, monkeypatch):
    here = tmp_path / "work" / "here"
    here.mkdir(parents=True)
    (tmp_path / "work" / "pattern.json").write_text("parent's own")
    monkeypatch.chdir(here)
    ok(["single", str(picture), "-o", "."], capsys)
    assert (here / "pattern.json").is_file() and (here / "chart.png").is_file()
    assert (tmp_path / "work" / "pattern.json").read_text() == "parent's own"
    assert sorted(p.name for p in (tmp_path / "work").iterdir()) == ["here", "pattern.json"]


def test_single_output_under_a_file_is_one_line(picture, tmp_path, run_cli):
    (tmp_path / "existing_file").write_text("x")
    code, _, err = run_cli(["single", str(picture), "-o", str(tmp_path / "existing_file" / "sub")])
    assert code == 2 and len(err.strip().splitlines()) == 1 and "file in the way" in err


def test_wrote_n_files_is_the_true_count(picture, tmp_path, capsys):
    out = tmp_path / "out"
    text = ok(["single", str(picture), "-o", str(out)], capsys)
    line = next(s for s in text.splitlines() if s.startswith("wrote"))
    n = len(list(out.iterdir()))
    assert line.startswith(f"wrote {n} files")
    assert all(p.name in line for p in out.iterdir())


@pytest.mark.parametrize("yarns", [None, "black,white"])
def test_legend_shows_the_middle_color_as_a_mix_of_two_yarns(tmp_path, capsys, yarns):
    rgb = np.full((12, 18, 3), 245, np.uint8)
    rgb[:, :6] = 15
    rgb[:, 6:12] = (200, 140, 90)  # a middle colour ("sandybrown"-like)
    Image.fromarray(rgb).save(tmp_path / "three.png")
    out = tmp_path / "out"
    args = ["single", str(tmp_path / "three.png"), "-o", str(out)]
    ok([*args, "--yarns", yarns] if yarns else args, capsys)
    legend = json.loads((out / "legend.json").read_text())["picture"]
    p = load_pattern(out / "pattern.json")
    knitted = {y.name: y.hex for y in p.yarns}
    mid = next(e for e in legend if e["yarn"] not in knitted)
    dark, light = (y for y in sorted(p.yarns, key=lambda y: sum(y.rgb)))
    assert mid["yarn"] == f"mix of {dark.name} and {light.name}"
    mix = np.round((np.array(dark.rgb) + np.array(light.rgb)) / 2).astype(int)
    assert mid["yarn_color"] == "#" + "".join(f"{v:02x}" for v in mix)
    assert mid["image_color"] != mid["yarn_color"]
    assert [e["yarn"] for e in legend if e is not mid] == [dark.name, light.name]
