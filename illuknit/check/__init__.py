"""The knitout checker: does this program knit, and does it make the fabric you meant?

Stages, one module each::

    text -> illuknit.knitout.parse_knitout -> KnitoutProgram
         -> simulate.simulate_program -> Simulation        (illuknit's machine model)
         -> rules.check_header + rules.machine_findings      (what the machine refuses)
         -> fabric.fabric_findings                           (what the machine accepts but ruins)
         -> [vm.run_vm]                                      (PyPI simulator, second opinion)
         -> report.CheckReport

:func:`check_knitout` runs them all. It reads knitout text, so it checks programs from any
generator, not just illuknit's; a program illuknit made is read as it is, without its text.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from illuknit.check.report import CheckReport, Finding, float_figures, render_report
from illuknit.core.arguments import check_bool, check_number, check_str
from illuknit.core.errors import OptionError
from illuknit.knitout.bumps import DeclaredBumps, declared_bumps
from illuknit.knitout.parse import KnitoutProgram, parse_knitout

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec

__all__ = [
    "CheckReport",
    "Finding",
    "check_knitout",
    "render_report",
]


def check_knitout(
    text: str | KnitoutProgram,
    *,
    machine: MachineSpec | str | None = None,
    float_limit: int | None = None,
    max_racking: float | None = None,
    bed_width: int | None = None,
    simulate: bool = False,
    split_bumps: bool | None = None,
) -> CheckReport:
    """Check a knitout program for machine-rule violations and fabric failures.

    The machine's limits (bed width, racking, float limit, carriers, model) are those of
    ``machine``; without one, of the machine the program's headers name
    (:func:`~illuknit.core.machine.machine_from_headers`): a program made for a preset is judged
    by that preset's rules, the same ones its scheduler used.

    Parameters
    ----------
    text : str or KnitoutProgram
        The knitout program: its text (parsed here: a file's edge) or the program itself
        (:func:`~illuknit.knitting.knit_pattern`'s ``KnitResult.knitout``), read as it is.
    machine : MachineSpec or str or None, keyword-only
        The machine, or a preset name (:data:`~illuknit.core.machine.MACHINES`); None reads it
        from the program's headers.
    float_limit : int or None, keyword-only
        Override of ``machine.float_limit``: longest float (needle slots crossed between two loops
        of one carrier) before a ``long-float`` warning. Must be >= 1.
    max_racking : float or None, keyword-only
        Override of ``machine.max_racking``: largest allowed |racking|.
    bed_width : int or None, keyword-only
        Override of the needles per bed (above the machine's range: ``MachineValueError``);
        None uses the ``;;Width`` header when present, else the machine's.
    simulate : bool, keyword-only
        Also run the PyPI knitout-interpreter / virtual-knitting-machine (needs the ``sim`` extra)
        and add its findings with ``source="vm"``. Slow on large programs.
    split_bumps : bool or None, keyword-only
        The program knits split bumps: a yarn change inside a bump is meant (no error). None
        (the default) reads it from the program: a program that declares its split bumps
        (:mod:`illuknit.knitout.bumps`, as every program ``knit_pattern`` writes does) is
        judged as one; the report's ``bumps`` says which and why.

    Returns
    -------
    CheckReport
        ``report.blocking`` lists what must be fixed; ``report.pieces`` counts separate pieces;
        ``report.machine`` names the machine judged against.

    Raises
    ------
    KnitoutParseError
        Binary input, a bad magic line, or a malformed instruction (with its line number).
    OptionError
        For out-of-range options.
    UnknownNameError
        For an unknown machine name.
    BackendUnavailableError
        ``simulate=True`` without the ``sim`` extra installed.

    Examples
    --------
    >>> report = check_knitout(open("swatch.k").read(), machine="swg091n2")  # doctest: +SKIP
    >>> [(f.line, f.code) for f in report.blocking]  # doctest: +SKIP
    [(42, 'face-float')]
    """
    _check_arguments(text, simulate, split_bumps)
    if max_racking is not None:
        check_number(max_racking, "max_racking", min=0, min_open=True)
    from illuknit.check.fabric import fabric_findings
    from illuknit.check.rules import check_header, machine_findings
    from illuknit.check.simulate import simulate_program
    from illuknit.core.machine import resolve_machine

    _check_options(float_limit=float_limit, max_racking=max_racking, bed_width=bed_width)
    named = None if machine is None else resolve_machine(machine)  # before any parsing
    program = text if isinstance(text, KnitoutProgram) else parse_knitout(text)
    spec = _judging_machine(program, named)
    racking = spec.max_racking if max_racking is None else max_racking
    limit = spec.float_limit if float_limit is None else float_limit
    width = _bed_width(program, spec, bed_width)
    sim = simulate_program(program, max_racking=racking, bed_width=width)
    findings = [*check_header(program, machine=spec), *machine_findings(sim)]
    declared = declared_bumps(program)
    split = bool(declared.split if split_bumps is None else split_bumps)
    fabric, suppressed = fabric_findings(sim, float_limit=limit, split_bumps=split)
    vm_findings, vm_summary = _second_opinion(program) if simulate else ([], None)
    return CheckReport(
        findings=(*findings, *fabric, *vm_findings),
        pieces=sim.pieces,
        n_lines=program.n_lines,
        n_operations=len(program.operations),
        n_loops=len(sim.loop_lines),
        suppressed={**sim.suppressed, **suppressed},
        vm=vm_summary,
        machine=_machine_info(spec, width, racking, limit),
        floats=float_figures(sim.floats, limit),
        bumps=_bumps_note(declared, split_bumps),
    )


def _bumps_note(declared: DeclaredBumps, split_bumps: bool | None) -> str | None:
    """What the report says about the bumps it judged, and why (None: plain, undeclared)."""
    if split_bumps is None:
        return f"{declared.text()}, as the program declares" if declared else None
    if not split_bumps and not declared.split:
        return f"{declared.text()}, as the program declares" if declared else None
    said = "split bumps" if split_bumps else "no split bumps"
    if bool(declared.split) != bool(split_bumps):
        return f"{said} as asked, though the program declares {declared.text()}"
    return (
        f"{said}, as asked and as the program declares" if declared.split else f"{said}, as asked"
    )


def _machine_info(spec: MachineSpec, width: int, racking: float, limit: int) -> dict[str, Any]:
    """The report's machine: ``name`` says what it is (a bed of another width than ``spec``'s,
    e.g. ``bed_width``, is a generic bed with its rules), ``model`` the ``;;Machine`` rules."""
    generic = f"generic {width}-needle V-bed ({spec.name} rules)"
    return {
        "name": spec.label if width == spec.needles else generic,
        "model": spec.name,
        "needles": width,
        "gauge": spec.gauge,
        "max_racking": racking,
        "float_limit": limit,
    }


def _bed_width(program: KnitoutProgram, spec: MachineSpec, bed_width: int | None) -> int:
    """The bed width to simulate: ``bed_width`` (refused above the machine's range; a bed
    narrower than any machine's is a checking aid), else ``;;Width`` when the machine takes it,
    else the machine's (an absurd ``;;Width`` is a ``machine-value`` error, not a bed)."""
    from illuknit.core.machine_ranges import check_machine_value, ranges_for

    needles = ranges_for(spec.runs_on())["needles"]
    if bed_width is not None:
        if bed_width > needles.high:
            check_machine_value("needles", bed_width, backend=spec.runs_on())
        return bed_width
    width = program.width
    if width is None or not needles.contains(width):
        return spec.needles
    return width


def _judging_machine(program: KnitoutProgram, named: MachineSpec | None) -> MachineSpec:
    """The machine ``program`` is judged against: the one named, else the one its headers name
    (the first of each header counts)."""
    from illuknit.core.machine import machine_from_headers

    if named is not None:
        return named
    return machine_from_headers({name: value for name, value, _ in reversed(program.headers)})


def _check_arguments(text: object, simulate: object, split_bumps: object) -> None:
    if not isinstance(text, KnitoutProgram):
        check_str(text, "text")
    check_bool(simulate, "simulate")
    if split_bumps is not None:
        check_bool(split_bumps, "split_bumps")


def _check_options(
    *, float_limit: int | None, max_racking: float | None, bed_width: int | None
) -> None:
    if float_limit is not None and (
        isinstance(float_limit, bool) or not isinstance(float_limit, int) or float_limit < 1
    ):
        raise OptionError(f"`float_limit` must be an integer >= 1, got {float_limit!r}")
    if max_racking is not None and not max_racking > 0:
        raise OptionError(f"`max_racking` must be > 0, got {max_racking!r}")
    if bed_width is not None and (
        isinstance(bed_width, bool) or not isinstance(bed_width, int) or bed_width < 1
    ):
        raise OptionError(f"`bed_width` must be a positive integer, got {bed_width!r}")


def _second_opinion(program: KnitoutProgram) -> tuple[list[Finding], dict[str, Any]]:
    """The PyPI simulator's findings (``source="vm"``) and the report's summary of its run
    (it reads text: the program is formatted for it)."""
    from illuknit.check.vm import run_vm
    from illuknit.knitout.program import format_knitout

    result = run_vm(format_knitout(program), program)
    summary = {
        "ran": True,
        "seconds": round(result.seconds, 3),
        "versions": result.versions,
        "pieces": result.pieces,
        "findings": len(result.findings),
    }
    return list(result.findings), summary
