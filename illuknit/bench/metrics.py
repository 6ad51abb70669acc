"""What the benchmark measures for one pattern against its instance's targets.

* **Logical error** per view: the fraction of units whose colour, as the boolean model
  (:func:`illuknit.core.views.can_see`) sees it from that side, differs from the *original* target
  (not from a repainted image a method may have designed against). Colours are compared by yarn
  colour, so a pattern may use a subset or a reordering of the instance's yarns.
* **Render error, readability, ghosting, head-on visibility, colour changes**: the picture
  measures of :mod:`illuknit.design.measures`, which the ranking of tile designs uses too.
* **Knitting**: the carriage passes the machine runs for the pattern's program (the SWG backend's
  pass rows), transfer passes and the estimated time on them (:func:`knit_stats`); when the
  pattern cannot be knit (e.g. wider than the bed) the fields are empty and ``knit_note`` gives
  the reason.
* **Peak memory**: resident set size sampled every 5 ms while the cell runs
  (:class:`PeakMemory`), reported as the peak and as the peak above the level at the start.
"""

from __future__ import annotations

import os
import resource
import threading
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from illuknit.bench.instances import Targets
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.core.views import View, can_see
from illuknit.knitting.stats import knit_stats

if TYPE_CHECKING:
    pass

__all__ = [
    "PeakMemory",
    "boolean_render",
    "knit_stats",
    "logical_errors",
    "seen_in_target_yarns",
    "yarn_map",
]


def yarn_map(pattern_yarns: tuple[Yarn, ...], yarns: tuple[Yarn, ...]) -> NDArray[np.int16]:
    """Index of each pattern yarn among ``yarns`` by colour (-1 where it is not one of them)."""
    lookup = {y.rgb: i for i, y in enumerate(yarns)}
    return np.array([lookup.get(y.rgb, -1) for y in pattern_yarns], dtype=np.int16)


def seen_in_target_yarns(
    pattern: LogicalPattern, view: View, yarns: tuple[Yarn, ...]
) -> NDArray[np.int16]:
    """ndarray of shape (N, M): the yarn seen from ``view``, as an index into ``yarns``."""
    return yarn_map(pattern.yarns, yarns)[can_see(pattern, view)]


def logical_errors(pattern: LogicalPattern, targets: Targets) -> dict[str, float]:
    """Fraction of wrongly seen units in view A and view B against the original targets.

    Returns
    -------
    dict
        ``{"A": float, "B": float}``, each in [0, 1].
    """
    out: dict[str, float] = {}
    pairs: tuple[tuple[View, NDArray[np.int16]], ...] = (("A", targets.a), ("B", targets.b))
    for view, target in pairs:
        if pattern.shape != target.shape:
            raise ValueError(f"pattern shape {pattern.shape} differs from target {target.shape}")
        seen = seen_in_target_yarns(pattern, view, targets.yarns)
        out[view] = float(np.mean(seen != target))
    return out


def boolean_render(pattern: LogicalPattern, view: View) -> NDArray[np.float64]:
    """The boolean can_see view in yarn colours, float sRGB of shape (N, M, 3)."""
    from illuknit.outputs.previews import view_rgb

    return view_rgb(pattern, view).astype(np.float64) / 255.0


def _rss_bytes() -> int:
    try:
        with open("/proc/self/statm", encoding="ascii") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:  # not Linux: fall back to the lifetime peak
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


class PeakMemory:
    """Context manager: peak resident memory of this process while the block runs.

    A daemon thread samples ``/proc/self/statm`` every ``interval`` seconds (native allocations
    of solvers count too, unlike tracemalloc). Attributes after exit: ``start_mb``, ``peak_mb``,
    ``delta_mb`` (peak above start).
    """

    def __init__(self, interval: float = 0.005) -> None:
        self.interval = interval
        self.start_mb = self.peak_mb = self.delta_mb = 0.0
        self._stop = threading.Event()
        self._peak = 0

    def _sample(self) -> None:
        while not self._stop.wait(self.interval):
            self._peak = max(self._peak, _rss_bytes())

    def __enter__(self) -> PeakMemory:
        self._start = self._peak = _rss_bytes()
        self._thread = threading.Thread(target=self._sample, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._peak = max(self._peak, _rss_bytes())
        self._stop.set()
        self._thread.join()
        mb = 1024.0 * 1024.0
        self.start_mb = self._start / mb
        self.peak_mb = self._peak / mb
        self.delta_mb = (self._peak - self._start) / mb
