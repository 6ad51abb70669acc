"""Per-tab design sessions of the app.

Each browser tab creates its own session (the page keeps the id in ``sessionStorage``, which is
per tab), so two tabs never see each other's images, settings, candidates or downloads. A session
holds everything the designer has done so far; every change of input (an image, a setting) bumps
``revision``, and derived results (quantised inputs, candidates, knitout) remember the revision
they were computed from, so a result computed from stale inputs is never shown as current.

Requests of one session are serialised by its lock; requests of different sessions run in
parallel. Idle sessions expire, and the number of live sessions is capped (oldest idle evicted),
so a long-running server does not grow without bound.
"""

from __future__ import annotations

import secrets
import threading
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.app.schemas import DesignSettings
from illuknit.errors import AppRequestError

__all__ = ["DesignSettings", "Session", "SessionStore", "UploadedImage"]


@dataclass(frozen=True)
class UploadedImage:
    """An uploaded picture: the file as sent, and its decoded float RGB (H, W, 3) in [0, 1]."""

    filename: str
    data: bytes
    rgb: NDArray[np.float64]

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in pixels."""
        return (int(self.rgb.shape[1]), int(self.rgb.shape[0]))


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
    knit: Any = None  # design.KnitResult, for pattern_key
    jobs: dict[str, Any] = field(default_factory=dict)  # kind -> Job
    lock: threading.RLock = field(default_factory=threading.RLock, repr=False)

    def touch(self) -> None:
        self.last_seen = time.time()

    def bump(self) -> None:
        """Inputs changed: derived results are stale."""
        self.revision += 1
        self.prepared = None
        self.candidates = []
        self.candidates_revision = -1
        self.selected = 0
        self.overrides = {}
        self.knit = None
        for kind in ("candidates", "knit"):
            job = self.jobs.get(kind)
            if job is not None and job.live:
                job.cancel()


class SessionStore:
    """Thread-safe map of session id -> :class:`Session` with expiry and a size cap.

    Parameters
    ----------
    max_sessions : int
        Live sessions kept; creating one more evicts the longest-idle one.
    ttl : float
        Seconds of inactivity after which a session is forgotten.
    """

    def __init__(self, *, max_sessions: int = 64, ttl: float = 6 * 3600) -> None:
        self.max_sessions = max_sessions
        self.ttl = ttl
        self._sessions: dict[str, Session] = {}
        self._lock = threading.Lock()

    def create(self) -> Session:
        with self._lock:
            self._expire_locked()
            while len(self._sessions) >= self.max_sessions:
                oldest = min(self._sessions.values(), key=lambda s: s.last_seen)
                self._drop_locked(oldest.id)
            sid = secrets.token_urlsafe(12)
            session = Session(id=sid)
            self._sessions[sid] = session
            return session

    def get(self, sid: str) -> Session:
        with self._lock:
            self._expire_locked()
            session = self._sessions.get(sid)
        if session is None:
            raise AppRequestError(
                "unknown or expired session; reload the page to start a new one",
                field="session",
                code="no_session",
                status=404,
            )
        session.touch()
        return session

    def delete(self, sid: str) -> bool:
        with self._lock:
            return self._drop_locked(sid)

    def __len__(self) -> int:
        with self._lock:
            return len(self._sessions)

    def _drop_locked(self, sid: str) -> bool:
        session = self._sessions.pop(sid, None)
        if session is None:
            return False
        for job in session.jobs.values():
            job.cancel()
        return True

    def _expire_locked(self) -> None:
        now = time.time()
        for sid in [s.id for s in self._sessions.values() if now - s.last_seen > self.ttl]:
            self._drop_locked(sid)
