"""Split bumps and tall bumps on the knitting side: lowering, both schedulers, the checker's
bump rules, and the two reference backends (Shima SWG ``.dat``, Kniterate ``.kc``) on tiny
patterns.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.core.pattern import LogicalPattern, Yarn, load_pattern
from illuknit.design.render.params import RenderParams, load_params, save_params
from illuknit.formats.kc import knitout_to_kc
from illuknit.knit.ir import Opcode, Pass, PassKind, Role
from illuknit.knit.options import KnitOptions
from illuknit.knit.schedule import Schedule
from illuknit.knit.stitches import PURL, lower_to_stitches
from illuknit.knitting import knit_pattern
from tests.knit.test_mixed import mixed_patterns, replay

YARNS = (Yarn("cream", (244, 240, 232)), Yarn("dark", (27, 27, 27)), Yarn("red", (200, 16, 46)))

#: one colour per course (stripes), bumps in both colours: the one-colour scheduler
STRIPES = LogicalPattern(
    np.array([[0] * 4, [1] * 4, [0] * 4, [1] * 4]),
    np.array([[1, 0, 1, 0], [0, 1, 0, 1], [1, 1, 0, 0], [0, 0, 1, 1]], dtype=bool),
    YARNS[:2],
)
#: colour changes inside courses: the mixed-colourwork scheduler
_YARN = np.array([[0, 0, 1, 1, 0], [0, 1, 1, 0, 0], [1, 1, 0, 0, 1], [0, 0, 0, 1, 1]])
_RAISED = np.array([[1, 0, 0, 1, 0], [0, 1, 0, 0, 1], [1, 0, 1, 0, 0], [0, 1, 0, 1, 1]], dtype=bool)
MIXED = LogicalPattern(_YARN, _RAISED, YARNS)
#: every bump of MIXED split: view B's colour (the other yarn, red on dark) in its second course
SPLIT = MIXED.replace(upper=np.where(_RAISED, np.where(_YARN == 1, 2, 1), _YARN))


def _tucks_then_knits(schedule: Schedule) -> None:
    """After a carrier's passes of back-bed tucks (tall bumps; float tucks on free back needles
    ride in knit passes), its next knit pass knits those needles (the purls that clear them),
    and no transfer moves them in between."""
    steps = [s for s in schedule.steps if isinstance(s, Pass)]
    pending: dict[tuple[str, ...], set[int]] = {}
    for i, p in enumerate(steps):
        if p.kind is PassKind.XFER:
            moved = {o.needle for o in p.ops}
            assert not any(moved & t for t in pending.values())
            continue
        made = [o for o in p.ops if o.op is not Opcode.MISS]
        back_tucks = {o.needle for o in made if o.op is Opcode.TUCK and o.bed == "b"}
        if made and len(back_tucks) == len(made):
            # (Tucks that cut the float into the pass go to the front in the transfer pass
            # right after it: float tucks, not the bumps'.)
            nxt = steps[i + 1] if i + 1 < len(steps) else None
            if nxt is not None and nxt.kind is PassKind.XFER and nxt.role is Role.FLOAT_AVOIDANCE:
                back_tucks -= {o.needle for o in nxt.ops if o.bed == "b"}
            pending.setdefault(p.carriers, set()).update(back_tucks)
        elif made and p.carriers in pending:
            purled = {o.needle for o in made if o.op is Opcode.KNIT and o.bed == "b"}
            assert pending.pop(p.carriers) <= purled
    assert not pending


def test_lowering_split_and_tall_bumps() -> None:
    plain = lower_to_stitches(MIXED)
    assert plain.tuck_first is None
    split = lower_to_stitches(SPLIT)
    assert np.array_equal(split.kind, plain.kind)
    assert np.array_equal(split.yarn[0::2], plain.yarn[0::2])  # first courses: `yarn`
    upper = np.repeat(np.repeat(SPLIT.upper_yarn[::-1], 2, axis=0), 2, axis=1)[1::2]
    assert np.array_equal(split.yarn[1::2], upper)  # second courses: `upper`
    assert (split.yarn != plain.yarn).sum() == 2 * SPLIT.split.sum()
    tall = lower_to_stitches(MIXED, tall_bumps=True)
    assert tall.tuck_first is not None
    assert np.array_equal(tall.tuck_first, tall.kind == PURL)
    flat = LogicalPattern(np.zeros((2, 2), int), np.zeros((2, 2), bool), YARNS[:1])
    assert lower_to_stitches(flat, tall_bumps=True).tuck_first is None  # no bump, no tuck


def test_tall_bumps_one_colour_per_course_cost_one_pass_per_purl_course() -> None:
    plain, tall = knit_pattern(STRIPES), knit_pattern(STRIPES, tall_bumps=True)
    purl_courses = int((tall.stitches.kind == PURL).any(axis=1).sum())
    assert tall.schedule.stats.passes == plain.schedule.stats.passes + purl_courses
    assert tall.schedule.stats.lower_bound == tall.schedule.stats.passes  # meets the bound
    assert tall.schedule.stats.kickbacks == 0
    assert tall.summary()["tall_bump_tucks"] == int((tall.stitches.kind == PURL).sum())
    assert "tall_bump_tucks" not in plain.summary()
    _tucks_then_knits(tall.schedule)
    assert check_knitout(tall.program).findings == ()


@pytest.mark.parametrize("machine", ["swg091n2", "kniterate"])
@pytest.mark.parametrize("pattern", ["mixed", "split"])
def test_mixed_colourwork_tall_and_split_bumps_are_clean(pattern: str, machine: str) -> None:
    p = SPLIT if pattern == "split" else MIXED
    result = knit_pattern(p, machine=machine, options=KnitOptions(tall_bumps=True))
    assert result.split_bumps == int(p.split.sum())
    _tucks_then_knits(result.schedule)
    report = check_knitout(result.program, machine=machine, split_bumps=result.split_bumps > 0)
    assert report.findings == (), [f"{f.line}: {f.code}" for f in report.findings[:5]]
    assert report.pieces == 1


def test_the_float_into_a_tall_bump_tuck_pass_is_tucked(
    tmp_path: Path, swg_backend: Path, kniterate_backend: Path
) -> None:
    # One unit row, 13 units: dark knits the two units at the right in the first course and
    # the split bump's upper course at the left edge in the second. Parked left of the fabric,
    # it comes back to just beside its last loop and its tall-bump tuck pass lays the float
    # from there to the bump, 21 needles: float tucks in that tuck pass cut it, on both
    # machines (it was refused as a long float).
    yarn = np.array([[0] * 11 + [1] * 2])
    raised = np.array([[1, 0, 0, 0, 0] + [1] * 8], dtype=bool)
    p = LogicalPattern(yarn, raised, YARNS[:2], upper=np.where(np.arange(13) == 0, 1, yarn))
    for machine, backend, suffix in (
        ("swg091n2", swg_backend, ".dat"),
        ("kniterate", kniterate_backend, ".kc"),
    ):
        result = knit_pattern(p, machine=machine, tall_bumps=True)
        assert result.schedule.long_floats == ()
        _tucks_then_knits(result.schedule)
        report = check_knitout(result.program, machine=machine, split_bumps=True)
        assert report.findings == (), [f"{f.line}: {f.code}" for f in report.findings[:5]]
        _run(backend, result.program, tmp_path, suffix)


def test_split_bumps_are_declared_and_the_checker_reads_them() -> None:
    # the program declares its split bumps (illuknit.knitout.bumps): one verdict, no flag
    result = knit_pattern(SPLIT)
    assert check_knitout(result.program).ok
    assert check_knitout(result.program, split_bumps=True).ok
    # told otherwise, the checker finds each purl of each split bump
    codes = check_knitout(result.program, split_bumps=False).codes()
    assert codes["bump-yarn-change"] == 2 * int(SPLIT.split.sum())
    assert "split_bumps" not in knit_pattern(MIXED).summary()


def test_plain_patterns_knit_as_before() -> None:
    # the option off and no `upper`: the same program as the stitches without the new fields
    for p in (STRIPES, MIXED):
        assert knit_pattern(p).program == knit_pattern(p, tall_bumps=False).program
        assert "tuck" not in {
            o.op
            for s in knit_pattern(p).schedule.steps
            if isinstance(s, Pass)
            for o in s.ops
            if o.bed == "b"
        }


def _run(backend: Path, program: str, tmp_path: Path, suffix: str) -> Path:
    k, out = tmp_path / "p.k", tmp_path / f"p{suffix}"
    k.write_text(program)
    proc = subprocess.run(
        ["node", str(backend), str(k), str(out)], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 0 and out.exists(), proc.stderr + proc.stdout
    assert "assert" not in (proc.stderr + proc.stdout).lower()
    return out


def test_reference_backends_accept_tall_and_split_bumps(
    tmp_path: Path, swg_backend: Path, kniterate_backend: Path
) -> None:
    # Split bumps with tall bumps: the richest structure, on a Shima and on the Kniterate.
    swg = knit_pattern(SPLIT, machine="swg091n2", tall_bumps=True)
    _run(swg_backend, swg.program, tmp_path, ".dat")
    plain = knit_pattern(SPLIT, machine="kniterate")
    tall = knit_pattern(SPLIT, machine="kniterate", tall_bumps=True)
    kc = _run(kniterate_backend, tall.program, tmp_path, ".kc").read_text()
    # ours is byte-identical to the backend's but for line 3 (the file name)
    ours = knitout_to_kc(tall.program, name="p.kc")
    assert ours.splitlines()[3:] == kc.splitlines()[3:]
    # the machine runs the tall bumps' tucks in passes of their own (tuck passes: "Tu-Tu")
    extra = knitout_to_kc(tall.program, name="p").count("Tu-Tu") - knitout_to_kc(
        plain.program, name="p"
    ).count("Tu-Tu")
    assert extra >= int((tall.stitches.kind == PURL).any(axis=1).sum())


def test_the_simulator_runs_tall_split_bumps() -> None:
    pytest.importorskip("knitout_interpreter")
    result = knit_pattern(SPLIT, tall_bumps=True)
    report = check_knitout(result.program, split_bumps=True, simulate=True)
    assert report.vm is not None and report.vm["pieces"] == 1
    assert report.findings == (), [f"{f.line}: {f.code}" for f in report.findings[:5]]


@settings(max_examples=12, deadline=None)
@given(mixed_patterns(max_rows=3, max_cols=5), st.data())
def test_random_tall_split_bumps_are_clean_and_every_stitch_made_once(
    pattern: LogicalPattern, data: st.DataObject
) -> None:
    k = len(pattern.yarns)
    n, m = pattern.shape
    upper = np.array(data.draw(st.lists(st.integers(0, k - 1), min_size=n * m, max_size=n * m)))
    p = pattern.replace(upper=np.where(pattern.raised, upper.reshape(n, m), pattern.yarn))
    tall = bool(data.draw(st.booleans()))
    result = knit_pattern(p, tall_bumps=tall, allow_long_floats=True)
    if result.stitches.mixed_courses().size:
        replay(result.schedule, result.stitches)
    _tucks_then_knits(result.schedule)
    report = check_knitout(result.program, split_bumps=bool(p.split.any()))
    assert report.ok and report.pieces == 1, [f"{f.line}: {f.code}" for f in report.blocking[:5]]
    assert "tuck-not-cleared" not in report.codes()


def test_calibration_swatch_of_tall_and_split_bumps_and_its_fit(tmp_path: Path, run_cli) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "swatch"
    args = ["calibrate", "swatch", "-o", str(out), "--bump-sizes", "1", "--flat-sizes", "1,2"]
    code, _, err = run_cli(
        [*args, "--cell-width", "3", "--knitout", "--split-bumps", "--tall-bumps"]
    )
    assert code == 0, err
    swatch = load_pattern(out / "swatch.json")
    r0, r1 = swatch.meta["split_band"]["rows"]
    assert swatch.split[r0:r1].any() and int(swatch.split.sum()) == int(swatch.split[r0:r1].sum())
    knit = json.loads((out / "knit.json").read_text())
    assert knit["split_bumps"] == int(swatch.split.sum())
    assert knit["tall_bump_tucks"] == 2 * int(swatch.raised.sum())  # one per wale of a bump
    assert json.loads((out / "check.json").read_text())["ok"]
    # the tall swatch's fit sets tall_bump_height and keeps the plain bump height
    plain = tmp_path / "plain.json"
    save_params(RenderParams(), plain)
    csv = tmp_path / "m.csv"
    csv.write_text("bump_rows,flat_rows,angle_deg\n1,1,45\n1,2,27\n")
    fitted = tmp_path / "p.json"
    code, _, err = run_cli(
        ["calibrate", "fit", str(csv), "--tall-bumps", "--params", str(plain), "-o", str(fitted)]
    )
    assert code == 0, err
    p = load_params(fitted)
    assert p.bump_height == RenderParams().bump_height
    assert p.tall_bump_height is not None and p.tall_bump_height > p.bump_height


def test_tall_bump_tucks_far_apart_catch_their_float_on_knit_needles() -> None:
    # one colour, bumps 28 units apart: the tuck pass would float 56 needles; it tucks front
    # needles of the course's knits in between instead, which the knit pass then knits through
    raised = np.zeros((2, 30), dtype=bool)
    raised[0, [0, 29]] = True
    p = LogicalPattern(np.zeros((2, 30), int), raised, YARNS[:1])
    result = knit_pattern(p, tall_bumps=True)
    report = check_knitout(result.program)
    assert report.findings == (), [f"{f.line}: {f.code}" for f in report.findings[:3]]
    tucks = [
        s
        for s in result.schedule.steps
        if isinstance(s, Pass)
        and {o.op for o in s.ops} == {Opcode.TUCK, Opcode.MISS}
        and s.course is not None
    ]
    assert len(tucks) == 1 and {o.bed for o in tucks[0].ops if o.op is Opcode.TUCK} == {"f", "b"}
    _tucks_then_knits(result.schedule)
