"""Run a solve in a child process whose time and memory the parent enforces, as the MaxSAT
Evaluation enforces them on a solver.

Solvers written in C can crash the interpreter, ignore a time limit (several hermax solvers
refuse one) or eat the machine's memory; python-sat's RC2 even rewrites the formula it is handed.
:func:`run_in_child` forks a child that runs the solve on its own copy of everything and sends
back progress events and the answer through a pipe. The parent watches the child's **whole
process tree** -- the child, its own children, and programs they start in sessions of their own
(external MaxSAT binaries, hermax's workers) -- and

* **time**: at ``time_limit`` (plus ``ask_delay``, time for a backend honouring its own limit to
  return) it asks the child to stop with ``SIGINT`` -- the Python ``KeyboardInterrupt`` every
  backend turns into "return the best assignment so far", which python-sat's C oracles honour
  too, and on which the external-solver backend sends ``SIGTERM`` to its binary. After
  ``grace`` more seconds it kills the whole tree (``SIGKILL``, status ``timeout``). An answer
  that arrives after ``time_limit`` is kept but marked ``late``: a proof after the limit is a
  timeout, as the Evaluation counts it.
* **memory**: it samples the resident memory of the whole tree every :data:`POLL` seconds and
  kills the tree when it exceeds ``memory_mb`` (status ``memout``). As a backstop against an
  allocation faster than the sampling, the child also sets ``RLIMIT_AS`` to its own address
  space at the fork plus ``memory_mb`` (inherited by everything it starts); an allocation
  refused there surfaces as a ``MemoryError`` (status ``memout``) or as a crash of the program
  that made it. (A cgroup would account memory exactly; the machines this runs on do not
  always let a process create one, so the tree sampling is the one mechanism everywhere.)
* **CPU**: it records the CPU seconds (user + system) of the tree: the child's own resource
  usage (which includes the programs it waited for) or, when larger, the sum of the last
  sampled CPU time of every process seen in the tree.
* turns a crash or a silent exit (no answer on the pipe) into status ``error`` with the reason
  (the signal, or the exit code).

So a misbehaving solver costs one result, never the caller's process. The child is started with
``os.fork`` itself (not :mod:`multiprocessing`), so it also works inside daemonic worker
processes such as a Dask worker's. Linux (``/proc``, ``psutil``); elsewhere memory is not
enforced.
"""

from __future__ import annotations

import contextlib
import faulthandler
import multiprocessing as mp
import os
import shutil
import signal
import tempfile
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from illuknit.solvers.base import ProgressCallback, ProgressEvent

__all__ = ["ChildResult", "child_memory_limit", "run_in_child"]

#: Seconds of polling between memory samples.
POLL = 0.1

#: True inside a child: a nested child (a backend isolating itself inside a benchmark run) stays
#: in the outer child's process group, so killing the outer group kills it too.
_IN_CHILD = False

#: The memory limit (MB) the enclosing run enforces, seen from inside the child (None outside).
_MEMORY_MB: float | None = None


def child_memory_limit() -> float | None:
    """The memory limit (MB) of the isolated run this code executes in, or None outside one."""
    return _MEMORY_MB


@dataclass(frozen=True)
class ChildResult:
    """What came back from the child.

    ``status`` is ``ok`` (``value`` holds the function's return value), ``timeout`` (killed
    after the time limit and the grace period), ``memout`` (the tree's resident memory passed
    the limit, or an allocation was refused) or ``error`` (raised, crashed or exited silently;
    ``reason`` says which). ``events`` are the progress events the child sent, re-timed by the
    parent (seconds since the child started). ``answered_at`` is when the answer arrived
    (seconds since the start, None without one) and ``late`` says it arrived after
    ``time_limit``. ``cpu_time`` is the tree's CPU seconds (user + system).
    """

    status: str
    value: Any
    reason: str
    wall_time: float
    peak_rss_mb: float | None
    events: tuple[ProgressEvent, ...] = ()
    cpu_time: float | None = None
    answered_at: float | None = None
    late: bool = False


_SUBREAPER: bool | None = None


def become_subreaper() -> bool:
    """Make this process a child subreaper (Linux ``prctl(PR_SET_CHILD_SUBREAPER)``): a
    process a run leaves behind -- a double-forked helper whose parent exited -- is adopted by
    this process instead of init, so the run's watch still sees it, counts its memory, kills it
    and reaps it. True when this process is one (once set, it stays)."""
    global _SUBREAPER
    if _SUBREAPER is None:
        _SUBREAPER = False
        try:
            import ctypes
            import sys

            if sys.platform.startswith("linux"):
                libc = ctypes.CDLL(None, use_errno=True)
                _SUBREAPER = libc.prctl(36, 1, 0, 0, 0) == 0  # PR_SET_CHILD_SUBREAPER
        except (OSError, AttributeError):
            _SUBREAPER = False
    return _SUBREAPER


def _children_of_self() -> set[int]:
    """Pids of this process's children now (/proc; empty elsewhere)."""
    try:
        import psutil

        return {p.pid for p in psutil.Process().children(recursive=False)}
    except Exception:
        return set()


def _set_memory_backstop(memory_mb: float) -> None:
    """RLIMIT_AS = this process's address space now + ``memory_mb`` (see the module docstring)."""
    try:
        import resource

        import psutil

        vms = psutil.Process().memory_info().vms
        limit = int(vms + memory_mb * 2**20)
        _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        if hard != resource.RLIM_INFINITY:
            limit = min(limit, hard)
        resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    except (ImportError, OSError, ValueError):
        pass  # no backstop; the parent's sampling still enforces the limit


def _child(
    fn: Callable[[ProgressCallback], Any],
    conn: Any,
    own_group: bool,
    memory_mb: float | None,
    interruptible: bool = True,
    run_dir: str | None = None,
) -> None:
    global _IN_CHILD, _MEMORY_MB
    _IN_CHILD = True
    _MEMORY_MB = memory_mb
    if run_dir is not None:  # every temporary file of the run (and of what it starts) goes here
        import tempfile

        tempfile.tempdir = run_dir
        os.environ["TMPDIR"] = run_dir
    faulthandler.disable()  # a crash is the row's reason, not a traceback on the parent's stderr
    if own_group:
        os.setpgrp()  # one process group: the parent can kill anything the solver starts
    asked: list[int] = []

    def on_sigint(signum: int, frame: Any) -> None:
        if not asked:  # the first request to stop interrupts the solve; later ones are ignored
            asked.append(signum)
            raise KeyboardInterrupt

    signal.signal(signal.SIGINT, on_sigint if interruptible else signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if memory_mb is not None:
        _set_memory_backstop(memory_mb)
    try:

        def progress(event: ProgressEvent) -> None:
            conn.send(("event", event))

        value = fn(progress)
        conn.send(("done", value))
    except MemoryError as e:
        conn.send(("memout", str(e) or "an allocation was refused (MemoryError)"))
    except BaseException as e:  # the child reports everything; the parent decides
        tb = traceback.format_exception_only(type(e), e)[-1].strip()
        if asked or isinstance(e, KeyboardInterrupt) or "keyboard interrupt" in tb.lower():
            # stopped at the limit: python-sat's C code catches SIGINT itself (our handler never
            # runs) and raises its own exceptions ("Caught keyboard interrupt"), encodings too
            conn.send(("timeout", f"stopped at the limit without an answer ({tb})"))
        else:
            conn.send(("error", f"raised {tb}"))
    finally:
        conn.close()


class _Tree:
    """The child's process tree as the parent samples it (psutil; nothing without it)."""

    def __init__(self, pid: int, others: set[int] | None = None) -> None:
        self.pid = pid
        #: the caller's children that are not this run's (any other child it adopts is an
        #: orphan of this run: the caller is a subreaper, see :func:`become_subreaper`)
        self.others = set() if others is None else set(others)
        self.seen: dict[int, float] = {}  # pid -> create time, for a safe kill later
        self.cpu: dict[int, float] = {}  # pid -> last sampled user + system seconds
        self.peak: float | None = None
        try:
            import psutil

            self._psutil: Any = psutil
            self.root: Any = psutil.Process(pid)
        except Exception:  # no psutil, or the child is already gone
            self._psutil = None
            self.root = None

    def sample(self) -> float | None:
        """Resident memory (MB) of the tree now; also remembers members and CPU times."""
        if self._psutil is None:
            return None
        ps = self._psutil
        try:
            procs = self.members()
        except ps.Error:
            return None
        total = 0
        for p in procs:
            try:
                with p.oneshot():
                    total += p.memory_info().rss
                    t = p.cpu_times()
                    self.cpu[p.pid] = max(self.cpu.get(p.pid, 0.0), t.user + t.system)
                    self.seen.setdefault(p.pid, p.create_time())
            except ps.Error:
                continue
        mb = total / 2**20
        if mb > 0:
            self.peak = mb if self.peak is None else max(self.peak, mb)
        return mb

    def adopted(self) -> list[Any]:
        """The run's orphans this (subreaper) process adopted, with their descendants."""
        out: list[Any] = []
        for p in self._psutil.Process().children(recursive=False):
            if p.pid != self.pid and p.pid not in self.others:
                out.append(p)
                with contextlib.suppress(self._psutil.Error):
                    out.extend(p.children(recursive=True))
        return out

    def members(self) -> list[Any]:
        """Every process of the run now: the child, its descendants, the adopted orphans."""
        procs = [self.root]
        with contextlib.suppress(self._psutil.Error):
            procs.extend(self.root.children(recursive=True))
        return procs + self.adopted()

    def reap(self) -> None:
        """Wait for the adopted orphans killed at the end (they are this process's children
        now: without a wait they stay zombies)."""
        end = time.monotonic() + 2.0
        pending = {pid for pid in self.seen if pid != self.pid and pid not in self.others}
        while pending and time.monotonic() < end:
            for pid in list(pending):
                try:
                    got, _ = os.waitpid(pid, os.WNOHANG)
                except ChildProcessError:  # not ours (a grandchild its parent reaps) or gone
                    pending.discard(pid)
                    continue
                if got == pid:
                    pending.discard(pid)
            if pending:
                time.sleep(0.01)

    def kill(self, own_group: bool) -> None:
        """SIGKILL the child's group and every process ever seen in the tree (by identity)."""
        with contextlib.suppress(ProcessLookupError, PermissionError):
            if own_group:
                os.killpg(self.pid, signal.SIGKILL)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(self.pid, signal.SIGKILL)  # also before it made its group
        if self._psutil is None:
            return
        if self.root is not None:
            with contextlib.suppress(Exception):
                for p in self.members()[1:]:
                    self.seen.setdefault(p.pid, p.create_time())
        for pid, created in self.seen.items():
            if pid == self.pid:
                continue
            try:
                p = self._psutil.Process(pid)
                if p.create_time() == created:  # never a process that reused the id
                    p.kill()
            except Exception:
                continue

    def ask_to_stop(self, sig: int) -> None:
        """Send ``sig`` to the child only (its backend forwards the request to what it runs)."""
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(self.pid, sig)


def _exit_reason(status: int | None) -> tuple[str, str]:
    """(status, reason) of a child that exited without an answer."""
    if status is None:
        return "error", "the child process did not exit"
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        try:
            name = signal.Signals(sig).name
        except ValueError:
            name = f"signal {sig}"
        return "error", f"crashed ({name})"
    return "error", f"exited with code {os.WEXITSTATUS(status)} without an answer"


def _reap(pid: int, timeout: float) -> tuple[int | None, float | None]:
    """(wait status, CPU seconds of the child and what it waited for) within ``timeout``."""
    end = time.monotonic() + timeout
    while True:
        try:
            got, status, usage = os.wait4(pid, os.WNOHANG)
        except ChildProcessError:
            return None, None
        if got == pid:
            return status, usage.ru_utime + usage.ru_stime
        if time.monotonic() >= end:
            return None, None
        time.sleep(0.01)


def run_in_child(
    fn: Callable[[ProgressCallback], Any],
    *,
    time_limit: float | None,
    memory_mb: float | None = None,
    grace: float | None = None,
    ask_delay: float | None = None,
    on_event: ProgressCallback | None = None,
    interruptible: bool = True,
) -> ChildResult:
    """Run ``fn(progress)`` in a forked child; see the module docstring.

    Parameters
    ----------
    fn : callable
        Called in the child with a progress callback; its return value must pickle.
    time_limit : float or None
        Seconds the function is allowed. At ``time_limit + ask_delay`` the child is asked to
        stop (SIGINT); at ``time_limit + grace`` its tree is killed.
    memory_mb : float, optional
        Most resident memory of the child's process tree.
    grace : float, optional
        Seconds after ``time_limit`` before the kill (default ``3 + 0.1 * time_limit``: a
        stopped backend still needs to hand back its best assignment).
    ask_delay : float, optional
        Seconds after ``time_limit`` before the request to stop (default ``1 + 0.03 *
        time_limit``, less than ``grace``).
    on_event : callable, optional
        Called in the parent with each progress event as it arrives.
    interruptible : bool
        False for a function that stops at its own limit and must not be interrupted (a C
        solver handed a time limit: an interrupt would only lose its answer); the child then
        ignores the request to stop, and only the kill at ``time_limit + grace`` ends it.

    A ``KeyboardInterrupt`` in the caller while it waits (Ctrl-C, or the request to stop of an
    enclosing run) is passed on to the child as its request to stop, and the wait goes on until
    the child answers or the grace period ends -- so a nested isolation still hands back the
    answer its solver gives when stopped.
    """
    if grace is None:
        grace = 3.0 if time_limit is None else 3.0 + 0.1 * time_limit
    if ask_delay is None:
        ask_delay = 0.0 if time_limit is None else 1.0 + 0.03 * time_limit
    ask_delay = min(ask_delay, 0.5 * grace)
    ctx = mp.get_context("fork")  # only its Pipe: the child is started with os.fork below
    recv, send = ctx.Pipe(duplex=False)
    own_group = not _IN_CHILD
    become_subreaper()
    others = _children_of_self()
    run_dir = tempfile.mkdtemp(prefix="illuknit-run-")
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:  # the child: never returns into the caller's code
        code = 0
        try:
            recv.close()
            _child(fn, send, own_group, memory_mb, interruptible, run_dir)
        except BaseException:
            code = 1
        finally:
            os._exit(code)
    send.close()
    watch = _Watch(pid, recv, t0, time_limit, grace, memory_mb, on_event, others)
    try:
        watch.run(ask_delay)
    finally:
        wall = time.perf_counter() - t0 if watch.answered_at is None else watch.answered_at
        watch.tree.kill(own_group)
        if watch.exit_status is None:
            watch.exit_status, watch.cpu_child = _reap(pid, 5.0)
        watch.tree.reap()
        recv.close()
        shutil.rmtree(run_dir, ignore_errors=True)  # on every exit path, a kill included
    tree = watch.tree
    cpu = max(
        [c for c in (watch.cpu_child, sum(tree.cpu.values()) or None) if c is not None],
        default=None,
    )
    answered_at = watch.answered_at
    late = answered_at is not None and time_limit is not None and answered_at > time_limit
    return ChildResult(
        watch.status,
        watch.value,
        watch.reason,
        wall,
        tree.peak,
        tuple(watch.events),
        cpu_time=cpu,
        answered_at=answered_at,
        late=late,
    )


class _Watch:
    """The parent's side of one child: it polls the pipe, enforces the limits on the process
    tree, and keeps what it saw (status, answer, reason, events, exit status)."""

    def __init__(
        self,
        pid: int,
        recv: Any,
        t0: float,
        time_limit: float | None,
        grace: float,
        memory_mb: float | None,
        on_event: ProgressCallback | None,
        others: set[int] | None = None,
    ) -> None:
        self.pid, self.recv, self.t0 = pid, recv, t0
        self.time_limit, self.grace, self.memory_mb = time_limit, grace, memory_mb
        self.on_event = on_event
        self.tree = _Tree(pid, others)
        self.events: list[ProgressEvent] = []
        self.status, self.value, self.reason = "error", None, ""
        self.answered_at: float | None = None
        self.exit_status: int | None = None
        self.cpu_child: float | None = None

    def run(self, ask_delay: float) -> None:
        """Wait for the answer: ask the child to stop at ``time_limit + ask_delay``, kill it
        at ``time_limit + grace`` (or past the memory limit). A ``KeyboardInterrupt`` here is
        passed on to the child as its request to stop, with the grace period to answer."""
        limit = self.time_limit
        ask_at = None if limit is None else self.t0 + limit + ask_delay
        deadline = None if limit is None else self.t0 + limit + self.grace
        while True:
            try:
                now = time.perf_counter()
                if deadline is not None and now >= deadline:
                    self.status = "timeout"
                    self.reason = f"no answer within {limit:g} s + {self.grace:g} s (then killed)"
                    return
                if ask_at is not None and now >= ask_at:
                    self.tree.ask_to_stop(signal.SIGINT)
                    ask_at = None
                wait = POLL if deadline is None else max(0.0, min(POLL, deadline - now))
                if self._poll(wait):
                    return
            except KeyboardInterrupt:
                # asked to stop ourselves (Ctrl-C, or an enclosing run's request): ask the
                # child, and give it the grace period to answer
                self.tree.ask_to_stop(signal.SIGINT)
                ask_at = None
                end = time.perf_counter() + self.grace
                deadline = end if deadline is None else min(deadline, end)

    def _poll(self, wait: float) -> bool:
        """One poll of the pipe and one memory sample; True once the run is over."""
        got = self.recv.poll(wait)
        rss = self.tree.sample()
        if self.memory_mb is not None and rss is not None and rss > self.memory_mb:
            self.status = "memout"
            self.reason = (
                f"memory limit: {rss:.0f} MB resident in the process tree > {self.memory_mb:g} MB"
            )
            return True
        if not got:
            return False
        try:
            msg = self.recv.recv()
        except (EOFError, OSError):
            self.exit_status, self.cpu_child = _reap(self.pid, 1.0)
            self.status, self.reason = _exit_reason(self.exit_status)
            return True
        if msg[0] == "event":
            ev = msg[1]
            ev = ProgressEvent(time.perf_counter() - self.t0, ev.objective, ev.bound, ev.message)
            self.events.append(ev)
            if self.on_event is not None:
                self.on_event(ev)
            return False
        if msg[0] == "done":
            self.status, self.value = "ok", msg[1]
            self.answered_at = time.perf_counter() - self.t0
        elif msg[0] == "timeout":
            self.status = "timeout"
            self.reason = f"no answer within {self.time_limit:g} s: {msg[1]}"
        else:
            self.status = "memout" if msg[0] == "memout" else "error"
            self.reason = str(msg[1])
        return True
