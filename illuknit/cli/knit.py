"""``illuknit knit``: compile a saved pattern to a knitout program and check it."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from illuknit.cli.knitout_bridge import long_floats_option, machine_option
from illuknit.cli.options import (
    GAUGE,
    NEEDLES,
    PASS_SECONDS,
    InputFile,
    OutputFile,
    declared_option,
)
from illuknit.core.progress import run_with_bar
from illuknit.knit.options import KnitOptions

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec

__all__ = ["KnitMachine", "knit", "run_knit"]


@dataclass(frozen=True)
class KnitMachine:
    """The machine ``illuknit knit`` knits on, as its switches name it: a preset name (or a
    spec) and what overrides the preset's values.

    Attributes
    ----------
    machine : str or MachineSpec, optional
        The preset (default machine when None).
    gauge : float, optional
        Needles per inch.
    machine_width : int, optional
        Needles per bed.
    seconds_per_needle, seconds_per_turn : float, optional
        A linear time model of the user's own instead of the carriage speeds (the other one 0
        when only one is given).
    float_limit : int, optional
        The longest float, in needles skipped.
    """

    machine: str | MachineSpec | None = None
    gauge: float | None = None
    machine_width: int | None = None
    seconds_per_needle: float | None = None
    seconds_per_turn: float | None = None
    float_limit: int | None = None


def run_knit(
    pattern_path: str | Path,
    output: str | Path,
    *,
    machine: KnitMachine | str | MachineSpec | None = None,
    options: KnitOptions | None = None,
    check: bool = True,
    output_format: str = "knitout",
) -> dict[str, Any]:
    """Compile ``pattern_path`` to knitout (or a machine file: ``output_format="dat"``) at
    ``output``; return the summary (and checker verdict).

    ``machine`` is a preset name, a spec, or a :class:`KnitMachine` whose gauge, width, time
    model and float limit override its preset's values. A pattern wider than the bed is refused
    before compiling; nothing is written when compilation fails. ``output_format`` is
    ``knitout`` or a machine file the machine takes (``kc`` for the Kniterate). ``options``
    says how to knit (:class:`~illuknit.knit.options.KnitOptions`): a float that stays longer
    than the float limit is refused (:class:`~illuknit.core.errors.LongFloatError`) unless
    ``options.allow_long_floats``, which keeps it with a
    :class:`~illuknit.knitting.pipeline.LongFloatWarning`.
    """
    import warnings
    from dataclasses import replace

    from illuknit.cli.knitout_bridge import check_fits, resolve_machine
    from illuknit.core.errors import LongFloatError
    from illuknit.core.files import STDOUT, write_output_file
    from illuknit.core.machine import BedFitWarning
    from illuknit.core.pattern import load_pattern
    from illuknit.formats import check_format, knitout_to_format
    from illuknit.knitting import knit_pattern
    from illuknit.outputs.machine_sheet import machine_headline, machine_sheet

    m = machine if isinstance(machine, KnitMachine) else KnitMachine(machine)
    spec = resolve_machine(m.machine, gauge=m.gauge)
    check_format(spec, output_format)
    if m.machine_width is not None:
        spec = spec.with_width(m.machine_width)
    pattern = load_pattern(pattern_path)
    check_fits(spec, pattern.shape[1], hint="use a narrower pattern or a wider --machine-width")
    note = spec.fit_note(pattern.shape[1])  # it fits this bed, but maybe no real machine's
    if note is not None:
        warnings.warn(note, BedFitWarning, stacklevel=2)  # one `illuknit: note:` line
    changes: dict[str, Any] = {}
    if m.seconds_per_needle is not None or m.seconds_per_turn is not None:
        # a linear model of the user's own instead of the carriage speeds
        changes["seconds_per_needle"] = m.seconds_per_needle or 0.0
        changes["seconds_per_turn"] = m.seconds_per_turn or 0.0
    if m.float_limit is not None:
        changes["float_limit"] = m.float_limit
    if changes:
        spec = replace(spec, **changes)
    try:
        result = knit_pattern(pattern, machine=spec, options=options)
    except LongFloatError as e:
        from illuknit.knitting.remedies import knit_refusal

        # the remedies measured on this pattern, not guessed
        raise knit_refusal(
            pattern, e, machine=spec, options=options, pattern_file=str(pattern_path)
        ).error from None
    summary = result.summary()
    if check:
        from illuknit.check import check_knitout

        report = check_knitout(result.knitout, machine=spec)  # it declares its bumps
        summary["check"] = {
            "errors": report.n_blocking,
            "warnings": report.n_warnings,
            "pieces": report.pieces,
            "findings": [
                {"line": f.line, "code": f.code, "severity": f.severity, "message": f.message}
                for f in report.findings[:20]
            ],
        }
    name = "program" if str(output) == STDOUT else Path(output).name
    sheet = machine_sheet(result, name=name)
    # the headline passes and time are the machine's (the .kc's on the Kniterate)
    summary = machine_headline(summary, sheet)
    if output_format in sheet.files:  # made for the sheet already (the .kc)
        data = sheet.files[output_format].encode("utf-8")
    else:
        data = knitout_to_format(result.knitout, output_format, name=name)
    summary["output"] = write_output_file(output, data)
    summary["format"] = output_format
    return summary


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("pattern", type=InputFile("pattern"))
@click.option(
    "-o",
    "--output",
    required=True,
    type=OutputFile(allow_dash=True),
    help="File to write: knitout (e.g. prog.k) or, with --format dat, a Shima .dat; - for "
    "standard output (the summary then goes to standard error).",
)
@machine_option()
@click.option(
    "--gauge",
    type=GAUGE,
    default=None,
    help="Needles per inch [the machine's, 7].",
)
@click.option(
    "--machine-width",
    type=click.IntRange(min=8),
    default=None,
    help="Needles per bed [the machine's: 540 for generic540, 252 for swg091n2]; 8-2000 "
    "(at most 252 on the Kniterate). Any width but the real machine's is a generic bed with "
    "the preset's rules.",
)
@declared_option(KnitOptions, "cast_on_courses")
@click.option(
    "--seconds-per-needle",
    type=PASS_SECONDS,
    default=None,
    help="A linear time model instead of the machine's carriage speeds: seconds per needle "
    "crossed (with --seconds-per-turn; the other one 0 when not given).",
)
@click.option(
    "--seconds-per-turn",
    type=PASS_SECONDS,
    default=None,
    help="A linear time model instead of the machine's: fixed seconds per carriage pass "
    "(with --seconds-per-needle).",
)
@click.option(
    "--float-limit",
    type=NEEDLES,
    default=None,
    help="Longest yarn float for mixed colourwork, in needles skipped [the machine's, 20].",
)
@declared_option(KnitOptions, "strict_floats")
@long_floats_option(expose_value=True)
@declared_option(KnitOptions, "tuck_passes")
@declared_option(KnitOptions, "tall_bumps")
@click.option(
    "--float-avoidance",
    "float_avoidance_on",
    is_flag=True,
    help="Move purls to the front around floats that cross them (the default).",
)
@click.option(
    "--no-float-avoidance",
    is_flag=True,
    help="Ablation (paper Fig. 20): let floats cross the face of the purls.",
)
@click.option(
    "--catching",
    "catching_on",
    is_flag=True,
    help="Join colour regions at colour changes (the default: tuck joins).",
)
@click.option(
    "--plate",
    is_flag=True,
    help="Join colour regions with the paper's plated stitches (Algorithm 2) instead of tuck "
    "joins (more passes, longer floats).",
)
@click.option(
    "--no-catching",
    is_flag=True,
    help="Ablation (paper Fig. 20): nothing joins colour regions.",
)
@declared_option(KnitOptions, "catch_every")
@click.option(
    "--path-planning",
    "path_planning",
    type=click.Choice(["anchor", "split", "none"]),
    multiple=True,
    help="Yarn path strategy (paper Algorithm 3) [anchor]; 'none' is the Fig. 20 ablation.",
)
@click.option(
    "--format",
    "output_format",
    type=click.Choice(["knitout", "dat", "kc"]),
    default="knitout",
    show_default=True,
    help="What -o holds: knitout, a Shima .dat (dat; Shima machines) or the Kniterate's "
    "k-code (kc, with --machine kniterate).",
)
@click.option("--no-check", is_flag=True, help="Skip the knitout checker.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
def knit(
    pattern: Path,
    output: Path,
    machine: str | None,
    gauge: float | None,
    machine_width: int | None,
    cast_on_courses: int,
    seconds_per_needle: float | None,
    seconds_per_turn: float | None,
    float_limit: int | None,
    strict_floats: bool,
    allow_long_floats: bool,
    tuck_passes: bool,
    tall_bumps: bool,
    float_avoidance_on: bool,
    no_float_avoidance: bool,
    catching_on: bool,
    plate: bool,
    no_catching: bool,
    catch_every: int,
    path_planning: tuple[str, ...],
    output_format: str,
    no_check: bool,
    as_json: bool,
) -> None:
    """Compile a saved PATTERN (JSON) to a knitout program for a V-bed machine.

    Prints carriage passes, their lower bound, the estimated knitting time and the checker's
    verdict. Patterns that change colour inside a course go through the mixed-colourwork
    scheduler (float avoidance, catching, yarn path planning; the --no-... and --path-planning
    none switches are the paper's Fig. 20 ablations). Exit code 1 when the checker finds a
    blocking problem, 2 on bad input.
    """
    summary = run_with_bar(
        "knit",
        "scheduling, writing and checking the program",
        run_knit,
        pattern,
        output,
        options=_knit_options(
            cast_on_courses=cast_on_courses,
            strict_floats=strict_floats,
            allow_long_floats=allow_long_floats,
            tuck_passes=tuck_passes,
            tall_bumps=tall_bumps,
            float_avoidance_on=float_avoidance_on,
            no_float_avoidance=no_float_avoidance,
            catching_on=catching_on,
            plate=plate,
            no_catching=no_catching,
            catch_every=catch_every,
            path_planning=path_planning,
        ),
        machine=KnitMachine(
            machine, gauge, machine_width, seconds_per_needle, seconds_per_turn, float_limit
        ),
        check=not no_check,
        output_format=output_format,
    )
    echo = partial(click.echo, err=str(output) == "-")  # (stdout may hold the program)
    if as_json:
        echo(json.dumps(summary, indent=1))
    else:
        _echo_summary(summary, output_format, echo)
    chk = summary.get("check")
    if chk and chk["errors"]:
        raise click.exceptions.Exit(1)


def time_line(s: dict[str, Any]) -> str:
    """One line: the estimated time, its range and the bind-off's part of it."""
    basis = "calibrated" if "calibrated on" in s["time_model"] else "preset's"
    check = f", {s['time_check']}" if "time_check" in s else ""
    return (
        f"estimated knitting time: {s['time']}, of which the bind-off {s['bind_off_time']}; "
        f"the model's range {s['time_range']} at the {basis} carriage speeds{check}; "
        "docs/knitting.md, Time model"
    )


def _echo_summary(s: dict[str, Any], output_format: str, echo: Callable[[str], object]) -> None:
    """The summary for a reader: what was written, size, passes, time, sheet, the checker's
    verdict."""
    what = f"{s['lines']} lines" if output_format == "knitout" else f"{output_format} file"
    echo(f"wrote {s['output']} ({what}) for {s['machine']}")
    echo(f"stitches: {s['wales']} wales x {s['courses']} courses at gauge {s['gauge']:g}")
    echo(
        f"finished size: about {s['finished_size_text']} at "
        f"{s['finished_size']['gauge']} ({s['finished_size']['gauge_source']})"
    )
    from illuknit.knitting.pipeline import passes_text

    if s.get("passes_counted_on") == "kc":
        echo(f"{passes_text(s)}; the schedule's lower bound {s['schedule_lower_bound']}")
    else:
        echo(f"{passes_text(s)}; lower bound {s['lower_bound']}, ratio {s['ratio']:.2f}")
    if s.get("scheduler") == "mixed-colourwork":
        echo(
            f"mixed colourwork: {s['carriers']} carrier(s), {s['tuck_joins']} tuck join(s), "
            f"{s['plated_stitches']} plated catching stitch(es), "
            f"{s['explicit_kickbacks']} carrier move pass(es), "
            f"{s['float_avoidance_transfers']} float-avoidance transfer pass(es), "
            f"{s['kickbacks']} backend kickback(s)"
        )
    echo(time_line(s))
    if "bumps" in s:
        echo(f"bumps: {s['bumps']}; illuknit check reads it")
    _echo_machine_sheet(s, echo)
    chk = s.get("check", False)
    if chk is None:
        echo("check: checker not available in this install")
    elif chk:
        echo(
            f"check: {chk['errors']} error(s), {chk['warnings']} warning(s), {chk['pieces']} piece(s)"
        )
        for f in chk["findings"][:10]:
            echo(f"  line {f['line']}: {f['severity']} [{f['code']}] {f['message']}")


def describe_settings(s: dict[str, Any]) -> str:
    """One line: the knit and transfer passes' stitch, speed and roller settings, with the source."""

    def v(x: object) -> str:
        return "machine's own" if x is None else str(x)

    k, t = s["knit_settings"], s["transfer_settings"]
    roller = (
        ""
        if t["roller_advance"] is None
        else f", roller advance {t['roller_advance']} on the first of a run, 0 after"
    )
    return (
        f"knit passes: stitch {v(k['stitch_number'])}, speed {v(k['speed_number'])}; "
        f"transfer passes: stitch {v(t['stitch_number'])}, speed {v(t['speed_number'])}"
        f"{roller} ({t['source']})"
    )


def _echo_machine_sheet(s: dict[str, Any], echo: Callable[[str], object] = click.echo) -> None:
    """What the machine knitter sets up: cones on carriers, stitch numbers, needles, time."""
    echo(
        f"on the {s['machine']}: {s['machine_passes']} passes, about {s['machine_time']} "
        f"(the model's range {s['machine_time_range']})"
    )
    for row in s["carrier_table"]:
        echo(f"  carrier {row['carrier']}: {row['yarn']} ({row['role']})")
    numbers = ", ".join(map(str, s["stitch_numbers"])) or "machine default"
    lo, hi = s["needle_range"]
    echo(f"  stitch numbers: {numbers}; needles {lo}..{hi}")
    if "floats" in s:
        echo(f"  floats: {s['floats']}")
    echo("  " + describe_settings(s))


def _knit_options(**switches: Any) -> KnitOptions:
    """The knitting options the switches of ``illuknit knit`` ask for (contradictions refused)."""
    from illuknit.knit.options import Catching, PathPlanning

    s = {"tall_bumps": False, **switches}
    strict_floats, allow_long_floats = s["strict_floats"], s["allow_long_floats"]
    no_catching, plate, path_planning = s["no_catching"], s["plate"], s["path_planning"]
    no_float_avoidance = s["no_float_avoidance"]
    if strict_floats and allow_long_floats:
        raise click.UsageError("--strict-floats and --allow-long-floats contradict each other")
    if s["float_avoidance_on"] and no_float_avoidance:
        raise click.UsageError("--float-avoidance and --no-float-avoidance contradict each other")
    if (s["catching_on"] or plate) and no_catching:
        what = "--plate" if plate else "--catching"
        raise click.UsageError(f"{what} and --no-catching contradict each other")
    if len(set(path_planning)) > 1:
        raise click.UsageError(
            f"--path-planning given contradictory values: {', '.join(sorted(set(path_planning)))}"
        )
    return KnitOptions(
        cast_on_courses=s["cast_on_courses"],
        strict_floats=strict_floats,
        allow_long_floats=allow_long_floats,
        tuck_passes=s["tuck_passes"],
        tall_bumps=s["tall_bumps"],
        float_avoidance=not no_float_avoidance,
        catching=Catching.OFF if no_catching else (Catching.PLATE if plate else Catching.TUCK),
        catch_every=s["catch_every"],
        path_planning=PathPlanning(path_planning[0] if path_planning else "anchor"),
    )
