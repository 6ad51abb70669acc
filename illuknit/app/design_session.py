"""One browser tab's design session: its pictures (:class:`UploadedImage`), settings,
candidates, pick, edits, undo and redo steps and jobs (:class:`Session`).

Every change of input bumps ``revision``; derived results remember the revision they were
computed from, so a result computed from stale inputs is never shown as current. Requests of one
session are serialised by its lock. The sessions of all tabs are kept, bounded and evicted by
:class:`~illuknit.app.sessions.SessionStore`, and saved whole by
:class:`~illuknit.app.store.DiskStore`.
"""

from __future__ import annotations

import copy
import sys
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.app import history
from illuknit.app.schemas import DesignSettings

__all__ = ["Session", "UploadedImage"]


@dataclass(frozen=True)
class UploadedImage:
    """An uploaded picture, decoded and reduced to the working grid.

    Attributes
    ----------
    filename : str
        The name it was sent under.
    sent_bytes : int
        Size of the file as sent (the file itself is not kept).
    rgb : ndarray of shape (H, W, 3), uint8
        The picture on white, upright, at most ``MAX_WORKING_SIDE`` pixels on its long side.
    notes : tuple of str
        What was done while reading it (a reduction, an animation's first frame, ...).
    """

    filename: str
    sent_bytes: int
    rgb: NDArray[np.uint8]
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.rgb.dtype != np.uint8 or self.rgb.ndim != 3 or self.rgb.shape[2] != 3:
            raise ValueError(
                f"`rgb` must be uint8 of shape (H, W, 3), got {self.rgb.dtype} {self.rgb.shape}"
            )

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in pixels."""
        return (int(self.rgb.shape[1]), int(self.rgb.shape[0]))

    @property
    def nbytes(self) -> int:
        return int(self.rgb.nbytes)


@dataclass
class Session:
    """One tab's design state (mutable; guarded by ``lock``)."""

    id: str
    created: float = field(default_factory=time.time)
    last_seen: float = field(default_factory=time.time)
    images: dict[str, UploadedImage] = field(default_factory=dict)
    settings: DesignSettings = field(default_factory=DesignSettings)
    revision: int = 0
    # derived state, each stamped with the revision it came from
    prepared: Any = None  # design.Prepared
    candidates: list[Any] = field(default_factory=list)  # design.Candidate
    candidates_revision: int = -1
    selected: int = 0
    overrides: dict[tuple[int, int], str] = field(default_factory=dict)
    knit: Any = None  # design.CheckedKnitout, for pattern_key
    suggestions: Any = None  # suggestions.SuggestionSet of this revision's design
    refused: set[str] = field(default_factory=set)  # ids of refused suggestions (hidden)
    # ids of suggestion sets made for earlier designs of this session (answered 410, not 404)
    retired_suggestions: OrderedDict[str, None] = field(default_factory=OrderedDict)
    # earlier and undone designs (history.DesignState), oldest first (see illuknit.app.history)
    undo_steps: list[Any] = field(default_factory=list)
    redo_steps: list[Any] = field(default_factory=list)
    # the smallest width at which both sides read (reading.WidthsResult, with what it holds for)
    legible_widths: Any = None
    # the row tracker: the row the knitter is on, per pattern key (illuknit.app.routers.tracker)
    tracker: dict[str, int] = field(default_factory=dict)
    jobs: dict[str, Any] = field(default_factory=dict)  # kind -> Job
    # id of a replaced job -> id of the job that replaced it (a poll of the old id follows it)
    successors: dict[str, str] = field(default_factory=dict)
    lock: threading.RLock = field(default_factory=threading.RLock, repr=False)
    # -- kept in memory only (see __getstate__) --
    #: stores the session (SessionStore.save), or None when sessions are kept in memory only
    saver: Callable[[Session], None] | None = field(default=None, repr=False)
    #: requests working on it now (a session in use is never evicted from memory)
    pins: int = field(default=0, repr=False)
    #: no longer the store's copy (evicted from memory): never saved again
    detached: bool = field(default=False, repr=False)
    #: inside :meth:`changing`: the jobs the change cancels once it is saved (else None)
    cancel_on_commit: list[Any] | None = field(default=None, repr=False)

    #: Attributes that are not the designer's work: never stored.
    RUNTIME = ("lock", "saver", "pins", "detached", "cancel_on_commit")

    #: Replaced job ids remembered per session (a page polls only its latest few).
    SUCCESSORS_KEPT = 64
    #: Suggestion sets of earlier designs remembered per session.
    RETIRED_KEPT = 64

    # -- kept on disk (illuknit.app.store) ---------------------------------------------------
    def __getstate__(self) -> dict[str, Any]:
        """The session as stored: every field (a field added later is stored with no other
        change) except the runtime ones; jobs as their records (:meth:`Job.record`)."""
        state = {k: v for k, v in self.__dict__.items() if k not in self.RUNTIME}
        state["jobs"] = {kind: job.record() for kind, job in self.jobs.items()}
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        """A stored session back: fields it was stored without get their defaults, and a job
        that was still running when it was stored is *interrupted* (it can be run again)."""
        from illuknit.app.jobs import Job

        fresh = Session(id=state["id"])
        self.__dict__.update(fresh.__dict__)
        self.__dict__.update({k: v for k, v in state.items() if k in fresh.__dict__})
        self.jobs = {kind: Job.restored(rec) for kind, rec in state.get("jobs", {}).items()}

    def save(self) -> None:
        """Store the session now (nothing when it is kept in memory only, or evicted); raises
        :class:`~illuknit.app.store.SessionNotSavedError` when the disk refuses."""
        if self.saver is not None and not self.detached:
            self.saver(self)

    @contextmanager
    def changing(self) -> Iterator[None]:
        """A change of the session that is kept only once it is saved.

        The block changes the session with its lock held; the session is then stored. If the
        store refuses (a full disk, a read-only folder:
        :class:`~illuknit.app.store.SessionNotSavedError`), or the block raises, the session is
        put back as it was before the block and the error propagates: a change answered as
        failed is never kept, so no later save writes it. Jobs the change cancels (work on the
        inputs it replaces) are cancelled only once it is saved; jobs it started are cancelled
        when it is not kept. A change inside a change is part of the outer one.
        """
        with self.lock:
            if self.cancel_on_commit is not None:
                yield
                return
            before = {k: _copied(v) for k, v in self.__dict__.items() if k not in self.RUNTIME}
            self.cancel_on_commit = []
            try:
                yield
                self.save()
            except BaseException:
                self.cancel_on_commit = None
                started = [j for j in self.jobs.values() if _not_in(j, before["jobs"].values())]
                self.__dict__.update(before)
                for job in started:
                    job.cancel()
                raise
            cancelled, self.cancel_on_commit = self.cancel_on_commit, None
            for job in cancelled:
                job.cancel()

    def cancel_job(self, job: Any) -> None:
        """Cancel ``job`` now, or once the change being made is saved (:meth:`changing`)."""
        if self.cancel_on_commit is not None:
            self.cancel_on_commit.append(job)
        else:
            job.cancel()

    def _save_after_job(self) -> None:
        """Store the session with a job's result; a disk that refuses keeps the result in
        memory (the next saved change stores it), said in one line on the server's stderr."""
        from illuknit.app.store import SessionNotSavedError

        try:
            self.save()
        except SessionNotSavedError as e:
            print(
                f"illuknit app: a background job's result is kept in memory but not on disk "
                f"(the next saved change stores it): {e}",
                file=sys.stderr,
                flush=True,
            )

    def replace_job(self, kind: str, job: Any) -> None:
        """Make ``job`` the session's job of ``kind``; polls of the one it replaces follow it.
        The session is stored again when the job ends (its result is part of the session)."""
        job.when_finished(lambda _job: self._save_after_job())
        old = self.jobs.get(kind)
        if old is not None:
            if old.live:
                self.cancel_job(old)
            self.successors[old.id] = job.id
            while len(self.successors) > self.SUCCESSORS_KEPT:
                self.successors.pop(next(iter(self.successors)))
        self.jobs[kind] = job

    def find_job(self, job_id: str) -> Any | None:
        """The job ``job_id``, or the live job that (transitively) replaced it, or None."""
        seen = set()
        while job_id not in seen:
            seen.add(job_id)
            for job in self.jobs.values():
                if job.id == job_id:
                    return job
            if job_id not in self.successors:
                return None
            job_id = self.successors[job_id]
        return None

    def nbytes(self) -> int:
        """Memory the session holds: its pictures, quantised inputs, candidates, suggested edits
        (their pictures) and knitout, and those of its undo and redo steps; an array the steps
        share with the session or each other counts once."""
        held = history.held_arrays(
            images=self.images,
            prepared=self.prepared,
            candidates=self.candidates,
            suggestions=self.suggestions,
        )
        for state in (*self.undo_steps, *self.redo_steps):
            held.update(state.held())
        n = sum(held.values())
        if self.knit is not None:
            n += len(self.knit.knitout) + len(self.knit.report_text)
        return int(n)

    def set_suggestions(self, suggestions: Any) -> None:
        """Make ``suggestions`` the current set; the one it replaces is remembered as retired."""
        if self.suggestions is not None:
            self.retired_suggestions[self.suggestions.id] = None
            while len(self.retired_suggestions) > self.RETIRED_KEPT:
                self.retired_suggestions.popitem(last=False)
        self.suggestions = suggestions
        self.refused = set()

    # -- undo and redo of accepted edits (illuknit.app.history) -------------------------------
    def remember(self, label: str) -> None:
        """Keep the session's state as an undo step before a change described by ``label``
        (call with the lock held, before changing anything; the change then forgets the redo
        steps)."""
        self.undo_steps.append(self._snapshot(label))
        del self.undo_steps[: -history.STEPS_KEPT]

    def undo(self) -> str:
        """Return to the state before the last remembered change; its label (409
        ``nothing_to_undo`` when there is none)."""
        return self._step(self.undo_steps, self.redo_steps, "undo")

    def redo(self) -> str:
        """Make the last undone change again; its label (409 ``nothing_to_redo``)."""
        return self._step(self.redo_steps, self.undo_steps, "redo")

    def _step(self, source: list[Any], other: list[Any], what: str) -> str:
        if not source:
            raise history.nothing_to(what)
        state: history.DesignState = source.pop()
        other.append(self._snapshot(state.label))
        del other[: -history.STEPS_KEPT]
        self._restore(state)
        return state.label

    def _snapshot(self, label: str) -> history.DesignState:
        """The state now; candidates (and the pick, the tile edits) only when current."""
        current = self.candidates_revision == self.revision
        return history.DesignState(
            label=label,
            images=dict(self.images),
            settings=self.settings,
            prepared=self.prepared,
            candidates=tuple(self.candidates) if current else (),
            selected=self.selected if current else 0,
            overrides=dict(self.overrides) if current else {},
            suggestions=self.suggestions,
            refused=frozenset(self.refused),
        )

    def _restore(self, state: history.DesignState) -> None:
        """Make ``state`` the session's, as a new revision (work on the state left is
        cancelled, its suggestion set retired: its ids answer 410)."""
        self.cancel_design_jobs()
        self.revision += 1
        self.images = dict(state.images)
        self.settings = state.settings
        self.prepared = state.prepared
        self.candidates = list(state.candidates)
        self.candidates_revision = self.revision if state.candidates else -1
        self.selected = state.selected
        self.overrides = dict(state.overrides)
        self.knit = None
        self.set_suggestions(None)
        if state.suggestions is not None:
            self.retired_suggestions.pop(state.suggestions.id, None)
            self.suggestions = replace(state.suggestions, revision=self.revision)
        self.refused = set(state.refused)

    def touch(self) -> None:
        self.last_seen = time.time()

    def bump(self) -> None:
        """Inputs changed: derived results are stale, and what was undone cannot be redone."""
        self.revision += 1
        self.prepared = None
        self.candidates = []
        self.candidates_revision = -1
        self.selected = 0
        self.overrides = {}
        self.knit = None
        self.set_suggestions(None)
        self.redo_steps.clear()
        self.cancel_design_jobs()

    def remeasure(self) -> None:
        """The measuring viewpoint changed: the designs stand, their measures were taken from
        elsewhere. The candidates become unmeasured copies (the undo steps keep the measured
        ones, with the viewpoint they were measured from), a measures job running stops, and
        what was undone cannot be redone."""
        job = self.jobs.get("measures")
        if job is not None and job.live:
            self.cancel_job(job)
        self.candidates = [replace(c, measured=None) for c in self.candidates]
        self.redo_steps.clear()

    def cancel_design_jobs(self) -> None:
        """Cancel the work on the current design (its inputs are about to change)."""
        for kind in ("candidates", "knit", "measures", "suggestions"):
            job = self.jobs.get(kind)
            if job is not None and job.live:
                self.cancel_job(job)


def _copied(value: Any) -> Any:
    """A session field as it is now: containers copied (a change replaces or fills them in
    place), everything else shared (pictures, designs and settings are never changed in place)."""
    if isinstance(value, (dict, list, set)):
        return copy.copy(value)
    return value


def _not_in(job: Any, jobs: Iterable[Any]) -> bool:
    return all(job is not other for other in jobs)
