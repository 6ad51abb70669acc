"""Peak memory of one design-app session with two 50-megapixel pictures, through the HTTP API.

A fresh Python process (so that nothing else counts) starts the app, opens a session, uploads a
50-megapixel JPEG as picture A and a 50-megapixel PNG as picture B (the two ways a picture is
reduced: while decoding, and after) into a session kept on disk, quantises them for a double view 120 units wide, finds
candidates, then suggested edits, accepts the first and undoes it (what the undo history holds).
It prints the process's resident memory after importing the app and its peak over
the whole session (``ru_maxrss``), against the target: peak under 1 GB; and what the session
takes on disk and how long it takes to read it back (as after a restart or an eviction).

Run: python benchmarks/app_memory.py
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

TARGET_BYTES = 1 * 2**30
#: 8640 x 5760 = 49.8 megapixels, under the 50-megapixel cap (illuknit.pictures.images.MAX_PIXELS).
SIZE = (8640, 5760)


def photo_like(width: int, height: int, *, seed: int) -> Image.Image:
    """A smooth picture with shapes: big to decode, small enough to upload (a few MB)."""
    small = np.random.default_rng(seed).integers(0, 256, (height // 240, width // 240, 3))
    im = Image.fromarray(small.astype(np.uint8)).resize((width, height), Image.Resampling.BICUBIC)
    return im


def write_pictures(folder: Path) -> tuple[Path, Path]:
    a, b = folder / "a.jpg", folder / "b.png"
    photo_like(*SIZE, seed=1).save(a, format="JPEG", quality=85)
    photo_like(*SIZE, seed=2).save(b, format="PNG", compress_level=1)
    return a, b


CHILD = r"""
import json, resource, sys, time
from fastapi.testclient import TestClient
from illuknit.app import create_app
from illuknit.app.server import AppConfig

def hwm() -> int:
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM"))

def rss() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * resource.getpagesize()

a, b, data = sys.argv[1], sys.argv[2], sys.argv[3]
out = {}
app = create_app(AppConfig(isolate_knit=False, data_dir=data))
with TestClient(app) as c:
    out["rss_after_import"] = rss()
    sid = c.post("/api/sessions").json()["id"]
    t = time.perf_counter()
    for slot, path, mime in (("a", a, "image/jpeg"), ("b", b, "image/png")):
        with open(path, "rb") as f:
            r = c.put(f"/api/sessions/{sid}/images/{slot}", files={"file": (path, f.read(), mime)})
        assert r.status_code == 200, r.text
    out["upload_seconds"] = time.perf_counter() - t
    out["peak_after_upload"] = hwm()
    r = c.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 120})
    assert r.status_code == 200, r.text
    assert c.get(f"/api/sessions/{sid}/inputs").status_code == 200
    out["peak_after_inputs"] = hwm()
    jid = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"}).json()["id"]
    while (job := c.get(f"/api/sessions/{sid}/jobs/{jid}").json())["status"] in ("queued", "running"):
        time.sleep(0.05)
    assert job["status"] == "done", job
    out["session_bytes"] = app.state.store.nbytes()
    out["peak_after_candidates"] = hwm()

    def run(kind):
        jid = c.post(f"/api/sessions/{sid}/jobs", json={"kind": kind}).json()["id"]
        while (job := c.get(f"/api/sessions/{sid}/jobs/{jid}").json())["status"] in ("queued", "running"):
            time.sleep(0.05)
        assert job["status"] == "done", job

    # undo's cost: the design before an accepted edit is kept whole (its uploaded pictures most)
    t = time.perf_counter()
    run("suggestions")
    out["suggestions_seconds"] = time.perf_counter() - t
    edits = c.get(f"/api/sessions/{sid}/suggestions").json()["suggestions"]
    out["suggestions"] = len(edits)
    out["session_bytes_suggestions"] = app.state.store.nbytes()
    out["peak_after_suggestions"] = hwm()
    if edits:
        r = c.post(f"/api/sessions/{sid}/suggestions/{edits[0]['id']}/accept")
        assert r.status_code == 200, r.text
        run("candidates")
        out["session_bytes_accepted"] = app.state.store.nbytes()
        s = app.state.store.get(sid)
        with s.lock:  # the same session without its undo step: what the step costs
            steps, s.undo_steps = s.undo_steps, []
            out["session_bytes_no_history"] = s.nbytes()
            s.undo_steps = steps
        assert c.post(f"/api/sessions/{sid}/history/undo").status_code == 200
        out["session_bytes_undone"] = app.state.store.nbytes()
    out["peak_after_undo"] = hwm()  # the accept designs again from the edited pictures
    disk = app.state.store.disk
    out["stored_bytes"] = disk.used_bytes()
    out["disk_file_bytes"] = disk.file_bytes()
    # the session leaves memory and comes back from disk, as after a restart or an eviction
    t = time.perf_counter()
    api_evict = app.state.store
    with api_evict._lock:
        api_evict._drop_locked(sid, None)
    assert c.get(f"/api/sessions/{sid}").status_code == 200
    out["reload_seconds"] = time.perf_counter() - t
    out["session_bytes_reloaded"] = app.state.store.nbytes()
    out["rss_end"] = rss()
out["peak_rss"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps(out))
"""


def main() -> None:
    with tempfile.TemporaryDirectory(prefix="illuknit-app-memory-") as tmp:
        a, b = write_pictures(Path(tmp))
        sizes = {p.name: p.stat().st_size for p in (a, b)}
        t = time.perf_counter()
        run = subprocess.run(
            [sys.executable, "-c", CHILD, str(a), str(b), str(Path(tmp) / "data")],
            capture_output=True,
            text=True,
            check=False,
        )
        wall = time.perf_counter() - t
    if run.returncode != 0:
        sys.exit(f"the app session failed:\n{run.stderr[-2000:]}")
    m = json.loads(run.stdout.strip().splitlines()[-1])
    mb = 2**20
    print(f"pictures: {SIZE[0]} x {SIZE[1]} = {SIZE[0] * SIZE[1] / 1e6:.1f} megapixels each;")
    print("  " + ", ".join(f"{k} {v / mb:.1f} MB" for k, v in sizes.items()))
    print(f"resident after importing the app   {m['rss_after_import'] / mb:8.0f} MB")
    print(f"upload and reduce both pictures    {m['upload_seconds']:8.1f} s")
    print(f"peak after the uploads             {m['peak_after_upload'] / mb:8.0f} MB")
    print(f"peak after quantising              {m['peak_after_inputs'] / mb:8.0f} MB")
    print(f"peak after finding candidates      {m['peak_after_candidates'] / mb:8.0f} MB")
    print(f"memory the session holds           {m['session_bytes'] / mb:8.1f} MB")
    print(
        f"suggested edits ({m['suggestions']}) found in        {m['suggestions_seconds']:8.1f} s;"
        f" the session then holds {m['session_bytes_suggestions'] / mb:.1f} MB"
    )
    print(f"peak after suggested edits         {m['peak_after_suggestions'] / mb:8.0f} MB")
    if "session_bytes_accepted" in m:
        print(
            f"one edit accepted: the session holds {m['session_bytes_accepted'] / mb:.1f} MB, of which"
            f" the undo step (the design before) {(m['session_bytes_accepted'] - m['session_bytes_no_history']) / mb:.1f} MB;"
            f" undone: {m['session_bytes_undone'] / mb:.1f} MB (the redo step kept)"
        )
    print(f"peak after accept and undo         {m['peak_after_undo'] / mb:8.0f} MB")
    print(
        f"saved on disk: {m['stored_bytes'] / mb:.1f} MB stored (the database file "
        f"{m['disk_file_bytes'] / mb:.1f} MB); read back from disk in {m['reload_seconds']:.2f} s,"
        f" holding {m['session_bytes_reloaded'] / mb:.1f} MB"
    )
    print(f"resident at the end                {m['rss_end'] / mb:8.0f} MB")
    verdict = "OK" if m["peak_rss"] < TARGET_BYTES else "OVER"
    print(
        f"peak resident (whole session)      {m['peak_rss'] / mb:8.0f} MB"
        f"   target < {TARGET_BYTES / mb:.0f} MB: {verdict}   ({wall:.0f} s in all)"
    )


if __name__ == "__main__":
    main()
