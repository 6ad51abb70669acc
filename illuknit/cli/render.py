"""``illuknit render``: ray-cast previews of a pattern from both sides, head-on, and a sweep GIF."""

from __future__ import annotations

from pathlib import Path

import click

from illuknit.cli.options import FINITE, outdir_option

__all__ = ["render"]


@click.command("render")
@click.argument("pattern_file", metavar="PATTERN", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--angle",
    type=FINITE,  # the range (0, 90] is checked with the other render parameters
    default=None,
    help="Side-view elevation in degrees, in (0, 90] (default: the params' theta).",
)
@click.option(
    "--params",
    "params_file",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Renderer parameters JSON (heights, unit length, theta, shading); see docs/render.md.",
)
@click.option(
    "--scale",
    type=click.IntRange(1, 64),
    default=None,
    help="Pixels per unit (default: about 640 px on the long side).",
)
@click.option(
    "--frames",
    type=click.IntRange(2, 400),
    default=31,
    show_default=True,
    help="GIF frames from one side to the other.",
)
@outdir_option()
def render(
    pattern_file: Path,
    angle: float | None,
    params_file: Path | None,
    scale: int | None,
    frames: int,
    outdir: Path,
) -> None:
    """Render PATTERN as a person sees it: view A (from above), view B (from below) and head-on
    PNGs, a contact sheet, and sweep.gif walking from one side through head-on to the other."""
    from illuknit.outputs import staged_dir
    from illuknit.pattern import load_pattern
    from illuknit.previews import contact_sheet, save_png, unit_scale
    from illuknit.render.params import RenderParams, check_angle, load_params, save_params
    from illuknit.render.raycast import render_image, sweep_angles

    params = load_params(params_file) if params_file is not None else RenderParams()
    a = check_angle(params.theta if angle is None else angle, name="--angle")
    params = params.with_angle(a)
    pattern = load_pattern(pattern_file)
    s = scale or max(2, unit_scale(pattern.shape))
    views = {
        "view_a": render_image(pattern, a, params=params, scale=s),
        "view_b": render_image(pattern, -a, params=params, scale=s),
        "headon": render_image(pattern, 90.0, params=params, scale=s),
    }
    # Frames go A -> head-on -> B and back, so the loop has no jump.
    angles = sweep_angles(a, frames)
    images = [render_image(pattern, x, params=params, scale=s) for x in angles]
    images += images[-2:0:-1]
    with staged_dir(outdir) as tmp:
        for name, img in views.items():
            save_png(img, tmp / f"{name}.png")
        sheet = contact_sheet(
            [
                (f"view A (from above, {a:g} deg)", views["view_a"]),
                ("head-on", views["headon"]),
                (f"view B (from below, {a:g} deg)", views["view_b"]),
            ]
        )
        save_png(sheet, tmp / "contact.png")
        _save_gif(images, tmp / "sweep.gif")
        save_params(params, tmp / "params.json")
    names = ", ".join(sorted(p.name for p in outdir.iterdir()))
    click.echo(f"wrote {outdir}: {names}")


def _save_gif(images: list, path: Path) -> None:
    from PIL import Image

    frames = [
        Image.fromarray(im).convert("P", palette=Image.Palette.ADAPTIVE, colors=64) for im in images
    ]
    n = len(images)
    # Hold the two side views and head-on a little longer than the frames in between.
    half = (n + 2) // 4
    durations = [500 if i in (0, half, 2 * half) else 60 for i in range(n)]
    frames[0].save(
        path, save_all=True, append_images=frames[1:], duration=durations, loop=0, disposal=1
    )
