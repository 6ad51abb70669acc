"""Writing a knitout program next to a pattern's other outputs (``--knitout`` of the commands)."""

from __future__ import annotations

from pathlib import Path

from illuknit.outputs import atomic_write_text
from illuknit.pattern import LogicalPattern

__all__ = ["write_program"]


def write_program(pattern: LogicalPattern, outdir: Path) -> dict[str, Path]:
    """Compile ``pattern`` to ``program.k`` and write the checker's report beside it.

    Writes ``program.k``, ``knit.json`` (passes, lower bound, time estimate), ``check.json`` and
    ``check.txt``; returns name -> path. Prints a one-line summary of each.
    """
    import json

    from illuknit.check import check_knitout
    from illuknit.cli.summary import console
    from illuknit.knit import knit_pattern

    result = knit_pattern(pattern)
    report = check_knitout(result.program)
    summary = result.summary()
    console().print(f"knitout: {_describe(summary)}")
    console().print(f"check: {report.to_text(name='program.k').splitlines()[0]}")
    return {
        "program": atomic_write_text(outdir / "program.k", result.program),
        "knit": atomic_write_text(outdir / "knit.json", json.dumps(summary, indent=1) + "\n"),
        "check": atomic_write_text(outdir / "check.json", report.to_json(indent=1) + "\n"),
        "check_text": atomic_write_text(
            outdir / "check.txt", report.to_text(name="program.k") + "\n"
        ),
    }


def _describe(summary: dict[str, object]) -> str:
    parts = []
    for key in ("passes", "lower_bound", "ratio"):
        if key in summary:
            parts.append(f"{key.replace('_', ' ')} {summary[key]}")
    for key, val in summary.items():
        if "time" in key and isinstance(val, (int, float, str)):
            parts.append(f"{key.replace('_', ' ')} {val}")
    return ", ".join(parts) or "written"
