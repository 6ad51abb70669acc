"""The app's sessions on disk: one SQLite file (the standard library's ``sqlite3``) per data folder.

    Session (in memory) --save--> sessions row: the session pickled whole, its arrays by hash
                                  blobs rows:    each array (a picture, a quantised grid) once
    sessions row + blobs --load--> Session (an evicted session, or one from before a restart)

A session is stored *whole*: everything on the :class:`~illuknit.app.sessions.Session` object
(pictures, settings, candidates with their measures, the pick, tile edits, suggested edits,
undo and redo steps, the records of its jobs, and any field added to it later) is pickled as one
value, so a new field persists without a change of schema. Arrays of :data:`BLOB_MIN_BYTES` or
more are kept out of the pickle (:mod:`illuknit.app.session_pickle`): each is stored once as
an ``.npy`` blob (compressed below :data:`COMPRESS_BELOW`) named by the SHA-256 of its bytes,
so a picture shared by the session and its undo steps, or by two saves, is written once. A
table of references (session, hash) lets a blob go when no session needs it.

Every save is one SQLite transaction in WAL mode with ``synchronous=FULL``: a crash, a ``kill -9``
or a power cut during a save leaves the session as it was saved last, never half of two saves.
Saves of one session are ordered by a sequence number, so an older snapshot written late never
replaces a newer one.

What the folder may hold is bounded (:class:`Retention`): sessions unused for ``days`` are
deleted, and when all sessions together pass ``max_bytes`` the least recently used are deleted
first (never the one being saved). A deleted session's id is remembered with the reason, so its
tab is told what happened instead of "unknown session".

The pickle is read back only from this folder, which belongs to the user running the app (the
folder is created readable by them alone). Should a pickle not load (a session saved by a
version of illuknit whose classes changed), the session's pictures and settings, which are also
kept in plain JSON and ``.npy`` beside it, come back without the design made from them.
"""

from __future__ import annotations

import contextlib
import errno
import io
import json
import os
import pickle
import sqlite3
import sys
import threading
import time
import zlib
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from illuknit import __version__
from illuknit.app.session_pickle import (
    BLOB_MIN_BYTES,
    Loaded,
    _core_of,
    _HashCache,
    _npy_bytes,
    _Pickler,
    _Unpickler,
)
from illuknit.core.errors import AppRequestError, OutputPathError

__all__ = [
    "BLOB_MIN_BYTES",
    "DataDirInUseError",
    "DiskStore",
    "Retention",
    "SessionNotSavedError",
    "default_data_dir",
    "storage_problem",
]

#: Blobs smaller than this are compressed (zlib); bigger ones (pictures) are stored as ``.npy``.
COMPRESS_BELOW = 2**20
#: Version of the stored layout (the tables and the pickle's conventions).
FORMAT = 1

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS sessions (
    id TEXT PRIMARY KEY,
    created REAL NOT NULL,
    last_seen REAL NOT NULL,
    saved REAL NOT NULL,
    seq INTEGER NOT NULL,
    version TEXT NOT NULL,
    core TEXT NOT NULL,
    state BLOB NOT NULL
);
CREATE TABLE IF NOT EXISTS blobs (hash TEXT PRIMARY KEY, nbytes INTEGER NOT NULL, data BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS refs (
    session TEXT NOT NULL, hash TEXT NOT NULL, PRIMARY KEY (session, hash)
) WITHOUT ROWID;
CREATE INDEX IF NOT EXISTS refs_by_hash ON refs (hash);
CREATE TABLE IF NOT EXISTS gone (id TEXT PRIMARY KEY, reason TEXT NOT NULL, at REAL NOT NULL);
"""


class DataDirInUseError(OutputPathError):
    """Another running app keeps its sessions in the same data folder."""


class SessionNotSavedError(AppRequestError):
    """A change could not be stored (the disk is full, the folder became read-only, ...): the
    change is not kept, the session stays as it was saved last. ``code`` names the cause
    (``disk_full``, ``read_only``, ``busy``, ``disk_error``, ``not_saved``); ``status`` is 507
    (Insufficient Storage) for a full disk, else 503."""


#: SQLite's result codes (the low byte of an extended code) for the causes said in words.
_SQLITE_FULL, _SQLITE_READONLY, _SQLITE_BUSY, _SQLITE_LOCKED, _SQLITE_IOERR = 13, 8, 5, 6, 10


def storage_problem(e: BaseException) -> tuple[str, str, int]:
    """Why a write to the data folder failed, as (code, words for a designer, HTTP status):
    from an :class:`OSError`'s errno or an :class:`sqlite3.Error`'s result code and message."""
    number = getattr(e, "errno", None)
    code = getattr(e, "sqlite_errorcode", None)
    code = None if code is None else int(code) & 0xFF
    text = str(e).lower()
    if number in (errno.ENOSPC, errno.EDQUOT) or code == _SQLITE_FULL or "disk is full" in text:
        return "disk_full", "the disk is full", 507
    if number == errno.EROFS or code == _SQLITE_READONLY or "readonly" in text:
        return "read_only", "the data folder is read-only", 503
    if code in (_SQLITE_BUSY, _SQLITE_LOCKED) or "locked" in text:
        return "busy", "the saved work is locked by another program", 503
    if number == errno.EIO or code == _SQLITE_IOERR or "i/o error" in text:
        return "disk_error", "the disk reported an input/output error", 503
    return "not_saved", f"the disk refused it ({type(e).__name__}: {e})", 503


def not_saved(e: BaseException, folder: Path, what: str = "this change") -> SessionNotSavedError:
    """The error a designer sees when ``what`` could not be stored in ``folder``."""
    code, words, status = storage_problem(e)
    return SessionNotSavedError(
        f"{what} was not saved: {words} ({folder}); your work is as it was before it. "
        "Free some space or fix the folder, then try again",
        code=code,
        status=status,
    )


def default_data_dir() -> Path:
    """Where ``illuknit app`` keeps sessions unless told otherwise: the per-user data folder
    (``$XDG_DATA_HOME/illuknit/app``, else ``~/.local/share/illuknit/app``; on macOS
    ``~/Library/Application Support/illuknit/app``; on Windows ``%LOCALAPPDATA%\\illuknit\\app``)."""
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Application Support"
    else:
        xdg = os.environ.get("XDG_DATA_HOME", "")
        base = Path(xdg) if os.path.isabs(xdg) else Path.home() / ".local" / "share"
    return base / "illuknit" / "app"


@dataclass(frozen=True)
class Retention:
    """How long and how much the data folder keeps.

    Attributes
    ----------
    days : float
        A session unused for this long is deleted.
    max_bytes : int
        All sessions together (their pickles and distinct blobs, as stored) may take this much;
        beyond it, the least recently used sessions are deleted first.
    """

    days: float = 30.0
    max_bytes: int = 2 * 2**30

    def describe(self) -> str:
        days = _days(self.days)
        return (
            f"a session unused for {days} is deleted, and when all sessions together pass "
            f"{_size_text(self.max_bytes)} the least recently used go first"
        )


def _days(n: float) -> str:
    return f"{n:g} day" + ("" if n == 1 else "s")


def _size_text(n: int) -> str:
    for unit, size in (("GB", 2**30), ("MB", 2**20), ("kB", 2**10)):
        if n >= size:
            return f"{n / size:.1f}".removesuffix(".0") + f" {unit}"
    return f"{n} bytes"


# -- the store -----------------------------------------------------------------------------------


class DiskStore:
    """The sessions of one data folder, in ``sessions.sqlite3`` (thread-safe; one app at a time).

    Parameters
    ----------
    folder : path
        Created when missing (readable by the user alone). Another app already using it is
        refused (:class:`DataDirInUseError`), as is a folder that cannot be written
        (:class:`~illuknit.errors.OutputPathError`).
    retention : Retention
    """

    FILE = "sessions.sqlite3"
    #: Deleted session ids remembered with their reason.
    GONE_KEPT = 4096

    def __init__(self, folder: str | os.PathLike[str], retention: Retention | None = None) -> None:
        self.folder = Path(folder).expanduser().absolute()
        self.retention = retention or Retention()
        self._lock = threading.RLock()
        self._hashes = _HashCache()
        try:
            self.folder.mkdir(parents=True, exist_ok=True, mode=0o700)
            self._lockfile = _hold_lock(self.folder / "app.lock")
            self._db = sqlite3.connect(
                self.folder / self.FILE, check_same_thread=False, isolation_level=None, timeout=30
            )
            self._db.execute("PRAGMA auto_vacuum = INCREMENTAL")  # before the first table only
            self._db.execute("PRAGMA journal_mode = WAL")
            self._db.execute("PRAGMA synchronous = FULL")
            self._db.execute("PRAGMA journal_size_limit = 67108864")
            self._db.executescript(_SCHEMA)
            self._db.execute(
                "INSERT OR IGNORE INTO meta (key, value) VALUES ('format', ?)", (str(FORMAT),)
            )
        except DataDirInUseError:
            raise
        except (OSError, sqlite3.Error) as e:
            raise OutputPathError(
                f"cannot keep the app's sessions in {self.folder}: {e}; choose another folder "
                "with --data-dir"
            ) from None
        self._last_retention = 0.0

    # -- writing -------------------------------------------------------------------------------
    def save(self, session: Any, *, seq: int, lock: Any) -> None:
        """Store ``session`` whole (pickled under ``lock``, its arrays as blobs) as save number
        ``seq`` of that session; an older ``seq`` arriving late is ignored."""
        blobs: dict[str, Any] = {}
        buf = io.BytesIO()
        with lock:
            _Pickler(buf, blobs, self._hashes).dump(session)
            core = _core_of(session, self._hashes, blobs)
            sid, created, last_seen = session.id, session.created, session.last_seen
        state = buf.getvalue()
        try:
            self._write(sid, seq, created, last_seen, core, state, blobs)
        except (sqlite3.Error, OSError) as e:
            raise not_saved(e, self.folder) from e

    def _write(
        self,
        sid: str,
        seq: int,
        created: float,
        last_seen: float,
        core: dict[str, Any],
        state: bytes,
        blobs: dict[str, Any],
    ) -> None:
        now = time.time()
        with self._lock, self._transaction() as db:
            row = db.execute("SELECT seq FROM sessions WHERE id = ?", (sid,)).fetchone()
            if row is not None and row[0] >= seq:
                return
            have = {
                h
                for (h,) in db.execute(
                    f"SELECT hash FROM blobs WHERE hash IN ({','.join('?' * len(blobs))})",
                    tuple(blobs),
                )
            }
            for digest, value in blobs.items():
                if digest in have:
                    continue
                data = value if isinstance(value, bytes) else _npy_bytes(value)
                # small arrays (grids) compress well and fast; a picture is stored as it is
                # (compressing 12 MB takes most of a second on a busy laptop)
                packed = zlib.compress(data, 1) if len(data) < COMPRESS_BELOW else data
                db.execute(
                    "INSERT INTO blobs (hash, nbytes, data) VALUES (?, ?, ?)",
                    (digest, len(packed), packed),
                )
            db.execute(
                "INSERT INTO sessions (id, created, last_seen, saved, seq, version, core, state) "
                "VALUES (?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (id) DO UPDATE SET "
                "last_seen = excluded.last_seen, saved = excluded.saved, seq = excluded.seq, "
                "version = excluded.version, core = excluded.core, state = excluded.state",
                (sid, created, last_seen, now, seq, __version__, json.dumps(core), state),
            )
            db.execute("DELETE FROM refs WHERE session = ?", (sid,))
            db.executemany(
                "INSERT INTO refs (session, hash) VALUES (?, ?)", [(sid, h) for h in blobs]
            )
            db.execute("DELETE FROM gone WHERE id = ?", (sid,))
            _drop_unreferenced(db)

    def touch(self, sid: str, last_seen: float) -> None:
        """Record that session ``sid`` was used at ``last_seen`` (for the age bound). Best
        effort: on a full or read-only disk the time saved with the session stands."""
        with self._lock, contextlib.suppress(sqlite3.Error):
            self._db.execute(
                "UPDATE sessions SET last_seen = max(last_seen, ?) WHERE id = ?",
                (last_seen, sid),
            )

    def delete(self, sid: str, reason: str | None = None) -> bool:
        """Delete session ``sid`` (its blobs when no other session holds them); remember
        ``reason`` for its tab when given. True if it was stored. A delete the disk refuses
        raises :class:`SessionNotSavedError` (the session stays stored)."""
        try:
            with self._lock, self._transaction() as db:
                return self._delete(db, sid, reason)
        except (sqlite3.Error, OSError) as e:
            raise not_saved(e, self.folder, "ending this session") from e

    def _delete(self, db: sqlite3.Connection, sid: str, reason: str | None) -> bool:
        found = db.execute("DELETE FROM sessions WHERE id = ?", (sid,)).rowcount > 0
        db.execute("DELETE FROM refs WHERE session = ?", (sid,))
        _drop_unreferenced(db)
        if reason is not None and found:
            db.execute(
                "INSERT OR REPLACE INTO gone (id, reason, at) VALUES (?, ?, ?)",
                (sid, reason, time.time()),
            )
            db.execute(
                "DELETE FROM gone WHERE id NOT IN (SELECT id FROM gone ORDER BY at DESC LIMIT ?)",
                (self.GONE_KEPT,),
            )
        return found

    def enforce(self, *, keep: Iterable[str] = (), force: bool = False) -> list[str]:
        """Apply the retention: delete sessions unused for too long, then the least recently used
        until all fit (never those in ``keep``). Answers the ids deleted. At most once a second
        unless ``force``. A disk that refuses even the deletes deletes nothing now (the next
        save tries again)."""
        now = time.time()
        if not force and now - self._last_retention < 1.0:
            return []
        with self._lock:
            self._last_retention = now
            try:
                with self._transaction() as db:
                    deleted = self._retire(db, now, set(keep))
            except (sqlite3.Error, OSError):
                return []
            if deleted:
                with contextlib.suppress(sqlite3.Error):  # the next saves reuse the space
                    self._db.execute("PRAGMA incremental_vacuum")
        return deleted

    def _retire(self, db: sqlite3.Connection, now: float, keep: set[str]) -> list[str]:
        deleted = []
        cutoff = now - self.retention.days * 86400
        for (sid,) in db.execute(
            "SELECT id FROM sessions WHERE last_seen < ? ORDER BY last_seen", (cutoff,)
        ).fetchall():
            if sid not in keep:
                why = f"this session was deleted after {_days(self.retention.days)} unused"
                self._delete(db, sid, why)
                deleted.append(sid)
        order = db.execute("SELECT id FROM sessions ORDER BY last_seen").fetchall()
        for (sid,) in order:
            if self._used(db) <= self.retention.max_bytes:
                break
            if sid in keep:
                continue
            self._delete(
                db,
                sid,
                "this session was deleted to keep the app's saved work under "
                f"{_size_text(self.retention.max_bytes)} (the least recently used goes first)",
            )
            deleted.append(sid)
        return deleted

    # -- reading -------------------------------------------------------------------------------
    def load(self, sid: str) -> Loaded | None:
        """Session ``sid`` as stored, or None when it is not."""
        with self._lock:
            row = self._db.execute(
                "SELECT state, core, version FROM sessions WHERE id = ?", (sid,)
            ).fetchone()
        if row is None:
            return None
        state, core_text, version = row
        core = json.loads(core_text)
        try:
            obj = _Unpickler(io.BytesIO(state), self._blob).load()
        except Exception as e:  # a pickle of another version's classes: keep what is plain
            arrays = {slot: self._blob(im["hash"]) for slot, im in core["images"].items()}
            return Loaded(
                None,
                core,
                arrays,
                problem=f"saved by illuknit {version}, its design could not be read back ({e})",
            )
        return Loaded(obj, core, {})

    def summaries(self, limit: int = 50) -> list[dict[str, Any]]:
        """The stored sessions that hold a picture, most recently used first (at most
        ``limit``): id, created, last_seen and their core (settings, pictures by name)."""
        with self._lock:
            rows = self._db.execute(
                "SELECT id, created, last_seen, core FROM sessions ORDER BY last_seen DESC"
            ).fetchall()
        out = []
        for sid, created, seen, core in rows:
            plain = json.loads(core)
            if plain["images"]:
                out.append({"id": sid, "created": created, "last_seen": seen, **plain})
            if len(out) == limit:
                break
        return out

    def last_seq(self) -> int:
        """The highest save number stored (a restarted server numbers its saves after it)."""
        with self._lock:
            (seq,) = self._db.execute("SELECT coalesce(max(seq), 0) FROM sessions").fetchone()
        return int(seq)

    def gone_reason(self, sid: str) -> str | None:
        with self._lock:
            row = self._db.execute("SELECT reason FROM gone WHERE id = ?", (sid,)).fetchone()
        return None if row is None else str(row[0])

    def ids(self) -> list[str]:
        with self._lock:
            return [r[0] for r in self._db.execute("SELECT id FROM sessions ORDER BY last_seen")]

    def used_bytes(self) -> int:
        """What the sessions take as stored (pickles and distinct blobs)."""
        with self._lock:
            return self._used(self._db)

    def file_bytes(self) -> int:
        """Size of the store's files on disk (the database and its write-ahead log)."""
        return sum(p.stat().st_size for p in self.folder.glob(self.FILE + "*") if p.is_file())

    def close(self) -> str | None:
        """Fold the write-ahead log into the database and close it; what went wrong, in one
        line, when the disk refused (a full disk: the log stays beside the database, and the
        next start reads it; nothing saved is lost), else None."""
        problem = None
        with self._lock:
            try:
                self._db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
            except (sqlite3.Error, OSError) as e:
                problem = (
                    f"the saved sessions in {self.folder} were closed without tidying their "
                    f"log: {storage_problem(e)[1]} (nothing saved is lost)"
                )
            finally:
                with contextlib.suppress(sqlite3.Error):
                    self._db.close()
                self._lockfile.close()
        return problem

    # -- internals -----------------------------------------------------------------------------
    def _blob(self, digest: str) -> np.ndarray:
        with self._lock:
            row = self._db.execute("SELECT data FROM blobs WHERE hash = ?", (digest,)).fetchone()
        if row is None:
            raise pickle.UnpicklingError(f"a stored picture is missing (blob {digest[:12]})")
        data = bytes(row[0])
        if not data.startswith(b"\x93NUMPY"):  # compressed
            data = zlib.decompress(data)
        arr: np.ndarray = np.lib.format.read_array(io.BytesIO(data), allow_pickle=False)
        return arr

    @staticmethod
    def _used(db: sqlite3.Connection) -> int:
        (states,) = db.execute("SELECT coalesce(sum(length(state)), 0) FROM sessions").fetchone()
        (blobs,) = db.execute("SELECT coalesce(sum(nbytes), 0) FROM blobs").fetchone()
        return int(states) + int(blobs)

    def _transaction(self) -> Any:
        return _Transaction(self._db)


class _Transaction:
    """``BEGIN IMMEDIATE`` ... ``COMMIT`` (``ROLLBACK`` on any error)."""

    def __init__(self, db: sqlite3.Connection) -> None:
        self.db = db

    def __enter__(self) -> sqlite3.Connection:
        self.db.execute("BEGIN IMMEDIATE")
        return self.db

    def __exit__(self, kind: Any, value: Any, tb: Any) -> None:
        if kind is None:
            try:
                self.db.execute("COMMIT")
            except BaseException:
                self._rollback()
                raise
        else:
            self._rollback()

    def _rollback(self) -> None:
        # SQLite has already rolled back after some errors (a full disk: "database or disk is
        # full"); a ROLLBACK then fails with "no transaction is active", and must not replace
        # the error that says why
        if self.db.in_transaction:
            with contextlib.suppress(sqlite3.Error):
                self.db.execute("ROLLBACK")


def _drop_unreferenced(db: sqlite3.Connection) -> None:
    db.execute("DELETE FROM blobs WHERE hash NOT IN (SELECT hash FROM refs)")


def _hold_lock(path: Path) -> Any:
    """An open file holding an exclusive lock on ``path`` while the app runs."""
    f = open(path, "a+b")  # noqa: SIM115 - held open for the store's life
    try:
        import fcntl
    except ImportError:  # Windows: SQLite's own locking keeps the file consistent
        return f
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        f.close()
        raise DataDirInUseError(
            f"another illuknit app keeps its sessions in {path.parent}; stop it, or give this "
            "one its own folder with --data-dir"
        ) from None
    return f
