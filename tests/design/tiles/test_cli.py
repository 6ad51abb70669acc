"""The tiles / double / headon commands, and the two CI demonstrations at small sizes."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from illuknit.core.colors import luminance
from illuknit.pictures.drawings import draw_heart, draw_text


def _png(path, mask, ink=(20, 20, 20), paper=(240, 240, 240)):
    img = np.where(mask[..., None], np.array(ink, np.uint8), np.array(paper, np.uint8)).astype(
        np.uint8
    )
    Image.fromarray(img).save(path)
    return path


@pytest.fixture(scope="module")
def words(tmp_path_factory):
    d = tmp_path_factory.mktemp("words")
    a = _png(d / "illusion.png", draw_text("ILLUSION", shape=(16, 64)))
    b = _png(d / "knitting.png", draw_text("KNITTING", shape=(16, 64)))
    c = _png(d / "tall.png", draw_text("K", shape=(30, 20)))
    return a, b, c


def test_tiles_command_lists_and_draws(tmp_path, run_cli):
    code, out, err = run_cli(["tiles", "--yarns", "black,white", "-o", str(tmp_path / "bank")])
    assert code == 0, err
    assert "tile bank" in out and "0/1/0^" in out
    doc = json.loads((tmp_path / "bank" / "bank.json").read_text())
    pictures = sorted((tmp_path / "bank").glob("tile_*.png"))
    assert len(pictures) == len(doc["tiles"]) == 23
    with Image.open(pictures[0]) as im:
        assert im.width > im.height  # four panels side by side
    # the written bank loads back as a custom bank
    code, out, err = run_cli(
        ["tiles", "--yarns", "black,white", "--bank", str(tmp_path / "bank" / "bank.json")]
    )
    assert code == 0, err


def test_tiles_command_bad_bank(tmp_path, run_cli):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": "illuknit-tile-bank", "version": 1, "tiles": [
        {"rows": ["0", "1", "0^"], "fills": {"B": {"1": "1"}}}]}))  # fmt: skip
    code, _out, err = run_cli(["tiles", "--yarns", "black,white", "--bank", str(bad)])
    assert code == 2
    assert err.startswith("illuknit: error:") and "can_see gives" in err and err.count("\n") == 1


def test_double_writes_ranked_candidates(words, tmp_path, run_cli):
    a, b, _ = words
    out_dir = tmp_path / "out"
    code, out, err = run_cli(
        ["double", str(a), str(b), "--candidates", "2", "--pick", "2", "-o", str(out_dir)]
    )
    assert code == 0, err
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["default"] == 2 and len(summary["candidates"]) == 2
    assert [c["default"] for c in summary["candidates"]] == [False, True]
    for k in (1, 2):
        sub = out_dir / f"candidate_{k}"
        for name in ("pattern.json", "headon.png", "view_a.png", "view_b.png", "repainted_a.png",
                     "repainted_b.png", "fills.json", "legend.json", "report.json"):  # fmt: skip
            assert (sub / name).is_file(), name
    assert (out_dir / "pattern.json").read_text() == (
        out_dir / "candidate_2" / "pattern.json"
    ).read_text()
    assert "*" in (out_dir / "summary.txt").read_text()
    assert "default" in out


def test_double_sizes_must_match_or_resize(words, tmp_path, run_cli):
    a, _, tall = words
    code, _, err = run_cli(["double", str(a), str(tall), "-o", str(tmp_path / "x")])
    assert code == 2 and "different sizes" in err and "--resize" in err
    assert not (tmp_path / "x").exists()
    code, _, err = run_cli(
        ["double", str(a), str(tall), "--resize", "--candidates", "1", "-o", str(tmp_path / "y")],
    )
    assert code == 0, err
    assert (tmp_path / "y" / "pattern.json").is_file()


def test_double_too_many_colors_for_the_bank(words, tmp_path, run_cli):
    a, b, _ = words
    solids = tmp_path / "solids.json"
    solids.write_text(json.dumps({"format": "illuknit-tile-bank", "version": 1,
                                  "tiles": [{"rows": ["0"]}, {"rows": ["1"]}]}))  # fmt: skip
    # three colours in each picture: a grey band added
    for p in (a, b):
        img = np.asarray(Image.open(p)).copy()
        img[:3] = 128
        Image.fromarray(img).save(tmp_path / p.name)
    code, _, err = run_cli(["double", str(tmp_path / a.name), str(tmp_path / b.name), "--colors", "3",
                         "--yarns", "black,white", "--bank", str(solids), "-o", str(tmp_path / "o")])  # fmt: skip
    assert code == 2 and "distinct brightness" in err


def test_double_without_candidates_explains_and_exits_2(words, tmp_path):
    a, b, _ = words
    solids = tmp_path / "solids.json"
    solids.write_text(json.dumps({"format": "illuknit-tile-bank", "version": 1,
                                  "tiles": [{"rows": ["0"]}, {"rows": ["1"]}]}))  # fmt: skip
    r = subprocess.run(
        [sys.executable, "-m", "illuknit", "double", str(a), str(b), "--yarns", "black,white",
         "--bank", str(solids), "-o", str(tmp_path / "none")],
        capture_output=True, text=True,
    )  # fmt: skip
    assert r.returncode == 2
    assert "cannot all be realised" in r.stderr and "Would fix it" in r.stderr
    assert "Traceback" not in r.stderr and r.stderr.count("\n") == 1
    assert not (tmp_path / "none").exists()


def test_double_pick_out_of_range(words, tmp_path, run_cli):
    a, b, _ = words
    code, _, err = run_cli(
        ["double", str(a), str(b), "--candidates", "1", "--pick", "3", "-o", str(tmp_path / "p")],
    )
    assert code == 2 and "--pick" in err


def test_headon_command(tmp_path, run_cli):
    front = _png(tmp_path / "heart.png", draw_heart((20, 20)))
    code, _out, err = run_cli(
        ["headon", str(front), "--candidates", "1", "-o", str(tmp_path / "h")]
    )
    assert code == 0, err
    s = json.loads((tmp_path / "h" / "summary.json").read_text())
    assert s["mode"] == "headon" and len(s["candidates"][0]["fills_b"]) == 1


# -- the two demonstrations (small sizes) -----------------------------------------------------


def test_demo_illusion_knitting_two_yarns():
    from illuknit.design.tiles.demos import text_pair_demo

    r = text_pair_demo((24, 96), candidates=2)
    assert len(r.yarns) == 2 and len(r.pattern.yarns) == 2
    assert r.report.error_repainted_interior == {"A": 0.0, "B": 0.0}
    for c in r.candidates:  # ink darker than the ground on both sides
        assert c.fills_a[1].brightness < c.fills_a[0].brightness
        assert c.fills_b[1].brightness < c.fills_b[0].brightness
    # the two views really differ where the words differ
    from illuknit.core.views import can_see

    assert (can_see(r.pattern, "A") != can_see(r.pattern, "B")).any()


def test_demo_skimage_pair_three_yarns():
    from illuknit.design.tiles.demos import skimage_pair_demo

    r = skimage_pair_demo((24, 32), candidates=2)
    assert len(r.yarns) == 3
    assert r.report.error_repainted_interior == {"A": 0.0, "B": 0.0}
    for (idx, cols), fills in zip(
        r.inputs, (r.candidates[0].fills_a, r.candidates[0].fills_b), strict=True
    ):
        used = sorted(np.unique(idx), key=lambda k: luminance(cols[k].astype(float)))
        bright = [fills[k].brightness for k in used]
        assert bright == sorted(bright) and len(set(bright)) == len(bright)


def test_double_tile_override(words, tmp_path, run_cli):
    a, b, _ = words
    out_dir = tmp_path / "ov"
    code, _, err = run_cli(
        ["double", str(a), str(b), "--candidates", "1", "--tile", "0,1=0/1/1^", "-o", str(out_dir)],
    )
    assert code == 0, err
    rep = json.loads((out_dir / "candidate_1" / "report.json").read_text())
    assert rep["tiles_report"]["overrides"] == [
        {"a": 0, "b": 1, "tile": "0/1/1^", "keeps_fills": False}
    ]
    for bad, msg in (("zz", "A,B=ROWS"), ("7,1=0", "does not occur")):
        code, _, err = run_cli(
            [
                "double",
                str(a),
                str(b),
                "--candidates",
                "1",
                "--tile",
                bad,
                "-o",
                str(tmp_path / "bad"),
            ],
        )
        assert code == 2 and msg in err
        assert not (tmp_path / "bad").exists()
