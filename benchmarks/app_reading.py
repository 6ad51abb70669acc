"""What the reader adds to the design app's candidate search (issue 38), through the real HTTP
API (TestClient), on the bundled word pair ``illusion-knitting-small`` (ILLUSION over KNITTING,
90 x 30 units, sized from the picture as the app does by default).

Prints the median wall time of the candidates job (search in its own process, 5 candidates, the
app's defaults) with the reader (tesseract reads both sides of the kept designs) and without it
(the reader hidden, as on a computer without tesseract), and the default card's verdict.

Run: python benchmarks/app_reading.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import io
import statistics
import time

import numpy as np
from fastapi.testclient import TestClient
from PIL import Image

import illuknit.design.legibility as legibility
from illuknit.app import create_app
from illuknit.bench.instances import instance_targets, load_manifest

NAME = "illusion-knitting-small"


def png(rgb: np.ndarray) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


def search_once(c: TestClient, sid: str) -> tuple[float, dict]:
    t = time.perf_counter()
    jid = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"}).json()["id"]
    while True:
        job = c.get(f"/api/sessions/{sid}/jobs/{jid}").json()
        if job["status"] not in ("queued", "running"):
            break
        time.sleep(0.02)
    took = time.perf_counter() - t
    assert job["status"] == "done", job
    cands = c.get(f"/api/sessions/{sid}/candidates").json()["candidates"]
    return took, cands[0]["details"]["legibility"]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    repeat = ap.parse_args().repeat
    inst = next(i for i in load_manifest().instances if i.name == NAME)
    t = instance_targets(inst)
    pics = [np.round(np.asarray(t.rgb(v), float) * 255).astype(np.uint8) for v in "AB"]
    times: dict[str, list[float]] = {"with the reader": [], "without": []}
    said = {}
    with TestClient(create_app()) as c:
        sid = c.post("/api/sessions").json()["id"]
        for slot, rgb in zip("ab", pics, strict=True):
            c.put(f"/api/sessions/{sid}/images/{slot}", files={"file": (f"{slot}.png", png(rgb))})
        c.put(f"/api/sessions/{sid}/settings", json={"mode": "double"})
        c.get(f"/api/sessions/{sid}/inputs")
        search_once(c, sid)  # warm: imports, the worker's first start
        real = legibility.READER
        for _ in range(repeat):
            for label in times:
                legibility.READER = real if label == "with the reader" else "no-such-reader"
                try:
                    took, verdict = search_once(c, sid)
                finally:
                    legibility.READER = real
                times[label].append(took)
                said[label] = verdict["sentence"]
    print(f"{NAME}: {pics[0].shape[1]} x {pics[0].shape[0]} units, 5 candidates, {repeat} runs")
    for label, ts in times.items():
        print(
            f"  {label:>16}: median {statistics.median(ts):.2f} s  ({', '.join(f'{x:.2f}' for x in ts)})"
        )
        print(f"  {'':>16}  default card: {said[label]}")
    extra = statistics.median(times["with the reader"]) - statistics.median(times["without"])
    print(f"  the reader adds {extra:.2f} s (median against median)")


if __name__ == "__main__":
    main()
