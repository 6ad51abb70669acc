"""Writing a knitout program next to a pattern's other outputs (``--knitout`` of the commands)."""

from __future__ import annotations

import json
from pathlib import Path

from illuknit.errors import BackendUnavailableError
from illuknit.outputs import atomic_write_text
from illuknit.pattern import LogicalPattern

__all__ = ["write_program"]


def write_program(pattern: LogicalPattern, outdir: Path) -> dict[str, Path]:
    """Compile ``pattern`` to ``program.k`` and check it into ``check.json``."""
    try:
        from illuknit.knit import knit_pattern
    except ImportError as e:  # pragma: no cover - only while the knitting pipeline is absent
        raise BackendUnavailableError(
            f"knitout output is not available in this install: {e}"
        ) from None
    result = knit_pattern(pattern)
    paths = {"program": atomic_write_text(outdir / "program.k", result.program)}
    try:
        from illuknit.check import check_knitout
    except ImportError:  # pragma: no cover
        return paths
    report = check_knitout(result.program)
    paths["check"] = atomic_write_text(
        outdir / "check.json", json.dumps(report.to_json(), indent=1) + "\n"
    )
    return paths
