"""Lowering a :class:`~illuknit.knit.schedule.Schedule` to a knitout-2 program.

:func:`lower_to_knitout` returns the program as data, a
:class:`~illuknit.knitout.program.KnitoutProgram` whose operations each carry their provenance
(the index of the schedule step they came from), which every later reader takes as it is;
:func:`write_knitout` is its text (:func:`~illuknit.knitout.program.format_knitout`), written at
the edge.

The text is what the CMU SWG converter (``knitout-to-dat.js``) accepts: the magic line
``;!knitout-2``, a header of ``;;Machine:``, ``;;Gauge:``, ``;;Width:``, ``;;Carriers:`` (the exact
string ``1 2 3 4 5 6 7 8 9 10`` for the default machine), ``;;Position:`` and one ``;;Yarn-N:`` per
carrier used; then one operation per line with tokens separated by single spaces and LF line
endings. ``rack`` lines are written only when the racking changes; ``x-stitch-number`` /
``x-speed-number`` only when the machine spec sets them. Transfer passes run at the spec's
:class:`~illuknit.core.machine.TransferSettings`: ``x-xfer-stitch-number`` once after the header,
``x-speed-number`` switched to the transfer speed before each run of transfer passes and back to
the knitting speed before the next knit pass, and ``x-add-roller-advance`` before the first
transfer of a run (Kniterate). Comments (``; course 12 ...``) mark where
each body course starts so that a checker's line numbers can be traced back to pattern rows.
The first comment under the header says what the machine is (:func:`machine_comment`):
``;;Machine`` names the model whose rules the program follows, which a generic bed is not.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from itertools import count

from illuknit.core.machine import MachineSpec
from illuknit.knit.ir import course_row
from illuknit.knit.schedule import CarrierAction, Pass, Schedule, Step
from illuknit.knitout.program import (
    KnitoutProgram,
    Needle,
    Operation,
    format_knitout,
    make_needle,
)

__all__ = [
    "format_racking",
    "knitout_header",
    "lower_to_knitout",
    "machine_comment",
    "step_lines",
    "step_operations",
    "write_knitout",
]

#: What a program may carry between its header and the schedule's own lines (a machine's waste
#: section, the bumps it declares): comment lines (``str``, starting with ``;``) and operations
#: (their line and provenance are set where they land; they come from no step of the schedule).
Prelude = Sequence[str | Operation]


def format_racking(r: float) -> str:
    """``0``, ``-1``, ``0.25``, ``-0.75``: integers without a decimal point."""
    return str(int(r)) if float(r) == int(r) else f"{r:g}"


def _header_fields(schedule: Schedule, machine: MachineSpec) -> list[tuple[str, str]]:
    """``(name, value)`` of each ``;;`` header line."""
    fields = [
        ("Machine", machine.name),
        ("Gauge", f"{machine.gauge:g}"),
        ("Width", f"{machine.needles}"),
        ("Carriers", " ".join(machine.carriers)),
        ("Position", f"{machine.position}"),
    ]
    used: dict[str, int] = {}
    for y, cars in schedule.carrier_of_yarn.items():
        for c in cars:
            used.setdefault(c, y)
    for c in sorted(used, key=machine.carriers.index):
        name = "-".join(schedule.yarns[used[c]].name.split()) or f"yarn{used[c]}"
        fields.append((f"Yarn-{c}", f"{machine.yarn_weight} {name}"))
    return fields


def knitout_header(schedule: Schedule, machine: MachineSpec) -> list[str]:
    """The magic line and the ``;;`` header lines."""
    return [";!knitout-2", *(f";;{k}: {v}" for k, v in _header_fields(schedule, machine))]


def machine_comment(machine: MachineSpec) -> str:
    """The comment line under the header that says what the machine is. ``;;Machine`` names the
    model whose rules and reference backend the program follows (the SWG backend ignores it;
    the PyPI simulator runs only ``SWG091N2`` programs as that model), which on a generic bed
    is not the machine itself.

    >>> from illuknit.core.machine import MACHINES
    >>> machine_comment(MACHINES["generic540"])
    '; machine: generic 540-needle V-bed (SWG091N2 rules); ;;Machine names the model whose rules it follows, not this bed'
    >>> machine_comment(MACHINES["swg091n2"])
    "; machine: SWG091N2, the real machine's bed of 252 needles"
    """
    if machine.is_real:
        return f"; machine: {machine.name}, the real machine's bed of {machine.needles} needles"
    return (
        f"; machine: {machine.label}; ;;Machine names the model whose rules it follows, "
        "not this bed"
    )


class _Lines:
    """The program as it is written: each comment or operation takes the next line."""

    def __init__(self, headers: list[tuple[str, str]]) -> None:
        self.headers = tuple((k, v, i) for i, (k, v) in enumerate(headers, start=2))
        self.line = count(len(headers) + 2)
        self.operations: list[Operation] = []
        self.comments: list[tuple[int, str]] = []

    def comment(self, text: str) -> None:
        self.comments.append((next(self.line), text))

    def setting(self, name: str, value: object) -> None:
        """An ``x-*`` extension line (``x-speed-number 300``)."""
        self.operations.append(_setting(name, str(value)).at(next(self.line)))

    def add(self, operations: Sequence[Operation], step: int | None) -> None:
        # Operation.at inlined: a big program places hundreds of thousands of operations
        line, append, new, set_fields = (
            self.line,
            self.operations.append,
            object.__new__,
            object.__setattr__,
        )
        for op in operations:
            fields = {**op.__dict__, "line": next(line), "step": step}
            placed = new(Operation)
            set_fields(placed, "__dict__", fields)
            append(placed)

    def program(self) -> KnitoutProgram:
        return KnitoutProgram(
            2,
            self.headers,
            tuple(self.operations),
            next(self.line) - 1,
            comments=tuple(self.comments),
        )


def lower_to_knitout(
    schedule: Schedule, *, machine: MachineSpec | None = None, prelude: Prelude = ()
) -> KnitoutProgram:
    """The knitout-2 program of a schedule, as data.

    Parameters
    ----------
    schedule : Schedule
    machine : MachineSpec, optional
        Header values; defaults to the machine the schedule was made for.
    prelude : sequence of str or Operation, optional
        Lines written right after the header (comments, and operations that come from no step).

    Returns
    -------
    KnitoutProgram
        Each operation the schedule's steps make carries ``step``, the index of its step in
        ``schedule.steps``; :func:`~illuknit.knitout.program.format_knitout` writes its text.
    """
    m = schedule.machine if machine is None else machine
    out = _Lines(_header_fields(schedule, m))
    for item in prelude:
        if isinstance(item, str):
            out.comment(item)
        else:
            out.add((item,), None)
    out.comment(machine_comment(m))
    out.comment(
        f"; illuknit: {schedule.wales} wales x {schedule.courses} courses, "
        f"wale 0 on needle {schedule.left}; course c is pattern row N-1-c//2"
    )
    xs = m.transfer
    if m.speed_number is not None:
        out.setting("x-speed-number", m.speed_number)
    if xs.stitch_number is not None:
        out.setting("x-xfer-stitch-number", _stitch_code(xs.stitch_number))
    _lower_steps(schedule, m, out)
    return out.program()


def _lower_steps(schedule: Schedule, m: MachineSpec, out: _Lines) -> None:
    """The schedule's steps, each with the settings it runs at (racking, stitch, speed)."""
    n_rows = schedule.units[0] if schedule.units is not None else None
    xs = m.transfer
    # 0 is the SWG's "machine default" speed; the Kniterate presets set a knitting speed
    knit_speed = m.speed_number if m.speed_number is not None else 0
    speed = m.speed_number
    in_transfers = False
    rack = 0.0
    stitch: int | None = None
    last_course: int | None = None
    for index, step in enumerate(schedule.steps):
        if isinstance(step, CarrierAction):
            if step.action in ("out", "outhook") and speed is not None and speed != knit_speed:
                # the backend's carrier-out move runs at the speed in force: not a transfer's
                speed = knit_speed
                out.setting("x-speed-number", speed)
            out.add(step_operations(step), index)
            continue
        assert isinstance(step, Pass)
        if (
            step.course is not None
            and step.course != last_course
            and step.role in ("body", "transfer")
        ):
            last_course = step.course
            row = f" = pattern row {course_row(step.course, n_rows)}" if n_rows is not None else ""
            out.comment(f"; course {step.course}{row}")
        if step.racking != rack:
            rack = step.racking
            out.add((_rack(rack),), None)
        if step.kind == "xfer":
            if xs.speed_number is not None and speed != xs.speed_number:
                speed = xs.speed_number
                out.setting("x-speed-number", speed)
            if xs.roller_advance and not in_transfers:
                out.setting("x-add-roller-advance", xs.roller_advance)
            in_transfers = True
        elif step.kind == "knit":
            in_transfers = False
            if speed is not None and speed != knit_speed:
                speed = knit_speed
                out.setting("x-speed-number", speed)
        if step.kind == "knit" and step.stitch_number not in (None, stitch):
            stitch = step.stitch_number
            # the Kniterate backend takes one character, 0-9 or A-Z (10-35)
            code = _stitch_code(stitch) if m.runs_on() == "kniterate" else stitch
            out.setting("x-stitch-number", code)
        out.add(step_operations(step), index)
    if rack != 0:
        out.add((_rack(0.0),), None)


def write_knitout(schedule: Schedule, *, machine: MachineSpec | None = None) -> str:
    """Knitout-2 program text for a schedule: :func:`lower_to_knitout`, formatted.

    Parameters
    ----------
    schedule : Schedule
    machine : MachineSpec, optional
        Header values; defaults to the machine the schedule was made for.

    Returns
    -------
    str
        The program, LF line endings, ending with a newline.
    """
    return format_knitout(lower_to_knitout(schedule, machine=machine))


def step_operations(step: Step) -> list[Operation]:
    """The knitout operations of one step, in order (a carrier action is one); the settings it
    runs at (racking, stitch number, speed) are the caller's to add. Their line is a
    placeholder (1) until :meth:`~illuknit.knitout.program.Operation.at` places them.

    >>> from illuknit.knit.ir import Op
    >>> [str(o) for o in step_operations(Pass("knit", (Op("knit", "f", 3),), "+", ("2",)))]
    ['knit + f3 2']
    """
    if isinstance(step, CarrierAction):
        return [_operation(step.action, None, None, 0, None, 0, step.carriers)]
    if step.kind == "knit":
        d, cs = step.direction, step.carriers
        return [
            _operation(o.op, d, o.bed, o.needle, o.to_bed, o.to_needle or 0, cs) for o in step.ops
        ]
    return [
        _operation(o.op, None, o.bed, o.needle, o.to_bed, o.to_needle or 0, ()) for o in step.ops
    ]


def step_lines(step: Step) -> list[str]:
    """The knitout lines of one step (:func:`step_operations` as text).

    >>> from illuknit.knit.ir import Op
    >>> step_lines(Pass("knit", (Op("knit", "f", 3), Op("tuck", "b", 4)), "+", ("2",)))
    ['knit + f3 2', 'tuck + b4 2']
    """
    return [str(o) for o in step_operations(step)]


@functools.lru_cache(maxsize=1 << 16)  # a program repeats few distinct operations
def _operation(
    op: str,
    direction: str | None,
    bed: str | None,
    needle: int,
    to_bed: str | None,
    to_needle: int,
    carriers: tuple[str, ...],
) -> Operation:
    needles: tuple[Needle, ...] = () if bed is None else (make_needle(bed, needle),)
    if to_bed is not None:
        needles += (make_needle(to_bed, to_needle),)
    return Operation(1, op, direction, needles, carriers)  # type: ignore[arg-type]


@functools.lru_cache(maxsize=256)
def _setting(name: str, value: str) -> Operation:
    return Operation(1, name, args=(value,))


def _rack(racking: float) -> Operation:
    return Operation(1, "rack", value=float(racking))


def _stitch_code(n: int) -> str:
    """Kniterate stitch numbers: 0-9, then A-Z for 10-35."""
    return "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"[n]
