"""Run a solve in a child process whose time and memory the parent enforces.

Solvers written in C can crash the interpreter, ignore a time limit (several hermax solvers
refuse one) or eat the machine's memory; python-sat's RC2 even rewrites the formula it is handed.
:func:`run_in_child` forks a child that runs the solve on its own copy of everything and sends
back progress events and the answer through a pipe; the parent

* kills the child's whole process group when ``time_limit + grace`` seconds pass without an answer
  (status ``timeout``), or when the resident memory of the group exceeds ``memory_mb``
  (status ``error``, "memory limit");
* turns a crash or a silent exit (no answer on the pipe) into status ``error`` with the reason
  (the signal, or the exit code);
* measures the group's peak resident memory itself.

So a misbehaving solver costs one result, never the caller's process. Linux and macOS (fork);
memory is read from ``/proc`` and is not enforced where that is missing.
"""

from __future__ import annotations

import contextlib
import faulthandler
import multiprocessing as mp
import os
import signal
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from illuknit.solvers.base import ProgressCallback, ProgressEvent

__all__ = ["ChildResult", "run_in_child"]

#: Seconds of polling between memory checks.
POLL = 0.1

#: True inside a child: a nested child (a backend isolating itself inside a benchmark run) stays
#: in the outer child's process group, so killing the outer group kills it too.
_IN_CHILD = False


@dataclass(frozen=True)
class ChildResult:
    """What came back from the child.

    ``status`` is ``ok`` (``value`` holds the function's return value), ``timeout`` (killed at
    the deadline) or ``error`` (raised, crashed, exited silently or hit the memory limit;
    ``reason`` says which). ``events`` are the progress events the child sent, re-timed by the
    parent (seconds since the child started).
    """

    status: str
    value: Any
    reason: str
    wall_time: float
    peak_rss_mb: float | None
    events: tuple[ProgressEvent, ...] = ()


def _child(fn: Callable[[ProgressCallback], Any], conn: Any, own_group: bool) -> None:
    global _IN_CHILD
    _IN_CHILD = True
    faulthandler.disable()  # a crash is the row's reason, not a traceback on the parent's stderr
    if own_group:
        os.setpgrp()  # one process group: the parent can kill anything the solver starts
    try:

        def progress(event: ProgressEvent) -> None:
            conn.send(("event", event))

        value = fn(progress)
        conn.send(("done", value))
    except MemoryError:
        conn.send(("error", "out of memory (MemoryError)"))
    except BaseException as e:  # the child reports everything; the parent decides
        tb = traceback.format_exception_only(type(e), e)[-1].strip()
        conn.send(("error", f"raised {tb}"))
    finally:
        conn.close()


def _group_rss_mb(pid: int, own_group: bool) -> float | None:
    """Resident memory (MB) of every process in group ``pid`` (or of process ``pid`` alone when
    it has no group of its own); None without /proc."""
    proc = Path("/proc")
    if not proc.is_dir():
        return None
    total = 0
    for d in proc.iterdir() if own_group else [proc / str(pid)]:
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
            fields = stat[stat.rindex(")") + 2 :].split()
            if own_group and int(fields[2]) != pid:  # field 5 of /proc/PID/stat: the group
                continue
            total += int(fields[21]) * os.sysconf("SC_PAGE_SIZE")  # field 24: rss in pages
        except (OSError, ValueError, IndexError):
            continue
    return total / 2**20


def _stat(pid: int) -> tuple[int, int] | None:
    """(parent pid, start time) of process ``pid`` from /proc, or None."""
    try:
        stat = (Path("/proc") / str(pid) / "stat").read_text()
        fields = stat[stat.rindex(")") + 2 :].split()
        return int(fields[1]), int(fields[19])  # fields 4 and 22 of /proc/PID/stat
    except (OSError, ValueError, IndexError):
        return None


def _descendants(pid: int) -> dict[int, int]:
    """Every live descendant of ``pid`` with its start time (from /proc; empty without it).
    Solvers such as hermax's subprocess workers start their own sessions, out of reach of the
    process-group kill."""
    proc = Path("/proc")
    if not proc.is_dir():
        return {}
    children: dict[int, list[tuple[int, int]]] = {}
    for d in proc.iterdir():
        if d.name.isdigit() and (st := _stat(int(d.name))) is not None:
            children.setdefault(st[0], []).append((int(d.name), st[1]))
    out: dict[int, int] = {}
    todo = [pid]
    while todo:
        for c, start in children.get(todo.pop(), []):
            if c not in out:
                out[c] = start
                todo.append(c)
    return out


def _kill(pid: int, own_group: bool, others: dict[int, int]) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        if own_group:
            os.killpg(pid, signal.SIGKILL)
        else:
            os.kill(pid, signal.SIGKILL)
    for p, start in others.items():
        st = _stat(p)
        if st is None or st[1] != start:
            continue  # gone, or the id now belongs to another process: never touch that one
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(p, signal.SIGKILL)


def _exit_reason(code: int | None) -> str:
    if code is None:
        return "the child process did not exit"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"crashed ({name})"
    return f"exited with code {code} without an answer"


def run_in_child(
    fn: Callable[[ProgressCallback], Any],
    *,
    time_limit: float | None,
    memory_mb: float | None = None,
    grace: float | None = None,
    on_event: ProgressCallback | None = None,
) -> ChildResult:
    """Run ``fn(progress)`` in a forked child; see the module docstring.

    Parameters
    ----------
    fn : callable
        Called in the child with a progress callback; its return value must pickle.
    time_limit : float or None
        Seconds the function is allowed; the child is killed at ``time_limit + grace``.
    memory_mb : float, optional
        Most resident memory of the child's process group.
    grace : float, optional
        Seconds after ``time_limit`` before the kill (default ``3 + 0.1 * time_limit``: a
        backend that stops on time still needs to hand back its best assignment).
    on_event : callable, optional
        Called in the parent with each progress event as it arrives.
    """
    ctx = mp.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)
    own_group = not _IN_CHILD
    proc = ctx.Process(target=_child, args=(fn, send, own_group))
    t0 = time.perf_counter()
    proc.start()
    send.close()
    assert proc.pid is not None
    pid = proc.pid
    if grace is None:
        grace = 3.0 if time_limit is None else 3.0 + 0.1 * time_limit
    deadline = None if time_limit is None else t0 + time_limit + grace
    events: list[ProgressEvent] = []
    seen: dict[int, int] = {}  # descendants, remembered while they still hang below the child
    peak: float | None = None
    status, value, reason = "error", None, ""
    try:
        while True:
            now = time.perf_counter()
            if deadline is not None and now >= deadline:
                status, reason = "timeout", f"no answer within {time_limit:g} s + {grace:g} s"
                break
            wait = POLL if deadline is None else min(POLL, deadline - now)
            got = recv.poll(wait)
            seen.update(_descendants(pid))
            rss = _group_rss_mb(pid, own_group)
            if rss is not None and rss > 0:
                peak = rss if peak is None else max(peak, rss)
                if memory_mb is not None and rss > memory_mb:
                    reason = f"memory limit: {rss:.0f} MB resident > {memory_mb:g} MB"
                    break
            if not got:
                continue
            try:
                msg = recv.recv()
            except (EOFError, OSError):
                proc.join(timeout=1.0)
                reason = _exit_reason(proc.exitcode)
                break
            if msg[0] == "event":
                ev = msg[1]
                ev = ProgressEvent(time.perf_counter() - t0, ev.objective, ev.bound, ev.message)
                events.append(ev)
                if on_event is not None:
                    on_event(ev)
                continue
            if msg[0] == "done":
                status, value = "ok", msg[1]
            else:
                reason = str(msg[1])
            break
    finally:
        wall = time.perf_counter() - t0
        seen.update(_descendants(pid))
        _kill(pid, own_group, seen)
        proc.join(timeout=5.0)
        recv.close()
    return ChildResult(status, value, reason, wall, peak, tuple(events))
