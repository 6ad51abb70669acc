"""Per-tab design sessions of the app, and the store that keeps them in memory.

Each browser tab creates its own session (the page keeps the id in ``sessionStorage``, which is
per tab), so two tabs never see each other's images, settings, candidates or downloads. A session
holds everything the designer has done so far; every change of input (an image, a setting) bumps
``revision``, and derived results (quantised inputs, candidates, knitout) remember the revision
they were computed from, so a result computed from stale inputs is never shown as current.

Requests of one session are serialised by its lock; requests of different sessions run in
parallel. Pictures are kept as uint8 RGB at the working grid (at most ``MAX_WORKING_SIDE`` on the
long side), never as the file sent nor as floats. Idle sessions expire, and all sessions together
are bounded by count and by bytes: the least recently used one is evicted first, and a request
for an evicted session says so (410, code ``evicted``) instead of "unknown session". A session's
undo and redo steps (:mod:`illuknit.app.history`: the designs before accepted edits) count in
those bytes.
"""

from __future__ import annotations

import secrets
import threading
import time
from collections import OrderedDict
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from illuknit.app.design_session import Session, UploadedImage
from illuknit.app.schemas import DesignSettings
from illuknit.core.errors import AppRequestError

__all__ = ["DesignSettings", "Session", "SessionStore", "UploadedImage"]


class SessionStore:
    """Thread-safe map of session id -> :class:`Session`, bounded by age, count and bytes in
    memory, and kept on disk when given a :class:`~illuknit.app.store.DiskStore`.

    Parameters
    ----------
    max_sessions : int
        Sessions kept in memory; opening one more evicts the least recently used one.
    ttl : float
        Seconds of inactivity after which a session leaves memory.
    max_bytes : int
        Memory all sessions together may hold (:meth:`Session.nbytes`); :meth:`trim` evicts the
        least recently used sessions until they fit, never one a request is working on.
    disk : DiskStore or None
        Where sessions are kept. With one, every change is stored (:meth:`save`), a session
        evicted from memory (or from before a restart) is read back when its tab asks for it,
        and only the disk's retention deletes work. Without one (the library's default), an
        evicted or expired session is gone, and its tab is told why (410 ``evicted``).
    """

    #: Evicted or expired session ids remembered, so that their tab is told what happened.
    GONE_KEPT = 4096

    def __init__(
        self,
        *,
        max_sessions: int = 64,
        ttl: float = 6 * 3600,
        max_bytes: int = 512 * 2**20,
        disk: Any = None,
    ) -> None:
        self.max_sessions = max_sessions
        self.ttl = ttl
        self.max_bytes = max_bytes
        self.disk = disk
        self._sessions: dict[str, Session] = {}
        self._gone: OrderedDict[str, str] = OrderedDict()
        self._lock = threading.Lock()
        # saves are numbered across restarts, so the newest snapshot of a session always wins
        self._seq = 0 if disk is None else disk.last_seq()

    def create(self) -> Session:
        with self._lock:
            self._expire_locked()
            self._make_room_locked(keep=None)
            sid = secrets.token_urlsafe(12)
            session = self._adopt_locked(Session(id=sid))
        try:
            session.save()
        except BaseException:  # a session that could not be saved is not kept
            with self._lock:
                self._sessions.pop(sid, None)
            raise
        return session

    def get(self, sid: str, *, pin: bool = False) -> Session:
        """Session ``sid``, read back from disk when it is not in memory (410 ``evicted`` when
        it was deleted or closed, 404 ``no_session`` when it never was). ``pin``: count it as in
        use, from the moment it is found (:meth:`using` unpins it)."""
        with self._lock:
            self._expire_locked()
            session = self._sessions.get(sid)
            loaded = session is None and self.disk is not None
            if loaded:
                session = self._load_locked(sid)
            if session is not None and pin:
                session.pins += 1
            gone = self._gone.get(sid)
        if session is None and gone is None and self.disk is not None:
            gone = self.disk.gone_reason(sid)
        if session is None and gone is not None:
            raise AppRequestError(
                f"{gone}; its pictures and settings are gone: start again (reload the page)",
                field="session",
                code="evicted",
                status=410,
            )
        if session is None:
            raise AppRequestError(
                "unknown or expired session; reload the page to start a new one",
                field="session",
                code="no_session",
                status=404,
            )
        session.touch()
        if loaded:  # it came back into memory: others make room
            self.trim(keep=sid)
        return session

    @contextmanager
    def using(self, sid: str) -> Iterator[Session]:
        """Session ``sid`` (as :meth:`get`), kept in memory while the block runs."""
        session = self.get(sid, pin=True)
        try:
            yield session
        finally:
            with self._lock:
                session.pins -= 1

    def save(self, session: Session) -> None:
        """Store ``session`` whole on disk (one transaction), then apply the disk's retention
        (never to ``session``); nothing without a disk or for an evicted copy."""
        if self.disk is None or session.detached:
            return
        with self._lock:
            self._seq += 1
            seq = self._seq
        self.disk.save(session, seq=seq, lock=session.lock)
        with self._lock:
            keep = {session.id, *(s.id for s in self._sessions.values() if s.pins)}
        for sid in self.disk.enforce(keep=keep):
            with self._lock:
                self._drop_locked(sid, None)

    def saved(self, limit: int = 50) -> list[dict[str, Any]]:
        """The sessions a designer can reopen (those holding a picture), most recently used
        first: ``id``, ``last_seen``, ``mode`` and ``pictures`` (slot -> file name). From the
        disk when there is one (every change is saved), else from memory."""
        if self.disk is not None:
            found = self.disk.summaries(limit)
        else:
            with self._lock:
                sessions = sorted(self._sessions.values(), key=lambda s: -s.last_seen)
            found = [
                {
                    "id": s.id,
                    "last_seen": s.last_seen,
                    "settings": s.settings.model_dump(mode="json"),
                    "images": {k: {"filename": im.filename} for k, im in s.images.items()},
                }
                for s in sessions
                if s.images
            ][:limit]
        return [
            {
                "id": f["id"],
                "last_seen": f["last_seen"],
                "mode": f["settings"].get("mode"),
                "pictures": {k: im["filename"] for k, im in sorted(f["images"].items())},
            }
            for f in found
        ]

    def delete(self, sid: str) -> bool:
        """End session ``sid``: deleted from disk first (a disk that refuses leaves it as it
        was: :class:`~illuknit.app.store.SessionNotSavedError`), then from memory."""
        found = self.disk.delete(sid) if self.disk is not None else False
        with self._lock:
            found = self._drop_locked(sid, None) or found
        return found

    def nbytes(self) -> int:
        """Memory all live sessions hold together."""
        with self._lock:
            sessions = list(self._sessions.values())
        return sum(s.nbytes() for s in sessions)

    def in_memory(self) -> list[str]:
        """Ids of the sessions held in memory now."""
        with self._lock:
            return list(self._sessions)

    def trim(self, *, keep: str) -> list[str]:
        """Evict least recently used sessions (never ``keep``, nor one a request is working on)
        from memory until all fit in ``max_bytes``; sessions with work running go last."""
        evicted = []
        with self._lock:
            sizes = {sid: s.nbytes() for sid, s in self._sessions.items()}
            total = sum(sizes.values())
            for s in sorted(self._sessions.values(), key=_eviction_order):
                if total <= self.max_bytes:
                    break
                if s.id == keep or s.pins:
                    continue
                total -= sizes[s.id]
                self._drop_locked(
                    s.id,
                    f"this session was closed to make room for newer work (the app keeps at most "
                    f"{self.max_bytes / 2**20:.0f} MB of pictures and results for all sessions; "
                    "the least recently used goes first)",
                )
                evicted.append(s.id)
        return evicted

    def close(self) -> str | None:
        """The server is stopping: record when each session in memory was last used, and close
        the disk (releasing its folder for the next server). Call it before cancelling the jobs:
        a job the stop cuts short then comes back *interrupted*, not *cancelled*. Answers what
        the disk refused, in one line (a full disk), else None: every change was saved as it
        was made, so a refusal here loses nothing."""
        if self.disk is None:
            return None
        with self._lock:
            sessions = list(self._sessions.values())
            for s in sessions:  # work cut short by the stop is stored as it was: interrupted
                s.detached = True
        for s in sessions:
            self.disk.touch(s.id, s.last_seen)
        problem: str | None = self.disk.close()
        return problem

    def __len__(self) -> int:
        with self._lock:
            return len(self._sessions)

    def _adopt_locked(self, session: Session) -> Session:
        if self.disk is not None:
            session.saver = self.save
        self._sessions[session.id] = session
        return session

    def _load_locked(self, sid: str) -> Session | None:
        loaded = self.disk.load(sid)
        if loaded is None:
            return None
        session = loaded.state
        if session is None:  # its design could not be read back: its pictures and settings can
            session = Session(
                id=sid, settings=DesignSettings.model_validate(loaded.core["settings"])
            )
            for slot, im in loaded.core["images"].items():
                session.images[slot] = UploadedImage(
                    im["filename"],
                    int(im["sent_bytes"]),
                    loaded.arrays[slot],
                    (*im["notes"], f"restored without its design: {loaded.problem}"),
                )
        self._make_room_locked(keep=sid)
        return self._adopt_locked(session)

    def _make_room_locked(self, keep: str | None) -> None:
        while len(self._sessions) >= self.max_sessions:
            candidates = [s for s in self._sessions.values() if s.id != keep and not s.pins]
            if not candidates:
                return
            oldest = min(candidates, key=_eviction_order)
            self._drop_locked(
                oldest.id,
                f"this session was closed because more than {self.max_sessions} sessions "
                "were open (the least recently used is closed first)",
            )

    def _drop_locked(self, sid: str, reason: str | None) -> bool:
        """Take session ``sid`` out of memory (kept on disk when there is one; else gone, its tab
        told ``reason``)."""
        session = self._sessions.pop(sid, None)
        if session is None:
            return False
        session.detached = True
        for job in session.jobs.values():
            job.cancel()
        if self.disk is not None:
            self.disk.touch(sid, session.last_seen)
        elif reason is not None:
            self._gone[sid] = reason
            while len(self._gone) > self.GONE_KEPT:
                self._gone.popitem(last=False)
        return True

    def _expire_locked(self) -> None:
        now = time.time()
        for sid in [s.id for s in self._sessions.values() if now - s.last_seen > self.ttl]:
            if not self._sessions[sid].pins:
                self._drop_locked(sid, "this session expired after a long time unused")


def _eviction_order(s: Session) -> tuple[bool, float]:
    """Sessions with work running leave memory last; then the least recently used first."""
    return (any(j.live for j in s.jobs.values()), s.last_seen)
