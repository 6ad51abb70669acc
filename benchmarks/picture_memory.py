"""Peak memory of the CLI on large pictures (issue target: under 1 GB for 50 megapixels).

Writes a 50-megapixel photograph-like PNG (smooth gradients with noise) and a 7000 x 7000 PNG,
runs ``illuknit single`` on each in a child process, and prints the child's peak resident memory
(``getrusage(RUSAGE_CHILDREN).ru_maxrss``, kilobytes on Linux) and wall time.

    python benchmarks/picture_memory.py
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

TARGET_MB = 1024


def photo(h: int, w: int, seed: int = 0) -> Image.Image:
    rng = np.random.default_rng(seed)
    rows = []
    for start in range(0, h, 1024):  # build in strips to keep this script's own memory low
        y, x = np.mgrid[start : min(h, start + 1024), 0:w]
        base = np.stack([x * 255 // w, y * 255 // h, (x + y) * 255 // (w + h)], axis=2)
        rows.append(np.clip(base + rng.integers(-6, 7, base.shape), 0, 255).astype(np.uint8))
    return Image.fromarray(np.concatenate(rows, axis=0))


def peak_of(cmd: list[str]) -> tuple[float, float]:
    """(peak resident MB, seconds) of ``cmd`` run as a child (run each in a fresh process)."""
    code = (
        "import resource, subprocess, sys, time; t = time.perf_counter(); "
        f"r = subprocess.run({cmd!r}, capture_output=True, text=True); "
        "dt = time.perf_counter() - t; "
        "assert r.returncode == 0, r.stderr[-2000:]; "
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024, dt)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    mb, seconds = out.stdout.split()
    return float(mb), float(seconds)


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        cases = {"50 MP (8660 x 5774)": (5774, 8660), "7000 x 7000": (7000, 7000)}
        print(
            f"{'picture':<22} {'file MB':>8} {'peak MB':>8} {'seconds':>8}  target < {TARGET_MB} MB"
        )
        for label, (h, w) in cases.items():
            path = Path(tmp) / f"{w}x{h}.png"
            t = time.perf_counter()
            photo(h, w).save(path, compress_level=1)
            made = time.perf_counter() - t
            cmd = [
                sys.executable,
                "-m",
                "illuknit",
                "single",
                str(path),
                "-o",
                str(Path(tmp) / "out"),
            ]
            mb, seconds = peak_of(cmd)
            size = path.stat().st_size / 1e6
            verdict = "ok" if mb < TARGET_MB else "OVER"
            print(
                f"{label:<22} {size:>8.1f} {mb:>8.0f} {seconds:>8.1f}  {verdict} (made in {made:.0f} s)"
            )


if __name__ == "__main__":
    main()
