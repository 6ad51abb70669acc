"""``illuknit legible``: how wide must a double view be for both of its sides to read?"""

from __future__ import annotations

from pathlib import Path

import click

from illuknit.cli.knitout_bridge import machine_option
from illuknit.cli.options import InputFile, declared_option
from illuknit.core.progress import work_bar
from illuknit.design.options import RankOptions

__all__ = ["legible", "parse_widths"]


def parse_widths(spec: str) -> tuple[int, ...]:
    """``"40,60,80"`` -> ``(40, 60, 80)``; anything else is refused naming ``--widths``."""
    from illuknit.core.errors import OptionError

    try:
        ws = tuple(int(p) for p in spec.split(",") if p.strip())
    except ValueError:
        ws = ()
    if not ws or any(w < 4 or w > 1000 for w in ws):
        raise OptionError(
            f"--widths must be whole numbers of units from 4 to 1000, like 40,60,80; got {spec!r}"
        )
    return ws


@click.command("legible")
@click.argument("image_a", type=InputFile("picture"))
@click.argument("image_b", type=InputFile("picture"))
@click.option(
    "--widths",
    default="40,50,60,70,80,100,120",
    show_default=True,
    metavar="W,W,...",
    help="Pattern widths in units to try, narrowest first.",
)
@click.option(
    "--colors",
    "n_colors",
    type=click.IntRange(2, 4),
    default=2,
    show_default=True,
    help="Colours each picture is quantised to (as `double`).",
)
@click.option(
    "--resize", is_flag=True, help="Stretch the second picture onto the first (as `double`)."
)
@declared_option(RankOptions, "angle")
@declared_option(RankOptions, "distance")
@click.option(
    "--all-widths",
    is_flag=True,
    help="Try every width, not only up to the first where both sides read.",
)
@machine_option("Machine whose gauge sets the finished size.", transfer=False)
def legible(image_a: Path, image_b: Path, widths: str, n_colors: int, resize: bool, angle: float,
            distance: float, all_widths: bool, machine: str | None) -> None:  # fmt: skip
    """The smallest width at which each side of a double view reads, before the full design.

    Designs IMAGE_A over IMAGE_B at each width (narrowest first, a small search each) ranked by
    the reader's verdict, and asks the reader (tesseract OCR) whether each side's words read
    from --distance at --angle. A picture that is not text is judged by its correlation (an
    estimate, said so). Needs the tesseract program (apt-get install tesseract-ocr).
    """
    from illuknit.cli.summary import console
    from illuknit.pipeline.legible import smallest_legible_width

    ws = parse_widths(widths)
    with work_bar("legible") as report:
        found = smallest_legible_width(
            image_a, image_b, widths=ws, n_colors=n_colors, angle=angle, distance=distance,
            machine=machine, stretch=resize, keep_going=all_widths, progress=report,
        )  # fmt: skip
    con = console()
    said = [w if w is not None else "(a picture)" for w in found.words]
    con.print(f"side A says {said[0]}, side B says {said[1]}", markup=False, highlight=False)
    for v in found.tried:
        yes = {True: "reads", False: "does not read"}
        con.print(
            f"  {v.width:>4} units ({v.width_cm:.1f} cm): side A {yes[v.a_reads]}, side B "
            f"{yes[v.b_reads]}; best design: {v.sentence}",
            markup=False,
            highlight=False,
        )
    con.print(found.sentence(), markup=False, highlight=False)
