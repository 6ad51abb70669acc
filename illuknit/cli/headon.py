"""``illuknit headon``: a picture seen head-on that disappears at an angle (paper Fig. 17)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from illuknit.cli.double import design_options, print_summary, run_design
from illuknit.cli.options import InputFile
from illuknit.core.progress import work_bar

__all__ = ["headon"]


@click.command("headon")
@click.argument("front", type=InputFile("picture"))
@click.argument("side", type=InputFile("picture"), required=False)
@design_options
def headon(front: Path, side: Path | None, outdir: Path, **kw: Any) -> None:
    """Design a head-on illusion: FRONT is seen looking straight at the fabric; at an angle it
    disappears into SIDE (seen the same from above and below), or into a plain field when SIDE
    is omitted.

    Uses tiles whose head-on fill differs from their side fill (e.g. a bump then a flat unit:
    a stripe head-on, solid from both sides). Writes ranked candidates like ``illuknit double``.
    """
    with work_bar("headon") as report:
        kw["soft_brightness"] = kw.pop("brightness") == "soft"
        summary = run_design(front, side, outdir, mode="headon", progress=report, **kw)
    print_summary(summary, outdir)
