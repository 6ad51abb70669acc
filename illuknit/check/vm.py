"""A second opinion: run the program on the PyPI virtual knitting machine.

``knitout-interpreter`` 0.1.8 with ``virtual-knitting-machine`` 0.0.31 (the ``sim`` extra:
``pip install 'illuknit[sim]'``) simulate the Shima SWG091N2 with its own rules. Their grammar is
narrower than knitout, so :func:`rewrite_for_vm` feeds them a lightly rewritten copy and keeps a
map from each rewritten line back to the original one:

* ``;;Width``, ``;;X-...``, ``;;Yarn-N`` headers not of the form ``int-int word`` and a
  ``;;Machine`` other than ``SWG091N2`` (the one machine it models; a Kniterate program is run on
  it as it is) become comments; ``stitch``, ``amiss`` and ``x-*`` operations become comments;
* multi-carrier ``in``/``inhook``/``releasehook``/``out``/``outhook`` lines are split into one
  line per carrier (the interpreter then sees a busy hook on the second part: findings on those
  extra lines are rewrite artefacts and dropped);
* tabs become spaces, and when any needle is negative every needle is shifted right so that the
  leftmost one is 0.

The executor normally stops at the first violation. Here every relaxable violation is set to
*warn* and collected with its line; violations it cannot relax (a misaligned transfer, ...) are
recorded and the offending instruction skipped, so one run reports everything. The packages are
imported only inside :func:`run_vm`; without them it raises :class:`BackendUnavailableError`.
"""

from __future__ import annotations

import re
import time
import warnings
from dataclasses import dataclass
from typing import Any

from illuknit.check.report import Finding
from illuknit.core.errors import BackendUnavailableError
from illuknit.knitout.parse import CARRIER_OPS, KnitoutProgram, parse_needle

__all__ = ["Rewrite", "VmResult", "rewrite_for_vm", "run_vm"]

_YARN_OK = re.compile(r"^\d+-\d+ \w+$")
_DROP_OPS = ("stitch", "amiss")

#: VM warning classes that report something the machine cannot do (-> error); other VM warnings
#: (knit on an empty needle, long floats) stay warnings.
_VM_ERRORS = {
    "Passed_Machine_Error_Warning",
    "Needle_Holds_Too_Many_Loops",
    "In_Active_Carrier_Warning",
    "Out_Inactive_Carrier_Warning",
    "Mismatched_Releasehook_Warning",
    "Duplicate_Carriers_In_Set",
    "Xfer_Dropped_Loop_Warning",
}


@dataclass(frozen=True)
class Rewrite:
    """The text given to the VM and, per rewritten line (0-based), the original 1-based line.

    ``extra[i]`` is True for the second and later parts of a split multi-carrier line.
    """

    text: str
    origin: tuple[int, ...]
    extra: tuple[bool, ...]
    shift: int


@dataclass(frozen=True)
class VmResult:
    """Findings of the VM (``source="vm"``), its piece count, run time and versions."""

    findings: tuple[Finding, ...]
    pieces: int | None
    seconds: float
    versions: str


def rewrite_for_vm(text: str, program: KnitoutProgram) -> Rewrite:
    """Rewrite knitout ``text`` (already parsed as ``program``) into the VM's dialect."""
    lines = text.replace("\r\n", "\n").split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    min_index = min((n.index for op in program.operations for n in op.needles), default=0)
    shift = -min_index if min_index < 0 else 0
    header_end = max((ln for _, _, ln in program.headers), default=1)
    out: list[str] = []
    origin: list[int] = []
    extra: list[bool] = []

    def emit(s: str, ln: int, is_extra: bool = False) -> None:
        out.append(s)
        origin.append(ln)
        extra.append(is_extra)

    for i, raw in enumerate(lines):
        ln = i + 1
        line = raw.replace("\t", " ")
        if 1 < ln <= header_end:
            m = re.match(r"^;;([^:]+): (.*)$", line)
            if m is not None:
                name, value = m.group(1), m.group(2).strip()
                if (
                    name == "Width"
                    or (name == "Machine" and value != "SWG091N2")
                    or name.startswith("X-")
                    or (name.startswith("Yarn-") and not _YARN_OK.match(value))
                ):
                    emit(f"; (illuknit: header hidden from the VM) {name}", ln)
                    continue
            emit(line, ln)
            continue
        body, sep, comment = line.partition(";")
        tokens = body.split()
        if ln == 1 or not tokens:
            emit(line, ln)
            continue
        op = tokens[0]
        if op in _DROP_OPS or op.startswith("x-"):
            emit(f"; (illuknit: hidden from the VM) {op}", ln)
            continue
        if op in CARRIER_OPS and len(tokens) > 2:
            for k, c in enumerate(tokens[1:]):
                emit(f"{op} {c}", ln, k > 0)
            continue
        if shift:
            new_tokens = []
            for t in tokens:
                n = parse_needle(t)
                new_tokens.append(f"{n.bed}{n.index + shift}" if n is not None else t)
            tokens = new_tokens
        emit(" ".join(tokens) + (f" ;{comment}" if sep and comment.strip() else ""), ln)
    return Rewrite("\n".join(out) + "\n", tuple(origin), tuple(extra), shift)


def _versions() -> str:
    from importlib.metadata import PackageNotFoundError, version

    parts = []
    for pkg in ("knitout-interpreter", "virtual-knitting-machine"):
        try:
            parts.append(f"{pkg} {version(pkg)}")
        except PackageNotFoundError:  # pragma: no cover - import succeeded, metadata missing
            parts.append(f"{pkg} ?")
    return ", ".join(parts)


def _clean(message: str) -> str:
    return " ".join(message.split())


def _error_text(e: Exception) -> str:
    # The interpreter prefixes its 0-based "line N: <instruction>" context; keep the reason only.
    text = str(e)
    if "\n:\n" in text:
        text = text.split("\n:\n", 1)[1]
    return _clean(text)


def run_vm(text: str, program: KnitoutProgram) -> VmResult:
    """Simulate ``text`` with knitout-interpreter / virtual-knitting-machine.

    Raises
    ------
    BackendUnavailableError
        When the ``sim`` extra is not installed.
    """
    try:
        from knitout_interpreter.knitout_execution import Knitout_Executer
        from knitout_interpreter.knitout_language.Knitout_Parser import parse_knitout
        from virtual_knitting_machine.machine_state_violation_handling.machine_state_violations import (
            Violation,
        )
    except ImportError as e:
        raise BackendUnavailableError(
            "the PyPI knitout simulator is not installed (knitout-interpreter, "
            f"virtual-knitting-machine: {e}); install it with: pip install 'illuknit[sim]'"
        ) from None

    rw = rewrite_for_vm(text, program)
    findings: list[Finding] = []
    seen: set[tuple[int, str, str]] = set()

    def add(vm_line: int | None, code: str, severity: str, message: str) -> None:
        if vm_line is not None and 0 <= vm_line < len(rw.origin):
            if rw.extra[vm_line]:
                return  # artefact of splitting a multi-carrier line
            line = rw.origin[vm_line]
        else:
            line = 0
        key = (line, code, message)
        if key not in seen:
            seen.add(key)
            findings.append(Finding(line, code, severity, message, source="vm"))

    t0 = time.perf_counter()
    recorded: list[warnings.WarningMessage] = []

    class _Executer(Knitout_Executer):
        """Executer that warns on every violation and skips instructions it cannot execute."""

        def relax_validation_policy(
            self, violations: Any = Violation, include_warnings: bool = True
        ) -> None:
            super().relax_validation_policy(violations, include_warnings=True)

        def _run_recorded(self, method: Any, instruction: Any) -> Any:
            line = getattr(instruction, "original_line_number", None)
            n0 = len(recorded)
            try:
                return method(instruction)
            except Exception as e:  # the VM's own machine-state errors: record, skip, go on
                cause = e.__cause__ if e.__cause__ is not None else e
                add(line, f"vm-{type(cause).__name__}", "error", _error_text(e))
                return None
            finally:
                for w in recorded[n0:]:
                    if not hasattr(w, "vm_line"):  # innermost instruction wins
                        w.vm_line = line  # type: ignore[attr-defined]

        def _execute_and_add_instruction(self, instruction: Any) -> None:
            self._run_recorded(super()._execute_and_add_instruction, instruction)

        def _process_next_instruction(self, instruction: Any) -> None:
            self._run_recorded(super()._process_next_instruction, instruction)

    pieces: int | None = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        recorded = caught
        try:
            lines = parse_knitout(rw.text, pattern_is_file=False)
        except Exception as e:
            msg = _clean(str(e))
            m = re.search(r"line (\d+)", msg)
            add(int(m.group(1)) if m else None, "vm-parse", "error", f"VM cannot parse: {msg}")
            lines = None
        if lines is not None:
            try:
                ex = _Executer(lines, relax_violations=True)
                pieces = _count_pieces(ex.resulting_knit_graph)
            except Exception as e:  # crash outside an instruction
                add(None, f"vm-{type(e).__name__}", "error", _clean(str(e)))
    for w in recorded:
        cat = w.category.__name__
        if cat in ("ResourceWarning", "DeprecationWarning", "PendingDeprecationWarning"):
            continue
        msg = _clean(str(w.message))
        inner = getattr(w.message, "exception", None)
        code = f"vm-{type(inner).__name__}" if inner is not None else f"vm-{cat}"
        severity = "error" if cat in _VM_ERRORS else "warning"
        add(getattr(w, "vm_line", None), code, severity, msg)
    seconds = time.perf_counter() - t0
    return VmResult(tuple(findings), pieces, seconds, _versions())


def _count_pieces(kg: Any) -> int:
    """Connected components of the VM's knit graph (stitch edges plus yarn order)."""
    parent: dict[int, int] = {}

    def find(a: int) -> int:
        parent.setdefault(a, a)
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    def union(a: Any, b: Any) -> None:
        ra, rb = find(id(a)), find(id(b))
        if ra != rb:
            parent[ra] = rb

    keep: list[Any] = []  # keep loops alive so id() stays unique
    for p, c, _ in kg.stitch_iter:  # a property in knit-graphs 0.1.4
        keep += [p, c]
        union(p, c)
    for yarn in kg.yarns:
        prev = None
        for loop in yarn:
            keep.append(loop)
            find(id(loop))
            if prev is not None:
                union(prev, loop)
            prev = loop
    return len({find(a) for a in list(parent)})
