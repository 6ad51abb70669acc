"""A change is kept only when its save committed (``Session.changing``): on a full disk, a
read-only data folder or a disk that fails, the app answers one clear error naming the cause
(507 for a full disk, 503 otherwise), the session stays as it was, no later save writes the
refused change, and the server stops cleanly with one line.

A full disk is SQLite's own: ``PRAGMA max_page_count`` makes the database refuse to grow, with
the very error (and the automatic rollback) a full file system gives ("database or disk is
full"). A read-only folder is the store's database opened again read-only.
"""

from __future__ import annotations

import errno
import io
import sqlite3

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig
from illuknit.app.store import DiskStore, SessionNotSavedError, storage_problem


def _noise_png(side: int, seed: int = 0) -> bytes:
    """A picture that does not compress: its working copy takes ``3 * side**2`` bytes on disk."""
    rgb = np.random.default_rng(seed).integers(0, 256, (side, side, 3), dtype=np.uint8)
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


@pytest.fixture()
def served(tmp_path):
    """(client, app) of an app keeping its sessions in ``tmp_path / "data"``."""
    app = create_app(AppConfig(data_dir=tmp_path / "data", isolate_knit=False))
    with TestClient(app) as c:
        yield c, app


def _fill_disk(app, spare_pages: int) -> None:
    """From now on the store's database may grow by ``spare_pages`` pages (4 kB) only."""
    db = app.state.store.disk._db
    (pages,) = db.execute("PRAGMA page_count").fetchone()
    db.execute(f"PRAGMA max_page_count = {pages + spare_pages}")


class _FullDisk:
    """The store's connection on a disk with no room left at all: every write fails as SQLite
    fails on a full disk (it rolls the transaction back itself, then raises)."""

    def __init__(self, db: sqlite3.Connection) -> None:
        self.real = db

    def execute(self, sql: str, *args):
        if sql.lstrip().split()[0].upper() in ("INSERT", "UPDATE", "DELETE"):
            if self.real.in_transaction:
                self.real.execute("ROLLBACK")
            raise sqlite3.OperationalError("database or disk is full")
        return self.real.execute(sql, *args)

    def __getattr__(self, name: str):
        return getattr(self.real, name)


def _disk_full(app) -> None:
    app.state.store.disk._db = _FullDisk(app.state.store.disk._db)


def _make_read_only(app) -> None:
    disk: DiskStore = app.state.store.disk
    disk._db.close()
    disk._db = sqlite3.connect(
        f"file:{disk.folder / disk.FILE}?mode=ro",
        uri=True,
        check_same_thread=False,
        isolation_level=None,
    )


def _state(c, sid: str) -> dict:
    state = c.get(f"/api/sessions/{sid}").json()
    state.pop("jobs")
    return state


def _stored(app, sid: str):
    """The session as a restarted server would read it back."""
    return app.state.store.disk.load(sid).state


def test_an_upload_refused_by_a_full_disk_is_not_kept(served, api, pictures):
    c, app = served
    sid = api.new_session(c)
    assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200
    before = _state(c, sid)
    _fill_disk(app, spare_pages=2)
    r = api.upload(c, sid, "b", _noise_png(300), name="big.png")
    assert r.status_code == 507, r.text
    err = api.error_of(r)
    assert err["code"] == "disk_full"
    assert "disk is full" in err["message"] and "not saved" in err["message"]
    assert "rollback" not in err["message"]  # the cause is said, never hidden by the rollback
    assert _state(c, sid) == before  # picture, revision, undo steps: all as they were
    assert set(_stored(app, sid).images) == {"a"}


def test_a_refused_picture_never_reaches_disk_through_a_later_save(served, api, pictures):
    c, app = served
    sid = api.new_session(c)
    _fill_disk(app, spare_pages=40)  # room for small saves, not for a 1 MB picture
    r = api.upload(c, sid, "a", _noise_png(600), name="big.png")
    assert r.status_code == 507, r.text
    # every later change that fits is saved, and the refused picture is not in it
    for width in (20, 22, 24):
        r = c.put(f"/api/sessions/{sid}/settings", json={"width_units": width})
        assert r.status_code == 200, r.text
        assert r.json()["images"] == {} and r.json()["history"]["undo"][-1].startswith("change")
    stored = _stored(app, sid)
    assert stored.images == {} and stored.settings.width_units == 24
    assert all("upload" not in step.label for step in stored.undo_steps)
    assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200  # small fits


def test_a_setting_refused_by_a_full_disk_is_not_kept(served, api):
    c, app = served
    sid = api.new_session(c)
    before = _state(c, sid)
    _disk_full(app)
    r = c.put(f"/api/sessions/{sid}/settings", json={"width_units": 31, "n_colors": 3})
    assert r.status_code == 507, r.text
    assert api.error_of(r)["code"] == "disk_full"
    assert _state(c, sid) == before
    app.state.store.disk._db = app.state.store.disk._db.real  # space again
    r = c.put(f"/api/sessions/{sid}/settings", json={"gauge": 8})
    assert r.status_code == 200
    stored = _stored(app, sid)
    assert (stored.settings.gauge, stored.settings.width_units) == (
        8,
        before["settings"]["width_units"],
    )


def test_a_read_only_folder_is_named_and_nothing_changes(served, api, pictures):
    c, app = served
    sid = api.new_session(c)
    before = _state(c, sid)
    _make_read_only(app)
    r = api.upload(c, sid, "a", pictures.box_picture())
    assert r.status_code == 503, r.text
    err = api.error_of(r)
    assert err["code"] == "read_only" and "read-only" in err["message"]
    assert _state(c, sid) == before
    r = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"})
    assert r.status_code in (409, 422, 503)  # refused either way; never a job left behind
    assert c.get(f"/api/sessions/{sid}").json()["jobs"] == {}
    r = c.post("/api/sessions")
    assert r.status_code == 503 and api.error_of(r)["code"] == "read_only"
    assert len(app.state.store) == 1  # the session that could not be saved is not kept


def test_a_job_start_refused_by_the_disk_leaves_no_job(served, api, pictures):
    c, app = served
    sid = api.new_session(c)
    assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200
    r = c.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 12})
    assert r.status_code == 200, r.text
    _disk_full(app)
    r = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"})
    assert r.status_code == 507, r.text
    assert c.get(f"/api/sessions/{sid}").json()["jobs"] == {}
    started = list(app.state.runner._jobs.values())
    assert started and all(job.cancelled for job in started)  # the work it began is stopped


def test_work_a_refused_change_would_cancel_goes_on(served, api, pictures):
    """An upload cancels the search of the pictures it replaces only once it is saved: a
    refused upload leaves that search running."""
    import threading

    c, app = served
    sid = api.new_session(c)
    assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200
    session = app.state.store.get(sid)
    release = threading.Event()
    with session.changing():
        job = app.state.runner.submit("candidates", lambda job: release.wait(30))
        session.replace_job("candidates", job)
    _disk_full(app)
    r = api.upload(c, sid, "a", pictures.box_picture(top=1))
    assert r.status_code == 507, r.text
    assert job.live and not job.cancelled
    assert c.get(f"/api/sessions/{sid}").json()["jobs"]["candidates"]["id"] == job.id
    app.state.store.disk._db = app.state.store.disk._db.real  # space again
    assert api.upload(c, sid, "a", pictures.box_picture(top=1)).status_code == 200
    assert job.cancelled  # now the change is kept, the search of the old picture stops
    release.set()


def test_ending_a_session_the_disk_refuses_keeps_it(served, api):
    c, app = served
    sid = api.new_session(c)
    _make_read_only(app)
    r = c.delete(f"/api/sessions/{sid}")
    assert r.status_code == 503
    assert c.get(f"/api/sessions/{sid}").status_code == 200


def test_stopping_on_a_full_disk_ends_cleanly_with_one_line(tmp_path, capfd):
    app = create_app(AppConfig(data_dir=tmp_path / "data", isolate_knit=False))
    with TestClient(app) as c:
        assert c.post("/api/sessions").status_code == 201
        disk = app.state.store.disk
        real = disk._db

        class FullDisk:  # a checkpoint needs room the disk no longer has
            def execute(self, sql, *args):
                if "checkpoint" in sql or sql.startswith("UPDATE"):
                    raise sqlite3.OperationalError("database or disk is full")
                return real.execute(sql, *args)

            def close(self):
                real.close()

        disk._db = FullDisk()
    err = capfd.readouterr().err
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "disk is full" in lines[0] and "nothing saved is lost" in lines[0]


@pytest.mark.parametrize(
    ("error", "code", "status"),
    [
        (sqlite3.OperationalError("database or disk is full"), "disk_full", 507),
        (OSError(errno.ENOSPC, "No space left on device"), "disk_full", 507),
        (OSError(errno.EDQUOT, "Disk quota exceeded"), "disk_full", 507),
        (sqlite3.OperationalError("attempt to write a readonly database"), "read_only", 503),
        (OSError(errno.EROFS, "Read-only file system"), "read_only", 503),
        (sqlite3.OperationalError("database is locked"), "busy", 503),
        (sqlite3.OperationalError("disk I/O error"), "disk_error", 503),
        (OSError(errno.EIO, "Input/output error"), "disk_error", 503),
        (sqlite3.DatabaseError("something else"), "not_saved", 503),
    ],
)
def test_every_cause_is_named(error, code, status, tmp_path, monkeypatch):
    assert storage_problem(error)[::2] == (code, status)
    from illuknit.app.sessions import Session

    disk = DiskStore(tmp_path)

    def refuse(*args, **kwargs):
        raise error

    monkeypatch.setattr(disk, "_write", refuse)
    with pytest.raises(SessionNotSavedError) as got:
        disk.save(Session(id="s"), seq=1, lock=Session(id="s").lock)
    assert (got.value.code, got.value.status) == (code, status)
    assert str(tmp_path) in str(got.value)
    disk.close()
