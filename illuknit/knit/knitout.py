"""Writing a :class:`~illuknit.knit.schedule.Schedule` as knitout-2 text.

The output is what the CMU SWG converter (``knitout-to-dat.js``) accepts: the magic line
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

from illuknit.core.machine import MachineSpec
from illuknit.knit.ir import course_row
from illuknit.knit.schedule import CarrierAction, Pass, Schedule, Step

__all__ = ["format_racking", "knitout_header", "machine_comment", "step_lines", "write_knitout"]


def format_racking(r: float) -> str:
    """``0``, ``-1``, ``0.25``, ``-0.75``: integers without a decimal point."""
    return str(int(r)) if float(r) == int(r) else f"{r:g}"


def knitout_header(schedule: Schedule, machine: MachineSpec) -> list[str]:
    """The magic line and the ``;;`` header lines."""
    lines = [
        ";!knitout-2",
        f";;Machine: {machine.name}",
        f";;Gauge: {machine.gauge:g}",
        f";;Width: {machine.needles}",
        ";;Carriers: " + " ".join(machine.carriers),
        f";;Position: {machine.position}",
    ]
    used: dict[str, int] = {}
    for y, cars in schedule.carrier_of_yarn.items():
        for c in cars:
            used.setdefault(c, y)
    for c in sorted(used, key=machine.carriers.index):
        name = "-".join(schedule.yarns[used[c]].name.split()) or f"yarn{used[c]}"
        lines.append(f";;Yarn-{c}: {machine.yarn_weight} {name}")
    return lines


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


def write_knitout(schedule: Schedule, *, machine: MachineSpec | None = None) -> str:
    """Knitout-2 program text for a schedule.

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
    m = schedule.machine if machine is None else machine
    n_rows = schedule.units[0] if schedule.units is not None else None
    lines = knitout_header(schedule, m)
    lines.append(machine_comment(m))
    lines.append(
        f"; illuknit: {schedule.wales} wales x {schedule.courses} courses, "
        f"wale 0 on needle {schedule.left}; course c is pattern row N-1-c//2"
    )
    xs = m.transfer
    if m.speed_number is not None:
        lines.append(f"x-speed-number {m.speed_number}")
    if xs.stitch_number is not None:
        lines.append(f"x-xfer-stitch-number {_stitch_code(xs.stitch_number)}")
    # 0 is the SWG's "machine default" speed; the Kniterate presets set a knitting speed
    knit_speed = m.speed_number if m.speed_number is not None else 0
    speed = m.speed_number
    in_transfers = False
    rack = 0.0
    stitch: int | None = None
    last_course: int | None = None
    append = lines.append
    for step in schedule.steps:
        if isinstance(step, CarrierAction):
            if step.action in ("out", "outhook") and speed is not None and speed != knit_speed:
                # the backend's carrier-out move runs at the speed in force: not a transfer's
                speed = knit_speed
                append(f"x-speed-number {speed}")
            lines.extend(step_lines(step))
            continue
        assert isinstance(step, Pass)
        if (
            step.course is not None
            and step.course != last_course
            and step.role in ("body", "transfer")
        ):
            last_course = step.course
            row = f" = pattern row {course_row(step.course, n_rows)}" if n_rows is not None else ""
            append(f"; course {step.course}{row}")
        if step.racking != rack:
            rack = step.racking
            append(f"rack {format_racking(rack)}")
        if step.kind == "xfer":
            if xs.speed_number is not None and speed != xs.speed_number:
                speed = xs.speed_number
                append(f"x-speed-number {speed}")
            if xs.roller_advance and not in_transfers:
                append(f"x-add-roller-advance {xs.roller_advance}")
            in_transfers = True
        elif step.kind == "knit":
            in_transfers = False
            if speed is not None and speed != knit_speed:
                speed = knit_speed
                append(f"x-speed-number {speed}")
        if step.kind == "knit" and step.stitch_number not in (None, stitch):
            stitch = step.stitch_number
            # the Kniterate backend takes one character, 0-9 or A-Z (10-35)
            code = _stitch_code(stitch) if m.runs_on() == "kniterate" else stitch
            append(f"x-stitch-number {code}")
        lines.extend(step_lines(step))
    if rack != 0:
        append("rack 0")
    return "\n".join(lines) + "\n"


def step_lines(step: Step) -> list[str]:
    """The knitout lines of one step: its operations in order (a carrier action is one line);
    the settings it runs at (racking, stitch number, speed) are the caller's to write.

    >>> from illuknit.knit.ir import Op
    >>> step_lines(Pass("knit", (Op("knit", "f", 3), Op("tuck", "b", 4)), "+", ("2",)))
    ['knit + f3 2', 'tuck + b4 2']
    """
    if isinstance(step, CarrierAction):
        return [f"{step.action} {' '.join(step.carriers)}"]
    if step.kind == "knit":
        tail = f" {' '.join(step.carriers)}"
        d = step.direction
        return [
            f"split {d} {o.bed}{o.needle} {o.to_bed}{o.to_needle}{tail}"
            if o.op == "split"
            else f"{o.op} {d} {o.bed}{o.needle}{tail}"
            for o in step.ops
        ]
    if step.kind == "xfer":
        return [f"xfer {o.bed}{o.needle} {o.to_bed}{o.to_needle}" for o in step.ops]
    return [f"drop {o.bed}{o.needle}" for o in step.ops]


def _stitch_code(n: int) -> str:
    """Kniterate stitch numbers: 0-9, then A-Z for 10-35."""
    return "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"[n]
