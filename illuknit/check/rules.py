"""Machine-rule findings: what the SWG091N2 (and its knitout converter) would refuse.

Two sources: the header and file form of the program (:func:`check_header`), and the events the
simulation recorded while running it (:func:`machine_findings`). ``RULES`` maps every code to its
severity and a one-line explanation; ``docs/checker.md`` lists the same table.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from illuknit.check.report import Finding
from illuknit.check.simulate import Simulation
from illuknit.knitout.parse import KnitoutProgram

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec

__all__ = ["RULES", "SWG_CARRIERS", "check_header", "machine_findings", "machine_value_findings"]

#: the only ;;Carriers: value the SWG converter accepts
SWG_CARRIERS = "1 2 3 4 5 6 7 8 9 10"

#: code -> (severity, what it means)
RULES: dict[str, tuple[str, str]] = {
    "header-version": ("warning", "magic line names a knitout version above 2"),
    "header-carriers": ("error", ";;Carriers: missing or not exactly the machine's carriers"),
    "header-value": ("error", "bad ;;Gauge, ;;Width or ;;Position value"),
    "header-machine": ("warning", ";;Machine is not the machine the checker models"),
    "machine-value": (
        "error",
        ";;Width, ;;Gauge or a stitch, speed or roller number outside the machine's range",
    ),
    "crlf": ("warning", "CRLF line endings (the converter warns)"),
    "tab-separator": ("error", "tokens separated by tabs (the SWG converter accepts spaces only)"),
    "carrier-unknown": ("error", "carrier not listed in the ;;Carriers: header"),
    "carrier-not-in": ("error", "carrier used without in/inhook (never brought in, or after out)"),
    "in-active-carrier": ("error", "in/inhook of a carrier that is already in"),
    "first-use-mismatch": ("error", "first use of a carrier not with exactly its in/inhook set"),
    "duplicate-carrier": ("error", "a carrier set names a carrier twice"),
    "hook-busy": ("error", "inhook while the inserting hook still holds another carrier"),
    "hook-rightward": ("error", "first stitch of a hooked carrier goes '+'"),
    "hook-blocked": ("error", "carrier operation at or right of the held inserting hook"),
    "release-empty": ("error", "releasehook while the hook holds nothing"),
    "release-wrong-set": ("error", "releasehook names a set other than what the hook holds"),
    "release-before-stitch": ("error", "releasehook before the hooked carrier stitched"),
    "outhook-hook-busy": ("error", "outhook while the hook holds another carrier"),
    "out-hooked": ("error", "out/outhook of a carrier still on the inserting hook"),
    "out-inactive": ("error", "out/outhook of a carrier that is not in"),
    "out-unused": ("error", "out/outhook of a carrier that never stitched"),
    "miss-without-carriers": ("error", "miss with no carrier"),
    "rack-range": ("error", "|racking| beyond the machine limit"),
    "rack-fraction": ("error", "racking not an integer or integer + 0.25"),
    "xfer-misaligned": ("error", "xfer/split between needles not aligned at the current racking"),
    "xfer-same-bed": ("error", "xfer/split between two needles of one bed"),
    "xfer-slider-slider": ("error", "xfer between two slider needles"),
    "stitch-on-slider": ("error", "knit/tuck/split on a slider needle (sliders cannot form loops)"),
    "too-many-loops": ("error", "a needle holds more loops than the machine allows"),
    "too-wide": ("error", "needles outside the bed width"),
    "knit-empty": ("warning", "knit on a needle that held loops and lost them (dropped, moved)"),
}


def _finding(line: int, code: str, message: str) -> Finding:
    return Finding(line, code, RULES[code][0], message)


def check_header(program: KnitoutProgram, *, machine: MachineSpec | None = None) -> list[Finding]:
    """Findings about the magic line, the header, the file's form and its machine values
    (:func:`machine_value_findings`).

    ``;;Carriers`` and ``;;Machine`` must be those of ``machine`` (default: the SWG091N2 as the
    reference converter takes it, which requires carriers ``1 .. 10``).
    """
    from illuknit.core.machine import DEFAULT_MACHINE

    m_spec = DEFAULT_MACHINE if machine is None else machine
    carriers = " ".join(m_spec.carriers)
    out: list[Finding] = []
    if program.version > 2:
        out.append(
            _finding(1, "header-version", f"knitout-{program.version}: the converter knows up to 2")
        )
    hc = program.header("Carriers")
    if hc is None:
        out.append(
            _finding(
                1,
                "header-carriers",
                f"no ';;Carriers: {carriers}' header (the {m_spec.label} requires exactly this)",
            )
        )
    elif hc[0] != carriers:
        out.append(
            _finding(
                hc[1],
                "header-carriers",
                f";;Carriers: {hc[0]!r}; the {m_spec.label} requires exactly {carriers!r}",
            )
        )
    g = program.header("Gauge")
    if g is not None and not _positive_number(g[0]):
        out.append(
            _finding(g[1], "header-value", f";;Gauge must be a positive number, got {g[0]!r}")
        )
    w = program.header("Width")
    if w is not None and program.width is None:
        out.append(
            _finding(w[1], "header-value", f";;Width must be a positive integer, got {w[0]!r}")
        )
    p = program.header("Position")
    if p is not None and p[0] not in ("Left", "Right", "Center", "Keep"):
        out.append(
            _finding(
                p[1],
                "header-value",
                f";;Position must be Left, Right, Center or Keep, got {p[0]!r}",
            )
        )
    m = program.header("Machine")
    if m is not None and m[0] != m_spec.name:
        out.append(
            _finding(
                m[1], "header-machine", f";;Machine {m[0]!r}: the checker models the {m_spec.label}"
            )
        )
    out += machine_value_findings(program, machine=m_spec)
    if program.crlf:
        out.append(_finding(1, "crlf", "CRLF line endings; write LF"))
    tabbed = [op.line for op in program.operations if op.tabs]
    if tabbed:
        more = f" (and {len(tabbed) - 1} more lines)" if len(tabbed) > 1 else ""
        out.append(
            _finding(
                tabbed[0],
                "tab-separator",
                f"tab between tokens{more}; the SWG converter accepts single spaces only",
            )
        )
    return out


def _positive_number(s: str) -> bool:
    try:
        return float(s) > 0
    except ValueError:
        return False


#: knitout extension -> its parameter in :data:`~illuknit.core.machine_ranges.MACHINE_RANGES`
_EXTENSION_VALUES = {
    "x-stitch-number": "stitch_number",
    "x-xfer-stitch-number": "transfer_stitch_number",
    "x-speed-number": "speed_number",
    "x-roller-advance": "roller_advance",
    "x-add-roller-advance": "roller_advance",
}
_STITCH_CODES = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"


def machine_value_findings(program: KnitoutProgram, *, machine: MachineSpec) -> list[Finding]:
    """``machine-value`` errors: a ``;;Width`` or ``;;Gauge`` header, or a stitch, speed or
    roller number, outside the range ``machine``'s backend takes
    (:data:`~illuknit.core.machine_ranges.MACHINE_RANGES`; each message names the range and its
    source). One finding per distinct value, at its first line."""
    from illuknit.core.machine_ranges import machine_value_problem

    backend = machine.runs_on()
    out: list[Finding] = []
    w = program.header("Width")
    if w is not None and program.width is not None:
        problem = machine_value_problem("needles", program.width, backend=backend)
        if problem is not None:
            out.append(_finding(w[1], "machine-value", f";;Width {_short(w[0])}: {problem}"))
    g = program.header("Gauge")
    if g is not None and _positive_number(g[0]):
        problem = machine_value_problem("gauge", float(g[0]), backend=backend)
        if problem is not None:
            out.append(_finding(g[1], "machine-value", f";;Gauge {_short(g[0])}: {problem}"))
    seen: set[tuple[str, tuple[str, ...]]] = set()
    for op in program.operations:
        name = _EXTENSION_VALUES.get(op.op)
        if name is None or (op.op, op.args) in seen:
            continue
        seen.add((op.op, op.args))
        problem = machine_value_problem(name, _extension_value(op.args, backend), backend=backend)
        if problem is not None:
            text = f"{op.op} {_short(' '.join(op.args))}"
            out.append(_finding(op.line, "machine-value", f"{text}: {problem}"))
    return out


def _extension_value(args: tuple[str, ...], backend: str | None) -> object:
    """The number an extension's argument stands for (a Kniterate stitch letter A-Z is 10-35),
    or the raw text when it is none."""
    raw = " ".join(args)
    if len(args) != 1:
        return raw
    arg = args[0]
    if backend == "kniterate" and len(arg) == 1 and arg in _STITCH_CODES:
        return _STITCH_CODES.index(arg)
    if arg.lstrip("+").isascii() and arg.lstrip("+").isdigit():
        return int(arg)
    try:
        value = float(arg)
    except ValueError:
        return raw
    return int(value) if value.is_integer() else value


def _short(text: str) -> str:
    return text if len(text) <= 24 else text[:21] + "..."


def machine_findings(sim: Simulation) -> list[Finding]:
    """Findings from the machine-rule events of a simulation."""
    return [_finding(e.line, e.code, e.message) for e in sim.events]
