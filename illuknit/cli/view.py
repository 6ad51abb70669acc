"""``illuknit view``: previews, chart and instructions of a saved pattern."""

from __future__ import annotations

from pathlib import Path

import click

from illuknit.cli.options import InputFile, outdir_option
from illuknit.cli.summary import print_written, summarise_pattern
from illuknit.outputs.hand_pattern import MAX_BORDER_UNITS

__all__ = ["view"]


@click.command("view")
@click.argument("pattern_file", metavar="PATTERN", type=InputFile("pattern"))
@outdir_option()
@click.option(
    "--chart",
    type=click.Choice(["units", "stitches"]),
    default="units",
    show_default=True,
    help="What a square of pattern.pdf's and chart.svg's chart is: a ridge unit of 2 stitches "
    "x 2 rows or one stitch.",
)
@click.option(
    "--border",
    type=click.IntRange(0, MAX_BORDER_UNITS),
    default=0,
    show_default=True,
    help="A garter border against curling around the hand pattern, this many ridge units wide "
    "(4 stitches and 4 rows more a unit; 0: none).",
)
def view(pattern_file: Path, outdir: Path, chart: str, border: int) -> None:
    """Write previews (head-on, view A, view B, contact sheet), the hand-knitting chart and written
    instructions of a pattern file."""
    from illuknit.core.files import staged_dir
    from illuknit.core.pattern import load_pattern
    from illuknit.core.progress import work_bar
    from illuknit.outputs.export import export_pattern

    pattern = load_pattern(pattern_file)
    with work_bar("view") as report, staged_dir(outdir) as tmp:
        paths = export_pattern(
            pattern,
            tmp,
            report={"source": str(pattern_file)},
            progress=report,
            chart=chart,
            border=border,
        )
    summarise_pattern(pattern)
    print_written(outdir, {k: outdir / p.name for k, p in paths.items()})
