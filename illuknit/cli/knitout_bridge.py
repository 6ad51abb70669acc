"""Writing a knitout program next to a pattern's other outputs (``--knitout`` of the commands).

One machine for the whole path: the ``--machine`` option (:func:`machine_option`) names a preset
of :data:`illuknit.core.machine.MACHINES`; :func:`resolve_machine` turns it (and a ``--gauge``)
into the :class:`~illuknit.core.machine.MachineSpec` that sizes the picture, refuses a pattern too
wide for the bed before any design work (:func:`check_fits`), schedules the program and checks it.

The ``--format`` option (:func:`format_option`) asks for machine files beside ``program.k``
(``--format dat`` writes ``program.dat``); :func:`resolve_machine` refuses a format the machine
cannot take, or one asked for without ``--knitout``, before any work is done.

One long-float policy (:func:`long_floats_option`): a float that stays longer than the machine's
float limit after tucking stops the command with one line naming the course and the remedies
that were tried and knit it (exit code 2); the design commands still write the pattern folder,
all but the program, with :data:`REFUSAL_NOTE` saying why. ``--allow-long-floats`` writes the
program anyway, with one ``illuknit: warning:`` line saying how long the longest float is and
where.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import click

from illuknit.core.declared import declared_options
from illuknit.core.errors import LongFloatError
from illuknit.core.files import atomic_write_text
from illuknit.core.machine import DEFAULT_MACHINE_NAME, MachineSpec, machine_names
from illuknit.core.machine import resolve_machine as machine_spec
from illuknit.core.pattern import LogicalPattern
from illuknit.knit.options import KnitOptions
from illuknit.outputs.hand_pattern import MAX_BORDER_UNITS

__all__ = [
    "REFUSAL_NOTE",
    "check_fits",
    "design_unit_aspect",
    "format_option",
    "long_floats_allowed",
    "long_floats_option",
    "machine_option",
    "requested_formats",
    "resolve_machine",
    "transfer_overrides",
    "write_program",
]

#: The note a design folder holds instead of ``program.k`` when the knitting was refused.
REFUSAL_NOTE = "program-refused.txt"

#: where the ``--format`` choices of the running command are kept (click context meta)
_FORMATS_KEY = "illuknit.machine_files"
#: where the running command's ``--allow-long-floats`` is kept (click context meta)
_LONG_FLOATS_KEY = "illuknit.allow_long_floats"
#: where the running command's ``--xfer-*`` transfer settings are kept (click context meta)
_TRANSFER_KEY = "illuknit.transfer"
#: where the running command's ``--fabric-gauge`` / ``--square-units`` are kept
_FABRIC_KEY = "illuknit.fabric"

LONG_FLOATS_HELP = declared_options(KnitOptions)["allow_long_floats"].declared.help


def machine_option(
    help: str = "Knitting machine the program is made for.", *, transfer: bool = True
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``--machine NAME``: a machine preset (unknown names are refused with the known ones).

    With ``transfer`` (commands that knit) also ``--xfer-stitch``, ``--xfer-speed`` and
    ``--xfer-roller``: the transfer passes' settings over the preset's
    (:class:`~illuknit.core.machine.TransferSettings`), kept on the click context where
    :func:`resolve_machine` applies them.
    """
    machine = click.option(
        "--machine",
        "machine",
        metavar="NAME",
        default=None,
        help=f"{help} One of {', '.join(machine_names())} [{DEFAULT_MACHINE_NAME}], or a "
        "machine file (FILE.json) from `illuknit calibrate time`.",
    )
    if not transfer:
        return machine

    def remember(ctx: click.Context, param: click.Parameter, value: int | None) -> None:
        if value is not None:
            ctx.meta.setdefault(_TRANSFER_KEY, {})[str(param.name)] = value

    flags = [
        (
            "--xfer-stitch",
            "stitch_number",
            click.IntRange(0, 35),
            "Stitch number of transfer "
            "passes (Kniterate x-xfer-stitch-number, 0-35 for 0-9/A-Z) [the machine's: 3 on the "
            "Kniterate].",
        ),
        (
            "--xfer-speed",
            "speed_number",
            click.IntRange(min=0),
            "Speed number of transfer passes "
            "(x-speed-number; 0-15 on a Shima, 0-600 on the Kniterate) [the machine's: 100 on "
            "the Kniterate, the machine's own table on a Shima].",
        ),
        (
            "--xfer-roller",
            "roller_advance",
            click.IntRange(min=0),
            "Kniterate roller advance on the first transfer pass of each run of transfers "
            "(0-1000) [0].",
        ),
    ]

    def remember_fabric(ctx: click.Context, param: click.Parameter, value: Any) -> None:
        if value not in (None, False):
            ctx.meta.setdefault(_FABRIC_KEY, {})[str(param.name)] = value

    options = [
        click.option(
            "--fabric-gauge",
            "fabric_gauge",
            metavar="SxR/LEN",
            default=None,
            expose_value=False,
            callback=remember_fabric,
            help="Stitch and row gauge of the finished fabric, e.g. 22x30/10cm or 5.5x7.5/in "
            "(measure a swatch): sizes the grid so the piece keeps the picture's proportions, "
            "and the finished size [the machine's: one stitch per needle, rows at 5:7].",
        ),
        click.option(
            "--chart",
            "chart",
            type=click.Choice(["units", "stitches"]),
            default=None,
            expose_value=False,
            callback=remember_fabric,
            help="What a square of pattern.pdf's chart is: a ridge unit of 2 stitches x 2 rows "
            "(fewer pages, as bought illusion charts) or one stitch [units].",
        ),
        _border_option(remember_fabric),
        click.option(
            "--square-units",
            "square_units",
            is_flag=True,
            expose_value=False,
            callback=remember_fabric,
            help="Size the grid with square units (as many rows as the picture is tall): the "
            "finished piece comes out shorter than the picture by the gauge's ratio.",
        ),
    ] + [
        click.option(
            flag, name, type=kind, default=None, expose_value=False, callback=remember, help=text
        )
        for flag, name, kind, text in flags
    ]

    def decorate(func: Callable[..., Any]) -> Callable[..., Any]:
        for opt in reversed(options):
            func = opt(func)
        return machine(func)

    return decorate


def _fabric_options() -> dict[str, Any]:
    ctx = click.get_current_context(silent=True)
    return dict(ctx.meta.get(_FABRIC_KEY, {})) if ctx is not None else {}


def chart_kind() -> str:
    """``--chart``: what a square of the hand pattern's chart is ("units" unless given)."""
    return str(_fabric_options().get("chart") or "units")


def _border_option(callback: Callable[..., Any]) -> Callable[..., Any]:
    """``--border``, kept on the click context beside ``--chart`` (:func:`hand_border`)."""
    return click.option(
        "--border",
        "border",
        type=click.IntRange(0, MAX_BORDER_UNITS),
        default=None,
        expose_value=False,
        callback=callback,
        help="A garter border against curling around the hand pattern, this many ridge units "
        "wide: 2 selvedge stitches a unit at each side and a garter ridge a unit at the "
        "cast-on and bind-off edges (4 stitches and 4 rows more a unit) [0: none].",
    )


def hand_border() -> int:
    """``--border``: the hand pattern's garter border in ridge units (0 unless given)."""
    return int(_fabric_options().get("border") or 0)


def design_unit_aspect(spec: MachineSpec, made_for: str = "machine") -> float:
    """Height over width of a unit for sizing a grid: 1.0 with ``--square-units``, else the
    fabric gauge's (``spec`` from :func:`resolve_machine`, which applies ``--fabric-gauge``),
    and made for ``"hands"`` the gauge the hand pattern gives
    (:func:`~illuknit.core.gauge.hand_gauge`: the estimate for hand-knitted illusion fabric
    unless a measured ``--fabric-gauge`` is given), so the pictures keep their proportions in
    the piece knitted by hand."""
    if _fabric_options().get("square_units"):
        return 1.0
    from illuknit.core.gauge import drawn_gauge

    return drawn_gauge(spec.fabric_gauge, made_for).unit_aspect


def transfer_overrides() -> dict[str, int]:
    """The running command's ``--xfer-*`` values by :class:`TransferSettings` field (else {})."""
    ctx = click.get_current_context(silent=True)
    return dict(ctx.meta.get(_TRANSFER_KEY, {})) if ctx is not None else {}


def format_option() -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``--format dat``: with ``--knitout``, also write the program as a machine file.

    The choice is kept on the click context (:func:`requested_formats`), where
    :func:`resolve_machine` checks it and :func:`write_program` reads it, so a command only adds
    the decorator.
    """

    def remember(ctx: click.Context, _param: click.Parameter, value: tuple[str, ...]) -> None:
        ctx.meta[_FORMATS_KEY] = tuple(dict.fromkeys(v for v in value if v != "knitout"))

    return click.option(
        "--format",
        "machine_files",
        type=click.Choice(["knitout", "dat", "kc"]),
        multiple=True,
        expose_value=False,
        callback=remember,
        help="With --knitout: also write the program as this machine file beside program.k "
        "(dat: program.dat for Shima machines, kc: program.kc for the Kniterate). Repeatable.",
    )


def long_floats_option(
    *, expose_value: bool = False
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``--allow-long-floats``: keep floats longer than the float limit, with a warning.

    The value is kept on the click context (:func:`long_floats_allowed`), where
    :func:`write_program` reads it, so a command with ``--knitout`` only adds the decorator;
    ``expose_value=True`` also passes it to the command as ``allow_long_floats``
    (``illuknit knit``).
    """

    def remember(ctx: click.Context, _param: click.Parameter, value: bool) -> bool:
        ctx.meta[_LONG_FLOATS_KEY] = bool(value)
        return bool(value)

    return click.option(
        "--allow-long-floats",
        "allow_long_floats",
        is_flag=True,
        expose_value=expose_value,
        callback=remember,
        help=LONG_FLOATS_HELP,
    )


def long_floats_allowed() -> bool:
    """Whether the running command was given ``--allow-long-floats`` (False outside a command)."""
    ctx = click.get_current_context(silent=True)
    return bool(ctx is not None and ctx.meta.get(_LONG_FLOATS_KEY, False))


def requested_formats() -> tuple[str, ...]:
    """Machine-file formats the running command was asked for with ``--format`` (else none)."""
    ctx = click.get_current_context(silent=True)
    if ctx is None:
        return ()
    return tuple(ctx.meta.get(_FORMATS_KEY, ()))


def resolve_machine(name: str | MachineSpec | None, *, gauge: float | None = None) -> MachineSpec:
    """The machine called ``name`` (default preset when None), at ``gauge`` when one is given.

    Raises :class:`~illuknit.core.errors.UnknownNameError` (listing the presets) for unknown names,
    and for a ``--format`` the machine cannot take; :class:`~illuknit.core.errors.OptionError` for a
    ``--format`` without ``--knitout``.
    """
    from illuknit.core.errors import OptionError
    from illuknit.formats import check_format

    spec = machine_spec(name)
    if gauge is not None and gauge != spec.gauge:
        spec = spec.with_gauge(gauge)
    fabric = _fabric_options().get("fabric_gauge")
    if fabric is not None:
        from illuknit.core.gauge import parse_gauge

        spec = replace(spec, fabric=parse_gauge(fabric, source="--fabric-gauge"))
    overrides = transfer_overrides()
    if overrides:
        transfer = replace(spec.transfer, source="set for this run (--xfer-*)", **overrides)
        spec = replace(spec, transfer=transfer)
    formats = requested_formats()
    for fmt in formats:
        check_format(spec, fmt)
    ctx = click.get_current_context(silent=True)
    if formats and ctx is not None and ctx.params.get("knitout") is False:
        raise OptionError(
            f"--format {formats[0]} writes program.{formats[0]} beside program.k: add --knitout"
        )
    if long_floats_allowed() and ctx is not None and ctx.params.get("knitout") is False:
        raise OptionError("--allow-long-floats applies to the knitout program: add --knitout")
    return spec


def check_fits(machine: MachineSpec, units: int, *, hint: str | None = None) -> None:
    """Refuse (:class:`~illuknit.core.errors.SchedulingError`) a pattern ``units`` wide that the bed
    cannot hold; call it before designing, so no time is spent on a piece that cannot be knit."""
    if hint is None:
        machine.check_units(units)
    else:
        machine.check_units(units, hint=hint)


def write_program(
    pattern: LogicalPattern,
    outdir: Path,
    *,
    machine: MachineSpec | str | None = None,
    formats: tuple[str, ...] | None = None,
    allow_long_floats: bool | None = None,
    tall_bumps: bool = False,
    refused: list[LongFloatError] | None = None,
) -> dict[str, Path]:
    """Compile ``pattern`` for ``machine`` to ``program.k`` and write the checker's report beside it.

    Writes ``program.k``, ``knit.json`` (passes, lower bound, time estimate, and the machine
    set-up sheet: carriers and their cones, stitch numbers, needle range, passes and time on the
    machine), ``check.json`` and ``check.txt``, ``program.<format>`` for each machine-file format
    (default: those asked for with ``--format``), and the machine's own file when illuknit writes
    one without a choice to make (``program.kc`` for the Kniterate); returns name -> path. Prints
    a one-line summary of each. The checker judges the program by the same machine the scheduler
    used.

    ``tall_bumps`` knits every bump as a tall bump (:class:`~illuknit.knit.options.KnitOptions`).

    A float longer than the machine's float limit raises
    :class:`~illuknit.core.errors.LongFloatError` before anything is written, unless
    ``allow_long_floats`` (default: whether the command was given ``--allow-long-floats``).
    Given a ``refused`` list, it instead writes :data:`REFUSAL_NOTE` (why, and the remedies
    measured by :func:`~illuknit.knitting.remedies.knit_refusal`), appends the error (its
    message naming those remedies) for the caller to raise once the rest of the design is
    written, and returns ``{"refused": path}``.
    """
    import json

    from illuknit.check import check_knitout
    from illuknit.cli.summary import console
    from illuknit.core.files import atomic_write_bytes
    from illuknit.formats import FORMAT_SUFFIXES, check_format, knitout_to_format
    from illuknit.knitting import knit_pattern
    from illuknit.outputs.machine_sheet import machine_headline, machine_sheet

    spec = machine_spec(machine)
    formats = requested_formats() if formats is None else formats
    for fmt in formats:
        check_format(spec, fmt)
    if allow_long_floats is None:
        allow_long_floats = long_floats_allowed()
    try:
        result = knit_pattern(
            pattern, machine=spec, allow_long_floats=allow_long_floats, tall_bumps=tall_bumps
        )
    except LongFloatError as e:
        if refused is None:
            raise
        from illuknit.knitting.remedies import knit_refusal

        refusal = knit_refusal(pattern, e, machine=spec, options=KnitOptions(tall_bumps=tall_bumps))
        refused.append(refusal.error)
        console().print(f"knitout: refused; the design is written, {REFUSAL_NOTE} says why")
        return {"refused": atomic_write_text(outdir / REFUSAL_NOTE, refusal.note)}
    report = check_knitout(result.knitout, machine=spec)  # it declares its bumps
    sheet = machine_sheet(result, name="program.kc")
    summary = machine_headline(result.summary(), sheet)
    for line in _describe(summary):
        console().print(line)
    console().print(f"check: {report.to_text(name='program.k').splitlines()[0]}")
    # convert before writing anything, so a program the machine file cannot hold leaves nothing
    extra = {
        fmt: knitout_to_format(result.knitout, fmt, name=f"program{FORMAT_SUFFIXES[fmt]}")
        for fmt in formats
        if fmt != "knitout" and fmt not in sheet.files
    }
    files = {
        "program": atomic_write_text(outdir / "program.k", result.program),
        "knit": atomic_write_text(outdir / "knit.json", json.dumps(summary, indent=1) + "\n"),
        "check": atomic_write_text(outdir / "check.json", report.to_json(indent=1) + "\n"),
        "check_text": atomic_write_text(
            outdir / "check.txt", report.to_text(name="program.k") + "\n"
        ),
    }
    if "kc" in sheet.files:
        files["kc"] = atomic_write_text(outdir / "program.kc", sheet.files["kc"])
    for fmt, data in extra.items():
        files[f"program_{fmt}"] = atomic_write_bytes(
            outdir / f"program{FORMAT_SUFFIXES[fmt]}", data
        )
    return files


def _describe(summary: dict[str, object]) -> list[str]:
    """Lines a person reads, each figure once: ``knitout:`` the machine and the passes against
    their lower bound; ``time:`` the knitting time with the time model's range and the
    bind-off's part; ``floats:`` and ``bumps:`` (the rest, with the time model, is in knit.json)."""
    get = summary.get
    head = f"knitout: program.k for {get('machine', 'the machine')}"
    if "passes" in summary:
        bound = f" (lower bound {get('lower_bound')})" if "lower_bound" in summary else ""
        head += f", {get('passes')} carriage passes{bound}"
    lines = [head]
    time, span = get("machine_time", get("time")), get("machine_time_range", get("time_range"))
    if time is not None:
        text = f"time: about {time} to knit"
        if span is not None:
            text += f" (the time model's range {span})"
        bind_off = get("bind_off_time")
        lines.append(text if bind_off is None else f"{text}, of which the bind-off {bind_off}")
    lines += [f"{key}: {summary[key]}" for key in ("floats", "bumps") if key in summary]
    return lines
