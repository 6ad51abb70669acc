"""Background jobs of the design app: long work with progress, cancellable from the page.

A :class:`Job` wraps one function ``fn(job) -> result`` run on a small thread pool. The function
reports progress with :meth:`Job.report`, which is also where a cancellation request takes effect
(cooperative cancellation: it raises :class:`JobCancelled` between stages). Work that is one long
library call with no stages of its own (compiling knitout, simulating it) goes through
:meth:`Job.run_isolated`, which runs the call in a separate Python process that is killed when the
job is cancelled, so cancelling really stops the CPU work instead of abandoning a thread.

Jobs never raise into the server: a failure is stored as ``error`` (message, and the input
``field`` that caused it when the failure is the user's) and shown by the page.
"""

from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
import threading
import time
import traceback
import uuid
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal

from illuknit.core.errors import AppRequestError, IlluknitError

__all__ = ["Job", "JobCancelled", "JobRunner", "JobStatus"]

JobStatus = Literal["queued", "running", "done", "failed", "cancelled", "interrupted"]
_FINAL = ("done", "failed", "cancelled", "interrupted")
#: What a job that was running when the server stopped says once the session is read back.
INTERRUPTED = "interrupted: the server stopped while this ran; run it again"


class JobCancelled(Exception):
    """Raised inside a job function when the job has been cancelled (never escapes the runner)."""


class Job:
    """One unit of background work with progress, status and a result.

    Attributes
    ----------
    id : str
        Random id, unique per server.
    kind : str
        What the job does (``"candidates"``, ``"knit"``); at most one live job per kind per session.
    status : {"queued", "running", "done", "failed", "cancelled", "interrupted"}
        ``interrupted``: the job was live when the server stopped (a session read back from
        disk, :meth:`restored`); the page offers to run it again.
    progress : float
        0..1, monotone while running.
    message : str
        What the job is doing now (shown next to the progress bar).
    error : dict or None
        ``{"message": ..., "field": ...}`` when the job failed.
    result : object
        Whatever the job function returned (kept server-side; endpoints expose views of it).
    """

    def __init__(self, kind: str, *, revision: int = 0) -> None:
        self.id = uuid.uuid4().hex[:12]
        self.kind = kind
        self.revision = revision
        self.status: JobStatus = "queued"
        self.progress = 0.0
        self.message = "queued"
        self.error: dict[str, Any] | None = None
        self.result: Any = None
        self.created = time.time()
        self.started: float | None = None
        self.finished: float | None = None
        self._cancel = threading.Event()
        self._done = threading.Event()
        self._lock = threading.Lock()
        self._finished_callbacks: list[Callable[[Job], None]] = []

    # -- kept on disk with its session (illuknit.app.store) ----------------------------------
    def record(self) -> dict[str, Any]:
        """What is stored of the job: its state as polled (never its result, which its session
        holds, nor its thread)."""
        rec = self.to_json()
        rec["created"], rec["started"], rec["finished"] = self.created, self.started, self.finished
        return rec

    @classmethod
    def restored(cls, rec: dict[str, Any]) -> Job:
        """A stored job back, ended: one that was still queued or running is ``interrupted``."""
        job = cls(str(rec["kind"]), revision=int(rec.get("revision", 0)))
        job.id = str(rec["id"])
        job.created = float(rec.get("created") or job.created)
        job.started = rec.get("started")
        job.finished = rec.get("finished") or job.created
        job.progress = float(rec.get("progress", 0.0))
        job.error = rec.get("error")
        if rec.get("status") in _FINAL:
            job.status = rec["status"]
            job.message = str(rec.get("message", rec["status"]))
        else:
            job.status = "interrupted"
            job.message = INTERRUPTED
        job._done.set()
        return job

    def when_finished(self, fn: Callable[[Job], None]) -> None:
        """Call ``fn(job)`` once the job has ended (at once when it has)."""
        with self._lock:
            if self.status not in _FINAL:
                self._finished_callbacks.append(fn)
                return
        fn(self)

    # -- used by job functions ---------------------------------------------------------------
    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    def report(self, fraction: float, message: str | None = None) -> None:
        """Record progress; raise :class:`JobCancelled` if cancellation was requested."""
        if self._cancel.is_set():
            raise JobCancelled
        with self._lock:
            self.progress = max(self.progress, min(1.0, max(0.0, float(fraction))))
            if message is not None:
                self.message = message

    def run_isolated(
        self,
        fn: Callable[..., Any],
        *args: Any,
        poll: float = 0.05,
        tick: Callable[[float], None] | None = None,
        progress: tuple[float, float] | None = None,
    ) -> Any:
        """Run ``fn(*args)`` in a fresh Python process; kill it if the job is cancelled.

        The child is ``python -m illuknit.app.jobs`` fed ``(fn, args)`` pickled on stdin, so
        ``fn`` must be importable by name and its arguments and result picklable. (A
        ``multiprocessing`` child would re-run the parent's main script, which breaks servers
        started from unguarded scripts.) Library errors raised in the child come back as
        :class:`AppRequestError` with the original message.

        ``tick(seconds)`` is called with the time spent so far every ``poll`` seconds while the
        child works (to report progress the child cannot count for itself). With ``progress``
        ``(start, end)``, ``fn`` is called with a ``progress=`` keyword of its own, and the
        fractions it reports come back as this job's progress, mapped onto ``start..end``.
        """
        self.report(self.progress)
        payload = pickle.dumps((fn, args, progress is not None), protocol=pickle.HIGHEST_PROTOCOL)
        proc = subprocess.Popen(
            [sys.executable, "-m", "illuknit.app.jobs", str(os.getpid())],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        out: dict[str, bytes] = {}
        said: list[bytes] = []

        def talk() -> None:
            assert proc.stdin is not None and proc.stdout is not None
            try:
                proc.stdin.write(payload)
                proc.stdin.close()
            except BrokenPipeError:  # the child died at once: its stderr says why
                pass
            out["stdout"] = proc.stdout.read()

        def listen() -> None:
            assert proc.stderr is not None
            for line in proc.stderr:
                if line.startswith(_PROGRESS) and progress is not None:
                    _, fraction, message = line.rstrip(b"\n").split(b"\t", 2)
                    lo, hi = progress
                    f = lo + (hi - lo) * min(1.0, max(0.0, float(fraction)))
                    with self._lock:
                        self.progress = max(self.progress, f)
                        self.message = message.decode(errors="replace")
                else:
                    said.append(line)

        talker = threading.Thread(target=talk, name="illuknit-job-io", daemon=True)
        listener = threading.Thread(target=listen, name="illuknit-job-err", daemon=True)
        talker.start()
        listener.start()
        t0 = time.monotonic()
        try:
            while talker.is_alive():
                if self._cancel.is_set():
                    raise JobCancelled
                if tick is not None:
                    tick(time.monotonic() - t0)
                talker.join(poll)
        finally:
            if proc.poll() is None:
                proc.kill()
            talker.join(10)
            listener.join(10)
            proc.wait(10)
        data = out.get("stdout", b"")
        if not data:
            tail = b"".join(said).decode(errors="replace").strip().splitlines()[-3:]
            raise RuntimeError(
                f"worker process ended without an answer (exit code {proc.returncode}): {' | '.join(tail)}"
            )
        msg = pickle.loads(data)
        if msg[0] == "ok":
            return msg[1]
        if msg[0] == "err":
            raise AppRequestError(msg[2], code=msg[1])
        raise RuntimeError(f"{msg[1]}: {msg[2]}")

    # -- used by the runner and the server ---------------------------------------------------
    def cancel(self) -> bool:
        """Request cancellation; True if the job was still live."""
        if self.status in _FINAL:
            return False
        self._cancel.set()
        if self.status == "queued":
            self._finish("cancelled", message="cancelled")
        return True

    def wait(self, timeout: float | None = None) -> bool:
        """Block until the job ends (for tests and the CLI); True if it ended."""
        return self._done.wait(timeout)

    @property
    def live(self) -> bool:
        return self.status not in _FINAL

    def _finish(
        self, status: JobStatus, *, message: str, error: dict[str, Any] | None = None
    ) -> None:
        with self._lock:
            if self.status in _FINAL:
                return
            self.status = status
            self.message = message
            self.error = error
            self.finished = time.time()
            if status == "done":
                self.progress = 1.0
            callbacks, self._finished_callbacks = self._finished_callbacks, []
        self._done.set()
        for fn in callbacks:
            try:
                fn(self)
            except Exception:  # storing a result must not take the job runner down
                traceback.print_exc()

    def to_json(self) -> dict[str, Any]:
        with self._lock:
            return {
                "id": self.id,
                "kind": self.kind,
                "status": self.status,
                "progress": round(self.progress, 4),
                "message": self.message,
                "error": self.error,
                "revision": self.revision,
                "elapsed": round(
                    (self.finished or time.time()) - (self.started or self.created), 3
                ),
            }


class JobRunner:
    """A small thread pool running :class:`Job` functions.

    Parameters
    ----------
    workers : int
        Threads; two is right for a designer's laptop (one long job plus one quick one).
    """

    def __init__(self, workers: int = 2) -> None:
        self._pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="illuknit-job")
        self._jobs: dict[str, Job] = {}
        self._lock = threading.Lock()

    def submit(
        self,
        kind: str,
        fn: Callable[[Job], Any],
        *,
        revision: int = 0,
        on_done: Callable[[Job], None] | None = None,
    ) -> Job:
        """Queue ``fn(job)``; ``on_done(job)`` runs (in the worker) when the job ends successfully."""
        job = Job(kind, revision=revision)
        with self._lock:
            self._jobs[job.id] = job
            # forget old finished jobs so a long-running server does not grow
            if len(self._jobs) > 500:
                for jid in [j.id for j in self._jobs.values() if not j.live][:250]:
                    del self._jobs[jid]
        self._pool.submit(self._run, job, fn, on_done)
        return job

    def _run(
        self, job: Job, fn: Callable[[Job], Any], on_done: Callable[[Job], None] | None
    ) -> None:
        if job.cancelled:
            job._finish("cancelled", message="cancelled")
            return
        job.status = "running"
        job.started = time.time()
        job.message = "running"
        try:
            result = fn(job)
            if job.cancelled:
                raise JobCancelled
            job.result = result
            if on_done is not None:
                on_done(job)
            job._finish("done", message="done")
        except JobCancelled:
            job._finish("cancelled", message="cancelled")
        except AppRequestError as e:
            job._finish(
                "failed",
                message="failed",
                error={"message": str(e), "field": e.field, "code": e.code},
            )
        except IlluknitError as e:
            job._finish(
                "failed",
                message="failed",
                error={"message": str(e), "field": None, "code": type(e).__name__},
            )
        except Exception as e:  # a bug: the page still gets a message, the log the traceback
            traceback.print_exc()
            job._finish(
                "failed",
                message="failed",
                error={
                    "message": f"internal error: {type(e).__name__}: {e}",
                    "field": None,
                    "code": "internal",
                },
            )

    def shutdown(self) -> None:
        with self._lock:
            jobs = list(self._jobs.values())
        for job in jobs:
            job.cancel()
        self._pool.shutdown(wait=False, cancel_futures=True)


#: A line the child writes on stderr to report progress: marker, fraction, message (tab-separated).
_PROGRESS = b"\x00illuknit-progress"


def _die_with_parent(parent: int, poll: float = 0.2) -> None:
    """End this worker as soon as the server that started it (pid ``parent``) is gone, however
    it went (Ctrl-C, a crash, ``kill -9``): the kernel kills it on Linux (``PR_SET_PDEATHSIG``),
    and everywhere a watcher thread ends it within ``poll`` seconds of being orphaned."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # 1 = PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # no prctl: the watcher does it
            pass
    if os.getppid() != parent:  # gone before the kernel was asked
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(poll)
        os._exit(1)

    threading.Thread(target=watch, name="illuknit-parent-watch", daemon=True).start()


def _worker_main() -> None:
    """Child side of :meth:`Job.run_isolated`: read ``(fn, args)``, answer a pickled message.
    The worker ends with the server that started it (:func:`_die_with_parent`)."""
    if len(sys.argv) > 1:
        _die_with_parent(int(sys.argv[1]))
    answer = sys.stdout.buffer
    sys.stdout = sys.stderr  # anything the work prints must not corrupt the answer
    fn, args, with_progress = pickle.load(sys.stdin.buffer)
    err = sys.stderr.buffer

    def progress(fraction: float, message: str) -> None:
        line = message.replace("\n", " ").replace("\t", " ")
        err.write(_PROGRESS + f"\t{float(fraction):.4f}\t{line}\n".encode())
        err.flush()

    try:
        msg: tuple[Any, ...] = (
            "ok",
            fn(*args, progress=progress) if with_progress else fn(*args),
        )
    except IlluknitError as e:
        msg = ("err", type(e).__name__, str(e))
    except BaseException as e:  # a bug in the library: report it, the parent decides
        msg = ("bug", type(e).__name__, f"{e}\n{traceback.format_exc()}")
    answer.write(pickle.dumps(msg, protocol=pickle.HIGHEST_PROTOCOL))
    answer.flush()


if __name__ == "__main__":
    _worker_main()
