"""The Kniterate as a machine: hookless lowering with a waste section, the reference backend
accepting the programs, the set-up sheet, and the refusals of the ``knit`` command."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.errors import CarrierShortageError, SchedulingError, UnknownNameError
from illuknit.core.machine import KNITERATE, MACHINES, get_machine
from illuknit.core.pattern import LogicalPattern, parse_yarns, save_pattern
from illuknit.knitting import knit_pattern
from illuknit.outputs.machine_sheet import machine_sheet

sys.path.insert(0, str(Path(__file__).parents[1] / "formats"))
from test_kc import assert_same_as_reference

YARNS = parse_yarns("#1b1b1b,#f4f0e8")


def mixed(shape=(4, 10), k=2, seed=3) -> LogicalPattern:
    rng = np.random.default_rng(seed)
    yarns = parse_yarns("#1b1b1b,#f4f0e8,#b3202a,#2030a0,#20a030"[: 8 * k - 1])
    return LogicalPattern(rng.integers(0, k, size=shape), rng.random(shape) < 0.4, yarns)


def single() -> LogicalPattern:
    from illuknit.design.single_view import compile_single_view
    from illuknit.pictures.drawings import draw_shape, to_index_image

    img = to_index_image(draw_shape("heart", (5, 6)), ink=0, paper=1)
    return compile_single_view(img, yarns=YARNS)


def test_presets_and_unknown_machine() -> None:
    assert {"swg091n2", "generic540", "kniterate"} <= set(MACHINES)
    k = get_machine("Kniterate")
    assert (k.needles, len(k.carriers), k.inserting_hook) == (252, 6, False)
    assert set(k.pattern_carriers) == set(k.carriers) - {k.waste_carrier, k.draw_carrier}
    with pytest.raises(UnknownNameError, match="kniterate"):
        get_machine("knitmaster")


@pytest.mark.parametrize("make", [single, mixed], ids=["single-view", "mixed-2-yarns"])
def test_programs_check_clean_and_the_backend_accepts_them(make, tmp_path: Path) -> None:
    result = knit_pattern(make(), machine=KNITERATE)
    text = result.text
    assert ";;Carriers: 1 2 3 4 5 6" in text
    assert not any(w in text for w in ("inhook", "releasehook", "outhook"))
    assert "; draw thread" in text and f"out {KNITERATE.waste_carrier}" in text
    used = {ln.split()[-1] for ln in text.splitlines() if ln.startswith(("knit ", "tuck "))}
    assert used <= set(KNITERATE.carriers)
    # one carrier per stitch: the Kniterate runs one carrier per pass
    assert all(len(ln.split()) == 4 for ln in text.splitlines() if ln.startswith("knit "))
    report = check_knitout(text, float_limit=KNITERATE.float_limit)
    assert report.ok, [f.to_dict() for f in report.blocking][:3]
    assert not report.findings, report.findings[:3]  # the waste section is known: 0 warnings
    assert report.pieces == 1
    kc = assert_same_as_reference(text, tmp_path)
    assert kc is not None, "the reference backend refused the program"


def test_sheet_lists_cones_stitch_numbers_needles_time() -> None:
    result = knit_pattern(mixed(), machine=KNITERATE)
    sheet = machine_sheet(result, name="piece.kc")
    s = sheet.summary
    roles = {r["carrier"]: r["role"] for r in s["carrier_table"]}
    assert roles["6"] == "waste yarn" and roles["1"] == "draw thread"
    assert sorted(c for c, r in roles.items() if r == "pattern") == ["2", "3"]
    assert "6" in s["stitch_numbers"]
    lo, hi = s["needle_range"]
    assert 1 <= lo < hi <= 252 and hi - lo + 1 >= result.stitches.shape[1]
    assert s["machine_passes"] == sheet.files["kc"].count("\n>>") + sheet.files["kc"].count("\n<<")
    assert s["machine_passes"] > result.stats.passes  # the waste section is on the machine too
    assert sheet.files["kc"].split("\n")[2] == "// piece.kc"


def test_more_yarns_than_free_carriers_refuses() -> None:
    with pytest.raises(CarrierShortageError, match="draw thread and the waste yarn, leaving 4"):
        knit_pattern(mixed((4, 10), k=5, seed=1), machine=KNITERATE)


def test_wider_than_the_bed_refuses() -> None:
    wide = LogicalPattern(np.zeros((2, 130), int), np.zeros((2, 130), bool), YARNS)
    with pytest.raises(SchedulingError, match="252"):
        knit_pattern(wide, machine=KNITERATE)


def test_cli_writes_kc_and_the_sheet(tmp_path: Path, run_cli) -> None:
    save_pattern(mixed(), tmp_path / "p.json")
    out = tmp_path / "piece.kc"
    args = ["-o", str(out), "--machine", "kniterate", "--format", "kc", "--json", "--no-check"]
    code, output, err = run_cli(["knit", str(tmp_path / "p.json"), *args])
    assert code == 0, err
    s = json.loads(output)
    assert out.read_text().startswith("HOME\nRACK:0\n// piece.kc\n")
    assert s["format"] == "kc" and s["machine"] == "Kniterate"
    assert (
        s["passes"]
        == s["machine_passes"]
        == out.read_text().count("\n>>") + out.read_text().count("\n<<")
    )
    assert {row["role"] for row in s["carrier_table"]} == {"waste yarn", "draw thread", "pattern"}


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--machine", "kniterate", "--format", "dat"], "format"),
        (["--machine", "knitmaster"], "kniterate"),
        (["--machine", "swg091n2", "--format", "kc"], "format"),
    ],
)
def test_cli_bad_machine_or_format_writes_nothing(args, words, tmp_path: Path, run_cli) -> None:
    save_pattern(mixed(), tmp_path / "p.json")
    out = tmp_path / "out.x"
    code, _, output = run_cli(["knit", str(tmp_path / "p.json"), "-o", str(out), *args])
    assert code == 2
    assert words in output
    assert len(output.strip().splitlines()) == 1
    assert not out.exists()


def test_knitout_option_writes_kc_and_the_sheet_in_knit_json(tmp_path: Path) -> None:
    from illuknit.cli.knitout_bridge import write_program

    paths = write_program(mixed(), tmp_path, machine="kniterate")
    assert paths["kc"].read_text().startswith("HOME\nRACK:0\n// program.kc\n")
    s = json.loads(paths["knit"].read_text())
    # the headline passes are the machine's (.kc), the schedule's kept apart
    assert s["machine"] == "Kniterate" and s["machine_passes"] == s["passes"]
    assert s["schedule_passes"] < s["passes"] and s["passes_counted_on"] == "kc"
    assert s["time"] == s["machine_time"] and s["bind_off_time_seconds"] > 0
    assert {r["role"] for r in s["carrier_table"]} == {"waste yarn", "draw thread", "pattern"}
    swg = json.loads(
        write_program(mixed(), tmp_path / "swg", machine="swg091n2")["knit"].read_text()
    )
    assert [r["role"] for r in swg["carrier_table"]] == ["pattern", "pattern"]
    assert swg["needle_range"][0] >= 0 and swg["machine_time"]


def late_mid_row_yarn(units: int = 40) -> LogicalPattern:
    """Cream ground; a red block mid-row in the top two unit rows only (knitted last)."""
    yarn = np.zeros((6, units), int)
    yarn[:2, units // 2 - 3 : units // 2 + 3] = 2
    yarn[2:, :4] = 1
    return LogicalPattern(yarn, np.zeros(yarn.shape, bool), parse_yarns("#f4f0e8,#1b1b1b,#b3202a"))


def test_a_yarn_entering_mid_row_floats_no_further_than_the_limit(tmp_path: Path) -> None:
    from illuknit.knit.hookless import first_directions
    from illuknit.knitout.floats import program_floats
    from illuknit.knitout.parse import parse_knitout

    result = knit_pattern(late_mid_row_yarn(), machine=KNITERATE)
    floats = program_floats(parse_knitout(result.text))
    assert max(f.length for f in floats) <= KNITERATE.float_limit
    assert not check_knitout(result.text).findings
    red = result.schedule.carrier_of_yarn[2][0]
    # its first pass runs in from the edge it entered at, tucking on the way (back needles,
    # then moved to the front by the transfer pass right after)
    first = next(p for p in result.schedule.passes if red in p.carriers)
    assert first.direction == first_directions(result.schedule.steps)[red]
    assert [o.bed for o in first.ops if o.op == "tuck"][:1] == ["b"]
    assert assert_same_as_reference(result.text, tmp_path) is not None


def test_cli_refusal_names_the_course_and_the_options(tmp_path: Path, run_cli) -> None:
    save_pattern(mixed((4, 10), k=5, seed=1), tmp_path / "p.json")
    code, _, err = run_cli(
        ["knit", str(tmp_path / "p.json"), "-o", str(tmp_path / "p.k"), "--machine", "kniterate"]
    )
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "course" in err and "--colors / --yarns" in err and "float_limit" not in err
    assert not (tmp_path / "p.k").exists()


def _kc_passes(kc: str) -> list[tuple[str, str, str, set[str]]]:
    """(pass type, speed, roller advance, stitch numbers of its selected needles) per .kc pass."""
    lines = kc.split("\n")
    out = []
    for i, ln in enumerate(lines):
        if ln.startswith((">>", "<<")):
            _, kind, _, speed, roller = ln.split()
            # turning and carrier marks are inserted into the needle rows, not the stitch rows
            marks = {ord(c): None for c in "/\\123456"}
            rows = {
                r[:5]: r[5:].translate(marks) if r.startswith(("FRNT", "REAR")) else r[5:]
                for r in lines[i - 4 : i]
            }
            picked = {
                num
                for bed, nums in (("FRNT:", "STIF:"), ("REAR:", "STIR:"))
                for ch, num in zip(rows[bed], rows[nums], strict=True)
                if ch not in "._"
            }
            out.append((kind, speed, roller, picked))
    return out


@pytest.mark.parametrize("make", [single, mixed], ids=["single-view", "mixed-2-yarns"])
def test_transfer_passes_carry_the_transfer_settings(make, tmp_path: Path) -> None:
    from dataclasses import replace

    result = knit_pattern(make(), machine=KNITERATE)
    kc = assert_same_as_reference(result.text, tmp_path)
    assert kc is not None
    passes = _kc_passes(kc)
    xs = KNITERATE.transfer
    transfers = [p for p in passes if "T" in p[0] and "Tu" not in p[0]]  # Tr-Rr, Rl-Tr, ...
    knits = [p for p in passes if p[0] == "Kn-Kn" and p[3] - {"0"}]
    assert transfers and knits
    assert all(p[1] == str(xs.speed_number) and p[2] == "0" for p in transfers)
    assert all(p[3] <= {str(xs.stitch_number)} for p in transfers)
    assert all(p[1] == str(KNITERATE.speed_number) for p in knits)
    assert all(p[3] <= {str(KNITERATE.stitch_number)} for p in knits)

    # overridden per run: a roller advance on the first transfer pass of each run, other values
    custom = replace(
        KNITERATE,
        transfer=replace(xs, stitch_number=5, speed_number=150, roller_advance=30),
    )
    result = knit_pattern(make(), machine=custom)
    kc = assert_same_as_reference(result.text, tmp_path)
    assert kc is not None
    transfers = [p for p in _kc_passes(kc) if "T" in p[0] and "Tu" not in p[0]]
    assert {p[1] for p in transfers} == {"150"}
    assert {p[2] for p in transfers} >= {"30"}
    assert set().union(*(p[3] for p in transfers)) == {"5"}


def test_the_waste_section_is_schedule_steps_written_before_the_piece() -> None:
    from illuknit.knit.hookless import waste_knitout, waste_section
    from illuknit.knit.ir import CarrierAction, Pass, Role

    result = knit_pattern(mixed(k=3), machine="kniterate")
    section = waste_section(result.schedule, machine=KNITERATE)
    waste, draw = KNITERATE.waste_carrier, KNITERATE.draw_carrier
    passes = [s for s in section.steps if isinstance(s, Pass)]
    assert passes and all(p.role is Role.WASTE for p in passes)
    ins = [s.carriers for s in section.yarn_in if isinstance(s, CarrierAction)]
    assert ins[:2] == [(waste,), (draw,)] and len(ins) == 2 + len(result.schedule.carrier_of_yarn)
    assert {c for p in passes if p.kind == "knit" for c in p.carriers} == {c for (c,) in ins}
    outs = [s.carriers for s in section.steps if isinstance(s, CarrierAction) and s.action == "out"]
    assert outs == [(waste,), (draw,)]
    lines = waste_knitout(section)
    text = result.text.split("\n")
    start = text.index(lines[0])
    assert text[start : start + len(lines)] == lines


def test_the_library_summary_gives_the_machines_passes_on_every_machine() -> None:
    from illuknit.formats.dat import knitout_to_dat, read_dat
    from illuknit.formats.kc import knitout_to_kc, named_kc

    result = knit_pattern(mixed(), machine="kniterate")
    assert "kc_figures" not in vars(result)  # knit_pattern itself makes no .kc
    s = result.summary()
    kc = knitout_to_kc(result.text, name="piece.kc")
    assert s["passes"] == kc.count("\n>>") + kc.count("\n<<")
    assert s["passes_counted_on"] == "kc" and s["schedule_passes"] < s["passes"]
    assert s["schedule_passes"] == result.stats.passes and "lower_bound" not in s
    assert s["time_seconds"] > 0 and s["time"] != s["schedule_time"]
    # the one .kc, renamed, is what knitout_to_kc writes for that name
    assert named_kc(result.kc_figures.kc, "piece.kc") == kc
    assert machine_sheet(result).summary["machine_passes"] == s["passes"]
    shima = knit_pattern(mixed(), machine="swg091n2")
    assert shima.kc_figures is None and "passes_counted_on" not in shima.summary()
    assert shima.summary()["passes"] == len(read_dat(knitout_to_dat(shima.text)).passes)
