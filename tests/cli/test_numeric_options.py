"""Every numeric option of every command is finite and bounded where it is parsed (issue 34, 5).

A fuzz over the whole command line: every numeric option of every command, given ``nan``,
``inf``, ``1e308``, a 30-digit number and the like, is one error line naming the option, exit code
2, before any work starts. The machine parameters (``--xfer-*``, ``--machine-width``,
``--bed-width``) get their ranges from the machine's range table (another change); for them
only the absence of a traceback is checked here.
"""

from __future__ import annotations

import click
import pytest

from illuknit.cli.options import LARGEST, FiniteFloat

from .test_files_inputs import leaf_commands

#: Options whose ranges come from the machine parameter table, not from this file's types.
MACHINE_PARAMETERS = {
    "--xfer-stitch",
    "--xfer-speed",
    "--xfer-roller",
    "--machine-width",
    "--bed-width",
}

ABSURD = [
    "nan",
    "-nan",
    "inf",
    "-inf",
    "Infinity",
    "1e308",
    "-1e308",
    "1e400",
    "1e25",
    "-1e25",
    "1" + "0" * 29,  # 30 digits
    "-" + "9" * 30,
    str(10**25),
]


def numeric_options() -> list[tuple[str, str]]:
    """(command, option) for every numeric option of every command."""
    out = []
    for name, cmd in leaf_commands().items():
        for p in cmd.params:
            if isinstance(p, click.Option) and isinstance(p.type, click.types._NumberParamTypeBase):
                out.append((name, max(p.opts, key=len)))
    return out


def test_there_are_numeric_options_to_fuzz():
    options = numeric_options()
    assert len(options) > 40
    assert ("knit", "--seconds-per-turn") in options and ("calibrate time", "--minutes") in options


def test_every_numeric_option_has_a_finite_range():
    """Unbounded types (click.INT, an IntRange without a maximum) would let 10**25 through."""
    for name, cmd in leaf_commands().items():
        for p in cmd.params:
            t = p.type
            opt = max(p.opts, key=len)
            if not isinstance(t, click.types._NumberParamTypeBase) or opt in MACHINE_PARAMETERS:
                continue
            if isinstance(t, FiniteFloat):
                continue  # at most LARGEST in size, whatever its range
            assert isinstance(t, click.IntRange), (name, opt, t)
            assert t.min is not None and t.max is not None, (name, opt)


def test_every_numeric_option_refuses_absurd_values(run_cli, tmp_path, monkeypatch):
    """The whole command line in-process: an option refused where it is parsed stops the run
    before any work (the machine parameters, not refused here yet, are only converted)."""
    monkeypatch.chdir(tmp_path)
    raw, accepted, runs = [], [], 0
    for command, option in numeric_options():
        for value in ABSURD:
            runs += 1
            if option in MACHINE_PARAMETERS:
                param = next(p for p in leaf_commands()[command].params if option in p.opts)
                try:
                    param.type.convert(value, param, None)
                except click.BadParameter:
                    pass
                except Exception as e:  # a raw exception
                    raw.append((command, option, value, repr(e)))
                continue
            r = run_cli([*command.split(), option, value])
            lines = r.err.strip().splitlines()
            if "Traceback" in r.err or r.code != 2 or len(lines) != 1:
                raw.append((command, option, value, r.code, r.err[-300:]))
            elif option not in lines[0]:
                accepted.append((command, option, value, lines[0]))
    print(f"{runs} runs: {len(raw)} raw exceptions, {len(accepted)} absurd values accepted")
    assert not raw, raw[:5]
    assert not accepted, accepted[:5]


@pytest.mark.parametrize(
    "argv",
    [
        ["knit", "p.json", "-o", "x.k", "--seconds-per-turn", "1e308"],
        ["knit", "p.json", "-o", "x.k", "--seconds-per-needle", "nan"],
        ["calibrate", "time", "prog.k", "--minutes", "1e308", "-o", "m.json"],
        ["solve", "a.png", "--max-color-changes", str(10**25)],
        ["solve", "a.png", "--time-limit", "inf"],
        ["bench", "--jobs", "1" + "0" * 29],
    ],
)
def test_the_issue_cases_are_one_line(argv, run_cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    r = run_cli(argv)
    lines = r.err.strip().splitlines()
    assert r.code == 2 and len(lines) == 1 and "Traceback" not in r.err, r
    option = next(a for a in argv if a.startswith("--") and a != "--model")
    assert f"Invalid value for '{option}'" in lines[0], lines[0]


def test_a_float_without_a_range_is_bounded_by_largest():
    t = FiniteFloat()
    assert t.convert("1e12", None, None) == LARGEST
    for value in ("1.0000001e12", "-1e13", "nan", "inf"):
        with pytest.raises(click.BadParameter):
            t.convert(value, None, None)
