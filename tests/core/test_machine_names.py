"""Machine names that are true: a generic bed is called what it is, a real machine's name is
said only on its real bed, and a design that fits no bed of its machine says so when designed."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from illuknit.app.knitting import machines_json
from illuknit.check import check_knitout
from illuknit.core.errors import SchedulingError
from illuknit.core.machine import DEFAULT_MACHINE, MACHINES, BedFitWarning
from illuknit.core.pattern import LogicalPattern, parse_yarns, save_pattern
from illuknit.knit.knitout import machine_comment
from illuknit.knitting import knit_pattern
from illuknit.pipeline.stages import design_single

GENERIC = "generic 540-needle V-bed (SWG091N2 rules)"


def says_swg_as_the_machine(text: str) -> bool:
    """Whether ``text`` names the SWG091N2 other than as the rules of a generic bed, as the real
    one it is not, or in the knitout's ``;;Machine`` header (the model whose rules it follows)."""
    rest = re.sub(r"\(SWG091N2 rules\)|;;Machine: SWG091N2|real SWG091N2", "", text)
    return "SWG091N2" in rest


def stripes(width: int) -> LogicalPattern:
    yarn = np.tile(np.arange(width) % 2, (4, 1))
    return LogicalPattern(yarn, np.zeros(yarn.shape, bool), parse_yarns("black,white"))


def test_labels_say_what_the_machine_is() -> None:
    swg = MACHINES["swg091n2"]
    assert DEFAULT_MACHINE.label == GENERIC and not DEFAULT_MACHINE.is_real
    assert swg.label == "SWG091N2" and swg.is_real and MACHINES["kniterate"].label == "Kniterate"
    assert DEFAULT_MACHINE.with_width(680).label == "generic 680-needle V-bed (SWG091N2 rules)"
    # the real machine's name only on its real bed
    assert swg.with_width(300).label == "generic 300-needle V-bed (SWG091N2 rules)"
    assert not swg.with_gauge(12).is_real
    assert not says_swg_as_the_machine(DEFAULT_MACHINE.description)


def test_no_label_for_generic540_says_swg091n2_as_if_it_were_the_machine(tmp_path: Path) -> None:
    with pytest.raises(SchedulingError) as e:
        DEFAULT_MACHINE.check_units(300)
    texts = [DEFAULT_MACHINE.label, DEFAULT_MACHINE.bed_text, str(e.value)]
    result = knit_pattern(stripes(8), machine="generic540")
    summary = result.summary()
    texts.append(str(summary["machine"]))
    assert summary["machine"] == GENERIC
    # the knitout keeps ;;Machine (the rules' model) and says what the bed is under the header
    assert ";;Machine: SWG091N2\n" in result.text
    assert machine_comment(DEFAULT_MACHINE) in result.text and GENERIC in result.text
    texts.append(result.text)
    report = check_knitout(result.text)
    assert report.machine["name"] == GENERIC and report.machine["model"] == "SWG091N2"
    texts.append(report.to_text(name="p.k"))
    label = next(m["label"] for m in machines_json() if m["name"] == "generic540")
    texts.append(label)
    assert [t for t in texts if says_swg_as_the_machine(t)] == []


def test_the_real_machine_is_named_on_its_real_bed() -> None:
    result = knit_pattern(stripes(8), machine="swg091n2")
    assert result.summary()["machine"] == "SWG091N2"
    assert "; machine: SWG091N2, the real machine's bed of 252 needles\n" in result.text
    assert check_knitout(result.text).machine["name"] == "SWG091N2"
    with pytest.raises(SchedulingError, match="the SWG091N2's bed of 252 needles"):
        MACHINES["swg091n2"].check_units(124)


def test_a_260_stitch_design_warns_that_no_real_swg091n2_holds_it() -> None:
    picture = np.full((20, 40, 3), 0.9)
    picture[5:15, 10:30] = 0.1
    with pytest.warns(BedFitWarning, match="not a real SWG091N2"):
        design = design_single(picture, width=130)
    assert len(design.notes) == 1 and "130 units = 260 stitches" in design.notes[0]
    assert "--machine swg091n2" in design.notes[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", BedFitWarning)
        assert design_single(picture, width=60).notes == ()


def test_a_grid_that_fits_no_bed_says_knit_would_refuse_it() -> None:
    note = DEFAULT_MACHINE.fit_note(330)
    assert note is not None and "660 stitches" in note and "would refuse" in note
    assert "at most 267 units" in note and GENERIC in note
    assert MACHINES["swg091n2"].fit_note(123) is None
    assert "would refuse" in (MACHINES["swg091n2"].fit_note(124) or "")


def test_cli_design_prints_one_note_and_knit_names_the_bed(tmp_path: Path, run_cli) -> None:
    from PIL import Image

    rgb = np.full((20, 40, 3), 240, np.uint8)
    rgb[5:15, 10:30] = 20
    Image.fromarray(rgb).save(tmp_path / "pic.png")
    code, _, err = run_cli(["single", tmp_path / "pic.png", "--width", 130, "-o", tmp_path / "d"])
    assert code == 0, err
    notes = [line for line in err.splitlines() if "not a real SWG091N2" in line]
    assert len(notes) == 1 and notes[0].startswith("illuknit: note: the pattern is 130 units")
    save_pattern(stripes(8), tmp_path / "p.json")
    code, out, err = run_cli(["knit", tmp_path / "p.json", "-o", tmp_path / "p.k"])
    assert code == 0, err
    assert f"for {GENERIC}" in out + err and not says_swg_as_the_machine(out + err)
    code, out, err = run_cli(
        ["knit", tmp_path / "p.json", "-o", tmp_path / "w.k", "--machine-width", "680"]
    )
    assert code == 0, err
    assert "generic 680-needle V-bed (SWG091N2 rules)" in out + err
    assert "generic 680-needle" in (tmp_path / "w.k").read_text()
    # a 260-stitch pattern compiles for the generic bed, and says no real SWG091N2 holds it
    save_pattern(stripes(130), tmp_path / "wide.json")
    code, out, err = run_cli(["knit", tmp_path / "wide.json", "-o", tmp_path / "wide.k"])
    assert code == 0, err
    assert [line for line in err.splitlines() if "not a real SWG091N2" in line]
    assert f"for {GENERIC}" in out + err


def test_a_tile_design_wider_than_its_machine_warns_at_design_time() -> None:
    from illuknit.core.machine import MachineSpec
    from illuknit.design.options import RankOptions, SearchOptions
    from illuknit.pipeline.stages import design_double

    a = np.full((20, 40, 3), 0.9)
    a[5:15, 10:30] = 0.1
    b = np.full((20, 40, 3), 0.9)
    b[2:18, 18:22] = 0.1
    narrow = MachineSpec(needles=60)  # holds 27 units
    with pytest.warns(BedFitWarning, match="would refuse"):
        design = design_double(
            a, b, width=40, ranking=RankOptions(machine=narrow), search=SearchOptions(candidates=1)
        )
    assert len(design.notes) == 1 and "40 units = 80 stitches" in design.notes[0]
    assert "generic 60-needle V-bed (SWG091N2 rules) holds at most 27 units" in design.notes[0]


def test_single_notes_are_for_the_machine_chosen() -> None:
    picture = np.full((20, 40, 3), 0.9)
    picture[5:15, 10:30] = 0.1
    with pytest.warns(BedFitWarning, match="would refuse"):
        design = design_single(picture, width=130, machine="swg091n2")
    assert "the SWG091N2's bed of 252 needles holds at most 123 units" in design.notes[0]
