"""Any MaxSAT solver binary, through a WCNF file (solver name ``wcnf:COMMAND``).

The model is written in the MaxSAT Evaluation format (:meth:`Model.to_wcnf`, 2022+ style by
default; construct ``ExternalWCNFBackend(cmd, style="old")`` for solvers that need the pre-2022
``p wcnf`` header), then ``COMMAND`` runs with the file path substituted for ``{}`` (or appended when
there is no ``{}``). Its standard output is parsed as the Evaluation prescribes:

* ``s OPTIMUM FOUND`` / ``s SATISFIABLE`` / ``s UNSATISFIABLE`` / ``s UNKNOWN``;
* ``o COST`` lines (the last one counts);
* ``v`` lines: either the 2022+ single binary string (``v 0110...``, variable i is character i)
  or classic literal lists (``v 1 -2 3 ... 0``, possibly over several lines).

The returned assignment is checked against the model and its objective recomputed, so a solver
that lies is reported as an ``error``. On the time limit (or Ctrl-C) the child gets SIGTERM (most
solvers then print their best model), then SIGKILL after a grace period; the last ``o``/``v``
lines printed are the answer. Every ``o`` line is reported as a progress event when it is
printed, so the cost-over-time trace keeps each improvement the solver announced.
"""

from __future__ import annotations

import contextlib
import os
import shlex
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from illuknit.core.errors import SolverError
from illuknit.solvers.base import (
    BackendBase,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
)

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = ["ExternalWCNFBackend", "parse_maxsat_output"]

#: seconds between SIGTERM and SIGKILL
GRACE = 1.5


def _bad(line: str, why: str) -> SolverError:
    return SolverError(f"solver printed a malformed 'v' line ({why}): {line[:60]!r}")


def _read_v_line(line: str, nv: int, lits: list[int]) -> str | None:
    """One ``v`` line: its binary string (returned), or its literals (added to ``lits``)."""
    body = line[1:].split()
    if len(body) == 1 and set(body[0]) <= {"0", "1"} and (len(body[0]) > 1 or nv == 1):
        if len(body[0]) != nv:
            raise _bad(line, f"{len(body[0])} values for {nv} variables")
        return body[0]
    try:
        nums = [int(t) for t in body]
    except ValueError:
        raise _bad(line, "not a binary string nor literals") from None
    for x in nums:
        if x == 0:
            continue
        if abs(x) > nv:
            raise _bad(line, f"literal {x} out of range 1..{nv}")
    lits.extend(nums)
    return None


def parse_maxsat_output(text: str, nv: int) -> tuple[str | None, int | None, np.ndarray | None]:
    """(status word, last ``o`` cost, bool values indexed by id of length nv + 1) from solver output.

    ``nv`` is the number of variables of the WCNF file the solver read. The ``v`` line is read
    as strictly as the MaxSAT Evaluation reads it: a binary string must have exactly ``nv``
    characters, a literal must lie in 1..nv and appear in one polarity only, and the answer is
    one ``v`` line (a literal list may continue over several lines until its ``0``); anything
    else raises :class:`SolverError` naming the fault.
    """
    status: str | None = None
    cost: int | None = None
    bits: str | None = None
    lits: list[int] = []
    closed = False  # a complete answer has been read: a further v line is a second answer
    for raw in text.splitlines():
        line = raw.strip()
        if line.startswith("s "):
            status = line[2:].strip().upper()
        elif line.startswith("o "):
            try:
                cost = int(line[2:].split()[0])
            except (ValueError, IndexError):
                raise SolverError(f"solver printed a malformed cost line: {line[:60]!r}") from None
        elif line.startswith("v"):
            if closed or bits is not None:
                raise _bad(line, "a second 'v' line")
            if (got := _read_v_line(line, nv, lits)) is not None:
                if lits:
                    raise _bad(line, "a binary string after literals")
                bits = got
            closed = bool(lits) and lits[-1] == 0
    values = None
    if bits is not None:
        values = np.zeros(nv + 1, dtype=bool)
        values[1:] = np.frombuffer(bits.encode(), dtype=np.uint8) == ord("1")
    elif lits:
        a = np.asarray([x for x in lits if x != 0], dtype=np.int64)
        both = np.intersect1d(a[a > 0], -a[a < 0])
        if both.size:
            raise SolverError(
                f"solver printed a malformed 'v' line (variable {int(both[0])} in both polarities)"
            )
        values = np.zeros(nv + 1, dtype=bool)
        values[a[a > 0]] = True
    return status, cost, values


class ExternalWCNFBackend(BackendBase):
    """Runs a user-named MaxSAT solver command on a WCNF file."""

    #: the file formats carry no lower bound back
    proves_bound = False

    def __init__(self, command: str, *, style: str = "new") -> None:
        self.command = command.strip()
        self.name = f"wcnf:{self.command}"
        self.style = style
        try:
            self.argv = shlex.split(self.command)
        except ValueError as e:
            raise SolverError(f"cannot parse solver command {self.command!r}: {e}") from None

    def unavailable_reason(self) -> str | None:
        if not self.argv:
            return "no solver command given after 'wcnf:'"
        exe = self.argv[0]
        if shutil.which(exe) is not None or (Path(exe).is_file() and os.access(exe, os.X_OK)):
            return None
        return f"external solver binary {exe!r} not found (not on PATH and not a file)"

    def version(self) -> str:
        return f"external: {self.argv[0]}" if self.argv else ""

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        t0 = time.perf_counter()
        if not self.is_available():
            raise SolverError(str(self.unavailable_reason()))
        with tempfile.TemporaryDirectory(prefix="illuknit-wcnf-") as tmp:
            path = Path(tmp) / "model.wcnf"
            path.write_text(model.to_wcnf(style=self.style), encoding="ascii")
            if any("{}" in a for a in self.argv):
                argv = [a.replace("{}", str(path)) for a in self.argv]
            else:
                argv = [*self.argv, str(path)]
            err_path = Path(tmp) / "stderr.txt"
            killed = interrupted = False
            lines: list[str] = []
            with open(err_path, "wb") as err:
                try:
                    proc = subprocess.Popen(
                        argv, stdout=subprocess.PIPE, stderr=err, start_new_session=True
                    )
                except OSError as e:
                    raise SolverError(f"cannot run external solver {argv[0]!r}: {e}") from None
                reader = threading.Thread(
                    target=_read_lines, args=(proc, lines, t0, progress), daemon=True
                )
                reader.start()
                try:
                    proc.wait(timeout=time_limit)
                except subprocess.TimeoutExpired:
                    killed = True
                    _stop(proc)
                except KeyboardInterrupt:
                    interrupted = True
                    _stop(proc)
                reader.join(timeout=GRACE)
            text = "\n".join(lines)
            err_text = err_path.read_text(errors="replace").strip()
        wall = time.perf_counter() - t0
        stats: dict[str, object] = {"returncode": proc.returncode, "interrupted": interrupted}
        nv = _file_variables(model)
        try:
            status_word, cost, values = parse_maxsat_output(text, nv)
        except SolverError as e:
            stats["message"] = str(e)
            return Solution(Status.ERROR, None, None, None, wall, stats, self.name, model.pool)
        if status_word == "UNSATISFIABLE":
            stats["claimed_status"] = status_word
            return Solution(Status.INFEASIBLE, None, None, None, wall, stats, self.name, model.pool)
        if values is None:
            if killed or interrupted:
                return Solution(
                    Status.TIMEOUT, None, None, None, wall, stats, self.name, model.pool
                )
            tail = (err_text or text.strip())[-200:]
            _raise_if_out_of_memory(err_text + "\n" + text, proc.returncode)
            stats["message"] = f"solver printed no assignment (exit code {proc.returncode}): {tail}"
            return Solution(Status.ERROR, None, None, None, wall, stats, self.name, model.pool)
        named = np.zeros(model.pool.top + 1, dtype=bool)  # the model's own variables
        k = min(named.size, values.size)
        named[:k] = values[:k]
        values = named
        ok, evaluated = model.evaluate(values)
        stats["claimed_cost"] = cost
        if not ok:
            stats["message"] = "the solver's assignment violates hard constraints"
            return Solution(
                Status.ERROR, values, evaluated, None, wall, stats, self.name, model.pool
            )
        stats["reported_cost"] = cost
        stats["claimed_status"] = status_word or ""
        if status_word == "OPTIMUM FOUND" and not (killed or interrupted):
            return Solution(
                Status.OPTIMAL,
                values,
                evaluated,
                float(evaluated),
                wall,
                stats,
                self.name,
                model.pool,
            )
        st = Status.TIMEOUT if killed else Status.FEASIBLE
        return Solution(st, values, evaluated, None, wall, stats, self.name, model.pool)


#: What a program says when an allocation is refused (Python, C++, C, Java).
OUT_OF_MEMORY = ("MemoryError", "std::bad_alloc", "Cannot allocate memory", "OutOfMemoryError")


def _raise_if_out_of_memory(output: str, returncode: int | None) -> None:
    """Inside a run with a memory limit (an address-space limit the solver inherited), a solver
    that died saying an allocation was refused ran out of memory: raise ``MemoryError`` so the
    run is a ``memout``, not an ``error``."""
    from illuknit.solvers.isolate import child_memory_limit

    if returncode == 0 or child_memory_limit() is None:
        return
    said = next((w for w in OUT_OF_MEMORY if w in output), None)
    if said is not None:
        raise MemoryError(
            f"the solver died with {said!r} (exit code {returncode}) under the "
            f"{child_memory_limit():g} MB limit"
        )


def _file_variables(model: Model) -> int:
    """The number of variables of the model's WCNF file (its largest variable id)."""
    cs = model.to_clauses()
    return max((abs(int(x)) for c in (*cs.hard, *cs.soft) for x in c), default=0)


def _read_lines(
    proc: subprocess.Popen[bytes],
    lines: list[str],
    t0: float,
    progress: ProgressCallback | None,
) -> None:
    """Collect the solver's output as it comes; report each ``o`` line with its time (the
    solver's claimed cost: the trace keeps every improvement it announced)."""
    assert proc.stdout is not None
    for raw in proc.stdout:
        line = raw.decode(errors="replace").rstrip("\n")
        lines.append(line)
        if progress is not None and line.startswith("o "):
            with contextlib.suppress(ValueError, IndexError):
                progress(ProgressEvent(time.perf_counter() - t0, int(line[2:].split()[0]), None))


def _stop(proc: subprocess.Popen[bytes]) -> None:
    """SIGTERM the solver's process group, then SIGKILL after the grace period. A second request
    to stop (Ctrl-C, the benchmark's SIGINT) does not cut this short: the solver's last answer
    is printed in the grace period."""
    try:
        os.killpg(proc.pid, signal.SIGTERM)
    except (ProcessLookupError, PermissionError):
        return
    end = time.monotonic() + GRACE
    while True:
        try:
            proc.wait(timeout=max(0.0, end - time.monotonic()))
            return
        except subprocess.TimeoutExpired:
            break
        except KeyboardInterrupt:
            continue
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
