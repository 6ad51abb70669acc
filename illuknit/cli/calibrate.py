"""``illuknit calibrate``: the calibration swatch (paper Fig. 8) and the bump-height fit."""

from __future__ import annotations

import json
from pathlib import Path

import click

from illuknit.cli.knitout_bridge import (
    check_fits,
    format_option,
    long_floats_option,
    machine_option,
    resolve_machine,
    write_program,
)
from illuknit.cli.options import (
    LENGTH,
    MINUTES,
    InputFile,
    OutputFile,
    declared_option,
    knitout_option,
    outdir_option,
)
from illuknit.design.options import SearchOptions

__all__ = ["calibrate"]

#: Rows of split bumps in the swatch's split band (enough that no flat shows between them).
SPLIT_BAND_ROWS = 3


def _int_list(ctx: click.Context, param: click.Parameter, value: str) -> tuple[int, ...]:
    try:
        out = tuple(int(v) for v in value.split(",") if v.strip())
    except ValueError:
        raise click.BadParameter(
            f"expected comma-separated positive integers, got {value!r}"
        ) from None
    if not out or min(out) < 1:
        raise click.BadParameter(f"expected comma-separated positive integers, got {value!r}")
    return out


@click.group("calibrate")
def calibrate() -> None:
    """Tune the renderer to your yarn and machine: knit the swatch, measure, fit.

    \b
    1. illuknit calibrate swatch -o DIR
       writes the swatch pattern, a preview and measurements.csv to fill in.
    2. Knit it, hang it, and for each cell note the elevation (degrees) at
       which the flat stitches just disappear behind the bumps.
    3. illuknit calibrate fit DIR/measurements.csv -o params.json
       fits the bump height (see docs/render.md).
    For tall bumps knit a second swatch with --tall-bumps and fit it with
    --tall-bumps; for split bumps add --split-bumps (a band of split bumps)
    and pass the measured share to fit --split-share (docs/split-bumps.md).

    And the knitting time: illuknit calibrate time PROGRAM --minutes M -o my-machine.json
    fits the time model to one knit you timed; --machine my-machine.json then uses it.
    """


@calibrate.command("swatch")
@click.option(
    "--bump-sizes",
    default="1,2,3",
    show_default=True,
    callback=_int_list,
    help="Rows of bumps per cell band.",
)
@click.option(
    "--flat-sizes",
    default="1,2,3,4",
    show_default=True,
    callback=_int_list,
    help="Rows of flats per cell.",
)
@click.option(
    "--cell-width",
    type=click.IntRange(1, 100),
    default=6,
    show_default=True,
    help="Cell width in units.",
)
@click.option("--yarns", default="white,black", show_default=True, help="Bump yarn, flat yarn.")
@click.option(
    "--params",
    "params_file",
    type=InputFile("render parameters"),
    default=None,
    help="Current renderer parameters (for the preview and predicted angles).",
)
@click.option(
    "--tall-bumps",
    is_flag=True,
    help="Knit every bump of the swatch as a tall bump (with --knitout), and predict its "
    "angles with the tall bump height; fit its measurements with 'fit --tall-bumps'.",
)
@click.option(
    "--split-bumps",
    is_flag=True,
    help="Add a band of split bumps (first course bump yarn, second flat yarn) below the "
    "cells, to measure the split share from each side.",
)
@knitout_option("Also compile the swatch to DIR/program.k (mixed colourwork) and check it.")
@machine_option()
@format_option()
@long_floats_option()
@outdir_option()
def swatch(
    bump_sizes: tuple[int, ...],
    flat_sizes: tuple[int, ...],
    cell_width: int,
    yarns: str,
    params_file: Path | None,
    tall_bumps: bool,
    split_bumps: bool,
    knitout: bool,
    machine: str | None,
    outdir: Path,
) -> None:
    """Write swatch.json (the pattern), preview.png and measurements.csv (a template)."""
    from illuknit.core.files import atomic_write_text, staged_dir
    from illuknit.core.pattern import save_pattern
    from illuknit.core.progress import work_bar
    from illuknit.design.render.calibrate import calibration_swatch, measurements_template
    from illuknit.design.render.params import RenderParams, load_params
    from illuknit.design.render.raycast import render_image
    from illuknit.outputs.previews import chart_rgb, contact_sheet, save_png

    params = load_params(params_file) if params_file is not None else RenderParams()
    if tall_bumps:
        params = params.with_tall_bumps()
    spec = resolve_machine(machine)
    pattern = calibration_swatch(
        bump_sizes=bump_sizes,
        flat_sizes=flat_sizes,
        cell_width=cell_width,
        yarns=yarns,
        split_rows=SPLIT_BAND_ROWS if split_bumps else 0,
    )
    if knitout:
        check_fits(spec, pattern.shape[1])
    s = 8
    steps = 4 if knitout else 3  # the two renders and the knitout are the slow parts
    with work_bar("calibrate swatch") as report, staged_dir(outdir) as tmp:
        save_pattern(pattern, tmp / "swatch.json")
        report(0.0, "rendering view A")
        view_a = render_image(pattern, params.theta, params=params, scale=s)
        report(1 / steps, "rendering view B")
        view_b = render_image(pattern, -params.theta, params=params, scale=s)
        report(2 / steps, "writing the preview and the measurements template")
        sheet = contact_sheet(
            [
                ("head-on (raised marked)", chart_rgb(pattern, scale=s)),
                (f"view A, {params.theta:g} deg", view_a),
                (f"view B, {params.theta:g} deg", view_b),
            ]
        )
        save_png(sheet, tmp / "preview.png")
        atomic_write_text(tmp / "measurements.csv", measurements_template(pattern, params=params))
        if knitout:
            report(3 / steps, "compiling and checking the knitout program")
            write_program(pattern, tmp, machine=spec, tall_bumps=tall_bumps)
        report(1.0, "done")
    click.echo(
        f"wrote {outdir}: swatch.json ({pattern.shape[0]} x {pattern.shape[1]} units), preview.png, measurements.csv"
    )
    if tall_bumps:
        click.echo(
            "tall bumps: fit these measurements with 'illuknit calibrate fit ... --tall-bumps "
            "--params PARAMS' to keep the plain bump height and set tall_bump_height"
        )


@calibrate.command("fit")
@click.argument("measurements", type=InputFile("measurements"))
@click.option(
    "--params",
    "params_file",
    type=InputFile("render parameters"),
    default=None,
    help="Base parameters (flat height, unit length, theta, shading) to keep.",
)
@click.option("--flat-height", type=LENGTH, default=None, help="Override the base flat height.")
@click.option("--unit-length", type=LENGTH, default=None, help="Override the base unit length.")
@click.option(
    "--tall-bumps",
    is_flag=True,
    help="The measurements are of a swatch knit with tall bumps: the fit sets "
    "tall_bump_height and keeps the base bump height.",
)
@declared_option(
    SearchOptions, "split_share", default=None, note="Stored with the fitted parameters."
)
@click.option(
    "-o",
    "--output",
    type=OutputFile(allow_dash=True),
    required=True,
    help="Parameters JSON to write (- for standard output; the report then goes to standard "
    "error).",
)
def fit(
    measurements: Path,
    params_file: Path | None,
    flat_height: float | None,
    unit_length: float | None,
    tall_bumps: bool,
    split_share: float | None,
    output: Path,
) -> None:
    """Fit the bump height to MEASUREMENTS (CSV: flat_rows, angle_deg[, bump_rows, view, note])."""
    from dataclasses import replace

    from illuknit.core.files import STDOUT, write_output_file
    from illuknit.design.render.calibrate import fit_bump_height, read_measurements
    from illuknit.design.render.params import (
        RenderParams,
        load_params,
        params_to_json,
        save_params,
    )

    base = load_params(params_file) if params_file is not None else RenderParams()
    changes = {
        k: v
        for k, v in (("flat_height", flat_height), ("unit_length", unit_length))
        if v is not None
    }
    if changes:
        # Keep the base bump height valid while its flat height changes; the fit replaces it.
        fh = changes.get("flat_height", base.flat_height)
        base = replace(base, bump_height=max(base.bump_height, fh * 2), **changes)
    ms, skipped = read_measurements(measurements)
    result = fit_bump_height(ms, params=base, skipped=skipped)
    saved = result.params
    notes = []
    if tall_bumps:
        # The swatch had tall bumps: its fitted height is the tall one; the plain one stays.
        saved = replace(base, tall_bump_height=result.params.bump_height)
        notes.append(
            f"tall bumps: tall_bump_height = {saved.tall_bump_height:.4g}; bump_height kept at "
            f"{saved.bump_height:.4g}"
        )
    if split_share is not None:
        saved = replace(saved, split_share=split_share)
        notes.append(f"split_share = {split_share:g}")
    report = "\n".join([result.report(), *notes])
    if str(output) == STDOUT:
        text = json.dumps(params_to_json(saved), indent=1) + "\n"
        write_output_file(STDOUT, text.encode("utf-8"))
        click.echo(report, err=True)
        return
    save_params(saved, output)
    click.echo(report)
    click.echo(f"\nwrote {output}")


@calibrate.command("time")
@click.argument("program", type=InputFile("program"))
@click.option(
    "--minutes",
    type=MINUTES,
    required=True,
    help="How long the machine took to knit PROGRAM, start to finish, in minutes.",
)
@machine_option("Machine PROGRAM was knitted on (a preset, or a machine file).", transfer=False)
@click.option(
    "-o",
    "--output",
    type=OutputFile(),
    required=True,
    help="Machine file to write (JSON); name it with --machine for later estimates.",
)
def time_(program: Path, minutes: float, machine: str | None, output: Path) -> None:
    """Fit the knitting-time model to one timed knit of PROGRAM (a pattern JSON, a knitout
    file or a Kniterate .kc): the per-pass overhead that makes its machine passes take
    MINUTES, written as a machine file (see docs/knitting.md, "Time model")."""
    from illuknit.core.machine import DEFAULT_MACHINE_NAME, save_machine_file
    from illuknit.knitting.stats import calibrate_knit_time

    spec = resolve_machine(machine)
    fit = calibrate_knit_time(program, minutes, machine=spec)
    base = machine if machine and not machine.lower().endswith(".json") else None
    if base is None:
        # a machine file names its own preset; recalibrating keeps it
        from illuknit.core.documents import read_json_file
        from illuknit.core.errors import OptionError

        base = (
            str(read_json_file(machine, error=OptionError, what="machine").get("base"))
            if machine
            else DEFAULT_MACHINE_NAME
        )
    save_machine_file(fit.machine, output, base=base.lower())
    click.echo(fit.report())
    click.echo(f"wrote {output}: use it with --machine {output}")
