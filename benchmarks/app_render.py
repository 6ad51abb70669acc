"""Speed of the design app's edit -> look loop, through the real HTTP API (TestClient).

Prints the latency of the requests a designer waits for, at the paper's largest size
(330 x 200 units), against targets:

* live render (one view at a new angle, PNG): target < 150 ms, so the angle slider feels live;
* candidate search (tile assignment + compile of 5 candidates): target < 5 s;
* a tile override (recompile + render): target < 300 ms.

Run: python benchmarks/app_render.py
"""

from __future__ import annotations

import io
import statistics
import time

import numpy as np
from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.pictures.drawings import draw_heart, draw_text


def png(mask: np.ndarray) -> bytes:
    buf = io.BytesIO()
    rgb = np.where(mask[..., None], np.array([20, 20, 20]), np.array([245, 240, 230]))
    Image.fromarray(rgb.astype(np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


def timed(fn, repeat: int = 7) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    shape = (200, 330)
    with TestClient(create_app()) as c:
        sid = c.post("/api/sessions").json()["id"]
        c.put(
            f"/api/sessions/{sid}/images/a",
            files={"file": ("a.png", png(draw_text("ILLUSION", shape=shape)))},
        )
        c.put(f"/api/sessions/{sid}/images/b", files={"file": ("b.png", png(draw_heart(shape)))})
        c.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 330})
        c.get(f"/api/sessions/{sid}/inputs")
        t = time.perf_counter()
        jid = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"}).json()["id"]
        while c.get(f"/api/sessions/{sid}/jobs/{jid}").json()["status"] in ("queued", "running"):
            time.sleep(0.01)
        search = time.perf_counter() - t
        angles = iter(range(5, 90, 3))
        render = timed(
            lambda: c.get(
                f"/api/sessions/{sid}/render", params={"view": "A", "angle": next(angles)}
            )
        )
        pair = c.get(f"/api/sessions/{sid}/pairs").json()["pairs"][0]
        options = [o["id"] for o in pair["options"][:8]]
        k = iter(range(100))

        def override() -> None:
            tile = options[next(k) % len(options)]
            c.put(f"/api/sessions/{sid}/pairs/{pair['a']}/{pair['b']}", json={"tile": tile})
            c.get(f"/api/sessions/{sid}/render", params={"view": "B", "angle": 30})

        edit = timed(override)
    rows = [
        ("live render, 330 x 200, one view", render, 0.150),
        ("candidate search, 5 candidates", search, 5.0),
        ("tile override + render", edit, 0.300),
    ]
    print(f"{'step':40s} {'median':>10s} {'target':>10s}")
    for name, value, target in rows:
        flag = "ok" if value < target else "SLOW"
        print(f"{name:40s} {value * 1000:8.1f} ms {target * 1000:8.0f} ms  {flag}")


if __name__ == "__main__":
    main()
