"""``illuknit demo``: the whole single-view pipeline on the bundled sample picture."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import click

from illuknit.cli.knitout_bridge import format_option, long_floats_option, machine_option
from illuknit.cli.options import outdir_option
from illuknit.cli.summary import console, print_written, summarise_pattern

__all__ = ["demo", "demo_image"]

#: The demo's widths: an illusion needs a picture of at least 2 x 2 units, and the square sample
#: picture at width 1 is 1 x 1 (found by trying: width 1 was accepted here, then refused by the
#: pipeline; widths 2, 3, 4, 6 and 8 knit, knitout included).
DEMO_UNITS = click.IntRange(2, 1000)


def demo_image() -> Path:
    """Path of the bundled 3-colour sample picture (a heart in a ring, 64 x 64 pixels)."""
    return Path(str(resources.files("illuknit") / "data" / "demo.png"))


@click.command("demo")
@outdir_option(default=Path("illuknit-demo"))
@click.option(
    "--width", type=DEMO_UNITS, default=48, show_default=True, help="Pattern width in units."
)
@click.option(
    "--knitout/--no-knitout",
    default=True,
    show_default=True,
    help="Also compile and check a knitout program.",
)
@machine_option()
@format_option()
@long_floats_option()
def demo(outdir: Path, width: int, knitout: bool, machine: str | None) -> None:
    """Make a single-view illusion of the bundled sample picture (a heart in a grey ring).

    Writes the pattern, previews, a hand-knitting chart, written instructions and (by default) a
    checked knitout program into OUTDIR, and says where.
    """
    from illuknit.cli.single import SingleRequest, run_single
    from illuknit.core.pattern import load_pattern
    from illuknit.core.progress import work_bar

    console().print(
        f"illuknit demo: a single-view illusion of the bundled heart in a ring, {width} units "
        f"wide, into {outdir}/"
    )
    with work_bar("demo") as report:
        request = SingleRequest.from_switches(
            demo_image(),
            outdir,
            width=width,
            yarns="Charcoal=#1b1b1b,Cream=#f4f0e8",
            knitout=knitout,
            machine=machine,
            title="illuknit demo: a heart in a ring",
        )
        paths = run_single(request, progress=report)
    summarise_pattern(
        load_pattern(paths["pattern"]),
        legend_path=paths.get("legend"),
        report_path=paths.get("report"),
    )
    print_written(outdir, paths)
    console().print(
        f"Open [bold]{outdir / 'contact.png'}[/] to see the stripes head-on and the heart from "
        "either end; knit it from chart.png / instructions.txt"
        + (", or on a machine from program.k." if "program" in paths else ".")
    )
