"""What to change when a pattern is refused for a long float: remedies measured, not guessed.

:func:`knit_refusal` takes a :class:`~illuknit.core.errors.LongFloatError` from
:func:`~illuknit.knitting.knit_pattern` and knits the same pattern again with each knitting
switch that can shorten its floats (today: tall bumps, on a pattern with raised units). A remedy
is named only when that knit went through; the ones tried that did not help are named too, with
the float they left. Keeping the long floats (``--allow-long-floats``) always knits and is named
last, with the float it keeps. The caller writes :attr:`KnitRefusal.note` beside the design, so
a refusal never loses the design, and raises :attr:`KnitRefusal.error`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from typing import Any

from illuknit.core.errors import LongFloatError
from illuknit.core.machine import MachineSpec, resolve_machine
from illuknit.core.pattern import LogicalPattern
from illuknit.knit.options import KnitOptions
from illuknit.knitting.pipeline import FLOAT_UNIT, knit_pattern

__all__ = ["KnitRefusal", "Remedy", "knit_refusal"]

#: Knitting switches tried on a refusal: option field, CLI flag, what it does.
_TRIES = (
    (
        "tall_bumps",
        "--tall-bumps",
        "tall bumps: a tuck before each bump's purl, docs/split-bumps.md",
    ),
)


@dataclass(frozen=True)
class Remedy:
    """One knitting switch tried on a refused pattern, and what it gave.

    ``works`` is whether the pattern then knits within the float limit; ``longest`` is the
    longest float it then has (in :data:`~illuknit.knitting.pipeline.FLOAT_UNIT`) and
    ``passes`` the machine passes when it works."""

    option: str
    flag: str
    what: str
    works: bool
    longest: int
    passes: int | None = None

    def text(self) -> str:
        """One line: the switch and what it measured."""
        if self.works:
            return (
                f"{self.flag} knits it ({self.what}): longest float {self.longest} "
                f"{FLOAT_UNIT}, {self.passes} passes"
            )
        return f"{self.flag} was tried and does not help (a float of {self.longest} stays)"


@dataclass(frozen=True)
class KnitRefusal:
    """A refused knit: the error to raise (its message ends with the measured remedies), the
    remedies tried, and the note to write beside the design."""

    error: LongFloatError
    remedies: tuple[Remedy, ...]
    note: str

    @property
    def working(self) -> tuple[Remedy, ...]:
        return tuple(r for r in self.remedies if r.works)


def knit_refusal(
    pattern: LogicalPattern,
    error: LongFloatError,
    *,
    machine: str | MachineSpec | None = None,
    options: KnitOptions | None = None,
    program: str = "program.k",
    pattern_file: str = "pattern.json",
) -> KnitRefusal:
    """Measure what knits ``pattern`` after ``error`` refused it (see the module docstring).

    Parameters
    ----------
    pattern : LogicalPattern
        The refused pattern.
    error : LongFloatError
        The refusal of ``knit_pattern(pattern, machine=machine, options=options)``.
    machine : str or MachineSpec, optional
    options : KnitOptions, optional
        The options it was refused with (default ``KnitOptions()``).
    program, pattern_file : str
        The program's and the pattern's file names, for the message and the note.

    Returns
    -------
    KnitRefusal
    """
    m = resolve_machine(machine)
    base = KnitOptions() if options is None else options
    remedies = []
    for field, flag, what in _TRIES:
        if getattr(base, field) or (field == "tall_bumps" and not pattern.raised.any()):
            continue
        changed: dict[str, Any] = {field: True}
        remedies.append(_try(pattern, m, replace(base, **changed), field, flag, what))
    working = [r for r in remedies if r.works]
    lines = [r.text() for r in remedies]
    keep = (
        f"--allow-long-floats keeps the {error.count} long float(s) (the longest "
        f"{error.length} {FLOAT_UNIT}, at {error.where}) and knits it as it is"
    )
    head = (
        f"{error.count} float(s) stay longer than the float limit of {error.limit} "
        f"{FLOAT_UNIT}; the longest, {error.length} {FLOAT_UNIT} of carrier {error.carrier} "
        f"(needles {error.from_needle} to {error.to_needle}), is at {error.where}"
    )
    if working:
        fix = f"measured on this pattern with illuknit knit {pattern_file}: " + "; ".join(
            r.text() for r in working
        )
    else:
        tried = "; ".join(lines) if lines else "no knitting switch applies to this pattern"
        fix = (
            f"no knitting switch knits it ({tried}); a picture with fewer colour regions per "
            "row there would"
        )
    message = f"{head}: {fix}; or {keep}"
    note = "\n".join(
        [
            f"{program} was not written: the knitting was refused.",
            "",
            head + ".",
            "",
            f"Tried on this pattern (illuknit knit {pattern_file} -o {program} ...):",
            *(f"  {line}" for line in lines or ["(no knitting switch applies to this pattern)"]),
            f"  {keep}",
            "",
            "Everything else in this folder was written: the design is kept.",
            "",
        ]
    )
    return KnitRefusal(_with_message(error, message), tuple(remedies), note)


def _try(
    pattern: LogicalPattern,
    machine: MachineSpec,
    options: KnitOptions,
    field: str,
    flag: str,
    what: str,
) -> Remedy:
    """Knit ``pattern`` with ``options`` (long floats refused) and say what it gave."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = knit_pattern(pattern, machine=machine, options=options)
    except LongFloatError as e:
        return Remedy(field, flag, what, False, e.length)
    s = result.summary()
    return Remedy(field, flag, what, True, int(s["longest_float"]), int(s["passes"]))


def _with_message(error: LongFloatError, message: str) -> LongFloatError:
    return LongFloatError(
        message,
        length=error.length,
        carrier=error.carrier,
        from_needle=error.from_needle,
        to_needle=error.to_needle,
        course=error.course,
        where=error.where,
        limit=error.limit,
        count=error.count,
    )
