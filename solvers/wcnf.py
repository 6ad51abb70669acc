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
solvers then print their best model), then SIGKILL after a grace period.
"""

from __future__ import annotations

import contextlib
import os
import shlex
import shutil
import signal
import subprocess
import tempfile
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
    from illuknit.design.models.model import Model

__all__ = ["ExternalWCNFBackend", "parse_maxsat_output"]

#: seconds between SIGTERM and SIGKILL
GRACE = 3.0


def parse_maxsat_output(text: str, nv: int) -> tuple[str | None, int | None, np.ndarray | None]:
    """(status word, last ``o`` cost, bool values indexed by id of length nv + 1) from solver output.

    Raises :class:`SolverError` on a malformed ``v`` line.
    """
    status: str | None = None
    cost: int | None = None
    bits: str | None = None
    lits: list[int] = []
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
            body = line[1:].split()
            if len(body) == 1 and set(body[0]) <= {"0", "1"} and len(body[0]) > 1:
                bits = body[0]
                continue
            if len(body) == 1 and body[0] in ("0", "1") and nv == 1 and not lits:
                bits = body[0]
                continue
            try:
                lits.extend(int(t) for t in body)
            except ValueError:
                raise SolverError(f"solver printed a malformed 'v' line: {line[:60]!r}") from None
    values = None
    if bits is not None:
        values = np.zeros(nv + 1, dtype=bool)
        b = np.frombuffer(bits.encode()[:nv], dtype=np.uint8) == ord("1")
        values[1 : 1 + b.size] = b
    elif lits:
        values = np.zeros(nv + 1, dtype=bool)
        a = np.asarray(lits, dtype=np.int64)
        a = a[(a > 0) & (a <= nv)]
        values[a] = True
    return status, cost, values


class ExternalWCNFBackend(BackendBase):
    """Runs a user-named MaxSAT solver command on a WCNF file."""

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
            out_path = Path(tmp) / "stdout.txt"
            err_path = Path(tmp) / "stderr.txt"
            killed = interrupted = False
            with open(out_path, "wb") as out, open(err_path, "wb") as err:
                try:
                    proc = subprocess.Popen(argv, stdout=out, stderr=err, start_new_session=True)
                except OSError as e:
                    raise SolverError(f"cannot run external solver {argv[0]!r}: {e}") from None
                try:
                    proc.wait(timeout=time_limit)
                except subprocess.TimeoutExpired:
                    killed = True
                    _stop(proc)
                except KeyboardInterrupt:
                    interrupted = True
                    _stop(proc)
            text = out_path.read_text(errors="replace")
            err_text = err_path.read_text(errors="replace").strip()
        wall = time.perf_counter() - t0
        stats: dict[str, object] = {"returncode": proc.returncode, "interrupted": interrupted}
        nv = model.pool.top
        try:
            status_word, cost, values = parse_maxsat_output(text, nv)
        except SolverError as e:
            stats["message"] = str(e)
            return Solution(Status.ERROR, None, None, None, wall, stats, self.name, model.pool)
        if status_word == "UNSATISFIABLE":
            return Solution(Status.INFEASIBLE, None, None, None, wall, stats, self.name, model.pool)
        if values is None:
            if killed or interrupted:
                return Solution(
                    Status.TIMEOUT, None, None, None, wall, stats, self.name, model.pool
                )
            tail = (err_text or text.strip())[-200:]
            stats["message"] = f"solver printed no assignment (exit code {proc.returncode}): {tail}"
            return Solution(Status.ERROR, None, None, None, wall, stats, self.name, model.pool)
        ok, evaluated = model.evaluate(values)
        stats["claimed_cost"] = cost
        if not ok:
            stats["message"] = "the solver's assignment violates hard constraints"
            return Solution(
                Status.ERROR, values, evaluated, None, wall, stats, self.name, model.pool
            )
        stats["reported_cost"] = cost
        stats["claimed_status"] = status_word or ""
        if progress:
            progress(ProgressEvent(wall, evaluated, None))
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


def _stop(proc: subprocess.Popen[bytes]) -> None:
    """SIGTERM the solver's process group, then SIGKILL after the grace period."""
    try:
        os.killpg(proc.pid, signal.SIGTERM)
    except (ProcessLookupError, PermissionError):
        return
    try:
        proc.wait(timeout=GRACE)
    except subprocess.TimeoutExpired:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
