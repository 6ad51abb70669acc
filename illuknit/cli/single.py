"""``illuknit single``: a picture in, a single-view illusion pattern and its previews out."""

from __future__ import annotations

from dataclasses import dataclass
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
from illuknit.pipeline.inputs import PictureOptions

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec
    from illuknit.pipeline.designs import Stripe

__all__ = ["SingleRequest", "run_single", "single"]


@dataclass(frozen=True, eq=False)
class SingleRequest:
    """What ``illuknit single`` (or ``demo``) asks for, parsed once.

    Attributes
    ----------
    picture : path
    outdir : path
        The folder written (atomically).
    sizing : PictureOptions
        Width, height, width in cm at the machine's gauge, unit aspect, colours, yarns and
        whether to quantise.
    first : {"dark", "light"}
        The colour of the top stripe row.
    machine : MachineSpec
        The machine as the command resolved it (at ``--gauge``).
    knitout : bool
        Also knit the pattern on ``machine`` and check the program; a picture wider than the
        machine's bed is then refused before compiling.
    title : str or None
        The pattern's title (default: the picture's name).
    """

    picture: str | Path
    outdir: str | Path
    sizing: PictureOptions
    first: Stripe
    machine: MachineSpec
    knitout: bool = False
    title: str | None = None

    @classmethod
    def from_switches(cls, image: str | Path, outdir: str | Path, **switches: Any) -> SingleRequest:
        """The request of the command line's switches (``--width-cm`` is ``width_cm=``);
        ``gauge`` (default: the machine's) sizes ``width_cm`` and is the knitting machine's."""
        from illuknit.cli.knitout_bridge import design_unit_aspect, resolve_machine

        s = {**_SWITCH_DEFAULTS, **switches}
        unknown = sorted(set(s) - set(_SWITCH_DEFAULTS))
        if unknown:
            raise TypeError(f"unknown switch of illuknit single: {unknown[0]}")
        spec = resolve_machine(s["machine"], gauge=s["gauge"])
        sizing = PictureOptions(
            width=s["width"], height=s["height"], width_cm=s["width_cm"], gauge=spec.gauge,
            unit_aspect=design_unit_aspect(spec), n_colors=s["n_colors"],
            yarns=parse_yarn_option(s["yarns"]), quantise=s["quantise"],
        )  # fmt: skip
        return cls(image, outdir, sizing, s["first"], spec, s["knitout"], s["title"])


#: The switches of ``illuknit single`` and their defaults.
_SWITCH_DEFAULTS: dict[str, Any] = {
    "width": None, "height": None, "width_cm": None, "gauge": None, "yarns": None,
    "n_colors": None, "quantise": True, "first": "dark", "knitout": False, "machine": None,
    "title": None,
}  # fmt: skip


def run_single(request: SingleRequest, *, progress: Report | None = None) -> dict[str, Path]:
    """Compile ``request.picture`` and write the whole bundle into ``request.outdir``
    (atomically). ``progress(fraction, message)`` hears how far it is."""
    from illuknit.cli.knitout_bridge import chart_kind, hand_border
    from illuknit.core.files import staged_dir
    from illuknit.outputs.export import export_pattern
    from illuknit.pipeline.single import design_single

    say: Report = progress or (lambda fraction, message: None)
    spec, image, outdir, first = request.machine, request.picture, request.outdir, request.first
    knitout, title = request.knitout, request.title
    say(0.0, "reading, quantising and compiling the picture")
    design = design_single(
        image,
        pictures=request.sizing,
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
            border=hand_border(),
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
        request = SingleRequest.from_switches(
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
        )
        paths = run_single(request, progress=report)
    summarise_pattern(
        load_pattern(paths["pattern"]),
        legend_path=paths.get("legend"),
        report_path=paths.get("report"),
    )
    print_written(outdir, paths)
