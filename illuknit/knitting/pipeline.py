"""The whole knitting path in one call: pattern -> stitches -> schedule -> knitout program (+ stats).

:func:`knit_pattern` is what ``illuknit knit`` and the ``--knitout`` options of the other commands
call. One long-float policy for all of them: a float that stays longer than the machine's float
limit after tucking is refused (:class:`~illuknit.core.errors.LongFloatError`, naming the course and
what to change) unless ``allow_long_floats=True``, which keeps it, reports it in the summary
(``long_floats``, ``longest_float``, ``longest_float_at``) and issues a
:class:`LongFloatWarning` saying how long and where.

It does not run the checker (that is :func:`illuknit.check.check_knitout`, slower); callers
that want a verdict pass it the returned program (``KnitResult.knitout``, read as it is).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, fields, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

from illuknit.core.errors import (
    CarrierShortageError,
    OptionError,
    PatternValidationError,
    SchedulingError,
)
from illuknit.core.gauge import FinishedSize
from illuknit.core.machine import MachineSpec, resolve_machine
from illuknit.core.pattern import LogicalPattern
from illuknit.knit.float_tucks import LongFloat
from illuknit.knit.hookless import lower_hookless_knitout, yarn_entry
from illuknit.knit.knitout import lower_to_knitout
from illuknit.knit.mixed import long_float_error, refuses_long_floats, schedule_mixed
from illuknit.knit.options import Catching, KnitOptions
from illuknit.knit.schedule import Schedule, ScheduleStats, schedule_courses
from illuknit.knit.stitches import StitchPattern, lower_to_stitches
from illuknit.knit.timing import (
    MachineRun,
    TimeEstimate,
    estimate_knit_time,
    format_duration,
    paper_scale_text,
)
from illuknit.knitout.bumps import BUMPS_COMMENT, bumps_comment, declared_bumps
from illuknit.knitout.program import KnitoutProgram, format_knitout
from illuknit.knitting.carriage import kc_run, machine_run, machine_stats, runs_on_swg
from illuknit.knitting.floats import (
    FLOAT_UNIT,
    FloatFacts,
    program_float_facts,
    program_long_floats,
)

if TYPE_CHECKING:
    pass

__all__ = [
    "FLOAT_UNIT",
    "KC_NAME",
    "FloatFacts",
    "KcFigures",
    "KnitResult",
    "LongFloatWarning",
    "knit_pattern",
    "long_float_warning",
    "passes_text",
    "program_float_facts",
    "program_long_floats",
]


class LongFloatWarning(UserWarning):
    """Floats longer than the machine's float limit were kept because long floats were allowed
    (``allow_long_floats=True``); the message says how many, how long the longest is and where.
    The CLI prints it as one ``illuknit: warning:`` line."""


#: :class:`~illuknit.knit.schedule.MixedReport` fields that :meth:`KnitResult.summary` reports.
_SUMMARY_MIXED = ("tuck_joins", "plated_stitches", "carriers", "float_avoidance_transfers")

#: The file name :attr:`KnitResult.kc` names in its comment line.
KC_NAME = "command.kc"


@dataclass(frozen=True)
class KcFigures:
    """What the Kniterate runs for a program: its ``.kc`` (the comment line names
    :data:`KC_NAME`), the ``.kc``'s passes (:func:`~illuknit.knitting.carriage.kc_run`: waste
    section and the backend's carriage moves included) and the time counted on them."""

    kc: str
    run: MachineRun
    time: TimeEstimate

    @property
    def passes(self) -> int:
        """The ``.kc``'s passes (its ``>>`` / ``<<`` rows)."""
        return self.run.passes


@dataclass(frozen=True, eq=False)
class KnitResult:
    """A knitout program and what it took to make it.

    Attributes
    ----------
    knitout : KnitoutProgram
        The knitout-2 program, as data (each operation with the schedule step it came from);
        :attr:`text` is its text.
    stitches : StitchPattern
    schedule : Schedule
    stats : ScheduleStats
        Pass counts, lower bound and ratio.
    time : TimeEstimate
    machine : MachineSpec
    split_bumps : int
        Raised units knit as split bumps (``LogicalPattern.upper``); check the program with
        ``check_knitout(..., split_bumps=True)`` when there are any.
    floats : FloatFacts or None
        The program's longest float and its floats at and over the float limit.
    """

    knitout: KnitoutProgram
    stitches: StitchPattern
    schedule: Schedule
    stats: ScheduleStats
    time: TimeEstimate
    machine: MachineSpec
    split_bumps: int = 0
    floats: FloatFacts | None = None

    @cached_property
    def text(self) -> str:
        """The knitout text of :attr:`knitout`, formatted on first use and kept (the file edge:
        nothing inside :func:`knit_pattern` reads text)."""
        return format_knitout(self.knitout)

    @property
    def program(self) -> str:
        """The knitout text (same as ``text``)."""
        return self.text

    @cached_property
    def kc_figures(self) -> KcFigures | None:
        """The Kniterate's ``.kc`` of the program, its passes and time (None on a machine
        without the ``.kc`` format). Converted on first use and kept: seconds on big programs,
        so :func:`knit_pattern` does not pay it for callers that never ask."""
        if "kc" not in self.machine.formats:
            return None
        from illuknit.formats.kc import knitout_to_kc_code

        code = knitout_to_kc_code(self.knitout, name=KC_NAME)
        run = kc_run(code)  # the passes it wrote, not its text read back
        return KcFigures(
            code.text, run, estimate_knit_time(self.schedule, run=run, machine=self.machine)
        )

    def _longest_float(self) -> tuple[int, str | None]:
        """The longest float over the limit: its length and where it is (carrier, needles,
        course), or ``(0, None)``."""
        if not self.schedule.long_floats:
            return 0, None
        return self._float_place(max(self.schedule.long_floats, key=lambda x: x.length))

    def _float_place(self, f: LongFloat) -> tuple[int, str]:
        where = f.where(self.stitches)
        return (
            f.length,
            f"carrier {f.carrier}, needles {f.from_needle} to {f.to_needle}, at {where}",
        )

    def _bumps(self) -> dict[str, str]:
        """``{"bumps": ...}``: what bumps the program declares (none for plain bumps)."""
        declared = declared_bumps(self.knitout)
        if not declared:
            return {}
        return {"bumps": f"{declared.text()}, declared in the program ('{BUMPS_COMMENT}')"}

    def _float_summary(self) -> dict[str, Any]:
        """The summary's float figures: the longest float of the program (not only over the
        limit) and the counts at and over the limit, in :data:`FLOAT_UNIT`."""
        longest, longest_at = self._longest_float()
        facts = self.floats
        at_limit = 0
        text = None
        if facts is not None:
            at_limit, text = facts.at_limit, facts.text(self.stitches)
            if facts.longest is not None and facts.longest.length >= longest:
                longest, longest_at = self._float_place(facts.longest)
        return {
            "float_limit": self.machine.float_limit if facts is None else facts.limit,
            "float_unit": FLOAT_UNIT,
            "long_floats": len(self.schedule.long_floats),
            "floats_at_limit": at_limit,
            "longest_float": longest,
            "longest_float_at": longest_at,
            **({"floats": text} if text is not None else {}),
        }

    def summary(self) -> dict[str, Any]:
        """JSON-ready numbers: size, passes, bound, ratio, time.

        The headline ``passes`` and ``time`` are the machine's on every machine: on a Shima the
        SWG backend's passes (kickbacks, carrier moves and hook passes included); on the
        Kniterate the ``.kc``'s (:attr:`kc_figures`: waste section and the backend's carriage
        moves included), with the schedule's kept as ``schedule_passes``, ``schedule_time``,
        ``schedule_lower_bound`` and ``schedule_ratio``, and ``passes_counted_on`` ``"kc"``.
        """
        c, w = self.stitches.shape
        fabric = self.machine.fabric_gauge
        size = FinishedSize(w * fabric.stitch_cm, c * fabric.row_cm, fabric)
        wcm, hcm = size.width_cm, size.height_cm
        out = {
            "machine": self.machine.label,
            "needles": self.machine.needles,
            "gauge": self.machine.gauge,
            "wales": w,
            "courses": c,
            "width_cm": round(wcm, 1),
            "height_cm": round(hcm, 1),
            "finished_size": size.as_dict(),
            "finished_size_text": size.describe(),
            **self.stats.as_dict(),
            "scheduler": self.schedule.scheduler,
            # Carrier moves the schedule makes itself (miss-only passes), next to the backend's
            # own kickbacks in ``kickbacks``.
            "explicit_kickbacks": self.stats.miss_passes,
            **(
                {k: getattr(self.schedule.mixed, k) for k in _SUMMARY_MIXED}
                if self.schedule.mixed is not None
                else {}
            ),
            **self._float_summary(),
            "time_seconds": round(self.time.seconds, 1),
            "time": str(self.time),
            "time_range_seconds": [
                round(self.time.low_seconds, 1),
                round(self.time.high_seconds, 1),
            ],
            "time_range": self.time.range_text,
            "time_model": self.time.model,
            "time_range_is": "the model's range (the documented carriage speeds and overrun)",
            **({"time_check": paper_scale_text()} if self.time.preset_model else {}),
            "bind_off_time_seconds": round(self.time.bind_off_seconds, 1),
            "bind_off_time": format_duration(self.time.bind_off_seconds),
            "lines": self.knitout.n_lines,
            # (only when asked for: the summary of a plain pattern stays as it was)
            **({"split_bumps": self.split_bumps} if self.split_bumps else {}),
            **self._bumps(),
            **(
                {"tall_bump_tucks": int(self.stitches.tuck_first.sum())}
                if self.stitches.tuck_first is not None
                else {}
            ),
        }
        return _with_pass_splits(_on_kc(out, self.kc_figures), self)


def _with_pass_splits(summary: dict[str, Any], result: KnitResult) -> dict[str, Any]:
    """``summary`` with ``passes_by_kind`` (the headline ``passes`` split by what each pass
    does; the parts sum to ``passes``) and ``passes_by_part`` (the schedule's own passes split
    by the part of the piece they knit; the parts sum to ``schedule_passes``, or to ``passes``
    when the schedule's passes are the headline's). A pass is in one part of each split; the
    two splits cut the same passes two ways (a bind-off pass is also a knit or a transfer)."""
    s = summary
    kc = result.kc_figures
    kinds: dict[str, int]
    if kc is not None:
        kinds = dict(kc.run.kinds)
    else:
        kinds = {
            "knit": s["knit_passes"],
            "transfer": s["transfer_passes"],
            "carrier move": s["miss_passes"],
        }
        if s.get("schedule_passes") is not None:  # counted on the SWG machine's passes
            kinds.update({"hook": s["hook_passes"], "kickback": s["kickbacks"]})
    kinds["other"] = s["passes"] - sum(kinds.values())
    own = result.schedule.stats
    parts = {
        "cast-on": own.cast_on_passes,
        "body": own.body_passes,
        "bind-off": own.bind_off_passes,
    }
    parts["other"] = own.passes - sum(parts.values())
    return {
        **s,
        "passes_by_kind": {k: v for k, v in kinds.items() if v},
        "passes_by_part": {k: v for k, v in parts.items() if v},
        "schedule_passes": own.passes,
    }


def passes_text(summary: dict[str, Any]) -> str:
    """One line: the headline passes as the sum of their kinds, and the schedule's passes as
    the sum of the parts of the piece (both add up; see :meth:`KnitResult.summary`)."""
    s = summary
    kinds = " + ".join(f"{k} {v}" for k, v in s["passes_by_kind"].items())
    parts = " + ".join(f"{k} {v}" for k, v in s["passes_by_part"].items())
    on_kc = s.get("passes_counted_on") == "kc"
    if s["schedule_passes"] == s["passes"] and not on_kc:
        return f"passes: {s['passes']} = {kinds}; by part: {parts}"
    where, adds = (
        ("its .kc", "the .kc adds the waste section and the backend's carriage moves")
        if on_kc
        else ("the machine", "the machine adds hook passes and kickbacks")
    )
    return (
        f"passes: {s['passes']} on {where} = {kinds}; the schedule's {s['schedule_passes']} "
        f"by part: {parts} ({adds})"
    )


def _on_kc(summary: dict[str, Any], kc: KcFigures | None) -> dict[str, Any]:
    """``summary`` with its headline passes and time the ``.kc``'s (unchanged without one)."""
    if kc is None:
        return summary
    out = dict(summary)
    t = kc.time
    out["passes"] = kc.passes
    out["time_seconds"] = round(t.seconds, 1)
    out["time"] = format_duration(t.seconds)
    out["time_range"] = t.range_text
    out["time_range_seconds"] = [round(t.low_seconds, 1), round(t.high_seconds, 1)]
    out["bind_off_time_seconds"] = round(t.bind_off_seconds, 1)
    out["bind_off_time"] = format_duration(out["bind_off_time_seconds"])
    out["schedule_passes"] = summary["passes"]
    out["schedule_time"] = summary["time"]
    out["passes_counted_on"] = "kc"
    # the lower bound and ratio are the schedule's (the .kc adds the waste section)
    out["schedule_lower_bound"] = out.pop("lower_bound")
    out["schedule_ratio"] = out.pop("ratio")
    return out


def knit_pattern(
    pattern: LogicalPattern,
    *,
    machine: str | MachineSpec | None = None,
    options: KnitOptions | None = None,
    **knobs: Any,
) -> KnitResult:
    """Compile a logical pattern to a knitout program.

    Patterns with one colour per course go to :func:`~illuknit.knit.schedule.schedule_courses`;
    patterns that change colour inside a course to the mixed-colourwork scheduler
    :func:`~illuknit.knit.mixed.schedule_mixed`, to which the switches of
    :class:`~illuknit.knit.options.KnitOptions` other than ``cast_on_courses`` and
    ``tall_bumps`` (which shape the stitches, for both schedulers) apply.

    Parameters
    ----------
    pattern : LogicalPattern
    machine : str or MachineSpec, optional
        A preset name (``"swg091n2"``, ``"kniterate"``, ...) or a spec; defaults to the generic
        540-needle V-bed with the SWG091N2's rules
        (:data:`~illuknit.core.machine.DEFAULT_MACHINE`). Read by
        :func:`~illuknit.core.machine.resolve_machine`.
    options : KnitOptions, optional
        How to knit (defaults: ``KnitOptions()``). With ``allow_long_floats=False`` (the
        default) a float that stays longer than ``machine.float_limit`` after tucking is
        refused; with True it is kept, reported in :meth:`KnitResult.summary` and warned about.
    **knobs
        Shorthand for fields of ``options`` (``knit_pattern(p, catching="plate")`` is
        ``knit_pattern(p, options=KnitOptions(catching="plate"))``); they replace those fields
        of ``options`` when both are given.

    Returns
    -------
    KnitResult

    Warns
    -----
    LongFloatWarning
        With ``allow_long_floats=True``, when floats longer than the limit are kept: how many,
        the longest's length, carrier, needles and course.

    Raises
    ------
    LongFloatError
        If a float stays longer than the float limit after tucking (a course with more yarn
        regions than the machine has carriers to keep them apart), unless ``allow_long_floats``.
    CarrierShortageError
        If a course needs more carriers at once than the machine has.
    SchedulingError
        If the pattern is wider than the bed or has more yarns than carriers.
    """
    if not isinstance(pattern, LogicalPattern):
        raise PatternValidationError(
            f"`pattern` must be a LogicalPattern, got {type(pattern).__name__}"
        )
    m = resolve_machine(machine)
    opts = _knit_options(options, knobs)
    plan_machine = _planning_machine(m)
    stitches = lower_to_stitches(
        pattern,
        machine=plan_machine,
        cast_on_courses=opts.cast_on_courses,
        tall_bumps=opts.tall_bumps,
    )
    bumps = bumps_comment(split=int(pattern.split.sum()), tall=stitches.tuck_first is not None)
    program, schedule = _lowered(
        _schedule(stitches, m, plan_machine, opts), m, prelude=() if bumps is None else (bumps,)
    )
    # One float truth: the floats reported (and refused) are the program's, measured as the
    # checker measures them (the scheduler was told to keep them: the program decides, once).
    limit = plan_machine.float_limit
    facts = program_float_facts(program, schedule, limit)
    long = facts.long
    schedule = replace(schedule, long_floats=long)
    if refuses_long_floats(long, opts):
        raise long_float_error(long, stitches, limit)
    result = _measured(program, stitches, schedule, m, split=int(pattern.split.sum()), floats=facts)
    if schedule.long_floats:
        warnings.warn(LongFloatWarning(long_float_warning(result)), stacklevel=2)
    return result


def _planning_machine(m: MachineSpec) -> MachineSpec:
    """The machine the scheduler plans with: ``m`` itself, or without an inserting hook ``m``
    less the carriers of the waste yarn and draw thread (the scheduler then plans with the
    others only, and refuses a plan that needs more)."""
    if m.inserting_hook:
        return m
    return replace(m, carriers=m.pattern_carriers, waste_carrier=None, draw_carrier=None)


def _lowered(
    schedule: Schedule, m: MachineSpec, *, prelude: tuple[str, ...]
) -> tuple[KnitoutProgram, Schedule]:
    """The knitout program of ``schedule`` on ``m`` (``prelude`` after its header) and the
    schedule it runs, whose step indices its operations carry: on a machine without an
    inserting hook, the waste section first and the schedule lowered to match."""
    if m.inserting_hook:
        return lower_to_knitout(schedule, machine=m, prelude=prelude), schedule
    return lower_hookless_knitout(schedule, machine=m, prelude=prelude)


def _measured(
    program: KnitoutProgram,
    stitches: StitchPattern,
    schedule: Schedule,
    m: MachineSpec,
    *,
    split: int = 0,
    floats: FloatFacts | None = None,
) -> KnitResult:
    """The result with its passes and time: on a Shima, what the machine runs for ``program``
    (not the schedule's own passes); ``split`` is its count of split bumps, ``floats`` its
    float figures."""
    if runs_on_swg(m):
        run = machine_run(program)
        return KnitResult(
            program,
            stitches,
            schedule,
            machine_stats(schedule, run),
            estimate_knit_time(schedule, run=run),
            m,
            split,
            floats,
        )
    return KnitResult(
        program, stitches, schedule, schedule.stats, estimate_knit_time(schedule), m, split, floats
    )


def _schedule(
    stitches: StitchPattern, m: MachineSpec, plan_machine: MachineSpec, opts: KnitOptions
) -> Schedule:
    """Schedule the stitches on ``plan_machine`` (``m`` less its reserved carriers); a carrier
    shortage on a machine without an inserting hook says which carriers are reserved."""
    try:
        if stitches.mixed_courses().size:
            # (Long floats are judged by knit_pattern, on the program as written: a machine
            # without an inserting hook adds the waste section, and its yarns enter from there.)
            schedule = schedule_mixed(
                stitches,
                machine=plan_machine,
                options=replace(opts, allow_long_floats=True),
                yarn_entry=None if m.inserting_hook else yarn_entry(m),
            )
        else:
            schedule = schedule_courses(stitches, machine=plan_machine)
    except SchedulingError as e:
        if m.inserting_hook or type(e) not in (SchedulingError, CarrierShortageError):
            raise
        reserved = (
            f"; on the {m.label} carriers {m.draw_carrier} and {m.waste_carrier} hold the draw "
            f"thread and the waste yarn, leaving {len(plan_machine.carriers)} for the pattern"
        )
        if isinstance(e, CarrierShortageError):
            raise CarrierShortageError(
                f"{e}{reserved}", course=e.course, needed=e.needed, available=e.available
            ) from None
        raise SchedulingError(f"{e}{reserved}") from None
    return schedule


def _knit_options(options: KnitOptions | None, knobs: dict[str, Any]) -> KnitOptions:
    """``options`` with the shorthand ``knobs`` in place of its fields (one validation)."""
    if options is not None and not isinstance(options, KnitOptions):
        raise OptionError(f"`options` must be a KnitOptions, got {type(options).__name__}")
    base = KnitOptions() if options is None else options
    unknown = sorted(set(knobs) - {f.name for f in fields(KnitOptions)})
    if unknown:
        valid = ", ".join(f.name for f in fields(KnitOptions))
        raise OptionError(f"unknown knitting option {unknown[0]!r}; valid: {valid}")
    if "catching" in knobs and isinstance(knobs["catching"], bool):
        # the scheduler's old spelling: True (tuck joins) / False (no joins)
        knobs = {**knobs, "catching": Catching.TUCK if knobs["catching"] else Catching.OFF}
    return replace(base, **knobs) if knobs else base


def long_float_warning(result: KnitResult) -> str:
    """What the :class:`LongFloatWarning` of ``result`` says: how many floats
    stay over the float limit, how long the longest is and where (empty when none)."""
    # not from summary(): that converts a Kniterate program to .kc, which this needs not
    count = len(result.schedule.long_floats)
    if not count:
        return ""
    longest, at = result._longest_float()
    return (
        f"{count} float(s) longer than the float limit of "
        f"{result.machine.float_limit} {FLOAT_UNIT} kept (allowed long floats); the longest, "
        f"{longest} {FLOAT_UNIT}: {at}"
    )
