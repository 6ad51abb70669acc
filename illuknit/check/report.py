"""The checker's result: findings with line numbers, as data, JSON and human text.

A :class:`Finding` is one problem at one line: a stable ``code`` (documented in
``docs/checker.md``), a severity (``"error"`` blocks knitting, ``"warning"`` does not) and a
message saying what is wrong and how to fix it. :class:`CheckReport` gathers the findings of
illuknit's own checks and, when asked, of the PyPI virtual knitting machine (``source="vm"``).
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from illuknit.knitout.floats import is_long_float

if TYPE_CHECKING:
    from illuknit.knitout.floats import Float

__all__ = ["SEVERITIES", "CheckReport", "Finding", "float_figures", "float_line", "render_report"]

SEVERITIES = ("error", "warning")


@dataclass(frozen=True, order=True)
class Finding:
    """One problem of a knitout program.

    Attributes
    ----------
    line : int
        1-based line of the source text (0 when the problem has no line).
    code : str
        Stable identifier such as ``face-float`` or ``xfer-misaligned``.
    severity : str
        ``"error"`` (blocking) or ``"warning"``.
    message : str
        What is wrong, in one line.
    source : str
        ``"illuknit"`` for illuknit's own checks, ``"vm"`` for the PyPI simulator.
    """

    line: int
    code: str
    severity: str
    message: str
    source: str = "illuknit"

    def __post_init__(self) -> None:
        if self.severity not in SEVERITIES:
            raise ValueError(f"`severity` must be one of {SEVERITIES}, got {self.severity!r}")
        if self.line < 0:
            raise ValueError(f"`line` must be >= 0, got {self.line}")
        if not self.code:
            raise ValueError("`code` must be a non-empty string")

    @property
    def blocking(self) -> bool:
        """True for errors."""
        return self.severity == "error"

    def to_dict(self) -> dict[str, Any]:
        return {
            "line": self.line,
            "code": self.code,
            "severity": self.severity,
            "message": self.message,
            "source": self.source,
        }


@dataclass(frozen=True)
class CheckReport:
    """Everything the checker found in one program.

    Attributes
    ----------
    findings : tuple of Finding
        Sorted by line, then code.
    pieces : int
        Separate pieces of fabric in the loop/yarn graph (1 for a good program, 0 if no loop).
    n_lines : int
        Lines of the program.
    n_operations : int
        Instructions of the program.
    n_loops : int
        Loops the program makes.
    suppressed : dict of str to int
        Findings per code that were counted but not listed (a systematic error repeats).
    vm : dict or None
        Summary of the PyPI simulator run when ``simulate=True`` (``ran``, ``seconds``,
        ``versions``, ``pieces`` or ``reason`` when it could not run).
    machine : dict or None
        The machine judged against: ``name`` (what it is:
        :attr:`~illuknit.core.machine.MachineSpec.label`), ``model`` (the ``;;Machine`` whose
        rules it has), ``needles``, ``gauge``, ``max_racking``, ``float_limit``.
    floats : dict or None
        The program's floats, in needles skipped (``unit``; the slots strictly between two
        loops of one carrier): ``longest`` with its ``longest_line`` and ``longest_carrier``,
        ``at_limit`` (exactly ``limit``: allowed, as long as a float may be) and
        ``over_limit`` (the ``long-float`` warnings).
    bumps : str or None
        The bumps the program was judged as having, and why (declared by the program or asked
        for); None for a program that declares none and was not asked about.
    """

    findings: tuple[Finding, ...]
    pieces: int
    n_lines: int = 0
    n_operations: int = 0
    n_loops: int = 0
    suppressed: dict[str, int] = field(default_factory=dict)
    vm: dict[str, Any] | None = None
    machine: dict[str, Any] | None = None
    floats: dict[str, Any] | None = None
    bumps: str | None = None

    def __post_init__(self) -> None:
        if self.pieces < 0:
            raise ValueError(f"`pieces` must be >= 0, got {self.pieces}")
        object.__setattr__(self, "findings", tuple(sorted(self.findings)))

    @property
    def blocking(self) -> tuple[Finding, ...]:
        """The findings that must be fixed before knitting (errors)."""
        return tuple(f for f in self.findings if f.blocking)

    @property
    def warnings(self) -> tuple[Finding, ...]:
        """Findings that do not block."""
        return tuple(f for f in self.findings if not f.blocking)

    @property
    def n_blocking(self) -> int:
        """How many blocking findings there are, counting those not listed (``suppressed``)."""
        return len(self.blocking) + self._suppressed_count(blocking=True)

    @property
    def n_warnings(self) -> int:
        """How many warnings there are, counting those not listed (``suppressed``)."""
        return len(self.warnings) + self._suppressed_count(blocking=False)

    def _suppressed_count(self, *, blocking: bool) -> int:
        # A code is suppressed only after many listed findings of it, which carry its severity.
        severity = {f.code: f.blocking for f in self.findings}
        return sum(n for code, n in self.suppressed.items() if severity.get(code, True) == blocking)

    @property
    def ok(self) -> bool:
        """True when nothing blocks."""
        return not self.blocking

    def codes(self) -> Counter[str]:
        """How often each code occurs (listed findings plus suppressed ones)."""
        c = Counter(f.code for f in self.findings)
        c.update(self.suppressed)
        return c

    def to_dict(self) -> dict[str, Any]:
        return {
            "ok": self.ok,
            "blocking": self.n_blocking,
            "warnings": self.n_warnings,
            "pieces": self.pieces,
            "lines": self.n_lines,
            "operations": self.n_operations,
            "loops": self.n_loops,
            "suppressed": dict(self.suppressed),
            "vm": self.vm,
            "machine": self.machine,
            "floats": self.floats,
            "bumps": self.bumps,
            "findings": [f.to_dict() for f in self.findings],
        }

    def to_text(self, *, name: str = "program") -> str:
        """The human-readable report as plain text (no colour markup)."""
        from rich.text import Text

        return Text.from_markup(render_report(self, name=name)).plain

    def to_json(self, *, indent: int | None = 2) -> str:
        """The report as JSON (see :meth:`to_dict` for the keys)."""
        return json.dumps(self.to_dict(), indent=indent)


def render_report(report: CheckReport, *, name: str = "program", max_per_code: int = 20) -> str:
    """Human-readable text of ``report`` (rich markup), at most ``max_per_code`` lines per code."""
    from rich.markup import escape

    out: list[str] = []
    shown: Counter[str] = Counter()
    hidden: Counter[str] = Counter()
    for f in report.findings:
        key = f"{f.source}:{f.code}"
        if shown[key] >= max_per_code:
            hidden[key] += 1
            continue
        shown[key] += 1
        style = "bold red" if f.blocking else "yellow"
        src = "" if f.source == "illuknit" else f" [dim]({escape(f.source)})[/dim]"
        where = f"{escape(name)}:{f.line}" if f.line else f"{escape(name)} (file)"
        out.append(
            f"{where}: [{style}]{f.severity}[/{style}] "
            f"[bold]{escape(f.code)}[/bold]{src}: {escape(f.message)}"
        )
    for key, n in sorted(hidden.items()):
        out.append(f"[dim]... {n} more {escape(key.split(':', 1)[1])} finding(s) not shown[/dim]")
    for code, n in sorted(report.suppressed.items()):
        out.append(f"[dim]... {n} more {escape(code)} finding(s) counted, not listed[/dim]")
    verdict = (
        "[bold green]OK[/bold green]: nothing blocking"
        if report.ok
        else f"[bold red]BLOCKED[/bold red]: {report.n_blocking} blocking finding(s)"
    )
    out.append(
        f"{verdict}; {report.n_warnings} warning(s); {report.pieces} piece(s); "
        f"{report.n_operations} operations, {report.n_loops} loops"
    )
    if report.machine is not None:
        m = report.machine
        out.append(
            f"[dim]machine {escape(str(m['name']))}: {m['needles']} needles, gauge {m['gauge']:g}, "
            f"racking <= {m['max_racking']:g}, float limit {m['float_limit']}[/dim]"
        )
    if report.floats is not None:
        out.append(float_line(report.floats))
    if report.bumps is not None:
        out.append(f"bumps: {escape(report.bumps)}")
    if report.vm is not None:
        if report.vm.get("ran"):
            out.append(
                f"[dim]PyPI simulator ({escape(str(report.vm.get('versions', '')))}): "
                f"{report.vm.get('findings', 0)} finding(s) in {report.vm.get('seconds', 0):.2f} s[/dim]"
            )
        else:
            out.append(
                f"[dim]PyPI simulator not run: {escape(str(report.vm.get('reason', '')))}[/dim]"
            )
    return "\n".join(out)


def float_figures(floats: Sequence[Float], limit: int) -> dict[str, Any]:
    """The :attr:`CheckReport.floats` of a program whose floats are ``floats``."""
    longest = max(floats, key=lambda f: f.length, default=None)
    return {
        "unit": "needles skipped",
        "limit": limit,
        "longest": 0 if longest is None else longest.length,
        "longest_line": None if longest is None else longest.line,
        "longest_carrier": None if longest is None else longest.carrier,
        "at_limit": sum(f.length == limit for f in floats),
        "over_limit": sum(is_long_float(f.length, limit) for f in floats),
    }


def float_line(floats: dict[str, Any]) -> str:
    """One line of :attr:`CheckReport.floats`: the longest float and the counts at and over
    the limit, in needles skipped."""
    if not floats["longest"]:
        return f"floats: none skips a needle (float limit {floats['limit']} needles skipped)"
    return (
        f"floats: longest {floats['longest']} "
        f"{'needle' if floats['longest'] == 1 else 'needles'} skipped "
        f"(line {floats['longest_line']}, "
        f"carrier {floats['longest_carrier']}); {floats['at_limit']} at the float limit of "
        f"{floats['limit']}, {floats['over_limit']} over it"
    )
