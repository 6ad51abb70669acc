"""The sessions' store on disk (illuknit.app.store): whole sessions, arrays once by hash,
ordered saves, atomic writes (a kill -9 mid-save leaves the last whole save), retention."""

from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from illuknit.app.jobs import Job
from illuknit.app.sessions import Session, SessionStore, UploadedImage
from illuknit.app.store import (
    DataDirInUseError,
    DiskStore,
    Retention,
    SessionNotSavedError,
    default_data_dir,
)


def _picture(seed: int, side: int = 200) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (side, side, 3), dtype=np.uint8)


def _session(sid: str = "s1", seed: int = 0) -> Session:
    s = Session(id=sid)
    s.images["a"] = UploadedImage("a.png", 123, _picture(seed), ("a note",))
    s.images["b"] = UploadedImage("b.png", 456, _picture(seed + 1))
    s.overrides[(0, 1)] = "12"
    s.selected = 2
    return s


def _blobs(disk: DiskStore) -> int:
    return int(disk._db.execute("SELECT count(*) FROM blobs").fetchone()[0])


def test_a_session_comes_back_whole(tmp_path):
    disk = DiskStore(tmp_path)
    s = _session()
    s.remember("an edit")  # an undo step sharing the session's pictures
    disk.save(s, seq=1, lock=s.lock)
    back = disk.load("s1").state
    assert back is not s and back.id == "s1"
    for slot in ("a", "b"):
        assert np.array_equal(back.images[slot].rgb, s.images[slot].rgb)
        assert back.images[slot].notes == s.images[slot].notes
    assert back.overrides == {(0, 1): "12"} and back.selected == 2
    assert [st.label for st in back.undo_steps] == ["an edit"]
    # an array shared by the session and its undo step is stored once and shared once loaded
    assert _blobs(disk) == 2
    assert back.undo_steps[0].images["a"].rgb is back.images["a"].rgb
    # nothing runtime comes back: a fresh lock, no saver, not detached
    assert back.saver is None and not back.detached and back.pins == 0


def test_a_field_added_later_gets_its_default(tmp_path):
    """Sessions stored before a field existed load with that field's default (no schema)."""
    s = _session()
    state = s.__getstate__()
    del state["retired_suggestions"]  # as if stored before the field existed
    back = Session.__new__(Session)
    back.__setstate__(state)
    assert back.retired_suggestions == {} and back.images.keys() == {"a", "b"}


def test_candidates_measured_before_the_hours_were_counted_get_them(tmp_path):
    """A candidate whose hand cost was stored without its stitches and hours (saved before
    they were counted) comes back with the hand cost counted again from its pattern, so the
    cards and the order by hand time work on it."""
    from illuknit.app.candidates import Candidate
    from illuknit.app.measures import order_candidates
    from illuknit.core.pattern import LogicalPattern, parse_yarns
    from illuknit.design.hand_cost import hand_cost
    from illuknit.design.tiles.perception import CandidateMeasures

    yarns = parse_yarns("black,white")
    cands = []
    for rank, rows in enumerate(([[0, 1, 1, 0], [1, 1, 0, 0]], [[0, 0, 0, 0], [1, 1, 1, 1]]), 1):
        p = LogicalPattern(np.array(rows, np.int16), np.zeros((2, 4), bool), yarns)
        old = hand_cost(p)
        for name in ("stitches", "changes"):  # as a version before them pickled it
            del object.__getattribute__(old, "__dict__")[name]
        m = CandidateMeasures(("A", "B"), (0.9, 0.9), (0.5, 0.5), (0.1, 0.1), hand=old)
        cands.append(Candidate(rank, "x", 1.0, p, measured=m))
    s = _session()
    s.candidates = cands
    disk = DiskStore(tmp_path)
    disk.save(s, seq=1, lock=s.lock)
    back = disk.load(s.id).state
    for c in back.candidates:
        assert c.measured.hand == hand_cost(c.pattern)
        assert c.to_json()["measures"]["hand"]["hours"] == round(c.measured.hand.hours, 2)
    assert [c.rank for c in order_candidates(back.candidates, "hand_time")] == [2, 1]


def test_jobs_running_when_stored_come_back_interrupted():
    s = Session(id="j")
    running, done = Job("candidates"), Job("knit")
    running.status = "running"
    done._finish("done", message="done")
    s.jobs = {"candidates": running, "knit": done}
    back = pickle.loads(pickle.dumps(s))
    assert back.jobs["candidates"].status == "interrupted"
    assert back.jobs["candidates"].id == running.id
    assert "run it again" in back.jobs["candidates"].message
    assert back.jobs["knit"].status == "done" and not back.jobs["knit"].live


def test_an_older_save_arriving_late_is_ignored(tmp_path):
    disk = DiskStore(tmp_path)
    s = _session()
    s.selected = 5
    disk.save(s, seq=7, lock=s.lock)
    s.selected = 3
    disk.save(s, seq=6, lock=s.lock)
    assert disk.load("s1").state.selected == 5


def test_saves_after_a_restart_are_kept(tmp_path):
    """A restarted server numbers its saves after the stored ones (else its saves would be
    taken for stale ones and dropped)."""
    disk = DiskStore(tmp_path)
    store = SessionStore(disk=disk)
    s = store.create()
    for _ in range(5):
        store.save(s)
    disk.close()
    store = SessionStore(disk=DiskStore(tmp_path))
    s = store.get(s.id)
    s.selected = 9
    store.save(s)
    store.disk.close()
    assert DiskStore(tmp_path).load(s.id).state.selected == 9


def test_replaced_pictures_leave_the_disk(tmp_path):
    disk = DiskStore(tmp_path)
    s = _session()
    disk.save(s, seq=1, lock=s.lock)
    s.images["a"] = UploadedImage("c.png", 1, _picture(9))
    disk.save(s, seq=2, lock=s.lock)
    assert _blobs(disk) == 2
    disk.delete("s1")
    assert _blobs(disk) == 0 and disk.load("s1") is None


def test_a_failed_write_leaves_the_previous_save(tmp_path, monkeypatch):
    disk = DiskStore(tmp_path)
    s = _session()
    disk.save(s, seq=1, lock=s.lock)
    s.selected = 4
    s.images["a"] = UploadedImage("c.png", 1, _picture(9))

    def broken(*args):
        raise OSError("disk full")

    monkeypatch.setattr("illuknit.app.store.zlib.compress", broken)
    with pytest.raises(SessionNotSavedError, match="disk full"):  # the cause, named
        disk.save(s, seq=2, lock=s.lock)
    back = disk.load("s1").state
    assert back.selected == 2 and np.array_equal(back.images["a"].rgb, _picture(0))


SAVER = textwrap.dedent(
    """
    import sys, numpy as np
    from illuknit.app.sessions import Session, UploadedImage
    from illuknit.app.store import DiskStore
    disk = DiskStore(sys.argv[1])
    k = 0
    while True:
        k += 1
        s = Session(id="s")
        s.selected = k
        for slot in "ab":
            rgb = np.full((700, 700, 3), k % 251, np.uint8)
            rgb[0, 0, 0] = k // 251
            s.images[slot] = UploadedImage(f"{k}", k, rgb)
        disk.save(s, seq=k, lock=s.lock)
        print(k, flush=True)
    """
)


def test_a_kill_mid_save_leaves_one_whole_save(tmp_path):
    """kill -9 of a process saving sessions (each save 3 MB of new pictures) at 6 moments: the
    store opens, and the session is exactly one save, its pictures those of the same save."""
    for n in range(6):
        folder = tmp_path / f"d{n}"
        proc = subprocess.Popen(
            [sys.executable, "-c", SAVER, str(folder)],
            stdout=subprocess.PIPE,
            text=True,
            env=dict(os.environ),
        )
        assert proc.stdout is not None
        proc.stdout.readline()  # one save done
        time.sleep(0.05 + 0.07 * n)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        proc.stdout.close()
        disk = DiskStore(folder)
        s = disk.load("s").state
        k = s.selected
        for slot in "ab":
            im = s.images[slot]
            assert im.filename == str(k) and im.sent_bytes == k
            assert im.rgb[1, 1, 0] == k % 251 and im.rgb[0, 0, 0] == k // 251
        assert _blobs(disk) == 1  # both slots share the one picture; older ones went
        disk.close()


def test_retention_by_age_and_by_size(tmp_path):
    disk = DiskStore(tmp_path, Retention(days=1, max_bytes=10**9))
    old, new = _session("old", 0), _session("new", 10)
    old.last_seen = time.time() - 2 * 86400
    disk.save(old, seq=1, lock=old.lock)
    disk.save(new, seq=2, lock=new.lock)
    assert disk.enforce(force=True) == ["old"]
    assert "1 day unused" in (disk.gone_reason("old") or "")
    # by size: three sessions of ~240 kB of noise each, room for two
    disk.retention = Retention(days=30, max_bytes=600_000)
    for k, sid in enumerate(("x", "y")):
        s = _session(sid, 20 + 2 * k)
        s.last_seen = time.time() + k
        disk.save(s, seq=3 + k, lock=s.lock)
    assert disk.used_bytes() > 600_000
    assert disk.enforce(force=True, keep={"new"}) == ["x"]
    assert disk.used_bytes() <= 600_000
    assert "under 585.9 kB" in (disk.gone_reason("x") or "")
    assert sorted(disk.ids()) == ["new", "y"]


def test_a_session_deleted_by_retention_tells_its_tab(tmp_path):
    store = SessionStore(disk=DiskStore(tmp_path, Retention(days=1)))
    s = store.create()
    s.last_seen = time.time() - 3 * 86400
    store.save(s)
    store.disk.touch(s.id, s.last_seen)
    store.trim(keep="other")
    with store._lock:
        store._drop_locked(s.id, None)
    store.disk.enforce(force=True)
    from illuknit.core.errors import AppRequestError

    with pytest.raises(AppRequestError) as e:
        store.get(s.id)
    assert e.value.status == 410 and "deleted after 1 day unused" in str(e.value)


def test_an_unreadable_session_keeps_its_pictures_and_settings(tmp_path):
    disk = DiskStore(tmp_path)
    store = SessionStore(disk=disk)
    s = store.create()
    s.images["a"] = UploadedImage("a.png", 1, _picture(3))
    s.settings = s.settings.model_copy(update={"width_units": 77})
    store.save(s)
    with disk._lock:  # as if saved by a version whose classes are gone
        disk._db.execute("UPDATE sessions SET state = ?", (b"not a pickle",))
    with store._lock:
        store._drop_locked(s.id, None)
    back = store.get(s.id)
    assert back.settings.width_units == 77
    assert np.array_equal(back.images["a"].rgb, _picture(3))
    assert "restored without its design" in back.images["a"].notes[-1]


def test_one_app_per_data_folder(tmp_path):
    disk = DiskStore(tmp_path)
    with pytest.raises(DataDirInUseError, match="another illuknit app"):
        DiskStore(tmp_path)
    disk.close()
    DiskStore(tmp_path).close()


def test_the_default_folder_is_the_users_data_folder(monkeypatch, tmp_path):
    if sys.platform in ("win32", "darwin"):
        pytest.skip("XDG applies to Linux and the BSDs")
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path))
    assert default_data_dir() == tmp_path / "illuknit" / "app"
    monkeypatch.setenv("XDG_DATA_HOME", "relative/ignored")
    assert default_data_dir() == default_data_dir().home() / ".local/share/illuknit/app"
