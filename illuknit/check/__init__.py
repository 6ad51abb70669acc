"""The knitout checker: does this program knit, and does it make the fabric you meant?

Stages, one module each::

    text -> parse.parse_knitout -> KnitoutProgram
         -> simulate.simulate_program -> Simulation        (illuknit's machine model)
         -> rules.check_header + rules.machine_findings      (what the machine refuses)
         -> fabric.fabric_findings                           (what the machine accepts but ruins)
         -> [vm.run_vm]                                      (PyPI simulator, second opinion)
         -> report.CheckReport

:func:`check_knitout` runs them all. It reads knitout text only, so it checks programs from any
generator, not just illuknit's.
"""

from __future__ import annotations

from illuknit.check.parse import KnitoutProgram, parse_knitout
from illuknit.check.report import CheckReport, Finding, render_report

__all__ = [
    "CheckReport",
    "Finding",
    "KnitoutProgram",
    "check_knitout",
    "parse_knitout",
    "render_report",
]


def check_knitout(
    text: str,
    *,
    float_limit: int = 10,
    max_racking: float = 4,
    bed_width: int | None = None,
    simulate: bool = False,
) -> CheckReport:
    """Check a knitout program for machine-rule violations and fabric failures.

    Parameters
    ----------
    text : str
        The knitout program.
    float_limit : int, keyword-only
        Longest float (needle slots crossed between two loops of one carrier) before a
        ``long-float`` warning. Must be >= 1.
    max_racking : float, keyword-only
        Largest allowed |racking| (4 for the SWG091N2 as the PyPI simulator models it).
    bed_width : int or None, keyword-only
        Needles per bed; None uses the ``;;Width`` header when present.
    simulate : bool, keyword-only
        Also run the PyPI knitout-interpreter / virtual-knitting-machine (needs the ``sim`` extra)
        and add its findings with ``source="vm"``. Slow on large programs.

    Returns
    -------
    CheckReport
        ``report.blocking`` lists what must be fixed; ``report.pieces`` counts separate pieces.

    Raises
    ------
    KnitoutParseError
        Binary input, a bad magic line, or a malformed instruction (with its line number).
    OptionError
        For out-of-range options.
    BackendUnavailableError
        ``simulate=True`` without the ``sim`` extra installed.

    Examples
    --------
    >>> report = check_knitout(open("swatch.k").read())  # doctest: +SKIP
    >>> [(f.line, f.code) for f in report.blocking]  # doctest: +SKIP
    [(42, 'face-float')]
    """
    from illuknit.check.fabric import fabric_findings
    from illuknit.check.rules import check_header, machine_findings
    from illuknit.check.simulate import simulate_program
    from illuknit.errors import OptionError

    if isinstance(float_limit, bool) or not isinstance(float_limit, int) or float_limit < 1:
        raise OptionError(f"`float_limit` must be an integer >= 1, got {float_limit!r}")
    if not max_racking > 0:
        raise OptionError(f"`max_racking` must be > 0, got {max_racking!r}")
    if bed_width is not None and (
        isinstance(bed_width, bool) or not isinstance(bed_width, int) or bed_width < 1
    ):
        raise OptionError(f"`bed_width` must be a positive integer, got {bed_width!r}")

    program = parse_knitout(text)
    sim = simulate_program(program, max_racking=max_racking, bed_width=bed_width)
    findings = [*check_header(program), *machine_findings(sim)]
    fabric, suppressed = fabric_findings(sim, float_limit=float_limit)
    findings += fabric
    suppressed = {**sim.suppressed, **suppressed}
    vm_summary = None
    if simulate:
        from illuknit.check.vm import run_vm

        result = run_vm(text, program)
        findings += result.findings
        vm_summary = {
            "ran": True,
            "seconds": round(result.seconds, 3),
            "versions": result.versions,
            "pieces": result.pieces,
            "findings": len(result.findings),
        }
    return CheckReport(
        findings=tuple(findings),
        pieces=sim.pieces,
        n_lines=program.n_lines,
        n_operations=len(program.operations),
        n_loops=len(sim.loop_lines),
        suppressed=suppressed,
        vm=vm_summary,
    )
