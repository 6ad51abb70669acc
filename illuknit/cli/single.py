"""``illuknit single``: a picture in, a single-view illusion pattern and its previews out."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from illuknit.cli.knitout_bridge import format_option, long_floats_option, machine_option
from illuknit.cli.options import (
    InputFile,
    image_options,
    knitout_option,
    outdir_option,
    parse_yarn_option,
)
from illuknit.cli.summary import print_written, summarise_pattern
from illuknit.core.progress import Report, work_bar

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec
    from illuknit.pipeline.stages import Stripe

__all__ = ["run_single", "single"]


def run_single(
    image: str | Path,
    outdir: str | Path,
    *,
    width: int | None = None,
    height: int | None = None,
    width_cm: float | None = None,
    gauge: float | None = None,
    yarns: str | None = None,
    n_colors: int | None = None,
    quantise: bool = True,
    first: Stripe = "dark",
    knitout: bool = False,
    machine: str | MachineSpec | None = None,
    title: str | None = None,
    progress: Report | None = None,
) -> dict[str, Path]:
    """Compile ``image`` and write the whole bundle into ``outdir`` (atomically).

    ``gauge`` (default: the machine's) sizes ``width_cm`` and, with ``knitout``, is the gauge of
    the machine the program is knit on; with ``knitout`` a picture wider than the machine's bed
    is refused before compiling. ``progress(fraction, message)`` hears how far it is.
    """
    from illuknit.cli.knitout_bridge import chart_kind, design_unit_aspect, resolve_machine
    from illuknit.core.files import staged_dir
    from illuknit.outputs.export import export_pattern
    from illuknit.pipeline.stages import design_single

    say: Report = progress or (lambda fraction, message: None)
    spec = resolve_machine(machine, gauge=gauge)
    say(0.0, "reading, quantising and compiling the picture")
    design = design_single(
        image,
        width=width,
        height=height,
        width_cm=width_cm,
        gauge=spec.gauge,
        unit_aspect=design_unit_aspect(spec),
        n_colors=n_colors,
        yarns=parse_yarn_option(yarns),
        quantise=quantise,
        first=first,
        knit_on=spec if knitout else None,
        machine=spec,
    )
    q, chosen = design.quantised, design.first(first)
    pattern = chosen.pattern
    err_a, err_b = chosen.measures["mismatch_A"], chosen.measures["mismatch_B"]
    report = {
        "source": str(image),
        "compiler": "single-view",
        "legend": q.legend(),
        "logical_error": {
            "A": err_a,
            "B": err_b,
            "note": "fraction of outer-colour pixels whose view colour differs from "
            "the picture shifted by one row (middle-colour pixels are seen as "
            "stripes by design and are not counted)",
        },
    }
    refused: list[Any] = []  # a knitting refusal, raised once the design is written
    with staged_dir(outdir) as tmp:
        say(0.2, "writing the pattern, previews, chart and instructions")
        paths = export_pattern(
            pattern,
            tmp,
            quantised={"picture": q},
            report=report,
            title=title or f"Single-view illusion of {Path(str(image)).name}",
            gauge=spec.fabric_gauge,
            chart=chart_kind(),
        )
        from illuknit.cli.design_files import write_seen

        say(0.4, "drawing the views up close and from 3 m")
        paths["seen"] = write_seen(
            pattern, [q.rgb()], tmp, mode="single", gauge=spec.fabric_gauge, distance=3.0
        )
        if knitout:
            from illuknit.cli.knitout_bridge import write_program

            say(0.5, "knitting it and checking the program")
            paths.update(write_program(pattern, tmp, machine=spec, refused=refused))
    if refused:  # the design is written, with the note saying why there is no program
        raise refused[0]
    return {k: Path(outdir) / p.name for k, p in paths.items()}


@click.command("single")
@click.argument("image", type=InputFile("picture"))
@image_options
@click.option(
    "--first",
    type=click.Choice(["dark", "light"]),
    default="dark",
    show_default=True,
    help="Colour of the top stripe row.",
)
@knitout_option()
@machine_option()
@format_option()
@long_floats_option()
@outdir_option()
def single(
    image: Path,
    width: int | None,
    height: int | None,
    width_cm: float | None,
    gauge: float | None,
    yarns: str | None,
    n_colors: int | None,
    quantise: bool,
    first: Stripe,
    knitout: bool,
    machine: str | None,
    outdir: Path,
) -> None:
    """Compile a 2- or 3-colour picture into a single-view illusion.

    Rows alternate two yarns; the picture appears from either end at an angle. A third (middle)
    colour is shown as a stripe of the two yarns. Writes pattern.json, previews, a hand-knitting
    chart and written instructions into OUTDIR.
    """
    from illuknit.core.pattern import load_pattern

    with work_bar("single") as report:
        paths = run_single(
            image,
            outdir,
            width=width,
            height=height,
            width_cm=width_cm,
            gauge=gauge,
            yarns=yarns,
            n_colors=n_colors,
            quantise=quantise,
            first=first,
            knitout=knitout,
            machine=machine,
            progress=report,
        )
    summarise_pattern(
        load_pattern(paths["pattern"]),
        legend_path=paths.get("legend"),
        report_path=paths.get("report"),
    )
    print_written(outdir, paths)
