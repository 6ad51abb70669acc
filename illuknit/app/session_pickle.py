"""A session as the store keeps it: pickled whole, its big arrays (:data:`BLOB_MIN_BYTES` or
more) left out of the pickle as blobs named by the SHA-256 of their ``.npy`` bytes, and its core
(pictures by hash, settings) in plain JSON beside it, which comes back even when the pickle does
not (:class:`Loaded`).

:class:`~illuknit.app.store.DiskStore` writes and reads these in its SQLite file.
"""

from __future__ import annotations

import hashlib
import io
import pickle
import threading
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["BLOB_MIN_BYTES", "Loaded"]

#: Arrays at least this big are stored as blobs by hash; smaller ones stay inside the pickle.
BLOB_MIN_BYTES = 16 * 1024


class _HashCache:
    """SHA-256 of big arrays, remembered per array object (session arrays are never changed in
    place: the history already shares them), so a save does not hash every picture again."""

    def __init__(self) -> None:
        self._known: dict[int, tuple[weakref.ref[np.ndarray], str]] = {}
        self._lock = threading.Lock()

    def npy(self, arr: np.ndarray) -> tuple[str, bytes | None]:
        """(hash, npy bytes or None when the hash was remembered)."""
        with self._lock:
            got = self._known.get(id(arr))
            if got is not None and got[0]() is arr:
                return got[1], None
        data = _npy_bytes(arr)
        digest = hashlib.sha256(data).hexdigest()
        with self._lock:
            if len(self._known) > 4096:
                self._known = {k: v for k, v in self._known.items() if v[0]() is not None}
            self._known[id(arr)] = (weakref.ref(arr), digest)
        return digest, data


def _npy_bytes(arr: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.asanyarray(arr), allow_pickle=False)
    return buf.getvalue()


class _Pickler(pickle.Pickler):
    def __init__(self, file: io.BytesIO, blobs: dict[str, Any], hashes: _HashCache) -> None:
        super().__init__(file, protocol=5)
        self._blobs = blobs
        self._hashes = hashes

    def persistent_id(self, obj: Any) -> Any:
        if type(obj) is np.ndarray and obj.dtype != object and obj.nbytes >= BLOB_MIN_BYTES:
            digest, data = self._hashes.npy(obj)
            if digest not in self._blobs or self._blobs[digest] is None:
                self._blobs[digest] = obj if data is None else data
            return ("npy", digest)
        return None


class _Unpickler(pickle.Unpickler):
    def __init__(self, file: io.BytesIO, fetch: Any) -> None:
        super().__init__(file)
        self._fetch = fetch
        self._arrays: dict[str, np.ndarray] = {}

    def persistent_load(self, pid: Any) -> Any:
        kind, digest = pid
        if kind != "npy":
            raise pickle.UnpicklingError(f"unknown stored reference {kind!r}")
        arr = self._arrays.get(digest)
        if arr is None:  # an array shared in the session stays shared once loaded
            arr = self._arrays[digest] = self._fetch(digest)
        return arr


@dataclass
class Loaded:
    """A session read back: the object, or only its core (pictures and settings) when the whole
    state could not be read, with why."""

    state: Any
    core: dict[str, Any]
    arrays: dict[str, np.ndarray]
    problem: str | None = None


def _core_of(session: Any, hashes: _HashCache, blobs: dict[str, Any]) -> dict[str, Any]:
    """What a session is made of in plain JSON (its pictures by hash, its settings): what comes
    back even if its pickle cannot be read. Its pictures join ``blobs``, whatever their size."""
    images = {}
    for slot, im in session.images.items():
        digest, data = hashes.npy(im.rgb)
        if blobs.get(digest) is None:
            blobs[digest] = im.rgb if data is None else data
        images[slot] = {
            "filename": im.filename,
            "sent_bytes": im.sent_bytes,
            "notes": list(im.notes),
            "hash": digest,
        }
    return {"settings": session.settings.model_dump(mode="json"), "images": images}
